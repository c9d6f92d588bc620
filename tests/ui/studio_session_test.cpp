// The studio's session end to end on the synthetic demo scene: live fusion,
// the map legend, box editing with undo and files, the evaluation panel and
// a screenshot after fusion.
#include "lom/ui/studio_session.hpp"

#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QFontMetrics>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QStatusBar>
#include <QTableWidget>
#include <QTest>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "demo_window_fixture.hpp"
#include "dialog_answerer.hpp"
#include "lom/annotations.hpp"
#include "lom/evaluation.hpp"
#include "lom/height_colours.hpp"
#include "lom/ui/annotation_files.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/demo_scene.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/export_map_reaction.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/image_pane.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_legend_panel.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/objects_panel.hpp"
#include "lom/ui/picked_voxel_view.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/window_capture.hpp"
#include "onnx_model_builder.hpp"
#include "test_support.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;
using fixture::qPath;
using fixture::smallDemo;

class StudioSessionTest : public fixture::DemoWindowTest {
 protected:
  void waitForEvaluation() {
    EvaluationPanel& panel = window_.evaluationPanel();
    ASSERT_TRUE(QTest::qWaitFor([&] { return !panel.isBusy(); }, kTimeoutMs));
  }
};

TEST_F(StudioSessionTest, FusesTheDemoLiveAndTheLegendListsItsLabels) {
  // Before any fusion the frame count is not made up ("fused 0/1").
  EXPECT_EQ(window_.fusionStatusText().trimmed(), "not fused")
      << window_.fusionStatusText().toStdString();
  openAndFuse();
  EXPECT_TRUE(errors_.empty()) << errors_.front().toStdString();
  const auto snapshot = window_.session().worker().snapshot();
  const std::vector<int> listed = window_.mapLegend().listedLabels();
  const Sequence& sequence = *window_.session().sequence();
  for (int label : visibleObjectLabels()) {
    EXPECT_GT(snapshot->counts.count(label), 0u) << "no voxels of label " << label;
    const auto row = std::find(listed.begin(), listed.end(), label);
    ASSERT_NE(row, listed.end()) << "legend misses label " << label;
    EXPECT_EQ(window_.mapLegend().nameOf(static_cast<int>(row - listed.begin())).toStdString(),
              sequence.labels.at(label).name);
  }
  EXPECT_GT(window_.sceneView().voxelCount(), 0u);
  EXPECT_EQ(window_.sceneView().voxelCount(), snapshot->voxels.size());
  EXPECT_TRUE(window_.fusionStatusText().contains("6/6")) << window_.fusionStatusText().toStdString();

  // Hiding a label removes its voxels from the view at once.
  const int hidden = *visibleObjectLabels().begin();
  window_.mapLegend().showOnly(hidden);
  size_t shown = 0;
  for (const auto& voxel : snapshot->voxels) shown += voxel.label == hidden;
  EXPECT_EQ(window_.sceneView().voxelCount(), shown);
  window_.mapLegend().showAll();
  EXPECT_EQ(window_.sceneView().voxelCount(), snapshot->voxels.size());
}

// A fusion that fails says so in the status bar, with what it fused: nothing
// before the first frame (no made-up "0/1"), else the frames fused.
TEST_F(StudioSessionTest, TheStatusBarSaysWhereAFusionFailed) {
  const Sequence sequence = loadSequence(folder_);
  const auto depth_of = [&](size_t frame) { return sequence.pathOf(sequence.frames[frame].depth); };
  const auto hidden = temp_.path() / "hidden_depth.png";
  auto failAt = [&](size_t frame) {
    std::filesystem::rename(depth_of(frame), hidden);
    errors_.clear();
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
    StudioSession& session = window_.session();
    ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, kTimeoutMs));
    QTest::qWait(50);
    std::filesystem::rename(hidden, depth_of(frame));
    // The fusion's error (showing that frame's images may report it too).
    const auto stopped = std::find_if(errors_.begin(), errors_.end(), [](const QString& error) {
      return error.startsWith("Fusion stopped");
    });
    ASSERT_NE(stopped, errors_.end());
    const QString name = "frames[" + QString::number(frame) + "]";
    EXPECT_TRUE(stopped->contains(name)) << stopped->toStdString();
    EXPECT_EQ(stopped->count(name), 1) << "the frame named twice: " << stopped->toStdString();
  };
  failAt(0);
  EXPECT_EQ(window_.fusionStatusText(), "not fused failed before the first frame");
  failAt(2);
  EXPECT_EQ(window_.fusionStatusText(),
            QString("fused 2/%1 failed after 2/%1").arg(sequence.frames.size()));
  // A fusion that works afterwards shows its count alone.
  openAndFuse();
  EXPECT_FALSE(window_.fusionStatusText().contains("failed"))
      << window_.fusionStatusText().toStdString();
}

// A Re-fuse that fails on its first frame (a frame's image gone, a segmenter
// that cannot run on the frames) keeps the map the user had, with the
// settings it was fused with; the Fusion panel keeps the values typed.
TEST_F(StudioSessionTest, AReFuseThatFailsOnItsFirstFrameKeepsTheMap) {
  openAndFuse();
  StudioSession& session = window_.session();
  MapWorker& worker = session.worker();
  const auto before = worker.snapshot();
  ASSERT_GT(before->voxels.size(), 0u);
  ASSERT_TRUE(worker.hasUnsavedMap());
  const double max_range = session.fusionOptions().map.max_range;
  const QString status = window_.fusionStatusText();

  const Sequence& sequence = *session.sequence();
  const auto depth = sequence.pathOf(sequence.frames[0].depth);
  const auto hidden = temp_.path() / "hidden_depth.png";
  std::filesystem::rename(depth, hidden);
  errors_.clear();
  FusionPanel& panel = window_.fusionPanel();
  panel.maxRangeBox().setValue(max_range + 0.5);
  ASSERT_TRUE(panel.refuseButton().isEnabled());
  panel.refuseButton().click();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !worker.isFusing(); }, kTimeoutMs));
  QTest::qWait(50);  // the last snapshot arrives through the event loop
  std::filesystem::rename(hidden, depth);

  const auto stopped = std::find_if(errors_.begin(), errors_.end(), [](const QString& error) {
    return error.startsWith("Fusion stopped");
  });
  ASSERT_NE(stopped, errors_.end());
  EXPECT_TRUE(stopped->contains("the map shown before is kept")) << stopped->toStdString();
  const auto after = worker.snapshot();
  EXPECT_EQ(after->voxels.size(), before->voxels.size());
  EXPECT_EQ(after->frames_fused, before->frames_fused);
  EXPECT_EQ(window_.sceneView().voxelCount(), before->voxels.size());
  EXPECT_TRUE(worker.hasUnsavedMap());  // still the fused map, still not saved
  // The status says the map before is shown, and why the new one is not.
  EXPECT_TRUE(window_.fusionStatusText().startsWith(status.section(' ', 0, 1)))
      << window_.fusionStatusText().toStdString() << " after " << status.toStdString();
  EXPECT_TRUE(window_.fusionStatusText().contains("re-fuse failed, map kept"))
      << window_.fusionStatusText().toStdString();
  // The scores and baselines are the kept map's: its range, not the one typed.
  EXPECT_EQ(session.fusionOptions().map.max_range, max_range);
  EXPECT_DOUBLE_EQ(panel.maxRangeBox().value(), max_range + 0.5);
  EXPECT_TRUE(panel.refuseButton().isEnabled());  // the typed value can be tried again

  // With the frame back, that try fuses the new range.
  panel.refuseButton().click();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !worker.isFusing(); }, kTimeoutMs));
  EXPECT_EQ(session.fusionOptions().map.max_range, max_range + 0.5);
  EXPECT_FALSE(window_.fusionStatusText().contains("kept"))
      << window_.fusionStatusText().toStdString();
}

// Cancelled before its first frame, a Re-fuse leaves the map as it was too.
TEST_F(StudioSessionTest, AReFuseCancelledBeforeItsFirstFrameKeepsTheMap) {
  openAndFuse();
  StudioSession& session = window_.session();
  MapWorker& worker = session.worker();
  const size_t voxels = worker.snapshot()->voxels.size();
  ASSERT_GT(voxels, 0u);
  // The worker is held up by a job until the fusion queued behind it has been
  // cancelled, so that the fusion starts cancelled.
  std::atomic<bool> release{false};
  worker.withMap([&release](const LabelMap*) {
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  });
  session.fuse();
  worker.cancel();
  release = true;
  ASSERT_TRUE(QTest::qWaitFor([&] { return !worker.isFusing(); }, kTimeoutMs));
  QTest::qWait(50);
  EXPECT_EQ(worker.snapshot()->voxels.size(), voxels);
  EXPECT_TRUE(window_.fusionStatusText().contains("re-fuse stopped, map kept"))
      << window_.fusionStatusText().toStdString();
  EXPECT_TRUE(errors_.empty()) << errors_.front().toStdString();
  // Reset Map still empties it.
  window_.session().resetMap();
  ASSERT_TRUE(QTest::qWaitFor([&] { return worker.snapshot()->voxels.empty(); }, kTimeoutMs));
}

// A figure of the map may leave out the camera frustums, the axes in the
// corner and the boxes (with the selected box's handles): View menu toggles.
TEST_F(StudioSessionTest, AFigureCanLeaveOutTheCamerasTheAxesAndTheBoxes) {
  openAndFuse();
  window_.session().annotations().select(0);
  SceneView& view = window_.sceneView();
  ASSERT_TRUE(view.boxHandlesVisible());
  ASSERT_TRUE(QTest::qWaitFor([&] { return view.objectBoxCount() > 0; }, kTimeoutMs));
  ASSERT_TRUE(view.objectBoxesVisible());
  const QImage all = view.renderToImage();
  const QRect corner = view.axesMarkerRect();
  ASSERT_FALSE(corner.isEmpty());
  const char* names[] = {"Show Camera Frustums", "Show Axes Marker", "Show Box Outlines"};
  for (const char* name : names) {
    QAction* action = window_.findAction(name);
    ASSERT_NE(action, nullptr) << name;
    ASSERT_TRUE(action->isCheckable() && action->isChecked()) << name;
    action->trigger();
  }
  EXPECT_FALSE(view.camerasVisible());
  EXPECT_FALSE(view.axesVisible());
  EXPECT_FALSE(view.boxesVisible());
  EXPECT_FALSE(view.boxHandlesVisible());
  EXPECT_FALSE(view.currentCameraInView());  // nothing of a hidden camera is framed
  EXPECT_FALSE(view.objectBoxesVisible());   // the Objects panel's boxes go too
  const QImage bare = view.renderToImage();
  bare.save(QString::fromStdString((temp_.path() / "bare.png").string()));
  if (const char* keep = std::getenv("LOM_KEEP_SCREENSHOTS"))
    bare.save(QString(keep) + "/bare.png");
  ASSERT_EQ(bare.size(), all.size());
  EXPECT_NE(bare.copy(corner), all.copy(corner)) << "the axes are still drawn";
  EXPECT_NE(bare, all);

  // A figure larger than the view: File ▸ 3D View Picture Size ▸ 2x, then
  // Save 3D View… writes a picture twice as wide and high, of the same view.
  QAction* twice = window_.findAction("2x");
  ASSERT_NE(twice, nullptr);
  twice->trigger();
  {
    ui::test::DialogAnswerer answer("Replace|Yes", qPath(temp_.path() / "figure"));
    window_.findAction("Save 3D View…")->trigger();
  }
  const QImage figure(qPath(temp_.path() / "figure.png"));
  if (const char* keep = std::getenv("LOM_KEEP_SCREENSHOTS"))
    figure.save(QString(keep) + "/figure-2x.png");
  ASSERT_FALSE(figure.isNull());
  EXPECT_EQ(figure.size(), 2 * bare.size());
  // The same picture, at twice the size: shrunk back, it differs from the
  // view's little (the background is plain, the lines as thin as on screen).
  const QImage shrunk = figure.scaled(bare.size(), Qt::IgnoreAspectRatio, Qt::SmoothTransformation)
                            .convertToFormat(QImage::Format_RGB32);
  const QImage shown = bare.convertToFormat(QImage::Format_RGB32);
  double difference = 0.0;
  for (int y = 0; y < shown.height(); ++y)
    for (int x = 0; x < shown.width(); ++x) {
      const QRgb a = shown.pixel(x, y), b = shrunk.pixel(x, y);
      difference += std::abs(qRed(a) - qRed(b)) + std::abs(qGreen(a) - qGreen(b)) +
                    std::abs(qBlue(a) - qBlue(b));
    }
  difference /= 3.0 * shown.width() * shown.height();
  EXPECT_LT(difference, 25.0) << "mean difference per channel";
  window_.findAction("1x (as on screen)")->trigger();
  // A box selected or edited meanwhile stays hidden, and comes back when asked.
  window_.session().annotations().select(1);
  EXPECT_FALSE(view.boxHandlesVisible());
  for (const char* name : names) window_.findAction(name)->trigger();
  EXPECT_TRUE(view.camerasVisible() && view.axesVisible() && view.boxesVisible());
  EXPECT_TRUE(view.boxHandlesVisible());
  EXPECT_EQ(view.renderToImage().copy(corner), all.copy(corner));
}

// Screenshots frame the map and the camera of the frame shown (the camera of
// a later frame can lie outside the map's framing).
TEST_F(StudioSessionTest, ZoomingToTheMapCanKeepTheCurrentCameraInView) {
  openAndFuse();
  SceneView& view = window_.sceneView();
  for (int frame :
       {0, window_.controller().frameCount() / 2, window_.controller().frameCount() - 1}) {
    window_.controller().setCurrentFrame(frame);
    QTest::qWait(
        100);  // the panels' layout settles (the 3D view's size with it), as before a screenshot
    view.zoomToMap(/*with_current_camera=*/true);
    EXPECT_TRUE(view.currentCameraInView()) << "frame " << frame;
  }
}

TEST_F(StudioSessionTest, ThresholdReThresholdsAtOnceAndOtherParametersOfferReFusion) {
  openAndFuse();
  const size_t before = window_.session().worker().snapshot()->voxels.size();
  window_.fusionPanel().thresholdBox().setValue(0.9);
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return window_.session().worker().snapshot()->occupancy_threshold == 0.9; }, 10'000));
  EXPECT_LT(window_.session().worker().snapshot()->voxels.size(), before);
  EXPECT_FALSE(window_.fusionPanel().refuseButton().isEnabled());
  window_.fusionPanel().resolutionBox().setValue(0.02);
  EXPECT_TRUE(window_.fusionPanel().refuseButton().isEnabled());
  window_.fusionPanel().refuseButton().click();
  waitForFusion();
  EXPECT_DOUBLE_EQ(window_.session().worker().snapshot()->resolution, 0.02);
}

// F5 (Fusion > Fuse Sequence) fuses with the settings the panel shows, as
// Re-fuse does; it fused with the old ones while the panel said "Changed".
TEST_F(StudioSessionTest, FuseUsesTheSettingsTheFusionPanelShows) {
  openAndFuse();
  FusionPanel& panel = window_.fusionPanel();
  panel.resolutionBox().setValue(0.02);
  ASSERT_TRUE(panel.hasPendingChanges());
  QAction* fuse = window_.findAction("Fuse Sequence");
  ASSERT_NE(fuse, nullptr);
  EXPECT_EQ(fuse->shortcut(), QKeySequence(Qt::Key_F5));
  fuse->trigger();
  waitForFusion();
  EXPECT_DOUBLE_EQ(window_.session().worker().snapshot()->resolution, 0.02);
  EXPECT_FALSE(panel.hasPendingChanges());
  EXPECT_NE(panel.noteText(), "Changed: re-fuse to apply.");

  // A changed field that is not valid: nothing fused, and the status says why.
  panel.candidatesEdit().setText("0 99");
  const size_t fused_before = window_.session().worker().snapshot()->frames_fused;
  fuse->trigger();
  QTest::qWait(50);
  EXPECT_FALSE(window_.session().worker().isFusing());
  EXPECT_EQ(window_.session().worker().snapshot()->frames_fused, fused_before);
  EXPECT_TRUE(window_.statusBar()->currentMessage().startsWith("Not fused: Candidates: 99"))
      << window_.statusBar()->currentMessage().toStdString();
}

// A value typed into a Fusion panel field but not entered yet (no Enter, the
// field still focused) is the one F5 fuses with: the field shows it.
TEST_F(StudioSessionTest, FuseTakesAValueStillBeingTypedInTheFusionPanel) {
  openAndFuse();
  QDockWidget& fusion = dock("fusionDock");
  fusion.show();
  fusion.raise();
  window_.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
  QDoubleSpinBox& field = window_.fusionPanel().resolutionBox();
  ASSERT_NE(field.value(), 0.02);
  field.setFocus();
  ASSERT_TRUE(QTest::qWaitFor([&] { return field.hasFocus(); }, 5000));
  field.selectAll();
  QTest::keyClicks(&field, "0.02");
  ASSERT_FALSE(window_.fusionPanel().hasPendingChanges()) << "typed, not entered";
  window_.findAction("Fuse Sequence")->trigger();
  waitForFusion();
  EXPECT_DOUBLE_EQ(window_.session().worker().snapshot()->resolution, 0.02);
  EXPECT_FALSE(window_.fusionPanel().hasPendingChanges());
}

TEST_F(StudioSessionTest, FusionFieldsKeepTheCommandLinesLimits) {
  openAndFuse();
  FusionPanel& panel = window_.fusionPanel();
  // A threshold at or below the lower clamping bound would make every observed
  // voxel occupied; above the upper one, none.
  panel.thresholdBox().setValue(0.01);
  EXPECT_DOUBLE_EQ(panel.thresholdBox().value(), 0.121);  // just above 0.12
  panel.thresholdBox().setValue(0.99);
  EXPECT_DOUBLE_EQ(panel.thresholdBox().value(), 0.97);
  panel.resolutionBox().setValue(0.001);
  EXPECT_DOUBLE_EQ(panel.resolutionBox().value(), 0.002);

  // Rays longer than 1000 voxels need too much memory: no Re-fuse, and a note.
  panel.maxRangeBox().setValue(5.0);  // 2500 voxels of 2 mm
  EXPECT_FALSE(panel.refuseButton().isEnabled());
  EXPECT_TRUE(panel.noteText().contains("rays 2500 voxels long; at most 1000"))
      << panel.noteText().toStdString();
  panel.resolutionBox().setValue(0.005);  // 1000 voxels
  EXPECT_TRUE(panel.refuseButton().isEnabled());
  EXPECT_EQ(panel.noteText(), "Changed: re-fuse to apply.");
  panel.maxRangeBox().setValue(0.0);  // unlimited: the depths decide
  EXPECT_TRUE(panel.refuseButton().isEnabled());

  // Candidates must be labels of the sequence: Re-fuse stays off.
  panel.maxRangeBox().setValue(1.0);
  panel.resolutionBox().setValue(0.01);
  panel.candidatesEdit().setText("0 99");
  EXPECT_FALSE(panel.refuseButton().isEnabled());
  EXPECT_TRUE(panel.noteText().contains("Candidates: 99 is not a label of the sequence (0 to"))
      << panel.noteText().toStdString();
  panel.candidatesEdit().setText("0 1");
  EXPECT_TRUE(panel.refuseButton().isEnabled());
  EXPECT_FALSE(panel.noteText().contains("leave out 0")) << panel.noteText().toStdString();
  // Candidates without the background make every pixel an object: said, not refused.
  panel.candidatesEdit().setText("1 2");
  EXPECT_TRUE(panel.refuseButton().isEnabled());
  EXPECT_TRUE(panel.noteText().contains("The candidates leave out 0, the background"))
      << panel.noteText().toStdString();
}

// Frames without probability images fuse once a segmentation network is
// chosen in the Fusion panel.
TEST_F(StudioSessionTest, MostDepthsBeyondMaxRangeOfferARefuseThatReachesThem) {
  StudioSession& session = window_.session();
  openAndFuse();
  FusionPanel& panel = window_.fusionPanel();
  EXPECT_TRUE(panel.extendRangeButton().isHidden());  // 1 m reaches the shelf
  panel.maxRangeBox().setValue(0.3);  // the demo's shelf stands 0.5 to 0.9 m from the cameras
  panel.refuseButton().click();
  waitForFusion();
  EXPECT_TRUE(panel.noteText().contains("beyond the max range of 0.30 m and mapped nothing"))
      << panel.noteText().toStdString();
  ASSERT_FALSE(panel.extendRangeButton().isHidden());
  EXPECT_TRUE(panel.extendRangeButton().text().startsWith("Re-fuse up to "))
      << panel.extendRangeButton().text().toStdString();
  const size_t voxels_before = session.worker().snapshot()->voxels.size();

  panel.extendRangeButton().click();
  waitForFusion();
  EXPECT_GT(session.fusionOptions().map.max_range, 0.8);
  EXPECT_DOUBLE_EQ(session.fusionOptions().map.resolution,
                   0.01);  // 1 m rays need no coarser voxels
  EXPECT_DOUBLE_EQ(panel.maxRangeBox().value(), session.fusionOptions().map.max_range);
  EXPECT_TRUE(panel.extendRangeButton().isHidden());
  EXPECT_FALSE(panel.noteText().contains("beyond")) << panel.noteText().toStdString();
  EXPECT_GT(session.worker().snapshot()->voxels.size(), 10 * voxels_before + 100);

  // Depths that reach 10 m (a room): rays of at most 250 voxels, so 4 cm ones.
  FrameStats room;
  room.valid_pixels = 1000;
  room.beyond_range_pixels = 999;
  room.farthest_range = 9.93;
  panel.showDepthRanges(room, 1.0);
  EXPECT_TRUE(panel.noteText().contains("99.9% of the depths lay beyond the max range of 1.00 m"))
      << panel.noteText().toStdString();
  EXPECT_EQ(panel.extendRangeButton().text(), "Re-fuse up to 10.0 m, 4.0 cm voxels");
  room.beyond_range_pixels = 400;  // most depths mapped: nothing to offer
  panel.showDepthRanges(room, 1.0);
  EXPECT_TRUE(panel.extendRangeButton().isHidden());
  EXPECT_FALSE(panel.noteText().contains("beyond"));
  // Frames fused without a single valid depth: said plainly.
  FrameStats no_depth;
  no_depth.seconds = 0.01;
  panel.showDepthRanges(no_depth, 1.0);
  EXPECT_TRUE(panel.noteText().contains("No frame fused had a valid depth"))
      << panel.noteText().toStdString();
  EXPECT_TRUE(panel.extendRangeButton().isHidden());
  panel.showDepthRanges(FrameStats{}, 1.0);  // nothing fused yet: no claim
  EXPECT_FALSE(panel.noteText().contains("valid depth")) << panel.noteText().toStdString();
}

TEST_F(StudioSessionTest, SegmenterChosenInTheFusionPanelFusesFramesWithoutProba) {
  const auto wall = temp_ / "wall";
  (void)lom::test::writeColourWallSequence(wall, 1);
  const auto model = temp_ / "colours.onnx";
  lom::test::writeModel(model, lom::test::buildConvModel(lom::test::colourChannelModel()));
  StudioSession& session = window_.session();
  ASSERT_TRUE(window_.controller().openSequence(qPath(wall)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, kTimeoutMs));

  FusionPanel& panel = window_.fusionPanel();
  EXPECT_FALSE(panel.setSegmenterModel(qPath(temp_ / "missing.onnx")));
  EXPECT_TRUE(panel.noteText().contains("missing.onnx")) << panel.noteText().toStdString();
  // A model whose channels name a label the sequence does not have is
  // refused when chosen, not when Re-fuse has dropped the map.
  const auto misfit = temp_ / "misfit.onnx";
  lom::test::writeModel(misfit, lom::test::buildConvModel(lom::test::colourChannelModel()));
  std::ofstream(temp_ / "misfit.json") << R"({"labels": [0, 1, 41]})";
  EXPECT_FALSE(panel.setSegmenterModel(qPath(misfit)));
  EXPECT_TRUE(panel.noteText().contains("labels[2]")) << panel.noteText().toStdString();
  EXPECT_TRUE(session.fusionOptions().segmenter == nullptr);
  panel.maxRangeBox().setValue(2.0);  // the wall is 1 m away, its corners farther
  ASSERT_TRUE(panel.setSegmenterModel(qPath(model)));
  ASSERT_TRUE(panel.refuseButton().isEnabled());
  errors_.clear();
  panel.refuseButton().click();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, kTimeoutMs));
  QTest::qWait(50);  // the last snapshot arrives through the event loop
  EXPECT_TRUE(errors_.empty()) << errors_.front().toStdString();
  const auto snapshot = session.worker().snapshot();
  EXPECT_EQ(snapshot->frames_fused, 1u);
  // The network makes red win on the left half of the wall and green on the
  // right: both labels end up in the map.
  EXPECT_GT(snapshot->counts.count(1), 0u);
  EXPECT_GT(snapshot->counts.count(2), 0u);
  EXPECT_TRUE(session.fusionOptions().segmenter != nullptr);
}

// A recording whose world is not z-up (its first camera's, as frames and
// 3DMatch imports give): boxes added stand along the map's up, so that E/Q
// move them up and down and Shift+I grows their height.
TEST_F(StudioSessionTest, AddedBoxesStandAlongTheMapsUp) {
  Sequence sequence = loadSequence(folder_);
  // The same scene in a world turned 90 degrees about x: its up is now -y.
  const Eigen::Isometry3d turn(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  for (FrameRecord& frame : sequence.frames) frame.T_world_camera = turn * frame.T_world_camera;
  saveSequence(sequence, folder_);
  std::filesystem::remove(folder_ / "annotations.json");  // boxes of the old world
  openAndFuse();
  const auto snapshot = window_.session().worker().snapshot();
  ASSERT_TRUE(snapshot->up.has_value());
  const Eigen::Vector3d up = snapshot->up->normalized();
  ASSERT_GT(up.dot(-Eigen::Vector3d::UnitY()), 0.95) << up.transpose();

  AnnotationsModel& boxes = window_.session().annotations();
  const int label = *visibleObjectLabels().begin();
  window_.session().setSelectedLabel(label);
  QAction* add = window_.findAction("Add Box from Label Voxels");
  ASSERT_NE(add, nullptr);
  add->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return boxes.boxCount() == 1; }, kTimeoutMs));
  const OrientedBox added = boxes.box(0).box;
  EXPECT_GT((added.rotation * Eigen::Vector3d::UnitZ()).dot(up), 0.95) << "box z is the map's up";
  const GroundTruthBox* truth = truth_.find(label);
  ASSERT_NE(truth, nullptr);
  EXPECT_NEAR(added.size.z(), truth->box.size.z(), 0.03) << "its height is the object's";

  // A box at a clicked point is level too.
  window_.session().setPickedPoint(added.center + Eigen::Vector3d(0.3, 0.0, 0.0));
  window_.session().setSelectedLabel(*std::next(visibleObjectLabels().begin()));
  QAction* at_point = window_.findAction("Add Box at Clicked Point");
  ASSERT_NE(at_point, nullptr);
  at_point->trigger();
  ASSERT_EQ(boxes.boxCount(), 2);
  EXPECT_GT((boxes.box(1).box.rotation * Eigen::Vector3d::UnitZ()).dot(up), 0.999);
}

// A label the fused frames never gave evidence for has no voxels to fit:
// the message says so, not "fuse the sequence first" (fusing again would
// not help).
TEST_F(StudioSessionTest, FittingALabelTheFusedMapLacksSaysWhy) {
  openAndFuse();
  const auto snapshot = window_.session().worker().snapshot();
  int absent = -1;
  for (int label = 1; label < window_.session().sequence()->labels.size(); ++label)
    if (!snapshot->counts.count(label) && !truth_.find(label)) {
      absent = label;
      break;
    }
  ASSERT_GT(absent, 0);
  window_.session().setSelectedLabel(absent);
  errors_.clear();
  window_.findAction("Add Box from Label Voxels")->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !errors_.empty(); }, kTimeoutMs));
  EXPECT_TRUE(errors_.back().contains("its frames gave that label no evidence"))
      << errors_.back().toStdString();
  EXPECT_FALSE(errors_.back().contains("Fuse the sequence first")) << errors_.back().toStdString();
}

TEST_F(StudioSessionTest, BoxAddedMovedUndoneRedoneSavedAndReloaded) {
  openAndFuse();
  AnnotationsModel& boxes = window_.session().annotations();
  const int label = *visibleObjectLabels().begin();
  // One box per label: drop the demo's box of this label first.
  for (int i = 0; i < boxes.boxCount(); ++i)
    if (boxes.box(i).label == label) boxes.removeBox(i);
  const int initial = boxes.boxCount();
  window_.session().setSelectedLabel(label);
  QAction* add = window_.findAction("Add Box from Label Voxels");
  ASSERT_NE(add, nullptr);
  ASSERT_TRUE(add->isEnabled());
  add->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return boxes.boxCount() == initial + 1; }, kTimeoutMs));
  EXPECT_EQ(boxes.selected(), initial);
  EXPECT_TRUE(boxes.isDirty());
  EXPECT_TRUE(window_.isWindowModified());
  const GroundTruthBox added = boxes.box(initial);
  EXPECT_EQ(added.label, label);
  // The fitted box overlaps the object's true box.
  const GroundTruthBox* truth = truth_.find(label);
  ASSERT_NE(truth, nullptr);
  EXPECT_LT((added.box.center - truth->box.center).norm(), 0.05);

  // W moves the box forward along its own x axis by the move step.
  window_.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
  window_.sceneView().setFocus();
  QTest::keyClick(QApplication::focusWidget() ? QApplication::focusWidget() : &window_, Qt::Key_W);
  const GroundTruthBox moved = boxes.box(initial);
  const Eigen::Vector3d step = added.box.rotation * Eigen::Vector3d(BoxSteps::load().move, 0, 0);
  EXPECT_LT((moved.box.center - (added.box.center + step)).norm(), 1e-9);
  // The numeric fields follow.
  EXPECT_NEAR(window_.findChild<QDoubleSpinBox*>("boxField0")->value(), moved.box.center.x(), 1e-3);

  boxes.undoStack().undo();
  EXPECT_LT((boxes.box(initial).box.center - added.box.center).norm(), 1e-12);
  boxes.undoStack().redo();
  EXPECT_LT((boxes.box(initial).box.center - moved.box.center).norm(), 1e-12);

  QAction* save = window_.findAction("Save Boxes");
  ASSERT_NE(save, nullptr);
  save->trigger();
  EXPECT_TRUE(errors_.empty()) << errors_.front().toStdString();
  EXPECT_FALSE(boxes.isDirty());
  // The title still marks the map fused here, which is not saved.
  EXPECT_TRUE(window_.session().worker().hasUnsavedMap());
  EXPECT_TRUE(window_.isWindowModified());  // unsaved_map_test: Save Map… clears it

  const Annotations saved = boxes.annotations();
  boxes.reset({}, {});
  ASSERT_EQ(loadBoxes(window_.session(), qPath(folder_ / "annotations.json")).toStdString(), "");
  ASSERT_EQ(boxes.boxCount(), static_cast<int>(saved.boxes.size()));
  for (int i = 0; i < boxes.boxCount(); ++i) {
    EXPECT_EQ(boxes.box(i).label, saved.boxes[static_cast<size_t>(i)].label);
    EXPECT_LT((boxes.box(i).box.center - saved.boxes[static_cast<size_t>(i)].box.center).norm(), 1e-9);
    EXPECT_LT((boxes.box(i).box.size - saved.boxes[static_cast<size_t>(i)].box.size).norm(), 1e-9);
    EXPECT_LT(boxes.box(i).box.rotation.angularDistance(saved.boxes[static_cast<size_t>(i)].box.rotation),
              1e-9);
  }

  // Delete is undoable too, and the status bar names the box deleted.
  boxes.select(0);
  const GroundTruthBox first = boxes.box(0);
  QTest::keyClick(QApplication::focusWidget() ? QApplication::focusWidget() : &window_, Qt::Key_Delete);
  EXPECT_EQ(boxes.boxCount(), static_cast<int>(saved.boxes.size()) - 1);
  EXPECT_TRUE(window_.statusBar()->currentMessage().startsWith(
      QString("Deleted the box of %1 %2").arg(first.label).arg(QString::fromStdString(first.name))))
      << window_.statusBar()->currentMessage().toStdString();
  boxes.undoStack().undo();
  EXPECT_EQ(boxes.boxCount(), static_cast<int>(saved.boxes.size()));
}

TEST_F(StudioSessionTest, UnsavedBoxesAreOfferedBackFromTheRecoveryFile) {
  openAndFuse();
  AnnotationsModel& boxes = window_.session().annotations();
  const int initial = boxes.boxCount();
  boxes.removeBox(0);
  window_.autosave().writeNow();
  const QString recovery = window_.autosave().currentRecoveryPath();
  ASSERT_TRUE(QFileInfo::exists(recovery));

  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  next.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&next));
  QString offered;
  next.setRecoveryOffer([&](const QString& file) {
    offered = file;
    return true;
  });
  next.session().setAutoFuse(false);
  ASSERT_TRUE(next.controller().openSequence(qPath(folder_)));
  // Offered once the switch to the sequence has finished.
  ASSERT_TRUE(QTest::qWaitFor([&] { return !next.autosave().isOfferPending(); }, kTimeoutMs));
  EXPECT_EQ(offered, recovery);
  EXPECT_EQ(next.session().annotations().boxCount(), initial - 1);
  EXPECT_TRUE(next.session().annotations().isDirty());
  // Saving goes to the real file and drops the recovery copy.
  EXPECT_EQ(saveBoxes(next.session(), qPath(folder_ / "annotations.json")), QString());
  EXPECT_FALSE(QFileInfo::exists(recovery));
}

TEST_F(StudioSessionTest, ARecoveryQuestionAnsweredAfterTheFusionLeavesThePanelsUpToDate) {
  openAndFuse();
  window_.session().annotations().removeBox(0);
  window_.autosave().writeNow();

  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  next.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&next));
  // The user answers only once the fusion has finished behind the question.
  next.setRecoveryOffer([&](const QString&) {
    EXPECT_TRUE(QTest::qWaitFor(
        [&] {
          const auto snapshot = next.session().worker().snapshot();
          return !next.session().worker().isFusing() && snapshot && snapshot->frames_fused > 0;
        },
        60'000));
    QTest::qWait(100);
    return false;
  });
  ASSERT_TRUE(next.controller().openSequence(qPath(folder_)));
  EXPECT_TRUE(QTest::qWaitFor(
      [&] { return !next.evaluationPanel().isBusy() && next.evaluationPanel().canExport(); },
      60'000))
      << next.evaluationPanel().summaryText().toStdString();
  EXPECT_TRUE(QTest::qWaitFor(
      [&] { return !next.objectsPanel().isBusy() && !next.objectsPanel().objects().empty(); },
      60'000));
}

TEST_F(StudioSessionTest, EvaluationPanelShowsWhatTheScoreCommandComputes) {
  openAndFuse();
  waitForEvaluation();
  EvaluationPanel& panel = window_.evaluationPanel();
  ASSERT_TRUE(panel.report().has_value()) << panel.summaryText().toStdString();

  // `labeloctomap score SEQ --annotations annotations.json` runs scoreSequence.
  ScoreInputs inputs;
  inputs.sequence = folder_;
  inputs.annotations = folder_ / "annotations.json";
  EvaluationOptions options;
  options.fusion = window_.session().fusionOptions();
  const EvaluationReport expected = scoreSequence(inputs, options);

  QTableWidget& table = panel.table();
  ASSERT_EQ(table.rowCount(), static_cast<int>(expected.objects.size()));
  table.sortItems(EvaluationPanel::LabelOctoMap, Qt::DescendingOrder);  // sortable; order free
  for (int row = 0; row < table.rowCount(); ++row) {
    const int label = table.item(row, EvaluationPanel::Label)->data(EvaluationPanel::kValueRole).toInt();
    const auto object = std::find_if(expected.objects.begin(), expected.objects.end(),
                                     [&](const ObjectScore& o) { return o.label == label; });
    ASSERT_NE(object, expected.objects.end());
    auto value = [&](int column) {
      return table.item(row, column)->data(EvaluationPanel::kValueRole).toDouble();
    };
    EXPECT_NEAR(value(EvaluationPanel::ProjectionMean), object->iou_3d.projection_mean, 1e-12);
    EXPECT_NEAR(value(EvaluationPanel::ProjectionMax), object->iou_3d.projection_max, 1e-12);
    EXPECT_NEAR(value(EvaluationPanel::LabelOctoMap), object->iou_3d.labeloctomap, 1e-12);
    EXPECT_NEAR(value(EvaluationPanel::BoxIou), object->box_iou.labeloctomap, 1e-12);
    EXPECT_EQ(static_cast<size_t>(value(EvaluationPanel::Voxels)), object->voxels);
  }
  EXPECT_NEAR(panel.report()->summary.iou_3d.labeloctomap, expected.summary.iou_3d.labeloctomap,
              1e-12);
  EXPECT_TRUE(panel.summaryText().contains(
      QString::number(expected.summary.iou_3d.labeloctomap * 100.0, 'f', 1)));

  // Export report writes the CLI's files.
  const auto out = temp_.path() / "report";
  EXPECT_EQ(panel.exportReport(qPath(out)), QString());
  for (const char* name : {"report.json", "report.csv", "report.md", "report.svg"})
    EXPECT_TRUE(std::filesystem::exists(out / name)) << name;

  // A box change triggers a new evaluation.
  window_.session().annotations().removeBox(0);
  EXPECT_TRUE(panel.isBusy());
  waitForEvaluation();
  EXPECT_EQ(table.rowCount(), static_cast<int>(expected.objects.size()) - 1);
}

// The mouse resting on a frame image while the frame or the label changes:
// the readout describes the pixel shown now (it kept the last frame's depth
// and the last label's probability until the mouse moved).
TEST_F(StudioSessionTest, ThePixelReadoutFollowsTheFrameAndTheLabelShown) {
  openAndFuse();
  const LabelSet& labels = window_.session().sequence()->labels;
  const int label = *visibleObjectLabels().begin();
  window_.session().setSelectedLabel(label);
  SequenceController& controller = window_.controller();
  FrameImagesView& images = window_.frameImages();
  int changed = 0;
  for (int v = 40; v < 120; v += 20)
    for (int u = 40; u < 160; u += 20) {
      controller.setCurrentFrame(0);
      QApplication::processEvents();
      images.hoverPixel(QPoint(u, v));
      const QString first = images.readoutText();
      controller.setCurrentFrame(1);
      QApplication::processEvents();
      const QString shown = images.readoutText();
      images.hoverPixel(QPoint(u, v));  // as a move of the mouse would say
      EXPECT_EQ(shown, images.readoutText());
      if (first != shown) ++changed;
    }
  EXPECT_GT(changed, 0) << "the frames differ nowhere: the check above proves nothing";

  const int other = *std::next(visibleObjectLabels().begin());
  window_.session().setSelectedLabel(other);
  EXPECT_TRUE(images.readoutText().contains(
      QString("p(%1)").arg(QString::fromStdString(labels.at(other).name))))
      << images.readoutText().toStdString();
  // The background's row shows the background's probability.
  auto* legend = window_.findChild<MapLegendPanel*>();
  ASSERT_NE(legend, nullptr);
  emit legend->currentLabelChanged(0);
  EXPECT_TRUE(images.readoutText().contains(
      QString("p(%1)").arg(QString::fromStdString(labels.at(0).name))))
      << images.readoutText().toStdString();
  EXPECT_EQ(window_.session().selectedLabel(), other);  // still the label boxes are made for
}

TEST_F(StudioSessionTest, HeatMapHoverPickingAndProjectionVoxels) {
  openAndFuse();
  const int label = *visibleObjectLabels().begin();
  window_.session().setSelectedLabel(label);
  EXPECT_FALSE(window_.frameImages().heatPane().image().isNull());
  window_.frameImages().hoverPixel(QPoint(80, 60));
  EXPECT_TRUE(window_.frameImages().readoutText().contains("(80, 60)"))
      << window_.frameImages().readoutText().toStdString();

  // Picking the centre of a voxel of the label reports that label first.
  const auto snapshot = window_.session().worker().snapshot();
  const auto voxel = std::find_if(snapshot->voxels.begin(), snapshot->voxels.end(),
                                  [&](const OccupiedVoxel& v) { return v.label == label; });
  ASSERT_NE(voxel, snapshot->voxels.end());
  auto* picked = window_.findChild<PickedVoxelView*>("pickedVoxel");
  ASSERT_NE(picked, nullptr);
  window_.session().setPickedPoint(voxel->center);
  window_.session().worker().pick(voxel->center);
  const QString name = QString::fromStdString(window_.session().sequence()->labels.at(label).name);
  ASSERT_TRUE(QTest::qWaitFor([&] { return picked->text().contains("Occupied"); }, 10'000));
  EXPECT_TRUE(picked->text().contains(name)) << picked->text().toStdString();

  // Export ▸ Point Cloud writes the map's voxels on the worker.
  QAction* pcd = window_.findAction("Point Cloud (PCD)…");
  ASSERT_NE(pcd, nullptr);
  ASSERT_TRUE(pcd->isEnabled());
  auto* exporter = pcd->findChild<ExportMapReaction*>();
  ASSERT_NE(exporter, nullptr);
  bool exported = false;
  QObject::connect(exporter, &ExportMapReaction::finished, [&](const QString&, bool ok) { exported = ok; });
  exporter->exportTo(qPath(temp_.path() / "map.pcd"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return exported; }, 30'000));
  EXPECT_TRUE(std::filesystem::exists(temp_.path() / "map.pcd"));

  QAction* projection = window_.findAction("Show Projection Voxels of This View");
  ASSERT_NE(projection, nullptr);
  projection->trigger();
  EXPECT_GT(window_.sceneView().projectionVoxelCount(), 0u);
  projection->trigger();
  EXPECT_EQ(window_.sceneView().projectionVoxelCount(), 0u);
}

// The Picked Voxel panel tells the voxel of the map shown: after Reset Map the
// point clicked is unknown, after a new fusion it is looked up again, and
// another sequence forgets it.
TEST_F(StudioSessionTest, PickedVoxelFollowsTheMap) {
  openAndFuse();
  const auto snapshot = window_.session().worker().snapshot();
  ASSERT_FALSE(snapshot->voxels.empty());
  const Eigen::Vector3d point = snapshot->voxels.front().center;
  auto* picked = window_.findChild<PickedVoxelView*>("pickedVoxel");
  ASSERT_NE(picked, nullptr);
  window_.session().setPickedPoint(point);
  window_.session().worker().pick(point);
  ASSERT_TRUE(QTest::qWaitFor([&] { return picked->text().contains("Occupied"); }, 10'000));

  window_.session().resetMap();
  ASSERT_TRUE(QTest::qWaitFor([&] { return picked->text().contains("No map yet"); }, 10'000))
      << picked->text().toStdString();
  window_.session().fuse();
  waitForFusion();
  ASSERT_TRUE(QTest::qWaitFor([&] { return picked->text().contains("Occupied"); }, 10'000))
      << picked->text().toStdString();

  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  EXPECT_FALSE(window_.session().pickedPoint());
  EXPECT_TRUE(picked->text().startsWith("Click a voxel")) << picked->text().toStdString();
  waitForFusion();
  QTest::qWait(100);
  EXPECT_TRUE(picked->text().startsWith("Click a voxel")) << picked->text().toStdString();

  // An answer for a point no longer picked (asked before another sequence
  // opened, or before another click) describes another map: not shown.
  emit window_.session().worker().voxelPicked(point, VoxelState{});
  EXPECT_TRUE(picked->text().startsWith("Click a voxel")) << picked->text().toStdString();
  window_.session().setPickedPoint(point + Eigen::Vector3d(0.05, 0, 0));
  const QString shown = picked->text();
  emit window_.session().worker().voxelPicked(point, VoxelState{});
  EXPECT_EQ(picked->text(), shown);
}

// Class candidates name one scene's objects: another sequence is fused with
// all its labels, and the Fusion panel shows it.
TEST_F(StudioSessionTest, CandidatesDoNotCarryOverToAnotherSequence) {
  openAndFuse();
  QLineEdit* candidates = &window_.fusionPanel().candidatesEdit();
  candidates->setText(QString("0 %1").arg(*visibleObjectLabels().begin()));
  window_.fusionPanel().refuseButton().click();
  waitForFusion();
  ASSERT_TRUE(window_.session().fusionOptions().candidates.has_value());
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  EXPECT_FALSE(window_.session().fusionOptions().candidates.has_value());
  EXPECT_TRUE(candidates->text().isEmpty()) << candidates->text().toStdString();
  waitForFusion();
}

// Pause usually lands while a frame is being fused: that frame's progress,
// reported after it, moves the count on but leaves "paused" in the status bar.
TEST_F(StudioSessionTest, PauseStaysShownWhenTheFrameInFlightReports) {
  MapWorker& worker = window_.session().worker();
  std::atomic<bool> entered{false}, release{false};
  worker.setFrameFusedHook([&](size_t frames_fused) {
    if (frames_fused != 2) return;
    entered = true;
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return entered.load(); }, kTimeoutMs));
  worker.setPaused(true);
  EXPECT_TRUE(window_.fusionStatusText().contains("paused"));
  EXPECT_TRUE(window_.evaluationPanel().summaryText().startsWith("Fusion paused"))
      << window_.evaluationPanel().summaryText().toStdString();
  release = true;
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return window_.fusionStatusText().contains("fused 2/"); }, kTimeoutMs))
      << window_.fusionStatusText().toStdString();
  QTest::qWait(100);
  EXPECT_TRUE(window_.fusionStatusText().contains("paused"))
      << window_.fusionStatusText().toStdString();
  worker.setPaused(false);
  worker.setFrameFusedHook({});
  waitForFusion();
  EXPECT_FALSE(window_.fusionStatusText().contains("paused"))
      << window_.fusionStatusText().toStdString();
}

// A name typed without an extension in a save dialog gets the format's, as
// save dialogs do (the export refused it: "expected a file name ending in
// .ply"); a name with one is kept.
TEST_F(StudioSessionTest, SaveDialogsAddTheFormatsExtensionToANameWithout) {
  openAndFuse();
  const auto exported = temp_.path() / "my map";
  {
    ui::test::DialogAnswerer answer("Replace|Yes", qPath(exported));
    window_.findAction("Voxel Mesh (PLY)…")->trigger();
    ASSERT_TRUE(QTest::qWaitFor(
        [&] { return std::filesystem::exists(temp_.path() / "my map.ply"); }, kTimeoutMs));
  }
  EXPECT_FALSE(std::filesystem::exists(exported));
  window_.session().annotations().removeBox(0);  // something to save
  {
    ui::test::DialogAnswerer answer("Save|Replace|Yes", qPath(temp_.path() / "boxes"));
    window_.findAction("Save Boxes As…")->trigger();
  }
  EXPECT_TRUE(std::filesystem::exists(temp_.path() / "boxes.json"));
  EXPECT_FALSE(window_.session().annotations().isDirty());
  {
    ui::test::DialogAnswerer answer("Replace|Yes", qPath(temp_.path() / "view"));
    window_.findAction("Save 3D View…")->trigger();
  }
  EXPECT_TRUE(std::filesystem::exists(temp_.path() / "view.png"));
  // A name with a dot of its own gets the extension too (the dialog leaves
  // such names alone), and replacing an existing file of that name is asked.
  const auto dotted = temp_.path() / "shelf_0.005m.ply";
  std::ofstream(dotted) << "an earlier mesh";
  {
    ui::test::DialogAnswerer answer("No", qPath(temp_.path() / "shelf_0.005m"));
    window_.findAction("Voxel Mesh (PLY)…")->trigger();
    QTest::qWait(300);
    ASSERT_EQ(answer.questions.size(), 1) << answer.questions.join("\n").toStdString();
    EXPECT_TRUE(answer.questions.front().contains("shelf_0.005m.ply already exists"))
        << answer.questions.front().toStdString();
  }
  EXPECT_EQ(lom::test::slurp(dotted), "an earlier mesh");
  {
    ui::test::DialogAnswerer answer("Yes", qPath(temp_.path() / "shelf_0.005m"));
    window_.findAction("Voxel Mesh (PLY)…")->trigger();
    ASSERT_TRUE(
        QTest::qWaitFor([&] { return lom::test::slurp(dotted) != "an earlier mesh"; }, kTimeoutMs));
  }
  EXPECT_FALSE(std::filesystem::exists(temp_.path() / "shelf_0.005m"));
  {
    ui::test::DialogAnswerer answer("Replace|Yes", qPath(temp_.path() / "view_1.5x"));
    window_.findAction("Save 3D View…")->trigger();
  }
  EXPECT_TRUE(std::filesystem::exists(temp_.path() / "view_1.5x.png"));
}

// The fusion count in the status bar fits on its bar, also for a long
// recording and in a large font (it wrapped to two clipped lines).
TEST_F(StudioSessionTest, TheFusionCountFitsItsBarInALargeFont) {
  openAndFuse();
  auto* status = window_.findChild<QWidget*>("fusionStatus");
  ASSERT_NE(status, nullptr);
  auto* bar = status->findChild<QProgressBar*>();
  ASSERT_NE(bar, nullptr);
  // As a long recording would count (a sequence of 12,000 frames).
  bar->setRange(0, 12000);
  bar->setValue(12000);
  for (const double scale : {1.0, 1.6}) {
    QFont font = window_.font();
    font.setPointSizeF(font.pointSizeF() * scale);
    bar->setFont(font);
    settle();
    const int needed = QFontMetrics(bar->font()).horizontalAdvance(bar->text());
    EXPECT_TRUE(bar->text().startsWith("fused ")) << bar->text().toStdString();
    EXPECT_GE(bar->width(), needed + QFontMetrics(bar->font()).averageCharWidth())
        << "scale " << scale << ": " << bar->text().toStdString();
  }
}

TEST_F(StudioSessionTest, ExportsCanLeaveOutTheLabelsHiddenInThe3DView) {
  openAndFuse();
  QAction* only_shown = window_.findAction("Only Labels Shown");
  ASSERT_NE(only_shown, nullptr);
  EXPECT_TRUE(only_shown->isCheckable());
  EXPECT_FALSE(only_shown->isChecked());
  auto* exporter = window_.findAction("Voxel Mesh (PLY)…")->findChild<ExportMapReaction*>();
  ASSERT_NE(exporter, nullptr);
  QString message;
  bool done = false;
  QObject::connect(exporter, &ExportMapReaction::finished, [&](const QString& text, bool ok) {
    message = text;
    done = ok;
  });
  const auto exportTo = [&](const std::filesystem::path& path) {
    done = false;
    exporter->exportTo(qPath(path));
    ASSERT_TRUE(QTest::qWaitFor([&] { return done; }, 30'000)) << message.toStdString();
  };
  window_.session().setHiddenLabels({0});  // the background unticked in Map Labels
  const auto all = temp_.path() / "all.ply", shown = temp_.path() / "shown.ply";
  exportTo(all);  // unchecked: every label, whatever is hidden
  EXPECT_FALSE(message.contains("hidden")) << message.toStdString();
  only_shown->trigger();
  exportTo(shown);
  EXPECT_TRUE(message.contains("1 hidden")) << message.toStdString();
  EXPECT_LT(std::filesystem::file_size(shown), std::filesystem::file_size(all));
  // The file is the command line's `export --labels` of the labels shown.
  const auto expected = temp_.path() / "expected.ply";
  std::atomic<bool> written{false};
  window_.session().worker().withMap([&](const LabelMap* map) {
    ExportOptions options;
    options.format = ExportFormat::Ply;
    options.labels = std::set<int>();
    for (int label = 1; label < map->numLabels(); ++label) options.labels->insert(label);
    (void)exportMap(*map, options, expected);
    written = true;
  });
  ASSERT_TRUE(QTest::qWaitFor([&] { return written.load(); }, 30'000));
  EXPECT_EQ(lom::test::slurp(shown), lom::test::slurp(expected));
  only_shown->trigger();
}

TEST_F(StudioSessionTest, ScreenshotAfterFusionShowsLabelColours) {
  openAndFuse();
  window_.sceneView().setFrameCloudVisible(false);  // only the map's voxels
  const QImage shot = captureWindow(window_, window_.sceneView());
  ASSERT_FALSE(shot.isNull());
  const QRect area(window_.sceneView().mapTo(&window_, QPoint(0, 0)), window_.sceneView().size());
  std::map<int, size_t> pixels_per_label;
  for (int y = area.top(); y <= area.bottom(); y += 2)
    for (int x = area.left(); x <= area.right(); x += 2) {
      const QRgb pixel = shot.pixel(x, y);
      for (int label : visibleObjectLabels()) {
        const Rgb c = vocColor(label);
        // Shading darkens faces; compare the hue direction with a tolerance.
        const double scale = std::max({qRed(pixel), qGreen(pixel), qBlue(pixel), 1}) /
                             std::max({double(c[0]), double(c[1]), double(c[2]), 1.0});
        if (std::abs(qRed(pixel) - c[0] * scale) < 14 && std::abs(qGreen(pixel) - c[1] * scale) < 14 &&
            std::abs(qBlue(pixel) - c[2] * scale) < 14 && qGray(pixel) > 20)
          ++pixels_per_label[label];
      }
    }
  size_t labels_seen = 0;
  for (int label : visibleObjectLabels()) labels_seen += pixels_per_label[label] > 20;
  EXPECT_GE(labels_seen, 2u) << "label colours are missing from the 3D view";
}

// Pixels of the 3D view whose hue is that of the height ramp's low third and
// high third (shading scales a colour; the ramp is sampled finely enough that
// every voxel's colour is near a sample).
std::pair<size_t, size_t> lowAndHighRampPixels(const QImage& shot, const QRect& area) {
  size_t low = 0, high = 0;
  for (int y = area.top(); y <= area.bottom(); y += 2)
    for (int x = area.left(); x <= area.right(); x += 2) {
      const QRgb pixel = shot.pixel(x, y);
      // Dark pixels (the view's background, faces turned away) match any hue.
      if (std::max({qRed(pixel), qGreen(pixel), qBlue(pixel)}) < 90) continue;
      for (int i = 0; i <= 40; ++i) {
        const double t = i / 40.0;
        if (t > 0.3 && t < 0.7) continue;
        const Rgb c = heightRampColour(t);
        const double scale = std::max({qRed(pixel), qGreen(pixel), qBlue(pixel), 1}) /
                             std::max({double(c[0]), double(c[1]), double(c[2]), 1.0});
        if (std::abs(qRed(pixel) - c[0] * scale) < 8 &&
            std::abs(qGreen(pixel) - c[1] * scale) < 8 &&
            std::abs(qBlue(pixel) - c[2] * scale) < 8) {
          ++(t <= 0.3 ? low : high);
          break;
        }
      }
    }
  return {low, high};
}

TEST_F(StudioSessionTest, ColourByHeightPaintsLowVoxelsBlueAndHighOnesRed) {
  openAndFuse();
  window_.sceneView().setFrameCloudVisible(false);  // only the map's voxels
  QAction* by_height = window_.findAction("Colour by Height");
  ASSERT_NE(by_height, nullptr);
  ASSERT_TRUE(by_height->isCheckable());
  EXPECT_EQ(window_.sceneView().voxelColouring(), VoxelColouring::Labels);
  const QRect area(window_.sceneView().mapTo(&window_, QPoint(0, 0)), window_.sceneView().size());
  const auto [low_before, high_before] =
      lowAndHighRampPixels(captureWindow(window_, window_.sceneView()), area);

  by_height->trigger();
  EXPECT_EQ(window_.sceneView().voxelColouring(), VoxelColouring::Height);
  const size_t voxels = window_.sceneView().voxelCount();
  EXPECT_GT(voxels, 0u);
  const QImage shot = captureWindow(window_, window_.sceneView());
  ASSERT_FALSE(shot.isNull());
  const auto [low, high] = lowAndHighRampPixels(shot, area);
  EXPECT_GT(low, 4 * low_before + 50) << "no blue low voxels";
  EXPECT_GT(high, 4 * high_before + 50) << "no red high voxels";
  // The legend shows what blue and red stand for: the voxels' heights along the
  // map's up (the generated scene's cameras look down at a shelf: z up, within a metre).
  const auto range = window_.mapLegend().heightBarRange();
  ASSERT_TRUE(range.has_value());
  EXPECT_LT(range->first, range->second);
  EXPECT_GT(range->second - range->first, 0.05);
  EXPECT_LT(range->second - range->first, 1.0);

  by_height->trigger();  // back to label colours, the same voxels
  EXPECT_EQ(window_.sceneView().voxelColouring(), VoxelColouring::Labels);
  EXPECT_EQ(window_.sceneView().voxelCount(), voxels);
  EXPECT_FALSE(window_.mapLegend().heightBarRange().has_value());
}

}  // namespace
}  // namespace lom::ui
