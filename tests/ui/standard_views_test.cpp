// View > Look from Above / the Front / the Side: the 3D camera looks down the
// map's up, along the first camera's levelled viewing direction, or across
// it, and frames the map. (Pictures of the three views were looked at: the
// demo's bin from above, from the front and from its right.)
#include <gtest/gtest.h>

#include <QAction>
#include <QImage>
#include <QTest>
#include <array>

#include "demo_window_fixture.hpp"
#include "lom/ui/scene_view.hpp"

namespace lom::ui {
namespace {

class StandardViewsTest : public fixture::DemoWindowTest {};

// Pixels that differ from the view's background gradient in a picture (the
// gradient changes only from top to bottom: compare with the row's left end,
// which the map never reaches when it is framed with a margin).
size_t drawnPixels(const QImage& picture) {
  size_t drawn = 0;
  for (int y = 0; y < picture.height(); ++y)
    for (int x = 0; x < picture.width(); ++x) drawn += picture.pixel(x, y) != picture.pixel(0, y);
  return drawn;
}

TEST_F(StandardViewsTest, EachLooksAlongItsAxisAndFramesTheMap) {
  openAndFuse();
  SceneView& scene = window_.sceneView();
  scene.setFrameCloudVisible(false);
  const auto snapshot = window_.session().worker().snapshot();
  ASSERT_TRUE(snapshot->up.has_value());
  const Eigen::Vector3d up = snapshot->up->normalized();
  const Sequence& sequence = *window_.session().sequence();
  Eigen::Vector3d forward = sequence.frames.front().T_world_camera.linear().col(2);
  forward = (forward - forward.dot(up) * up).normalized();

  struct Expected {
    const char* action;
    Eigen::Vector3d direction, view_up;
  };
  for (const Expected& view :
       {Expected{"Look from Above", -up, forward}, Expected{"Look from the Front", forward, up},
        Expected{"Look from the Side", -forward.cross(up), up}}) {
    SCOPED_TRACE(view.action);
    QAction* action = window_.findAction(view.action);
    ASSERT_NE(action, nullptr);
    EXPECT_FALSE(action->isCheckable());
    action->trigger();
    EXPECT_GT(scene.cameraDirection().dot(view.direction), 0.999);
    EXPECT_GT(scene.cameraViewUp().dot(view.view_up), 0.999);
    const QImage picture = scene.renderToImage();
    EXPECT_GT(drawnPixels(picture), static_cast<size_t>(picture.width() * picture.height() / 20))
        << "the map fills a good part of the view";
    // Framed on the map: its middle is in the middle of the view.
    const QPoint middle(picture.width() / 2, picture.height() / 2);
    EXPECT_NE(picture.pixel(middle), picture.pixel(0, middle.y()));
  }
  EXPECT_EQ(window_.findAction("Look from Above")->shortcut(), QKeySequence(Qt::CTRL + Qt::Key_1));
}

// Where the corners of the picture a camera took land in the view, 0.8 m
// ahead of it: the least and greatest x (left, right) and y (bottom, top), in
// display pixels. The image spans [-0.5, size - 0.5] (pixel centres at
// integer coordinates).
std::array<double, 4> pictureInView(const SceneView& scene, const CameraIntrinsics& camera,
                                    const Eigen::Isometry3d& pose) {
  double left = 1e9, right = -1e9, bottom = 1e9, top = -1e9;
  for (const double u : {-0.5, camera.width - 0.5})
    for (const double v : {-0.5, camera.height - 0.5}) {
      const Eigen::Vector3d ray((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
      const Eigen::Vector2d at = scene.displayPointOf(pose * (0.8 * ray));
      left = std::min(left, at.x());
      right = std::max(right, at.x());
      bottom = std::min(bottom, at.y());
      top = std::max(top, at.y());
    }
  return {left, right, bottom, top};
}

// Look from Current Camera shows the whole picture the camera took: in the
// default layout the 3D view is narrower than the image, and fitting the
// image's height cut off a third of each side.
TEST_F(StandardViewsTest, TheCurrentCameraViewHoldsTheWholePicture) {
  openAndFuse();
  SceneView& scene = window_.sceneView();
  const Sequence& sequence = *window_.session().sequence();
  const QSize view = scene.viewPixels();
  ASSERT_GT(view.width(), 0);
  for (const size_t index : {size_t{0}, sequence.frames.size() - 1}) {
    SCOPED_TRACE(index);
    scene.lookFromFrame(sequence, index);
    const CameraIntrinsics& camera = sequence.cameraOf(index);
    const auto [left, right, bottom, top] =
        pictureInView(scene, camera, sequence.frames[index].T_world_camera);
    const double slack = 0.03 * std::max(view.width(), view.height());
    EXPECT_GE(left, -slack);
    EXPECT_LE(right, view.width() + slack);
    EXPECT_GE(bottom, -slack);
    EXPECT_LE(top, view.height() + slack);
    // ... and fills the view along one side.
    EXPECT_TRUE(right - left > 0.9 * view.width() || top - bottom > 0.9 * view.height())
        << left << ".." << right << " x " << bottom << ".." << top << " in " << view.width() << "x"
        << view.height();
  }
}

// The picture is centred in the view although the camera's principal point
// is off the image centre (real cameras' are): the optical axis is not the
// picture's middle, and centring the axis cut off one side.
TEST_F(StandardViewsTest, TheCurrentCameraViewIsCentredOnThePicture) {
  openAndFuse();
  SceneView& scene = window_.sceneView();
  const QSize view = scene.viewPixels();
  ASSERT_GT(view.width(), 0);
  for (const Eigen::Vector2d& shift : {Eigen::Vector2d(-0.2, 0.15), Eigen::Vector2d(0.25, -0.2)}) {
    Sequence sequence = *window_.session().sequence();
    CameraIntrinsics camera = sequence.cameraOf(0);
    camera.cx += shift.x() * camera.width;
    camera.cy += shift.y() * camera.height;
    sequence.camera = camera;
    for (auto& frame : sequence.frames) frame.camera.reset();
    ASSERT_DOUBLE_EQ(sequence.cameraOf(0).cx, camera.cx);
    SCOPED_TRACE(shift.transpose());
    scene.lookFromFrame(sequence, 0);
    const auto [left, right, bottom, top] =
        pictureInView(scene, camera, sequence.frames[0].T_world_camera);
    const double slack = 0.02 * std::max(view.width(), view.height());
    EXPECT_NEAR(0.5 * (left + right), 0.5 * view.width(), slack);
    EXPECT_NEAR(0.5 * (bottom + top), 0.5 * view.height(), slack);
    EXPECT_GE(left, -slack);
    EXPECT_LE(right, view.width() + slack);
    EXPECT_GE(bottom, -slack);
    EXPECT_LE(top, view.height() + slack);
  }
  // The overview views are centred again.
  window_.findAction("Look from Above")->trigger();
  const QImage picture = scene.renderToImage();
  const QPoint middle(picture.width() / 2, picture.height() / 2);
  EXPECT_NE(picture.pixel(middle), picture.pixel(0, middle.y()));
}

}  // namespace
}  // namespace lom::ui
