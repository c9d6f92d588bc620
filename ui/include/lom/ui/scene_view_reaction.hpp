#pragma once
// View menu items that change the 3D view: look from the current frame's
// camera, show the frame's points, show the projection-baseline voxels of the
// current view, opacity by probability, colour by height.
#include "lom/ui/reaction.hpp"

namespace lom::ui {

class SceneView;
class StudioSession;

class SceneViewReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Kind {
    LookFromFrame,
    ZoomToMap,
    FramePoints,
    ProjectionVoxels,
    OpacityByProbability,
    ColourByHeight,
    LookFromAbove,
    LookFromFront,
    LookFromSide,
    Cameras,  // show the camera frustums
    Axes,     // show the orientation axes
    Boxes     // show the boxes' outlines
  };
  SceneViewReaction(QAction* action, Kind kind, StudioSession& session, SceneView& scene);

 protected:
  void onTriggered() override;

 private:
  void showProjection();

  Kind kind_;
  StudioSession& session_;
  SceneView& scene_;
};

}  // namespace lom::ui
