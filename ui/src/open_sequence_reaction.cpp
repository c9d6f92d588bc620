#include "lom/ui/open_sequence_reaction.hpp"

#include <QAction>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>

#include "lom/ui/recent_sequences.hpp"
#include "lom/ui/sequence_controller.hpp"

namespace lom::ui {

OpenSequenceReaction::OpenSequenceReaction(QAction* action, Pick pick,
                                           SequenceController& controller,
                                           const RecentSequences& recent, QWidget* dialog_parent)
    : Reaction(action),
      pick_(pick),
      controller_(controller),
      recent_(recent),
      dialog_parent_(dialog_parent) {}

QString OpenSequenceReaction::startFolder() const {
  const QStringList recent = recent_.paths();
  if (recent.isEmpty()) return QDir::currentPath();
  // A recent entry is a folder or its sequence.json: start beside it.
  const QFileInfo last(recent.front());
  return last.isDir() ? last.absolutePath() : last.dir().absolutePath();
}

void OpenSequenceReaction::onTriggered() {
  const QString path =
      pick_ == Pick::Folder
          ? QFileDialog::getExistingDirectory(dialog_parent_,
                                              tr("Open Sequence or Dataset Folder"), startFolder())
          : QFileDialog::getOpenFileName(
                dialog_parent_, tr("Open Sequence"), startFolder(),
                tr("Sequences and ROS bags (sequence.json *.bag);;JSON files (*.json);;"
                   "ROS bags (*.bag)"));
  if (!path.isEmpty()) controller_.openSequence(path);
}

}  // namespace lom::ui
