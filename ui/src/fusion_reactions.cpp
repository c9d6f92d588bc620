#include "lom/ui/fusion_reactions.hpp"

#include <QAction>

#include "lom/ui/map_worker.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

QString FusionReaction::stoppingNote() { return tr("Stopping the fusion…"); }

FusionReaction::FusionReaction(QAction* action, Kind kind, StudioSession& session,
                               std::function<void()> fuse)
    : Reaction(action), kind_(kind), session_(session), fuse_(std::move(fuse)) {
  if (kind_ == Kind::Pause) action->setCheckable(true);
  connect(&session_.worker(), &MapWorker::stateChanged, this, &FusionReaction::updateState);
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          &FusionReaction::updateState);
  updateState();
}

void FusionReaction::onTriggered() {
  MapWorker& worker = session_.worker();
  switch (kind_) {
    case Kind::Fuse:
      if (fuse_)
        fuse_();
      else
        session_.fuse();
      break;
    case Kind::Pause:
      // The frame being fused is finished first (a fine room-scale one takes
      // a minute), while the status already says paused.
      if (action()->isChecked() && worker.isFusing())
        emit session_.controller().noteOccurred(
            tr("Pausing: the frame being fused is finished first."));
      worker.setPaused(action()->isChecked());
      break;
    case Kind::Cancel:
      // A frame's map update is finished (a fine room-scale one takes half a
      // minute). Say at once that the stop is coming (the status shows where
      // it stopped).
      if (worker.isFusing()) emit session_.controller().noteOccurred(stoppingNote());
      worker.cancel();
      break;
    case Kind::Reset:
      session_.resetMap();
      break;
  }
}

void FusionReaction::updateState() {
  const bool open = session_.controller().hasSequence();
  const bool fusing = session_.worker().isFusing();
  switch (kind_) {
    case Kind::Fuse:
    case Kind::Reset:
      action()->setEnabled(open);
      break;
    case Kind::Pause:
      action()->setEnabled(fusing);
      action()->setChecked(session_.worker().state() == MapWorker::State::Paused);
      break;
    case Kind::Cancel:
      action()->setEnabled(fusing);
      break;
  }
}

}  // namespace lom::ui
