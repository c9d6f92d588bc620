#pragma once
#include "lom/ui/reaction.hpp"

namespace lom::ui {

class SceneView;

// View > Reset Camera: frames the whole trajectory and the current cloud.
class ResetCameraReaction : public Reaction {
  Q_OBJECT

 public:
  ResetCameraReaction(QAction* action, SceneView& scene);

 protected:
  void onTriggered() override;

 private:
  SceneView& scene_;
};

}  // namespace lom::ui
