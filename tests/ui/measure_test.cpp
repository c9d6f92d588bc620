// Pointing at the map in the 3D view: a click picks the voxel seen, the
// resting mouse names it in a tooltip, and View > Measure Distance turns
// clicks into points on the surface clicked; two give the distance, in the
// view and in the status bar, also along and across the map's up. (A picture of a measurement
// across the demo's bin was looked at: the line and its length stay in front of the voxels.)
#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>

#include <QAction>
#include <QLabel>
#include <QRegularExpression>
#include <QStatusBar>
#include <QTest>
#include <cmath>

#include "demo_window_fixture.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/map_snapshot.hpp"
#include "lom/ui/measure_reaction.hpp"
#include "lom/ui/scene_view.hpp"

namespace lom::ui {
namespace {

class MeasureTest : public fixture::DemoWindowTest {
 protected:
  QString statusMessage() { return window_.statusBar()->currentMessage(); }
  // The demo fused and framed in the 3D view (frame points hidden); the view's
  // surface picks are collected in surface_.
  QVTKOpenGLNativeWidget* viewOfTheFusedMap() {
    openAndFuse();
    SceneView& scene = window_.sceneView();
    scene.setFrameCloudVisible(false);
    scene.zoomToMap();
    QObject::connect(&scene, &SceneView::surfacePicked,
                     [this](const Eigen::Vector3d& point) { surface_.push_back(point); });
    return scene.findChild<QVTKOpenGLNativeWidget*>();
  }
  std::vector<Eigen::Vector3d> surface_;
};

TEST(Measurement, DistanceAlongAndAcrossUp) {
  const Eigen::Vector3d a(0.1, 0.2, 0.3), b(0.4, 0.2, 0.7);  // 30 cm across, 40 cm up
  EXPECT_EQ(
      describeMeasurement(a, b, Eigen::Vector3d(0, 0, 2)),
      "Distance 50.0 cm from (0.100, 0.200, 0.300) to (0.400, 0.200, 0.700); 40.0 cm along "
      "the map's up, 30.0 cm across it (to within a voxel: points lie on the voxels' faces).");
  EXPECT_EQ(describeMeasurement(b, a, std::nullopt),
            "Distance 50.0 cm from (0.400, 0.200, 0.700) to (0.100, 0.200, 0.300) (to within a "
            "voxel: points lie on the voxels' faces).");
  EXPECT_EQ(formatLength(0.0123), "1.2 cm");
  EXPECT_EQ(formatLength(2.5), "2.500 m");
}

TEST(Measurement, ClicksPickTheFaceOfTheFirstVoxelAlongTheRay) {
  MapSnapshot snapshot;
  snapshot.resolution = 0.01;
  snapshot.voxels.push_back({Eigen::Vector3d(0.105, 0.005, 0.005), 0.01, 1, 0.9f});
  snapshot.voxels.push_back({Eigen::Vector3d(0.21, 0.01, 0.01), 0.02, 2, 0.9f});  // a pruned node
  const Eigen::Vector3d origin(0.0, 0.004, 0.006);
  const auto hit = firstVoxelHit(snapshot, {}, origin, Eigen::Vector3d(2.0, 0.0, 0.0));
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR((hit->point - Eigen::Vector3d(0.1, 0.004, 0.006)).norm(), 0.0, 1e-12);
  EXPECT_EQ(hit->voxel, 0u);
  // With label 1 hidden, the ray goes on to the larger voxel behind it.
  const auto behind = firstVoxelHit(snapshot, {1}, origin, Eigen::Vector3d(1.0, 0.0, 0.0));
  ASSERT_TRUE(behind.has_value());
  EXPECT_NEAR(behind->point.x(), 0.2, 1e-12);
  EXPECT_EQ(behind->voxel, 1u);
  // Parallel to a face outside the voxels, pointing away, or no voxels at all: nothing.
  EXPECT_FALSE(
      firstVoxelHit(snapshot, {}, Eigen::Vector3d(0, 0.05, 0.005), Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(firstVoxelHit(snapshot, {}, origin, -Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(firstVoxelHit(MapSnapshot{}, {}, origin, Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(firstVoxelHit(snapshot, {}, origin, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(firstVoxelHit(snapshot, {}, origin, Eigen::Vector3d(std::nan(""), 0.0, 0.0)));
  // A slanted ray enters through the face it meets first.
  const auto slanted = firstVoxelHit(snapshot, {}, Eigen::Vector3d(0.095, -0.005, 0.005),
                                     Eigen::Vector3d(1.0, 1.0, 0.0));
  ASSERT_TRUE(slanted.has_value());
  EXPECT_NEAR(slanted->point.x(), 0.1, 1e-12);
  EXPECT_NEAR(slanted->point.y(), 0.0, 1e-12);
}

// Without a map (nothing fused yet) a click on the frame's points picks the
// point drawn there, found by a ray as the voxels are: the depth buffer a
// picker would read is not readable under every OpenGL.
TEST_F(MeasureTest, ClicksOnTheFramePointsPickThemWithoutAMap) {
  StudioSession& session = window_.session();
  session.setAutoFuse(false);
  ASSERT_TRUE(window_.controller().openSequence(fixture::qPath(folder_)));
  SceneView& scene = window_.sceneView();
  scene.setFrameCloudVisible(true);
  scene.lookFromFrame(window_.controller().sequence(), 0);
  QObject::connect(&scene, &SceneView::surfacePicked,
                   [this](const Eigen::Vector3d& point) { surface_.push_back(point); });
  auto* vtk = scene.findChild<QVTKOpenGLNativeWidget*>();
  ASSERT_NE(vtk, nullptr);
  QTest::qWait(50);
  const QPoint middle(vtk->width() / 2, vtk->height() / 2);
  QTest::mouseClick(vtk, Qt::LeftButton, Qt::NoModifier, middle);
  ASSERT_EQ(surface_.size(), 1u) << "the frame's points fill the middle of its own view";
  // A point of frame 0: back in its camera, it lies at the depth measured there.
  const Sequence& sequence = window_.controller().sequence();
  const Eigen::Vector3d in_camera = sequence.frames[0].T_world_camera.inverse() * surface_[0];
  const Eigen::Vector2d pixel = sequence.cameraOf(0).project(in_camera);
  const FrameData* frame = window_.controller().currentFrameData();
  ASSERT_NE(frame, nullptr);
  const int u = static_cast<int>(std::floor(pixel.x())),
            v = static_cast<int>(std::floor(pixel.y()));
  ASSERT_TRUE(u >= 0 && v >= 0 && u < frame->depth.width && v < frame->depth.height);
  EXPECT_NEAR(in_camera.z(), frame->depth.at(u, v), 0.02);
  // The Picked Voxel panel has the point, and says there is no map yet.
  ASSERT_TRUE(session.pickedPoint().has_value());
  auto* panel = window_.findChild<QLabel*>("pickedVoxel");
  ASSERT_NE(panel, nullptr);
  ASSERT_TRUE(QTest::qWaitFor([&] { return panel->text().contains("No map yet"); }, 5000))
      << panel->text().toStdString();
}

TEST_F(MeasureTest, ClicksOnTheMapMeasureBetweenSurfacePoints) {
  auto* vtk = viewOfTheFusedMap();
  ASSERT_NE(vtk, nullptr);
  SceneView& scene = window_.sceneView();
  std::vector<Eigen::Vector3d>& surface = surface_;
  QAction* measure = window_.findAction("Measure Distance");
  ASSERT_NE(measure, nullptr);
  EXPECT_TRUE(measure->isCheckable());
  EXPECT_EQ(measure->shortcut(), QKeySequence("Ctrl+D"));

  // Off: a click on the map measures nothing.
  const QPoint middle(vtk->width() / 2, vtk->height() / 2);
  QTest::mouseClick(vtk, Qt::LeftButton, Qt::NoModifier, middle);
  ASSERT_EQ(surface.size(), 1u) << "the map lies in the middle of the view";
  EXPECT_EQ(scene.measurementPointCount(), 0u);
  // The click picks the voxel behind the surface point (Picked Voxel, Add Box at Clicked Point).
  StudioSession& session = window_.session();
  ASSERT_TRUE(session.pickedPoint().has_value());
  bool occupied = false;
  QObject::connect(
      &session.worker(), &MapWorker::voxelPicked,
      [&](const Eigen::Vector3d&, const VoxelState& voxel) { occupied = voxel.occupied; });
  ASSERT_TRUE(QTest::qWaitFor([&] { return occupied; }, 5000)) << "the voxel clicked is occupied";

  measure->trigger();
  EXPECT_EQ(statusMessage().toStdString(), "Measure: click the first point on the map.");
  QTest::mouseClick(vtk, Qt::LeftButton, Qt::NoModifier, middle);
  ASSERT_EQ(surface.size(), 2u);
  EXPECT_EQ(scene.measurementPointCount(), 1u);
  EXPECT_EQ(statusMessage().toStdString(), "Measure: click the second point.");
  // The point clicked lies on a voxel's face: within half a voxel's diagonal
  // of an occupied voxel's centre.
  const MapSnapshot& snapshot = *window_.session().worker().snapshot();
  double nearest = 1e9;
  for (const OccupiedVoxel& voxel : snapshot.voxels)
    nearest = std::min(nearest,
                       (voxel.center - surface.back()).norm() - 0.5 * std::sqrt(3.0) * voxel.size);
  EXPECT_LE(nearest, 1e-3);

  const Eigen::Vector3d first = surface.back();
  const Eigen::Vector3d second = first + Eigen::Vector3d(0.12, 0.0, 0.05);
  emit scene.surfacePicked(second);
  EXPECT_EQ(scene.measurementPointCount(), 2u);
  EXPECT_EQ(scene.measurementLabel().toStdString(), "13.0 cm");
  EXPECT_EQ(statusMessage().toStdString(),
            describeMeasurement(first, second, snapshot.up).toStdString());
  EXPECT_TRUE(statusMessage().startsWith("Distance 13.0 cm from "))
      << statusMessage().toStdString();

  // A third point starts a new measurement; off clears it.
  emit scene.surfacePicked(second);
  EXPECT_EQ(scene.measurementPointCount(), 1u);
  EXPECT_TRUE(scene.measurementLabel().isEmpty());
  measure->trigger();
  EXPECT_EQ(scene.measurementPointCount(), 0u);
  EXPECT_TRUE(statusMessage().isEmpty());
  emit scene.surfacePicked(second);
  EXPECT_EQ(scene.measurementPointCount(), 0u) << "measuring is off";
}

// The selected box's handles take every press on the box: a click on the map
// inside it picked nothing and measured nothing (the first box is selected
// from the start).
TEST_F(MeasureTest, AClickInsideTheSelectedBoxPicksAndMeasures) {
  auto* vtk = viewOfTheFusedMap();
  ASSERT_NE(vtk, nullptr);
  SceneView& scene = window_.sceneView();
  std::vector<Eigen::Vector3d>& surface = surface_;
  const QPoint middle(vtk->width() / 2, vtk->height() / 2);
  QTest::mouseClick(vtk, Qt::LeftButton, Qt::NoModifier, middle);
  ASSERT_EQ(surface.size(), 1u) << "the map lies in the middle of the view";

  // A box around the point clicked, selected: its handles are shown.
  AnnotationsModel& boxes = window_.session().annotations();
  GroundTruthBox around = boxes.box(0);
  around.box.center = surface.front();
  around.box.size = Eigen::Vector3d(0.15, 0.15, 0.15);
  around.box.rotation = Eigen::Quaterniond::Identity();
  boxes.addBox(around);
  boxes.select(boxes.boxCount() - 1);
  QApplication::processEvents();
  ASSERT_TRUE(scene.boxHandlesVisible());
  int edits = 0;
  QObject::connect(&scene, &SceneView::boxEdited, [&](const OrientedBox&) { ++edits; });
  const int steps = boxes.undoStack().count();

  QTest::mouseClick(vtk, Qt::LeftButton, Qt::NoModifier, middle);
  ASSERT_EQ(surface.size(), 2u) << "the click inside the box picked nothing";
  EXPECT_LE((surface.back() - surface.front()).norm(), 0.02);
  window_.findAction("Measure Distance")->trigger();
  QTest::mouseClick(vtk, Qt::LeftButton, Qt::NoModifier, middle);
  EXPECT_EQ(scene.measurementPointCount(), 1u);
  EXPECT_EQ(edits, 0);
  EXPECT_EQ(boxes.undoStack().count(), steps) << "a click is no edit of the box";
  window_.findAction("Measure Distance")->trigger();

  // Other buttons never pick, on the box or beside it.
  QTest::mouseClick(vtk, Qt::RightButton, Qt::NoModifier, middle);
  QTest::mouseClick(vtk, Qt::MiddleButton, Qt::NoModifier, middle);
  EXPECT_EQ(surface.size(), 3u);
  EXPECT_EQ(boxes.undoStack().count(), steps);
  // A drag that moves the box and ends within a click's slack of where it
  // began is an edit, not a click (it was dropped, the handles left moved).
  const auto send = [&](QEvent::Type type, QPoint at, Qt::MouseButtons buttons) {
    const Qt::MouseButton button = type == QEvent::MouseMove ? Qt::NoButton : Qt::LeftButton;
    QMouseEvent event(type, at, vtk->mapToGlobal(at), button, buttons, Qt::NoModifier);
    QApplication::sendEvent(vtk, &event);
    QApplication::processEvents();
  };
  send(QEvent::MouseButtonPress, middle, Qt::LeftButton);
  for (int x = 4; x <= 40; x += 4) send(QEvent::MouseMove, middle + QPoint(x, 0), Qt::LeftButton);
  for (int x = 36; x >= 2; x -= 2) send(QEvent::MouseMove, middle + QPoint(x, 0), Qt::LeftButton);
  send(QEvent::MouseButtonRelease, middle + QPoint(2, 0), Qt::NoButton);
  EXPECT_EQ(surface.size(), 3u) << "the drag was taken for a click";
  EXPECT_EQ(boxes.undoStack().count(), steps + 1) << "the drag that moved the box was dropped";
}

TEST_F(MeasureTest, RestingTheMouseOnAVoxelNamesItsLabel) {
  openAndFuse();
  SceneView& scene = window_.sceneView();
  scene.setFrameCloudVisible(false);
  scene.zoomToMap();
  auto* vtk = scene.findChild<QVTKOpenGLNativeWidget*>();
  ASSERT_NE(vtk, nullptr);
  QTest::mouseMove(vtk, QPoint(vtk->width() / 2, vtk->height() / 2));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !scene.hoverText().isEmpty(); }, 5000))
      << "the map lies in the middle of the view";
  const QString text = scene.hoverText();
  const LabelSet& labels = window_.session().sequence()->labels;
  bool named = false;
  for (const LabelInfo& label : labels.all())
    named = named || text.startsWith(QString::fromStdString(label.name) + " (label ");
  EXPECT_TRUE(named) << text.toStdString();
  EXPECT_TRUE(text.contains("), p = 0.")) << text.toStdString();
  // The voxel's edge: 1 cm, or 2 cm, 4 cm... for a merged leaf of the 1 cm map.
  EXPECT_TRUE(QRegularExpression("\\b[124] cm voxel at \\(").match(text).hasMatch())
      << text.toStdString();
  // Over the background of the view: no voxel, no text.
  QTest::mouseMove(vtk, QPoint(3, 3));
  ASSERT_TRUE(QTest::qWaitFor([&] { return scene.hoverText().isEmpty(); }, 5000))
      << scene.hoverText().toStdString();
}

}  // namespace
}  // namespace lom::ui
