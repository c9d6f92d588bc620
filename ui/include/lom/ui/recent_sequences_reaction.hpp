#pragma once
#include <QObject>

class QMenu;

namespace lom::ui {

class RecentSequences;
class SequenceController;

// Fills File > Open Recent from RecentSequences each time it is shown.
class RecentSequencesReaction : public QObject {
  Q_OBJECT

 public:
  RecentSequencesReaction(QMenu* menu, RecentSequences& recent, SequenceController& controller);

 private:
  void rebuildMenu();

  QMenu* menu_;
  RecentSequences& recent_;
  SequenceController& controller_;
};

}  // namespace lom::ui
