#pragma once
// Fusion > Fuse / Pause / Cancel / Reset Map.
#include "lom/ui/reaction.hpp"

namespace lom::ui {

class StudioSession;

class FusionReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Kind { Fuse, Pause, Cancel, Reset };
  FusionReaction(QAction* action, Kind kind, StudioSession& session);

 protected:
  void onTriggered() override;

 private:
  void updateState();

  Kind kind_;
  StudioSession& session_;
};

}  // namespace lom::ui
