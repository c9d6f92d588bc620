#pragma once
// The ground-truth boxes being edited, the selected box and the undo stack
// that records every change (add, delete, move, label change).
#include <QByteArray>
#include <QObject>
#include <QString>
#include <QUndoStack>
#include <map>

#include "lom/annotations.hpp"

namespace lom::ui {

class AnnotationsModel : public QObject {
  Q_OBJECT

 public:
  explicit AnnotationsModel(QObject* parent = nullptr);
  ~AnnotationsModel() override;

  [[nodiscard]] const Annotations& annotations() const { return annotations_; }
  [[nodiscard]] int boxCount() const { return static_cast<int>(annotations_.boxes.size()); }
  [[nodiscard]] const GroundTruthBox& box(int index) const { return annotations_.boxes.at(index); }
  [[nodiscard]] int selected() const { return selected_; }  // -1 for none
  // The first box of `label` (one box per object), -1 when it has none.
  [[nodiscard]] int indexOfLabel(int label) const;
  [[nodiscard]] QUndoStack& undoStack() { return undo_stack_; }
  [[nodiscard]] bool isDirty() const { return !undo_stack_.isClean(); }
  // The file the boxes were loaded from or last saved to (empty when new).
  [[nodiscard]] QString path() const { return path_; }
  // The boxes file of the sequence that exists but could not be read (empty
  // when there is none), and why. It is never written without the user's
  // explicit confirmation: the boxes in it would be lost. Other boxes being
  // loaded, or saving over it, ends this.
  [[nodiscard]] QString unreadablePath() const { return unreadable_path_; }
  [[nodiscard]] QString unreadableError() const { return unreadable_error_; }
  // Boxes files as the studio last saw them (read, saved, or found absent
  // when the sequence opened), to tell whether another program or another
  // studio wrote one since: saving over it would lose that.
  enum class DiskChange {
    None,     // as seen, deleted since, or never seen
    Changed,  // other bytes than when read or saved
    Made,     // absent when seen, there now
  };
  [[nodiscard]] DiskChange diskChange(const QString& path) const;
  // Records what `path` holds now (or that it is absent).
  void noteFile(const QString& path);
  // Every file seen (absolute path -> SHA-256 of its bytes, empty: absent),
  // and the way to restore them (recovery copies carry them).
  [[nodiscard]] const std::map<QString, QByteArray>& knownFiles() const { return known_files_; }
  void setKnownFile(const QString& path, const QByteArray& digest);
  void forgetKnownFiles() { known_files_.clear(); }

  // Replaces everything, clears the undo history and marks the state clean.
  void reset(const Annotations& annotations, const QString& path);
  // Starts with `annotations` (no file) because `unreadable_path` failed to load.
  void resetUnreadable(const Annotations& annotations, const QString& unreadable_path,
                       const QString& error);
  void markSaved(const QString& path);
  void select(int index);  // clamped; -1 clears
  void selectNext(int step = 1);

  // Undoable edits.
  void addBox(const GroundTruthBox& box);
  // When the removed box is the selected one, `successor` (a box's index
  // before the removal; -1: the removed box's successor in file order) is
  // selected afterwards: a view sorted its own way moves its selection to
  // its next row.
  void removeBox(int index, int successor = -1);
  // Edits with the same non-negative merge id on the same box are merged into
  // one undo step (a drag of the 3D handles).
  void setBox(int index, const GroundTruthBox& box, const QString& text, int merge_id = -1);

  // Raw changes for the undo commands; they do not touch the undo stack.
  void insertRaw(int index, const GroundTruthBox& box);
  void removeRaw(int index, int successor = -1);
  void replaceRaw(int index, const GroundTruthBox& box);

 signals:
  void boxesChanged();
  void selectionChanged(int index);
  void dirtyChanged(bool dirty);
  void saved();

 private:
  Annotations annotations_;
  int selected_ = -1;
  QString path_;
  QString unreadable_path_;
  QString unreadable_error_;
  std::map<QString, QByteArray> known_files_;  // see knownFiles
  QUndoStack undo_stack_;
};

}  // namespace lom::ui
