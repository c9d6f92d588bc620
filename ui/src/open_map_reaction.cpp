#include "lom/ui/open_map_reaction.hpp"

#include <QAction>
#include <QFileDialog>

#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

OpenMapReaction::OpenMapReaction(QAction* action, StudioSession& session, QWidget* dialog_parent)
    : Reaction(action), session_(session), dialog_parent_(dialog_parent) {
  chooser_ = [this](const QString& start_folder) {
    return QFileDialog::getOpenFileName(dialog_parent_, tr("Open Map"), start_folder,
                                        tr("LabelOctoMap maps (*.ot);;All files (*)"));
  };
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          &OpenMapReaction::updateEnabled);
  updateEnabled();
}

void OpenMapReaction::updateEnabled() { action()->setEnabled(session_.sequence() != nullptr); }

void OpenMapReaction::onTriggered() {
  if (!session_.sequence()) return;
  // Maps are usually written beside the sequence folder (labeloctomap fuse
  // refuses to write inside it), or beside the recording that was converted.
  const QString start = session_.controller().outputFolder();
  const QString path = chooser_(start);
  if (!path.isEmpty()) session_.openMap(path);
}

}  // namespace lom::ui
