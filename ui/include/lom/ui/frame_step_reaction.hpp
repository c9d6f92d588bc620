#pragma once
#include "lom/ui/reaction.hpp"

namespace lom::ui {

class SequenceController;

// View > First / Previous / Next / Last Frame; enabled while a sequence is open.
class FrameStepReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Step { First, Previous, Next, Last };

  FrameStepReaction(QAction* action, Step step, SequenceController& controller);

 protected:
  void onTriggered() override;

 private:
  void updateEnabled();

  Step step_;
  SequenceController& controller_;
};

}  // namespace lom::ui
