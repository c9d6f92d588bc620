#include "lom/ui/frame_step_reaction.hpp"

#include <QAction>

#include "lom/ui/sequence_controller.hpp"

namespace lom::ui {

FrameStepReaction::FrameStepReaction(QAction* action, Step step, SequenceController& controller)
    : Reaction(action), step_(step), controller_(controller) {
  connect(&controller_, &SequenceController::sequenceChanged, this,
          &FrameStepReaction::updateEnabled);
  connect(&controller_, &SequenceController::currentFrameChanged, this,
          &FrameStepReaction::updateEnabled);
  updateEnabled();
}

void FrameStepReaction::onTriggered() {
  switch (step_) {
    case Step::First:
      controller_.setCurrentFrame(0);
      break;
    case Step::Previous:
      controller_.stepFrames(-1);
      break;
    case Step::Next:
      controller_.stepFrames(+1);
      break;
    case Step::Last:
      controller_.setCurrentFrame(controller_.frameCount() - 1);
      break;
  }
}

void FrameStepReaction::updateEnabled() {
  const int index = controller_.currentFrame();
  const bool at_start = index <= 0;
  const bool at_end = index >= controller_.frameCount() - 1;
  const bool backwards = step_ == Step::First || step_ == Step::Previous;
  action()->setEnabled(controller_.hasSequence() && (backwards ? !at_start : !at_end));
}

}  // namespace lom::ui
