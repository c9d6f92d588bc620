// A map fused earlier (.ot, as `labeloctomap fuse` writes it) shown instead of
// fusing: File > Open Map… and --map on the studio's command line. The map
// replaces the fused one with its own parameters and is scored as `score
// --map` scores it; a map of another label set or world frame, or a file that
// is no map, is refused with a message and leaves the map as it was.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QDoubleSpinBox>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QLineEdit>
#include <QMimeData>
#include <QProcess>
#include <QPushButton>
#include <QTest>
#include <QUrl>
#include <fstream>

#include "demo_window_fixture.hpp"
#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/objects.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/open_map_reaction.hpp"
#include "lom/ui/sequence_drop_handler.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;
using fixture::qPath;

class OpenMapTest : public fixture::DemoWindowTest {
 protected:
  StudioSession& session() { return window_.session(); }
  // The demo fused at 5 mm (the studio fuses at 1 cm), saved as a .ot file.
  std::filesystem::path writeFinerMap() {
    const Sequence sequence = loadSequence(folder_);
    FusionOptions options;
    options.map.resolution = 0.005;
    const LabelMap map = fuseSequence(sequence, options);
    occupied_ = map.occupiedCountPerLabel();
    const auto path = temp_.path() / "demo_5mm.ot";
    map.save(path);
    return path;
  }
  void waitForMap() {
    ASSERT_TRUE(QTest::qWaitFor(
        [&] { return !session().isOpeningMap() && !session().worker().isFusing(); }, kTimeoutMs));
    QTest::qWait(50);  // the snapshot arrives through the event loop
  }
  std::map<int, size_t> occupied_;
};

TEST_F(OpenMapTest, AMapFromAFileReplacesTheFusedOneWithItsParameters) {
  openAndFuse();
  ASSERT_DOUBLE_EQ(session().worker().snapshot()->resolution, 0.01);
  const auto path = writeFinerMap();
  QAction* open_map = window_.findAction("Open Map…");
  ASSERT_NE(open_map, nullptr);
  ASSERT_TRUE(open_map->isEnabled());
  auto* reaction = open_map->findChild<OpenMapReaction*>();
  ASSERT_NE(reaction, nullptr);
  QString offered_folder;
  reaction->setChooser([&](const QString& start) {
    offered_folder = start;
    return qPath(path);
  });
  const unsigned generation = session().mapGeneration();
  open_map->trigger();
  // While the file is read the status bar says so (it said nothing before).
  EXPECT_TRUE(window_.fusionStatusText().contains("reading map demo_5mm.ot"))
      << window_.fusionStatusText().toStdString();
  waitForMap();
  EXPECT_TRUE(errors_.empty()) << errors_.front().toStdString();
  // The dialog starts beside the sequence folder, where maps are written.
  EXPECT_EQ(offered_folder, qPath(folder_.parent_path()));

  // The map shown is the file's: its resolution and its voxels.
  const MapSnapshot& shown = *session().worker().snapshot();
  EXPECT_DOUBLE_EQ(shown.resolution, 0.005);
  EXPECT_EQ(shown.counts, occupied_);
  EXPECT_EQ(shown.frames_fused, static_cast<size_t>(fixture::smallDemo().frames));
  EXPECT_NE(session().mapGeneration(), generation);
  // The Fusion panel shows the map's parameters, with nothing to re-fuse.
  EXPECT_DOUBLE_EQ(session().fusionOptions().map.resolution, 0.005);
  EXPECT_NEAR(window_.fusionPanel().resolutionBox().value(), 0.005, 1e-9);
  EXPECT_FALSE(window_.fusionPanel().hasPendingChanges());
  EXPECT_TRUE(window_.fusionStatusText().contains("map from file"))
      << window_.fusionStatusText().toStdString();

  // Scored as `labeloctomap score --map` scores it.
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.evaluationPanel().isBusy(); }, kTimeoutMs));
  QTest::qWait(50);
  const auto& report = window_.evaluationPanel().report();
  ASSERT_TRUE(report.has_value());
  const EvaluationReport expected =
      evaluate(loadSequence(folder_), truth_, LabelMap::load(path), EvaluationOptions{});
  ASSERT_EQ(report->objects.size(), expected.objects.size());
  for (size_t i = 0; i < expected.objects.size(); ++i) {
    EXPECT_EQ(report->objects[i].label, expected.objects[i].label);
    EXPECT_DOUBLE_EQ(report->objects[i].iou_3d.labeloctomap,
                     expected.objects[i].iou_3d.labeloctomap);
    EXPECT_DOUBLE_EQ(report->objects[i].box_iou.labeloctomap,
                     expected.objects[i].box_iou.labeloctomap);
  }
}

// A map that records no camera (an older map, or one built without cameras)
// is levelled by the cameras of the sequence it is opened with: the views,
// colours by height and boxes placed by a click stand on their up, not on +z.
TEST_F(OpenMapTest, AMapWithoutCamerasTakesTheSequencesUp) {
  std::vector<QString> warnings;  // a block of voxels does not fit the depths: said, not asked
  window_.setWarningReporter([&](const QString& title, const QString& message) {
    warnings.push_back(title + ": " + message);
  });
  openAndFuse();
  const Sequence sequence = loadSequence(folder_);
  LabelMap bare(sequence.labels);
  OrientedBox block;
  block.center = Eigen::Vector3d(0.0, 0.0, 0.05);
  block.size = Eigen::Vector3d(0.1, 0.1, 0.1);
  ASSERT_GT(rasterizeBox(bare, block, 1, 0.9), 0u);
  ASSERT_FALSE(bare.camerasUp());
  const auto path = temp_.path() / "bare.ot";
  bare.save(path);
  session().openMap(qPath(path));
  waitForMap();
  const MapSnapshot& shown = *session().worker().snapshot();
  ASSERT_EQ(shown.counts.at(1), bare.occupiedCountPerLabel().at(1));
  const auto sequence_up = camerasUpOf(sequence);
  ASSERT_TRUE(sequence_up);
  ASSERT_TRUE(shown.up) << "no up: the views would stand on +z";
  EXPECT_GT(shown.up->dot(*sequence_up), std::cos(30.0 * M_PI / 180.0));
}

// `labeloctomap fuse` takes settings the Fusion panel's fields show rounded
// (more decimals) or that the studio once did not offer (max range beyond 20
// m). Such a map shows no change to re-fuse, and re-fusing for another edit
// keeps the settings that were not edited exactly.
TEST_F(OpenMapTest, SettingsTheFieldsShowRoundedAreKeptExactly) {
  openAndFuse();
  FusionOptions options;
  options.map.resolution = 0.03254;  // shown 0.0325 m (four decimals)
  options.map.max_range = 25.1254;   // shown 25.125 m; 772 voxels per ray, within the limit
  options.map.p_miss = 0.4951;      // shown 0.495
  options.map.occupancy_threshold = 0.125;         // just above the clamping bound 0.12
  options.candidates = std::vector<int>{4, 0, 6};  // recorded with the map, sorted
  const auto path = temp_.path() / "exact_settings.ot";
  fuseSequence(loadSequence(folder_), options).save(path);
  session().openMap(qPath(path));
  waitForMap();
  ASSERT_TRUE(errors_.empty()) << errors_.front().toStdString();
  FusionPanel& panel = window_.fusionPanel();
  // The map's candidates are the panel's and the projection baselines'.
  EXPECT_EQ(panel.candidatesEdit().text(), "0 4 6");
  EXPECT_EQ(session().fusionOptions().candidates, (std::vector<int>{0, 4, 6}));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.evaluationPanel().isBusy(); }, kTimeoutMs));
  QTest::qWait(50);
  ASSERT_TRUE(window_.evaluationPanel().report().has_value());
  EXPECT_EQ(window_.evaluationPanel().report()->candidates, (std::vector<int>{0, 4, 6}));
  EXPECT_NEAR(panel.maxRangeBox().value(), 25.125, 1e-9);  // not cut to an older 20 m limit
  EXPECT_NEAR(panel.resolutionBox().value(), 0.0325, 1e-9);
  // The tooltips give the map's exact values.
  EXPECT_EQ(panel.resolutionBox().toolTip(), "The map's value: 0.03254 m");
  EXPECT_EQ(panel.maxRangeBox().toolTip(), "The map's value: 25.1254 m");
  EXPECT_NEAR(panel.thresholdBox().value(), 0.125, 1e-9);
  EXPECT_TRUE(panel.thresholdBox().toolTip().isEmpty());
  EXPECT_FALSE(panel.hasPendingChanges());
  EXPECT_FALSE(panel.refuseButton().isEnabled());

  // Another edit re-fuses with the map's exact settings for the fields left alone.
  panel.candidatesEdit().setText("0 1");
  ASSERT_TRUE(panel.refuseButton().isEnabled());
  panel.refuseButton().click();
  waitForMap();
  const MapParameters& fused = session().fusionOptions().map;
  EXPECT_EQ(fused.resolution, 0.03254);
  EXPECT_EQ(fused.max_range, 25.1254);
  EXPECT_EQ(fused.p_miss, 0.4951);
  EXPECT_EQ(session().worker().snapshot()->resolution, 0.03254);
  EXPECT_FALSE(panel.hasPendingChanges());

  // An edit re-fuses with the field's value; the others keep the map's.
  panel.maxRangeBox().setValue(30.0);  // 922 voxels of 3.254 cm
  ASSERT_TRUE(panel.refuseButton().isEnabled());
  panel.refuseButton().click();
  waitForMap();
  EXPECT_EQ(session().fusionOptions().map.max_range, 30.0);
  EXPECT_EQ(session().fusionOptions().map.resolution, 0.03254);
  EXPECT_FALSE(panel.hasPendingChanges());
  // A value typed is the user's, also the one the box showed for the map's:
  // Re-fuse applies it rather than dropping it without a word.
  panel.resolutionBox().setValue(0.05);
  EXPECT_TRUE(panel.hasPendingChanges());
  panel.resolutionBox().setValue(0.0325);
  EXPECT_TRUE(panel.hasPendingChanges());
  ASSERT_TRUE(panel.refuseButton().isEnabled());
  panel.refuseButton().click();
  waitForMap();
  EXPECT_EQ(session().fusionOptions().map.resolution, 0.0325);
  EXPECT_TRUE(panel.resolutionBox().toolTip().isEmpty());
  EXPECT_FALSE(panel.hasPendingChanges());
}

// Frames A:B, as `fuse --frames`: a map fused from some frames (opened from
// a file, which does not record which) is fused again from the same ones.
TEST_F(OpenMapTest, TheFramesFieldFusesAFrameRange) {
  openAndFuse();
  FusionPanel& panel = window_.fusionPanel();
  const size_t count = loadSequence(folder_).frames.size();
  ASSERT_GE(count, 3u);
  EXPECT_TRUE(panel.framesEdit().text().isEmpty());
  panel.framesEdit().setText("5:2");
  EXPECT_FALSE(panel.refuseButton().isEnabled());
  EXPECT_TRUE(panel.noteText().startsWith("Frames: A:B")) << panel.noteText().toStdString();
  panel.framesEdit().setText(QString("%1:").arg(count));
  EXPECT_FALSE(panel.refuseButton().isEnabled());
  EXPECT_TRUE(panel.noteText().contains(QString("the sequence has %1 frames").arg(count)))
      << panel.noteText().toStdString();
  panel.framesEdit().setText("1:3");
  ASSERT_TRUE(panel.hasPendingChanges());
  ASSERT_TRUE(panel.refuseButton().isEnabled()) << panel.noteText().toStdString();
  panel.refuseButton().click();
  waitForMap();
  EXPECT_EQ(session().worker().snapshot()->frames_fused, 2u);
  EXPECT_EQ(session().fusionOptions().first_frame, 1u);
  EXPECT_EQ(session().fusionOptions().last_frame, 3u);
  EXPECT_FALSE(panel.hasPendingChanges());
  // F5 fuses them again.
  window_.findAction("Fuse Sequence")->trigger();
  waitForMap();
  EXPECT_EQ(session().worker().snapshot()->frames_fused, 2u);
  // Frames name one recording's: another sequence is fused whole.
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  waitForMap();
  EXPECT_TRUE(panel.framesEdit().text().isEmpty());
  EXPECT_EQ(session().worker().snapshot()->frames_fused, count);
}

TEST_F(OpenMapTest, OpeningAMapDuringFusionStopsTheFusion) {
  const auto path = writeFinerMap();
  session().worker().setSnapshotInterval(0);
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  session().worker().setPaused(true);
  ASSERT_TRUE(session().worker().isFusing());
  session().openMap(qPath(path));
  waitForMap();
  EXPECT_FALSE(session().worker().isFusing());
  EXPECT_DOUBLE_EQ(session().worker().snapshot()->resolution, 0.005);
  EXPECT_EQ(session().worker().snapshot()->counts, occupied_);
}

// A map whose voxels are not where the sequence's depths are (fused from
// another recording with the same labels, or with other poses) is shown with
// a warning; a map of the sequence opens without one.
// Fuse and Reset Map, asked for while a map file is still being read, are
// what the user wants last: the file read afterwards is dropped.
TEST_F(OpenMapTest, AFusionOrResetStartedWhileAMapIsReadIsNotReplacedByIt) {
  openAndFuse();
  const auto path = writeFinerMap();
  session().openMap(qPath(path));
  session().fuse();
  waitForMap();
  EXPECT_DOUBLE_EQ(session().worker().snapshot()->resolution, 0.01);
  EXPECT_DOUBLE_EQ(session().fusionOptions().map.resolution, 0.01);
  EXPECT_FALSE(window_.fusionStatusText().contains("map from file"))
      << window_.fusionStatusText().toStdString();

  session().openMap(qPath(path));
  session().resetMap();
  waitForMap();
  EXPECT_EQ(session().worker().snapshot()->frames_fused, 0u);
  EXPECT_TRUE(session().worker().snapshot()->empty());
  EXPECT_TRUE(errors_.empty()) << errors_.front().toStdString();
}

TEST_F(OpenMapTest, AMapThatDoesNotFitTheDepthsIsShownWithAWarning) {
  std::vector<QString> warnings;
  window_.setWarningReporter([&](const QString& title, const QString& message) {
    warnings.push_back(title + ": " + message);
  });
  openAndFuse();
  session().openMap(qPath(writeFinerMap()));
  waitForMap();
  EXPECT_TRUE(warnings.empty()) << warnings.front().toStdString();

  Sequence moved = loadSequence(folder_);
  for (FrameRecord& frame : moved.frames) frame.T_world_camera.translation().y() += 0.5;
  const auto path = temp_.path() / "moved.ot";
  fuseSequence(moved, FusionOptions{}).save(path);
  session().openMap(qPath(path));
  waitForMap();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(warnings.front().startsWith("Map of another scene?"))
      << warnings.front().toStdString();
  EXPECT_TRUE(warnings.front().contains("moved.ot: only ")) << warnings.front().toStdString();
  EXPECT_TRUE(errors_.empty());
  EXPECT_TRUE(window_.fusionStatusText().contains("map from file"));  // shown all the same
}

// A map whose labels have other colours than the sequence's (an edited label
// file) is shown, drawn in the sequence's colours, with a warning naming the
// labels and saying that exports take the map's.
TEST_F(OpenMapTest, AMapOfOtherLabelColoursIsShownWithAWarning) {
  std::vector<QString> warnings;
  window_.setWarningReporter([&](const QString& title, const QString& message) {
    warnings.push_back(title + ": " + message);
  });
  openAndFuse();
  Sequence recoloured = loadSequence(folder_);
  std::vector<LabelInfo> labels = recoloured.labels.all();
  labels.at(4).color = {1, 2, 3};
  recoloured.labels = LabelSet(labels);
  const auto path = temp_.path() / "recoloured.ot";
  fuseSequence(recoloured, FusionOptions{}).save(path);
  session().openMap(qPath(path));
  waitForMap();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(warnings.front().startsWith("Map colours differ: "))
      << warnings.front().toStdString();
  EXPECT_TRUE(warnings.front().contains(
      QString("4 %1: (1, 2, 3) in the map").arg(QString::fromStdString(labels.at(4).name))))
      << warnings.front().toStdString();
  EXPECT_TRUE(errors_.empty());
  EXPECT_TRUE(window_.fusionStatusText().contains("map from file"));  // shown all the same
}

TEST_F(OpenMapTest, AMapOfAnotherLabelSetOrNoMapAtAllIsRefused) {
  openAndFuse();
  const MapSnapshotPtr before = session().worker().snapshot();
  const unsigned generation = session().mapGeneration();
  const QString status = window_.fusionStatusText();

  LabelMap other(LabelSet({{0, "floor", {1, 2, 3}}, {1, "cup", {4, 5, 6}}}), MapParameters{});
  const auto other_path = temp_.path() / "other_labels.ot";
  other.save(other_path);
  session().openMap(qPath(other_path));
  waitForMap();
  ASSERT_EQ(errors_.size(), 1u);
  EXPECT_TRUE(errors_.front().contains("other_labels.ot")) << errors_.front().toStdString();
  EXPECT_TRUE(errors_.front().contains("labels")) << errors_.front().toStdString();
  EXPECT_TRUE(errors_.front().startsWith("Map of another label set: "))
      << errors_.front().toStdString();

  // The sequence's labels, but poses of another world frame than its own.
  LabelMap elsewhere(loadSequence(folder_).labels, MapParameters{});
  elsewhere.noteWorldFrame("odom");
  const auto elsewhere_path = temp_.path() / "odom_frame.ot";
  elsewhere.save(elsewhere_path);
  session().openMap(qPath(elsewhere_path));
  waitForMap();
  ASSERT_EQ(errors_.size(), 2u);
  EXPECT_TRUE(errors_.back().startsWith("Map of another world frame: "))
      << errors_.back().toStdString();
  EXPECT_TRUE(errors_.back().contains("odom_frame.ot")) << errors_.back().toStdString();
  EXPECT_TRUE(errors_.back().contains("\"odom\"")) << errors_.back().toStdString();

  const auto garbage = temp_.path() / "not_a_map.ot";
  std::ofstream(garbage) << "hello\n";
  session().openMap(qPath(garbage));
  waitForMap();
  ASSERT_EQ(errors_.size(), 3u);
  EXPECT_TRUE(errors_.back().contains("not_a_map.ot")) << errors_.back().toStdString();

  session().openMap(qPath(temp_.path() / "missing.ot"));
  waitForMap();
  ASSERT_EQ(errors_.size(), 4u);
  EXPECT_TRUE(errors_.back().contains("missing.ot")) << errors_.back().toStdString();

  // The fused map is still the one shown, with its parameters, and the status
  // bar says what it said before the files were read.
  EXPECT_EQ(window_.fusionStatusText(), status);
  EXPECT_TRUE(status.contains("fused")) << status.toStdString();
  EXPECT_EQ(session().worker().snapshot(), before);
  EXPECT_EQ(session().mapGeneration(), generation);
  EXPECT_DOUBLE_EQ(session().fusionOptions().map.resolution, 0.01);
}

TEST_F(OpenMapTest, ADroppedMapIsOpenedForTheSequenceShown) {
  const auto path = writeFinerMap();
  QMimeData mime;
  mime.setUrls({QUrl::fromLocalFile(qPath(path))});
  EXPECT_EQ(SequenceDropHandler::droppedMapPath(&mime), qPath(path));
  EXPECT_EQ(SequenceDropHandler::droppedSequencePath(&mime), QString());
  const auto drop = [&] {
    QDragEnterEvent enter(QPoint(40, 40), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&window_, &enter);
    EXPECT_TRUE(enter.isAccepted());
    QDropEvent dropped(QPointF(40, 40), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&window_, &dropped);
    QTest::qWait(50);
  };
  // Without a sequence: there is nothing to show it for, and the message says so.
  drop();
  ASSERT_EQ(errors_.size(), 1u);
  EXPECT_TRUE(errors_.front().contains("open the sequence it was fused from"))
      << errors_.front().toStdString();
  errors_.clear();

  openAndFuse();
  drop();
  waitForMap();
  EXPECT_TRUE(errors_.empty());
  EXPECT_DOUBLE_EQ(session().worker().snapshot()->resolution, 0.005);
  EXPECT_EQ(session().worker().snapshot()->counts, occupied_);
}

TEST_F(OpenMapTest, OpenMapNeedsASequence) {
  QAction* open_map = window_.findAction("Open Map…");
  ASSERT_NE(open_map, nullptr);
  EXPECT_FALSE(open_map->isEnabled());
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  EXPECT_TRUE(open_map->isEnabled());
}

TEST_F(OpenMapTest, StudioCommandLineShowsAMapInsteadOfFusing) {
  const auto path = writeFinerMap();
  const auto run = [](const QStringList& arguments) {
    QProcess studio;
    studio.start(LOM_STUDIO_PATH, arguments);
    EXPECT_TRUE(studio.waitForFinished(kTimeoutMs));
    return std::make_pair(studio.exitCode(), QString::fromLocal8Bit(studio.readAllStandardError()));
  };
  const auto picture = temp_.path() / "with_map.png";
  const auto [shown, shown_err] =
      run({"--screenshot", qPath(picture), "--map", qPath(path), qPath(folder_)});
  EXPECT_EQ(shown, 0) << shown_err.toStdString();
  EXPECT_TRUE(std::filesystem::exists(picture));

  const auto [missing, missing_err] = run({"--screenshot", qPath(temp_.path() / "x.png"), "--map",
                                           qPath(temp_.path() / "missing.ot"), qPath(folder_)});
  EXPECT_EQ(missing, 1);
  EXPECT_TRUE(missing_err.contains("missing.ot")) << missing_err.toStdString();
  EXPECT_FALSE(std::filesystem::exists(temp_.path() / "x.png"));

  const auto [both, both_err] = run({"--screenshot", qPath(temp_.path() / "x.png"), "--fuse",
                                     "--map", qPath(path), qPath(folder_)});
  EXPECT_EQ(both, 2);
  EXPECT_TRUE(both_err.contains("not both")) << both_err.toStdString();
  const auto [alone, alone_err] = run({"--map", qPath(path)});
  EXPECT_EQ(alone, 2);
  EXPECT_TRUE(alone_err.contains("--map needs the sequence")) << alone_err.toStdString();
}

}  // namespace
}  // namespace lom::ui
