#include "lom/ui/reset_camera_reaction.hpp"

#include "lom/ui/scene_view.hpp"

namespace lom::ui {

ResetCameraReaction::ResetCameraReaction(QAction* action, SceneView& scene)
    : Reaction(action), scene_(scene) {}

void ResetCameraReaction::onTriggered() { scene_.resetCamera(); }

}  // namespace lom::ui
