#include "lom/ui/box_file_reaction.hpp"

#include <QAction>
#include <QFileDialog>
#include <QMessageBox>

#include "lom/ui/annotation_files.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

BoxFileReaction::BoxFileReaction(QAction* action, Kind kind, StudioSession& session,
                                 QWidget* parent, const ErrorReporter& report)
    : Reaction(action), kind_(kind), session_(session), parent_(parent), report_(report) {
  auto update = [this] { this->action()->setEnabled(session_.controller().hasSequence()); };
  connect(&session_.controller(), &SequenceController::sequenceChanged, this, update);
  update();
}

void BoxFileReaction::onTriggered() {
  const QString start = defaultBoxesPath(session_);
  const QString json_filter = tr("Annotations (*.json)");
  QString path;
  switch (kind_) {
    case Kind::Save:
      path = start;
      break;
    case Kind::SaveAs:
      path = QFileDialog::getSaveFileName(parent_, tr("Save Boxes"), start, json_filter);
      break;
    case Kind::Open:
    case Kind::ImportYaml:
      if (session_.annotations().isDirty() &&
          QMessageBox::question(parent_, tr("Discard unsaved boxes?"),
                                tr("The boxes have unsaved changes. Discard them?"),
                                QMessageBox::Discard | QMessageBox::Cancel,
                                QMessageBox::Cancel) != QMessageBox::Discard)
        return;
      path = QFileDialog::getOpenFileName(
          parent_, kind_ == Kind::Open ? tr("Open Boxes") : tr("Import YAML Boxes"), start,
          kind_ == Kind::Open ? json_filter : tr("YAML boxes (*.yaml *.yml)"));
      break;
  }
  if (path.isEmpty()) return;
  QString error;
  if (kind_ == Kind::Open)
    error = loadBoxes(session_, path);
  else if (kind_ == Kind::ImportYaml)
    error = importYamlBoxes(session_, path);
  else
    error = saveBoxes(session_, path);
  if (!error.isEmpty()) report_(tr("Boxes"), error);
}

}  // namespace lom::ui
