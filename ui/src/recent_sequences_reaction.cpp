#include "lom/ui/recent_sequences_reaction.hpp"

#include <QAction>
#include <QDir>
#include <QFileInfo>
#include <QMenu>

#include "lom/ui/recent_sequences.hpp"
#include "lom/ui/sequence_controller.hpp"

namespace lom::ui {

RecentSequencesReaction::RecentSequencesReaction(QMenu* menu, RecentSequences& recent,
                                                 SequenceController& controller)
    : QObject(menu), menu_(menu), recent_(recent), controller_(controller) {
  connect(menu_, &QMenu::aboutToShow, this, &RecentSequencesReaction::rebuildMenu);
  connect(&controller_, &SequenceController::sequenceChanged, this,
          [this] { recent_.add(controller_.sequencePath()); });
}

void RecentSequencesReaction::rebuildMenu() {
  menu_->clear();
  const QStringList paths = recent_.paths();
  if (paths.isEmpty()) {
    menu_->addAction(tr("(none)"))->setEnabled(false);
    return;
  }
  int number = 1;
  for (const QString& path : paths) {
    // A sequence.json goes by its folder's name; a folder or a bag by its own.
    const QFileInfo info(QDir::cleanPath(path));
    const QString name =
        info.fileName() == QLatin1String("sequence.json") ? info.dir().dirName() : info.fileName();
    QAction* entry = menu_->addAction(
        tr("&%1 %2  (%3)").arg(number++).arg(name, QDir::toNativeSeparators(path)));
    // An entry whose sequence is gone is reported once (by the open) and
    // dropped; never without that report (an open cancelled at the question
    // about unsaved work, say, while the folder was being renamed).
    connect(entry, &QAction::triggered, this, [this, path] {
      bool reported = false;
      const auto report = connect(&controller_, &SequenceController::errorOccurred, this,
                                  [&reported] { reported = true; });
      const bool opened = controller_.openSequence(path);
      disconnect(report);
      if (!opened && reported && !QFileInfo::exists(path)) recent_.remove(path);
    });
  }
  menu_->addSeparator();
  connect(menu_->addAction(tr("Clear Recent")), &QAction::triggered, this,
          [this] { recent_.clear(); });
}

}  // namespace lom::ui
