#include "lom/ui/annotations_model.hpp"

#include <QCryptographicHash>
#include <QFile>
#include <QFileInfo>
#include <QUndoCommand>
#include <algorithm>

namespace lom::ui {

namespace {

class AddBoxCommand : public QUndoCommand {
 public:
  AddBoxCommand(AnnotationsModel& model, GroundTruthBox box)
      : model_(model),
        box_(std::move(box)),
        index_(model.boxCount()),
        selected_before_(model.selected()) {
    setText(QObject::tr("Add box %1").arg(QString::fromStdString(box_.name)));
  }
  void redo() override {
    model_.insertRaw(index_, box_);
    model_.select(index_);
  }
  // The box selected before the add is selected again (the one before the
  // removed box was, wherever the selection had been).
  void undo() override {
    model_.removeRaw(index_);
    model_.select(selected_before_);
  }

 private:
  AnnotationsModel& model_;
  GroundTruthBox box_;
  int index_;
  int selected_before_;
};

class RemoveBoxCommand : public QUndoCommand {
 public:
  RemoveBoxCommand(AnnotationsModel& model, int index, int successor)
      : model_(model), box_(model.box(index)), index_(index), successor_(successor) {
    setText(QObject::tr("Delete box %1").arg(QString::fromStdString(box_.name)));
  }
  void redo() override { model_.removeRaw(index_, successor_); }
  void undo() override {
    model_.insertRaw(index_, box_);
    model_.select(index_);
  }

 private:
  AnnotationsModel& model_;
  GroundTruthBox box_;
  int index_;
  int successor_;
};

class SetBoxCommand : public QUndoCommand {
 public:
  SetBoxCommand(AnnotationsModel& model, int index, GroundTruthBox after, const QString& text,
                int merge_id)
      : model_(model), index_(index), before_(model.box(index)), after_(std::move(after)),
        merge_id_(merge_id) {
    setText(text);
  }
  void redo() override {
    model_.replaceRaw(index_, after_);
    model_.select(index_);
  }
  void undo() override {
    model_.replaceRaw(index_, before_);
    model_.select(index_);
  }
  [[nodiscard]] int id() const override { return merge_id_; }
  bool mergeWith(const QUndoCommand* other) override {
    const auto* next = static_cast<const SetBoxCommand*>(other);
    if (next->index_ != index_) return false;
    after_ = next->after_;
    return true;
  }

 private:
  AnnotationsModel& model_;
  int index_;
  GroundTruthBox before_;
  GroundTruthBox after_;
  int merge_id_;
};

}  // namespace

AnnotationsModel::AnnotationsModel(QObject* parent) : QObject(parent) {
  connect(&undo_stack_, &QUndoStack::cleanChanged, this,
          [this](bool clean) { emit dirtyChanged(!clean); });
}

AnnotationsModel::~AnnotationsModel() {
  // Clearing the stack on destruction must not reach views being torn down.
  undo_stack_.blockSignals(true);
}

namespace {

// The digest of a file's bytes; empty when it cannot be read (or is absent).
QByteArray fileDigest(const QString& path) {
  if (path.isEmpty()) return {};
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly)) return {};
  QCryptographicHash hash(QCryptographicHash::Sha256);
  if (!hash.addData(&file)) return {};
  return hash.result();
}

// One key per file however its path is spelt (a recovery copy made when the
// sequence was opened through a link is restored when it is opened directly).
QString knownKey(const QString& path) {
  const QFileInfo info(path);
  const QString file = info.canonicalFilePath();
  if (!file.isEmpty()) return file;
  const QString folder = QFileInfo(info.absolutePath()).canonicalFilePath();
  return folder.isEmpty() ? info.absoluteFilePath() : folder + "/" + info.fileName();
}

}  // namespace

AnnotationsModel::DiskChange AnnotationsModel::diskChange(const QString& path) const {
  if (path.isEmpty()) return DiskChange::None;
  const auto seen = known_files_.find(knownKey(path));
  if (seen == known_files_.end()) return DiskChange::None;
  const QByteArray now = fileDigest(path);
  if (now.isEmpty() || now == seen->second) return DiskChange::None;
  return seen->second.isEmpty() ? DiskChange::Made : DiskChange::Changed;
}

void AnnotationsModel::noteFile(const QString& path) {
  if (!path.isEmpty()) known_files_[knownKey(path)] = fileDigest(path);
}

void AnnotationsModel::setKnownFile(const QString& path, const QByteArray& digest) {
  if (!path.isEmpty()) known_files_[knownKey(path)] = digest;
}

void AnnotationsModel::reset(const Annotations& annotations, const QString& path) {
  const bool was_dirty = isDirty();
  undo_stack_.clear();
  // Qt's clear() returns at once on an empty stack, keeping a clean state of
  // "never" (resetClean, restored or imported boxes): the boxes read now are
  // the clean state.
  undo_stack_.setClean();
  annotations_ = annotations;
  path_ = path;
  noteFile(path);
  unreadable_path_.clear();
  unreadable_error_.clear();
  selected_ = annotations_.boxes.empty() ? -1 : 0;
  emit boxesChanged();
  emit selectionChanged(selected_);
  if (was_dirty) emit dirtyChanged(false);
}

void AnnotationsModel::resetUnreadable(const Annotations& annotations,
                                       const QString& unreadable_path, const QString& error) {
  reset(annotations, QString());
  unreadable_path_ = unreadable_path;
  unreadable_error_ = error;
}

void AnnotationsModel::markSaved(const QString& path) {
  path_ = path;
  noteFile(path);
  // Replaced after the user's confirmation: it is a readable boxes file now.
  // (Saved elsewhere, it still holds the boxes that could not be read.)
  if (QFileInfo(path) == QFileInfo(unreadable_path_)) {
    unreadable_path_.clear();
    unreadable_error_.clear();
  }
  undo_stack_.setClean();
  emit saved();
}

int AnnotationsModel::indexOfLabel(int label) const {
  for (int i = 0; i < boxCount(); ++i)
    if (box(i).label == label) return i;
  return -1;
}

void AnnotationsModel::select(int index) {
  index = boxCount() == 0 ? -1 : std::clamp(index, -1, boxCount() - 1);
  if (index == selected_) return;
  selected_ = index;
  emit selectionChanged(selected_);
}

void AnnotationsModel::selectNext(int step) {
  if (boxCount() == 0) return;
  const int start = selected_ < 0 ? (step > 0 ? -1 : 0) : selected_;
  select(((start + step) % boxCount() + boxCount()) % boxCount());
}

void AnnotationsModel::addBox(const GroundTruthBox& box) {
  undo_stack_.push(new AddBoxCommand(*this, box));
}

void AnnotationsModel::removeBox(int index, int successor) {
  if (index < 0 || index >= boxCount()) return;
  if (successor == index || successor >= boxCount()) successor = -1;
  undo_stack_.push(new RemoveBoxCommand(*this, index, successor));
}

void AnnotationsModel::setBox(int index, const GroundTruthBox& box, const QString& text,
                              int merge_id) {
  if (index < 0 || index >= boxCount()) return;
  // An edit that changes nothing (the label chosen again, a shrink at the
  // smallest size) is no step to undo and leaves saved boxes saved.
  const GroundTruthBox& current = annotations_.boxes[static_cast<size_t>(index)];
  if (current.label == box.label && current.name == box.name &&
      current.box.center == box.box.center && current.box.size == box.box.size &&
      current.box.rotation.coeffs() == box.box.rotation.coeffs())
    return;
  undo_stack_.push(new SetBoxCommand(*this, index, box, text, merge_id));
}

// The selection follows the box, not its position: a box inserted or removed
// before the selected one moves the selected index with it, and every view
// hears of the new index (an undo or redo otherwise left the views on one box
// and the model on another).
void AnnotationsModel::insertRaw(int index, const GroundTruthBox& box) {
  annotations_.boxes.insert(annotations_.boxes.begin() + index, box);
  const bool moved = selected_ >= index;
  if (moved) ++selected_;
  emit boxesChanged();
  if (moved) emit selectionChanged(selected_);
}

void AnnotationsModel::removeRaw(int index, int successor) {
  annotations_.boxes.erase(annotations_.boxes.begin() + index);
  if (successor >= 0 && selected_ == index)
    selected_ = successor > index ? successor - 1 : successor;
  // The removed box's successor takes its place (the last box's predecessor).
  else if (index < selected_ || selected_ >= boxCount())
    --selected_;
  emit boxesChanged();
  emit selectionChanged(selected_);
}

void AnnotationsModel::replaceRaw(int index, const GroundTruthBox& box) {
  annotations_.boxes[static_cast<size_t>(index)] = box;
  emit boxesChanged();
}

}  // namespace lom::ui
