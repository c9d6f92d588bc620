#include "lom/ui/scene_view_reaction.hpp"

#include <QAction>

#include "lom/ui/projection_voxels.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

SceneViewReaction::SceneViewReaction(QAction* action, Kind kind, StudioSession& session,
                                     SceneView& scene)
    : Reaction(action), kind_(kind), session_(session), scene_(scene) {
  const bool one_shot = kind_ == Kind::LookFromFrame || kind_ == Kind::ZoomToMap ||
                        kind_ == Kind::LookFromAbove || kind_ == Kind::LookFromFront ||
                        kind_ == Kind::LookFromSide;
  action->setCheckable(!one_shot);
  action->setChecked(kind_ == Kind::FramePoints || kind_ == Kind::Cameras || kind_ == Kind::Axes ||
                     kind_ == Kind::Boxes);
  if (kind_ == Kind::ColourByHeight) {
    // Geometry without labels (a single label) shows its shape by height;
    // labelled sequences open in their label colours.
    connect(&session_.controller(), &SequenceController::sequenceChanged, this, [this] {
      const SequenceController& controller = session_.controller();
      this->action()->setChecked(controller.hasSequence() &&
                                 controller.sequence().labels.size() == 1);
      onTriggered();
    });
  }
  if (kind_ == Kind::ProjectionVoxels) {
    connect(&session_.controller(), &SequenceController::currentFrameChanged, this,
            &SceneViewReaction::showProjection);
    connect(&session_.controller(), &SequenceController::currentFrameDataChanged, this,
            &SceneViewReaction::showProjection);
    connect(&session_, &StudioSession::fusionOptionsChanged, this,
            &SceneViewReaction::showProjection);
  }
}

void SceneViewReaction::onTriggered() {
  SequenceController& controller = session_.controller();
  switch (kind_) {
    case Kind::LookFromFrame:
      if (controller.currentFrame() >= 0)
        scene_.lookFromFrame(controller.sequence(), static_cast<size_t>(controller.currentFrame()));
      break;
    case Kind::ZoomToMap:
      scene_.zoomToMap();
      break;
    case Kind::FramePoints:
      scene_.setFrameCloudVisible(action()->isChecked());
      break;
    case Kind::Cameras:
      scene_.setCamerasVisible(action()->isChecked());
      break;
    case Kind::Axes:
      scene_.setAxesVisible(action()->isChecked());
      break;
    case Kind::Boxes:
      scene_.setBoxesVisible(action()->isChecked());
      break;
    case Kind::OpacityByProbability:
      scene_.setOpacityByProbability(action()->isChecked());
      break;
    case Kind::ColourByHeight:
      scene_.setVoxelColouring(action()->isChecked() ? VoxelColouring::Height
                                                     : VoxelColouring::Labels);
      break;
    case Kind::ProjectionVoxels:
      showProjection();
      break;
    case Kind::LookFromAbove:
      scene_.lookFrom(SceneView::StandardView::Above);
      break;
    case Kind::LookFromFront:
      scene_.lookFrom(SceneView::StandardView::Front);
      break;
    case Kind::LookFromSide:
      scene_.lookFrom(SceneView::StandardView::Side);
      break;
  }
}

void SceneViewReaction::showProjection() {
  SequenceController& controller = session_.controller();
  const FrameData* frame = controller.currentFrameData();
  if (!action()->isChecked() || !frame || !session_.sequence()) {
    scene_.showProjectionVoxels(nullptr, {});
    return;
  }
  try {
    const MapSnapshot voxels =
        projectionVoxels(*session_.sequence(), static_cast<size_t>(controller.currentFrame()),
                         *frame, session_.fusionOptions());
    scene_.showProjectionVoxels(&voxels, session_.sequence()->labels);
  } catch (const std::exception&) {
    scene_.showProjectionVoxels(nullptr, {});  // the frame cannot give evidence
  }
}

}  // namespace lom::ui
