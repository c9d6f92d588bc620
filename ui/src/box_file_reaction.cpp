#include "lom/ui/box_file_reaction.hpp"

#include <QAction>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QMessageBox>
#include <QPushButton>

#include "lom/ui/annotation_files.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/pending_edits.hpp"
#include "lom/ui/save_file_dialog.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

namespace {

bool sameFile(const QString& a, const QString& b) {
  const QFileInfo first(a), second(b);
  if (first.exists() && second.exists())
    return first.canonicalFilePath() == second.canonicalFilePath();
  return first.absoluteFilePath() == second.absoluteFilePath();
}

// "annotations-2.json" (or -3, ...) beside `path`: a name nothing uses yet.
QString freeNameBeside(const QString& path) {
  const QFileInfo info(path);
  for (int n = 2;; ++n) {
    const QString candidate =
        info.absolutePath() + "/" + info.completeBaseName() + "-" + QString::number(n) + ".json";
    if (!QFileInfo::exists(candidate)) return candidate;
  }
}

}  // namespace

BoxFileReaction::BoxFileReaction(QAction* action, Kind kind, StudioSession& session,
                                 QWidget* parent, const ErrorReporter& report)
    : Reaction(action), kind_(kind), session_(session), parent_(parent), report_(report) {
  auto update = [this] { this->action()->setEnabled(session_.controller().hasSequence()); };
  connect(&session_.controller(), &SequenceController::sequenceChanged, this, update);
  update();
}

namespace {

enum class ReplaceAnswer { Replace, SaveAs, Cancel };

// A warning before `path` is replaced: Save As… (the default), Replace or Cancel.
ReplaceAnswer askBeforeReplacing(QWidget* parent, const QString& title, const QString& text,
                                 const QString& replace, const QString& path) {
  QMessageBox question(QMessageBox::Warning, title, text, QMessageBox::Cancel, parent);
  QPushButton* save_as = question.addButton(QObject::tr("Save As…"), QMessageBox::AcceptRole);
  QPushButton* replace_button =
      question.addButton(replace.arg(QFileInfo(path).fileName()), QMessageBox::DestructiveRole);
  question.setDefaultButton(save_as);
  question.setEscapeButton(QMessageBox::Cancel);
  question.exec();
  if (question.clickedButton() == replace_button) return ReplaceAnswer::Replace;
  return question.clickedButton() == save_as ? ReplaceAnswer::SaveAs : ReplaceAnswer::Cancel;
}

}  // namespace

bool BoxFileReaction::confirmTarget(QString& path) {
  const AnnotationsModel& model = session_.annotations();
  const QString json_filter = tr("Annotations (*.json)");
  while (!model.unreadablePath().isEmpty() && sameFile(path, model.unreadablePath())) {
    const ReplaceAnswer answer =
        askBeforeReplacing(parent_, tr("Overwrite an unreadable boxes file?"),
                           tr("%1 could not be read when the sequence was opened:\n\n%2\n\n"
                              "Saving there replaces it, and the boxes it holds are lost. Save the "
                              "boxes under another name instead?")
                               .arg(QDir::toNativeSeparators(path), model.unreadableError()),
                           tr("Overwrite %1"), path);
    if (answer == ReplaceAnswer::Replace) return true;
    if (answer == ReplaceAnswer::Cancel) return false;
    path = askSaveFileName(parent_, tr("Save Boxes"), freeNameBeside(path), json_filter, {"json"});
    if (path.isEmpty()) return false;
  }
  // Another program or another studio wrote the file since the studio read
  // or saved it (or made it since the sequence opened without it): saving
  // would replace that unseen.
  const AnnotationsModel::DiskChange change = model.diskChange(path);
  if (change == AnnotationsModel::DiskChange::None) return true;
  const ReplaceAnswer answer = askBeforeReplacing(
      parent_, tr("Replace boxes changed on disk?"),
      (change == AnnotationsModel::DiskChange::Changed
           ? tr("%1 was changed on disk after the studio read or saved it, by another "
                "program or another LabelOctoMap Studio.")
           : tr("%1 was made by another program or another LabelOctoMap Studio after this "
                "sequence was opened."))
              .arg(QDir::toNativeSeparators(path)) +
          tr("\n\nSaving there replaces those boxes with the ones shown here. Save these boxes "
             "under another name instead (Open Boxes… then shows the file's)?"),
      tr("Replace %1"), path);
  if (answer == ReplaceAnswer::Replace) return true;
  if (answer == ReplaceAnswer::Cancel) return false;
  path = askSaveFileName(parent_, tr("Save Boxes"), freeNameBeside(path), json_filter, {"json"});
  return !path.isEmpty();
}

void BoxFileReaction::onTriggered() {
  commitPendingEdits();  // a value still being typed belongs to the boxes
  const QString start = defaultBoxesPath(session_);
  const QString json_filter = tr("Annotations (*.json)");
  QString path;
  switch (kind_) {
    case Kind::Save:
      path = start;
      break;
    case Kind::SaveAs:
      path = askSaveFileName(parent_, tr("Save Boxes"), start, json_filter, {"json"});
      break;
    case Kind::Open:
    case Kind::ImportYaml:
      if (session_.annotations().isDirty()) {
        const UnsavedBoxesAnswer answer = askAboutUnsavedBoxes(parent_);
        if (answer == UnsavedBoxesAnswer::Cancel) return;
        if (answer == UnsavedBoxesAnswer::Save) {
          saveTo(start);
          if (session_.annotations().isDirty()) return;  // not saved: keep them
        }
      }
      path = QFileDialog::getOpenFileName(
          parent_, kind_ == Kind::Open ? tr("Open Boxes") : tr("Import YAML Boxes"), start,
          kind_ == Kind::Open ? json_filter : tr("YAML boxes (*.yaml *.yml)"));
      break;
  }
  if (path.isEmpty()) return;
  if (kind_ == Kind::Save || kind_ == Kind::SaveAs) return saveTo(path);
  const QString error =
      kind_ == Kind::Open ? loadBoxes(session_, path) : importYamlBoxes(session_, path);
  if (!error.isEmpty()) report_(tr("Boxes"), error);
}

bool BoxFileReaction::refuseSequenceFile(const QString& path) {
  const QString input = session_.controller().sequenceFileAt(path);
  if (input.isEmpty()) return false;
  // The open sequence's own boxes file is where its boxes belong.
  if (const auto sequence = session_.sequence())
    for (const char* name : {"annotations.json", "annotations.yaml", "annotations.yml"})
      if (input == QString::fromStdString((sequence->root / name).string())) return false;
  report_(tr("Boxes"), tr("%1 is a file of the sequence (%2): boxes are never saved over it. "
                          "Choose another name.")
                           .arg(QDir::toNativeSeparators(path), QDir::toNativeSeparators(input)));
  return true;
}

void BoxFileReaction::saveTo(QString path) {
  commitPendingEdits();  // a value still being typed belongs to the boxes
  if (refuseSequenceFile(path)) return;
  // The unreadable-file question may have had another name chosen.
  if (!confirmTarget(path) || refuseSequenceFile(path)) return;
  const QString error = saveBoxes(session_, path);
  if (!error.isEmpty()) return report_(tr("Boxes"), error);
  // Saved as they are (nothing is lost), but a file `labeloctomap score`
  // refuses is said at once, not when the scores are wanted.
  if (const auto sequence = session_.sequence())
    if (const QString unknown = unknownLabelsMessage(
            session_.annotations().annotations(), sequence->labels, QDir::toNativeSeparators(path));
        !unknown.isEmpty())
      emit session_.controller().warningOccurred(
          tr("Saved with labels the sequence lacks"),
          tr("The boxes were saved, but `labeloctomap score` refuses the file while it holds "
             "these:\n\n%1")
              .arg(unknown));
}

}  // namespace lom::ui
