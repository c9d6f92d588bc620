// What the 3D view frames of a map: the bulk of the voxels shown, as `render`
// frames it. A speck of flying pixels far from the scene no longer leaves the
// map small after Zoom to Map, a standard view or Reset Camera.
#include <gtest/gtest.h>

#include <QAction>
#include <QImage>
#include <string>

#include "demo_window_fixture.hpp"
#include "lom/box_fit.hpp"
#include "lom/ui/map_snapshot.hpp"
#include "lom/ui/scene_view.hpp"

namespace lom::ui {
namespace {

constexpr double kEdge = 0.01;

// A finest voxel at integer voxel coordinates (i, j, k).
OccupiedVoxel voxelAt(int i, int j, int k, int label) {
  return {Eigen::Vector3d((i + 0.5) * kEdge, (j + 0.5) * kEdge, (k + 0.5) * kEdge), kEdge, label,
          0.9f};
}

MapSnapshot blockAndSpeck() {
  MapSnapshot snapshot;
  snapshot.resolution = kEdge;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) snapshot.voxels.push_back(voxelAt(i, j, k, 1));
  snapshot.voxels.push_back(voxelAt(300, 0, 0, 2));  // 3 m away
  snapshot.voxels.push_back(voxelAt(301, 1, 0, 2));
  return snapshot;
}

void expectBox(const std::optional<Eigen::AlignedBox3d>& box, const Eigen::Vector3d& min,
               const Eigen::Vector3d& max) {
  ASSERT_TRUE(box.has_value());
  EXPECT_LT((box->min() - min).norm(), 1e-9) << box->min().transpose();
  EXPECT_LT((box->max() - max).norm(), 1e-9) << box->max().transpose();
}

TEST(BulkBounds, LeaveOutSpecksAndHiddenLabels) {
  MapSnapshot snapshot = blockAndSpeck();
  expectBox(bulkBounds(snapshot, {}), Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.03));
  // The speck alone (the block hidden) is framed: no part is large enough.
  expectBox(bulkBounds(snapshot, {1}), Eigen::Vector3d(3.0, 0.0, 0.0),
            Eigen::Vector3d(3.02, 0.02, 0.01));
  EXPECT_FALSE(bulkBounds(snapshot, {1, 2}).has_value()) << "nothing shown";
  EXPECT_FALSE(bulkBounds(MapSnapshot{}, {}).has_value());

  // A pruned leaf of 2^3 voxels is a part of 8 by itself, and joins the
  // voxels it touches.
  MapSnapshot leaf;
  leaf.resolution = kEdge;
  leaf.voxels.push_back({Eigen::Vector3d(0.51, 0.01, 0.01), 2 * kEdge, 3, 0.9f});  // 0.50-0.52
  leaf.voxels.push_back(voxelAt(52, 0, 0, 1));                                     // touches it
  leaf.voxels.push_back(voxelAt(-200, 0, 0, 1));
  expectBox(bulkBounds(leaf, {}), Eigen::Vector3d(0.5, 0.0, 0.0),
            Eigen::Vector3d(0.53, 0.02, 0.02));
  // A leaf of 32^3 voxels counts as bulk without being listed voxel by voxel.
  MapSnapshot big;
  big.resolution = kEdge;
  big.voxels.push_back({Eigen::Vector3d(0.16, 0.16, 0.16), 32 * kEdge, 3, 0.9f});
  big.voxels.push_back(voxelAt(-200, 0, 0, 1));
  expectBox(bulkBounds(big, {}), Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.32));
}

class MapFramingTest : public fixture::DemoWindowTest {
 protected:
  // The 3D view of the fused demo map alone (the frame's points hidden).
  SceneView& fusedMapView() {
    openAndFuse();
    SceneView& scene = window_.sceneView();
    scene.setFrameCloudVisible(false);
    return scene;
  }
  // Pixels of the picture that are not the view's background (its gradient
  // changes only from top to bottom; the left end of a row is background
  // when the map is framed with a margin).
  static size_t drawnPixels(const QImage& picture) {
    size_t drawn = 0;
    for (int y = 0; y < picture.height(); ++y)
      for (int x = 0; x < picture.width(); ++x) drawn += picture.pixel(x, y) != picture.pixel(0, y);
    return drawn;
  }
  size_t drawnAfter(const char* action) {
    QAction* found = window_.findAction(action);
    EXPECT_NE(found, nullptr) << action;
    if (found == nullptr) return 0;
    found->trigger();
    return drawnPixels(window_.sceneView().renderToImage());
  }
};

TEST_F(MapFramingTest, ASpeckFarFromTheMapDoesNotShrinkIt) {
  SceneView& scene = fusedMapView();
  const auto fused = window_.session().worker().snapshot();
  ASSERT_TRUE(fused && !fused->empty());
  const char* actions[] = {"Zoom to Map", "Look from Above", "Reset Camera"};
  size_t before[3];
  for (int i = 0; i < 3; ++i) before[i] = drawnAfter(actions[i]);
  double map[6];
  ASSERT_TRUE(scene.mapBounds(map));

  // Two stray voxels 5 m above the bin, as flying pixels leave them.
  MapSnapshot with_speck = *fused;
  const double r = with_speck.resolution;
  const Eigen::Vector3d far(0.5 * (map[0] + map[1]), 0.5 * (map[2] + map[3]), map[5] + 5.0);
  with_speck.voxels.push_back({far, r, 1, 0.9f});
  with_speck.voxels.push_back({far + Eigen::Vector3d(r, 0, 0), r, 1, 0.9f});
  scene.showVoxels(with_speck, window_.session().sequence()->labels, {});
  double framed[6];
  ASSERT_TRUE(scene.mapBounds(framed));
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(framed[i], map[i], 1e-9) << "the speck is not framed";
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(actions[i]);
    const size_t after = drawnAfter(actions[i]);
    EXPECT_GT(after, before[i] * 8 / 10) << "the map stays as large in the view";
    EXPECT_LT(after, before[i] * 12 / 10 + 100);
  }
}

TEST_F(MapFramingTest, TheMapFillsTheViewWithoutLosingItsSidesWhateverItsShape) {
  SceneView& scene = fusedMapView();
  double map[6];
  ASSERT_TRUE(scene.mapBounds(map));
  // The default window, then one whose 3D view is narrower than high (the
  // panels take the sides), then a wide one.
  for (const QSize size : {QSize(1280, 860), QSize(900, 1000), QSize(1280, 600)}) {
    window_.resize(size);
    settle();
    for (const char* action :
         {"Zoom to Map", "Look from Above", "Look from the Front", "Look from the Side"}) {
      SCOPED_TRACE(std::string(action) + " at " + std::to_string(size.width()) + "x" +
                   std::to_string(size.height()));
      window_.findAction(action)->trigger();
      const double extent = scene.mapExtentInView();
      EXPECT_LE(extent, 0.95) << "every voxel of the map is in the picture";
      EXPECT_GE(extent, 0.85) << "and the map fills it";
      EXPECT_LE(scene.boxExtentInView(map), 1.5) << "its box about so";
    }
  }
}

// Look from Current Camera takes the camera's own view angle (horizontal in a
// view narrower than the picture); Zoom to Map after it frames the map as
// ever.
TEST_F(MapFramingTest, ZoomToMapAfterLookingFromTheCameraFillsTheView) {
  SceneView& scene = fusedMapView();
  for (const QSize size : {QSize(900, 1000), QSize(1280, 860)}) {
    window_.resize(size);
    settle();
    window_.findAction("Look from Current Camera")->trigger();
    window_.findAction("Zoom to Map")->trigger();
    SCOPED_TRACE(std::to_string(size.width()));
    EXPECT_LE(scene.mapExtentInView(), 0.95);
    EXPECT_GE(scene.mapExtentInView(), 0.85);
  }
}

// A map deep along the view (a corridor seen end-on): the camera stays out of
// it and every corner of it is in view.
TEST_F(MapFramingTest, AMapDeepAlongTheViewIsFramedFromOutside) {
  SceneView& scene = fusedMapView();
  window_.findAction("Zoom to Map")->trigger();
  const Eigen::Vector3d along = scene.cameraDirection();
  MapSnapshot corridor;
  corridor.resolution = 0.02;
  for (int step = 0; step < 300; ++step)  // 6 m along the view, 2 cm thick
    corridor.voxels.push_back(
        {(0.02 * step) * along + Eigen::Vector3d(0.01, 0.01, 0.01), 0.02, 1, 0.9f});
  scene.showVoxels(corridor, window_.session().sequence()->labels, {});
  double map[6];
  ASSERT_TRUE(scene.mapBounds(map));
  for (const char* action : {"Zoom to Map", "Look from Above", "Look from the Side"}) {
    SCOPED_TRACE(action);
    window_.findAction(action)->trigger();
    const double extent = scene.mapExtentInView();
    EXPECT_LE(extent, 0.95) << "every voxel in view, none behind the camera";
    EXPECT_GE(extent, 0.85);
  }
}

// A plate turned against the world's axes: its box is far larger than the
// plate (as a room's is when its walls are not along x and y). The view
// frames the voxels, not the box's corners.
TEST_F(MapFramingTest, AMapTurnedAgainstTheWorldsAxesIsFramedByItsVoxels) {
  SceneView& scene = fusedMapView();
  window_.findAction("Zoom to Map")->trigger();
  const Eigen::Vector3d along = scene.cameraDirection();
  const Eigen::Vector3d up = scene.cameraViewUp();
  const Eigen::Vector3d right = along.cross(up).normalized();
  // In the plane of the view's right and of up tilted 45 degrees towards the
  // camera: 1.2 m by 0.8 m, 1 cm voxels.
  const Eigen::Vector3d slope = (up - along).normalized();
  MapSnapshot plate;
  plate.resolution = 0.01;
  for (int i = 0; i < 120; ++i)
    for (int j = 0; j < 80; ++j) {
      const Eigen::Vector3d p = 0.01 * i * right + 0.01 * j * slope;
      plate.voxels.push_back(
          {(p / 0.01).array().floor().matrix() * 0.01 + Eigen::Vector3d::Constant(0.005), 0.01, 1,
           0.9f});
    }
  scene.showVoxels(plate, window_.session().sequence()->labels, {});
  window_.findAction("Zoom to Map")->trigger();
  EXPECT_GE(scene.mapExtentInView(), 0.85) << "the plate fills the view";
  EXPECT_LE(scene.mapExtentInView(), 0.95);
}

}  // namespace
}  // namespace lom::ui
