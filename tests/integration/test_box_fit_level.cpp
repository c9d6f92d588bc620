// Boxes do not depend on how the world's axes lie: in a recording whose
// world is its first camera's frame (up tilted by the camera's pitch) every
// fitted box stands on the scene's up (its cameras' mean up levelled by the
// bin's floor), as in the same recording in a world whose z is up. Box IU
// still differs by what the two fused maps differ by: a grid tilted against
// the surfaces holds them in thicker layers of voxels.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "lom/box_fit.hpp"
#include "lom/evaluation.hpp"
#include "lom/objects.hpp"
#include "lom/synth.hpp"
#include "test_support.hpp"

namespace {

using lom::test::TempDir;

TEST(BoxFitLevel, BoxesStandOnTheScenesUpInAWorldThatIsTheFirstCamerasFrame) {
  lom::SynthOptions scene_options;
  scene_options.seed = 1;
  scene_options.objects = 6;
  scene_options.frames = 8;
  scene_options.views = 3;
  scene_options.width = 320;
  scene_options.height = 240;
  TempDir dir;
  const lom::SynthScene scene = lom::writeSyntheticScene(scene_options, dir.path());
  const lom::Sequence level_sequence = lom::loadSequence(dir.path());
  const lom::EvaluationOptions options;

  // The same recording and boxes, re-expressed in the first camera's frame.
  const Eigen::Isometry3d to_camera = level_sequence.frames.front().T_world_camera.inverse();
  lom::Sequence camera_sequence = level_sequence;
  for (lom::FrameRecord& frame : camera_sequence.frames)
    frame.T_world_camera = to_camera * frame.T_world_camera;
  lom::Annotations camera_boxes = scene.annotations;
  for (lom::GroundTruthBox& box : camera_boxes.boxes) {
    box.box.center = to_camera * box.box.center;
    box.box.rotation = Eigen::Quaterniond(to_camera.linear() * box.box.rotation.toRotationMatrix());
  }
  const Eigen::Vector3d true_up = to_camera.linear() * Eigen::Vector3d::UnitZ();
  ASSERT_LT(true_up.z(), 0.99) << "the first camera is pitched: its world is tilted";

  const lom::LabelMap level_map = lom::fuseSequence(level_sequence, options.fusion);
  const lom::LabelMap camera_map = lom::fuseSequence(camera_sequence, options.fusion);
  const lom::EvaluationReport level =
      lom::evaluate(level_sequence, scene.annotations, level_map, options);
  const lom::EvaluationReport camera =
      lom::evaluate(camera_sequence, camera_boxes, camera_map, options);
  ASSERT_EQ(level.objects.size(), camera.objects.size());
  std::cout << "Box IU (LabelOctoMap) x100: z-up world " << 100 * level.summary.box_iou.labeloctomap
            << ", first camera's world " << 100 * camera.summary.box_iou.labeloctomap << "\n";
  // The scene's up in the camera's world, as the studio finds it: the bin's
  // floor levels the cameras' mean up to within a degree or so of the truth.
  const lom::SceneLevel scene_level = lom::sceneLevelOf(camera_map);
  ASSERT_TRUE(scene_level.plane.has_value());
  ASSERT_GT(scene_level.up.dot(true_up), std::cos(2.0 * M_PI / 180.0));
  for (size_t i = 0; i < level.objects.size(); ++i) {
    const lom::ObjectScore& a = level.objects[i];
    const lom::ObjectScore& b = camera.objects[i];
    SCOPED_TRACE(a.name);
    ASSERT_EQ(a.label, b.label);
    if (!b.fitted_box) continue;
    // Every box stands on the scene's up (no object of the scene lies tilted).
    const Eigen::Vector3d box_z = b.fitted_box->rotation * Eigen::Vector3d::UnitZ();
    EXPECT_GT(box_z.dot(scene_level.up), 1.0 - 1e-9) << "the box stands along the scene's up";
  }
  EXPECT_NEAR(level.summary.box_iou.labeloctomap, camera.summary.box_iou.labeloctomap, 0.15);

  // Objects (export --format objects, plan) stand along the map's up as well.
  for (const lom::ObjectInstance& object : lom::extractObjects(camera_map)) {
    SCOPED_TRACE(object.name);
    const Eigen::Vector3d box_z = object.box.rotation * Eigen::Vector3d::UnitZ();
    EXPECT_GT(box_z.dot(scene_level.up), 1.0 - 1e-9);
  }
}

}  // namespace
