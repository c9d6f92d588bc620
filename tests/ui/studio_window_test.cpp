// The studio window end to end: open, navigate, 3D content, errors, screenshot.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QDialog>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileInfo>
#include <QLabel>
#include <QMimeData>
#include <QPushButton>
#include <QScrollBar>
#include <QSlider>
#include <QStatusBar>
#include <QTableWidget>
#include <QTest>
#include <QUrl>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "lom/annotations.hpp"
#include "lom/import.hpp"
#include "lom/sequence.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/image_pane.hpp"
#include "lom/ui/label_legend.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/sequence_drop_handler.hpp"
#include "lom/ui/shortcuts_help_reaction.hpp"
#include "lom/ui/studio_session.hpp"
#include "lom/ui/window_capture.hpp"
#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

struct ReportedError {
  QString title;
  QString message;
};

class StudioWindowTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tiny_ = test::writeTinySequence(temp_ / "tiny_shelf");
    window_.setErrorReporter([this](const QString& title, const QString& message) {
      errors_.push_back({title, message});
    });
    window_.setMapDiscardQuestion([](const QString&) { return true; });  // see unsaved_map_test.cpp
    window_.resize(1280, 800);
    window_.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&window_));
  }

  bool openTiny() { return window_.controller().openSequence(qPath(tiny_.folder)); }
  static QString qPath(const std::filesystem::path& path) {
    return QString::fromStdString(path.string());
  }
  QAction* menuAction(const QString& text) {
    for (QAction* action : window_.findChildren<QAction*>())
      if (action->text().remove('&') == text) return action;
    return nullptr;
  }

  test::TempDir temp_;
  test::TinySequence tiny_;
  MainWindow window_;
  std::vector<ReportedError> errors_;
};

TEST_F(StudioWindowTest, StartsEmptyWithNavigationDisabled) {
  EXPECT_FALSE(window_.controller().hasSequence());
  EXPECT_EQ(window_.controller().currentFrame(), -1);
  EXPECT_EQ(window_.statusText(), "No sequence open");
  EXPECT_FALSE(window_.timeline().slider().isEnabled());
  ASSERT_NE(menuAction("Next Frame"), nullptr);
  EXPECT_FALSE(menuAction("Next Frame")->isEnabled());
  EXPECT_EQ(window_.sceneView().framePointCount(), 0u);
  window_.controller().stepFrames(1);  // harmless without a sequence
  EXPECT_EQ(window_.controller().currentFrame(), -1);
  // The empty 3D view says how to open a sequence, until one is open; the
  // fusion settings and the legend's buttons have nothing to act on yet.
  EXPECT_TRUE(window_.sceneView().emptyHintShown());
  EXPECT_FALSE(window_.fusionPanel().isEnabled());
  auto* show_only = window_.findChild<QPushButton*>("showOnlyButton");
  ASSERT_NE(show_only, nullptr);
  EXPECT_FALSE(show_only->isEnabled());
  ASSERT_TRUE(openTiny());
  EXPECT_FALSE(window_.sceneView().emptyHintShown());
  EXPECT_TRUE(window_.fusionPanel().isEnabled());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.session().worker().isFusing(); }, 60'000));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return show_only->isEnabled(); }, 5'000));  // the map lists labels
}

// Actions with nothing to act on are disabled until there is something:
// views of the scene until a sequence (or a map) is open, Refresh of the
// objects until the map has voxels, Clear of the segmenter until one is set.
TEST_F(StudioWindowTest, ActionsWithNothingToActOnAreDisabled) {
  for (const char* text :
       {"Reset Camera", "Look from Current Camera", "Zoom to Map", "Look from Above",
        "Look from the Front", "Look from the Side", "Show Frame Points",
        "Show Projection Voxels of This View", "Show Score Breakdown", "Measure Distance"}) {
    ASSERT_NE(menuAction(text), nullptr) << text;
    EXPECT_FALSE(menuAction(text)->isEnabled()) << text;
  }
  // Display settings stay available, for whatever is opened next.
  EXPECT_TRUE(menuAction("Opacity by Probability")->isEnabled());
  EXPECT_TRUE(menuAction("Colour by Height")->isEnabled());
  auto* refresh = window_.findChild<QPushButton*>("refreshObjectsButton");
  auto* clear = window_.findChild<QPushButton*>("clearSegmenterButton");
  ASSERT_NE(refresh, nullptr);
  ASSERT_NE(clear, nullptr);
  EXPECT_FALSE(refresh->isEnabled());
  EXPECT_FALSE(clear->isEnabled());

  ASSERT_TRUE(openTiny());
  for (const char* text : {"Reset Camera", "Look from Current Camera", "Zoom to Map",
                           "Measure Distance", "Show Projection Voxels of This View"})
    EXPECT_TRUE(menuAction(text)->isEnabled()) << text;
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.session().worker().isFusing(); }, 60'000));
  ASSERT_TRUE(QTest::qWaitFor([&] { return refresh->isEnabled(); }, 5'000));
  EXPECT_FALSE(clear->isEnabled());
}

// A message in the status bar takes the frame text's place; the fusion
// indicator stays at the right edge.
TEST_F(StudioWindowTest, TheFusionIndicatorStaysAtTheRightOfTheStatusBar) {
  ASSERT_TRUE(openTiny());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.session().worker().isFusing(); }, 60'000));
  auto* indicator = window_.findChild<QWidget*>("fusionStatus");
  ASSERT_NE(indicator, nullptr);
  // The last frame's text and rate widen the indicator; the status bar lays
  // itself out again an event-loop round later.
  EXPECT_TRUE(QTest::qWaitFor(
      [&] { return indicator->width() >= indicator->minimumSizeHint().width(); }, 5'000))
      << "the indicator is narrower than its text: " << indicator->width() << " < "
      << indicator->minimumSizeHint().width();
  const auto right_edge = [&] {
    return indicator->mapTo(&window_, QPoint(indicator->width(), 0)).x();
  };
  const int before = right_edge();
  const int left_before = indicator->mapTo(&window_, QPoint(0, 0)).x();
  window_.statusBar()->showMessage("Measure: click the first point on the map.");
  QApplication::processEvents();
  QTest::qWait(50);
  EXPECT_NEAR(right_edge(), before, 2);
  EXPECT_NEAR(indicator->mapTo(&window_, QPoint(0, 0)).x(), left_before, 2)
      << "the indicator grew into the message's space";
  EXPECT_GT(before, window_.width() - 40);
}

TEST_F(StudioWindowTest, OpeningSetsTheTimelineAndStatus) {
  ASSERT_TRUE(openTiny());
  EXPECT_TRUE(errors_.empty());
  const QSlider& slider = window_.timeline().slider();
  EXPECT_EQ(slider.maximum() - slider.minimum() + 1, test::kTinyFrames);
  EXPECT_EQ(slider.value(), 0);
  EXPECT_EQ(window_.controller().currentFrame(), 0);
  EXPECT_TRUE(window_.statusText().contains("tiny_shelf")) << window_.statusText().toStdString();
  EXPECT_TRUE(window_.statusText().contains("frame 1 of 3")) << window_.statusText().toStdString();
  EXPECT_TRUE(window_.windowTitle().contains("tiny_shelf"));
  // The tiny sequence's frames are stamped 0.1 s apart.
  EXPECT_TRUE(window_.statusText().contains("t = 0.000 s")) << window_.statusText().toStdString();

  // Frames without a time stamp (a recording that kept none) show no time.
  Sequence unstamped = loadSequence(tiny_.folder);
  for (FrameRecord& frame : unstamped.frames) frame.stamp.reset();
  saveSequence(unstamped, tiny_.folder);
  window_.controller().setDiscardGuard([] { return true; });
  ASSERT_TRUE(openTiny());
  EXPECT_TRUE(window_.statusText().contains("frame 1 of 3")) << window_.statusText().toStdString();
  EXPECT_FALSE(window_.statusText().contains("t =")) << window_.statusText().toStdString();
}

// A folder in the frame-folder layout of many RGB-D tools (frame-NNNNNN.color.png,
// .depth.png in mm, .pose.txt, intrinsics.K.txt) opens like a sequence.
TEST_F(StudioWindowTest, OpensADatasetFolderByConvertingIt) {
  const auto folder = temp_ / "frames_layout";
  test::writeFramesLayout(tiny_, folder);
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder)))
      << (errors_.empty() ? std::string() : errors_.back().message.toStdString());
  EXPECT_TRUE(errors_.empty());
  EXPECT_EQ(window_.controller().frameCount(), test::kTinyFrames);
  // The converted frames carry the same depth, less the pixels at depth edges
  // that the importer's flying-pixel filter drops by default (docs/import.md).
  const size_t original = test::countValidDepth(tiny_.depths[0]);
  EXPECT_LE(window_.sceneView().framePointCount(), original);
  EXPECT_GE(window_.sceneView().framePointCount(), original * 8 / 10);
  // Without label images the sequence has one label: its voxels are coloured by height.
  EXPECT_EQ(window_.controller().sequence().labels.size(), 1);
  ASSERT_NE(menuAction("Colour by Height"), nullptr);
  EXPECT_TRUE(menuAction("Colour by Height")->isChecked());
  EXPECT_EQ(window_.sceneView().voxelColouring(), VoxelColouring::Height);
  // The recording's own files are the sequence's: no output of the studio
  // replaces them (a new file beside them is allowed).
  int recording_files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    ++recording_files;
    EXPECT_FALSE(window_.controller().sequenceFileAt(qPath(entry.path())).isEmpty())
        << entry.path();
  }
  EXPECT_GT(recording_files, 0);
  EXPECT_TRUE(window_.controller().sequenceFileAt(qPath(folder / "new.png")).isEmpty());
  // A labelled sequence opens in label colours.
  window_.controller().setDiscardGuard([] { return true; });
  ASSERT_TRUE(openTiny());
  EXPECT_FALSE(menuAction("Colour by Height")->isChecked());
  EXPECT_EQ(window_.sceneView().voxelColouring(), VoxelColouring::Labels);
}

// A colour image that cannot be read leaves its frame without colour; the
// warning names it on every open, fresh or from the import cache.
TEST_F(StudioWindowTest, ARecordingsUnreadableColourImageIsNamedOnEveryOpen) {
  const auto folder = temp_ / "frames_layout";
  test::writeFramesLayout(tiny_, folder);
  std::string broken;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    if (entry.path().filename().string().find(".color.png") != std::string::npos) {
      broken = entry.path().filename().string();
      std::ofstream(entry.path(), std::ios::trunc) << "";
      break;
    }
  ASSERT_FALSE(broken.empty());
  QStringList warnings;
  window_.setWarningReporter(
      [&](const QString& title, const QString& message) { warnings << title + ": " + message; });
  for (int open = 0; open < 2; ++open) {
    warnings.clear();
    window_.controller().setDiscardGuard([] { return true; });
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder)));
    EXPECT_EQ(window_.controller().frameCount(), test::kTinyFrames) << "no frame left out";
    ASSERT_EQ(warnings.filter("Colour images left out").size(), 1)
        << warnings.join('\n').toStdString();
    EXPECT_TRUE(
        warnings.filter("Colour images left out").front().contains(QString::fromStdString(broken)));
  }
}

// A recorded room without label images, opened with the shelf-bin defaults
// (1 cm voxels, 1 m max range): the Fusion panel offers to reach the room's
// depths with coarser voxels, and the voxels are coloured by height.
TEST_F(StudioWindowTest, RoomBeyondMaxRangeIsMappedByTheOfferedRefuse) {
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  ImportOptions import = window_.controller().importOptions();
  import.intrinsics = parseIntrinsics("518,519,325.5,253.5");
  window_.controller().setImportOptions(import);
  ASSERT_TRUE(window_.controller().openSequence(qPath(test::sharedDataDir() / "kinect-room-5")));
  MapWorker& worker = window_.session().worker();
  auto waitForFusion = [&] {
    ASSERT_TRUE(QTest::qWaitFor([&] { return !worker.isFusing(); }, 120'000));
    QTest::qWait(50);  // the last snapshot and the depth ranges arrive through the event loop
  };
  waitForFusion();
  FusionPanel& panel = window_.fusionPanel();
  ASSERT_FALSE(panel.extendRangeButton().isHidden()) << panel.noteText().toStdString();
  // The note and its button do not make the window too tall for a 1366x768 laptop.
  QTest::qWait(50);
  EXPECT_LE(window_.minimumSizeHint().height(), 700);
  // The room's depths reach about 10 m: rays of 250 voxels are 4 cm ones.
  EXPECT_EQ(panel.extendRangeButton().text(), "Re-fuse up to 10.0 m, 4.0 cm voxels");
  const size_t voxels_before = worker.snapshot()->voxels.size();

  panel.extendRangeButton().click();
  waitForFusion();
  EXPECT_TRUE(panel.extendRangeButton().isHidden());
  EXPECT_DOUBLE_EQ(window_.session().fusionOptions().map.resolution, 0.04);
  EXPECT_DOUBLE_EQ(window_.session().fusionOptions().map.max_range, 10.0);
  EXPECT_GT(worker.snapshot()->voxels.size(), 20 * voxels_before + 1000);
  EXPECT_EQ(window_.sceneView().voxelColouring(), VoxelColouring::Height);
}

// A frame step redraws the 3D view once (software GL takes most of a second
// for a redraw: a second one halved the playback speed).
TEST_F(StudioWindowTest, AFrameStepRedrawsTheViewOnce) {
  ASSERT_TRUE(openTiny());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.session().worker().isFusing(); }, 60000));
  QTest::qWait(300);  // what the fusion's end redraws
  QAction* next = menuAction("Next Frame");
  ASSERT_NE(next, nullptr);
  const size_t before = window_.sceneView().renderCount();
  next->trigger();
  QTest::qWait(300);
  EXPECT_EQ(window_.controller().currentFrame(), 1);
  EXPECT_EQ(window_.sceneView().renderCount(), before + 1);
}

TEST_F(StudioWindowTest, StepsThroughFramesWithActionsAndSlider) {
  ASSERT_TRUE(openTiny());
  QAction* next = menuAction("Next Frame");
  QAction* previous = menuAction("Previous Frame");
  ASSERT_NE(next, nullptr);
  ASSERT_NE(previous, nullptr);
  EXPECT_FALSE(previous->isEnabled());

  next->trigger();
  EXPECT_EQ(window_.controller().currentFrame(), 1);
  EXPECT_EQ(window_.timeline().slider().value(), 1);
  EXPECT_TRUE(window_.statusText().contains("frame 2 of 3")) << window_.statusText().toStdString();
  EXPECT_TRUE(previous->isEnabled());

  window_.timeline().slider().setValue(2);
  EXPECT_EQ(window_.controller().currentFrame(), 2);
  EXPECT_TRUE(window_.statusText().contains("frame 3 of 3"));
  EXPECT_FALSE(next->isEnabled());

  window_.controller().stepFrames(+5);  // clamps at the last frame
  EXPECT_EQ(window_.controller().currentFrame(), 2);
  previous->trigger();
  EXPECT_EQ(window_.controller().currentFrame(), 1);
  EXPECT_TRUE(errors_.empty());

  // Playing stops when another sequence opens: it starts still.
  window_.timeline().setPlaying(true);
  ASSERT_TRUE(window_.timeline().isPlaying());
  ASSERT_TRUE(openTiny());
  EXPECT_FALSE(window_.timeline().isPlaying());
}

// Space plays the frames, but a focused list row, button or field keeps its
// own use of the key (ticking a Map Labels row is the keyboard's way to hide
// a label).
TEST_F(StudioWindowTest, SpaceGoesToAFocusedControlAndPlaysElsewhere) {
  ASSERT_TRUE(openTiny());
  window_.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
  auto* button = new QPushButton("probe", window_.findChild<QDockWidget*>("boxesDock"));
  button->show();
  int clicks = 0;
  QObject::connect(button, &QPushButton::clicked, [&] { ++clicks; });
  button->setFocus();
  ASSERT_TRUE(QTest::qWaitFor([&] { return button->hasFocus(); }, 5000));
  QTest::keyClick(button, Qt::Key_Space);
  QTest::qWait(400);  // a shortcut clicks the play button after its 100 ms animation
  EXPECT_EQ(clicks, 1) << "the focused button is pressed";
  EXPECT_FALSE(window_.timeline().isPlaying());
  delete button;
  window_.sceneView().setFocus();
  ASSERT_TRUE(QTest::qWaitFor([&] { return window_.sceneView().hasFocus(); }, 5000));
  QTest::keyClick(&window_.sceneView(), Qt::Key_Space);
  EXPECT_TRUE(QTest::qWaitFor([&] { return window_.timeline().isPlaying(); }, 2000))
      << "elsewhere (the 3D view) Space plays";
  window_.timeline().setPlaying(false);
}

// The pixel readout under the frame images keeps its height: a readout that
// grew and shrank moved the pictures under the cursor.
TEST_F(StudioWindowTest, ThePixelReadoutKeepsItsHeight) {
  ASSERT_TRUE(openTiny());
  auto* readout = window_.findChild<QLabel*>("pixelReadout");
  ASSERT_NE(readout, nullptr);
  QApplication::processEvents();
  const QRect pane = window_.frameImages().depthPane().geometry();
  const int height = readout->height();
  window_.frameImages().hoverPixel(QPoint(80, 60));
  ASSERT_FALSE(window_.frameImages().readoutText().isEmpty());
  QApplication::processEvents();
  EXPECT_EQ(readout->height(), height);
  EXPECT_EQ(window_.frameImages().depthPane().geometry(), pane);
}

// In a narrow panel or a large font the readout is as high as its wrapped
// text: a fixed two lines cut off the third (the selected label's
// probability).
TEST_F(StudioWindowTest, ThePixelReadoutShowsEveryLineInANarrowPanel) {
  ASSERT_TRUE(openTiny());
  auto* readout = window_.findChild<QLabel*>("pixelReadout");
  ASSERT_NE(readout, nullptr);
  QFont large = readout->font();
  large.setPointSizeF(large.pointSizeF() * 1.5);
  readout->setFont(large);
  window_.frameImages().setFixedWidth(220);
  QApplication::processEvents();
  QTest::qWait(100);
  window_.frameImages().hoverPixel(QPoint(80, 60));
  const QString text = window_.frameImages().readoutText();
  ASSERT_FALSE(text.isEmpty());
  QApplication::processEvents();
  const QRect needed =
      readout->fontMetrics().boundingRect(QRect(0, 0, readout->contentsRect().width(), 1 << 20),
                                          Qt::TextWordWrap | Qt::AlignLeft, text);
  const QFontMetrics metrics = readout->fontMetrics();
  EXPECT_GT(needed.height(), metrics.lineSpacing()) << "wraps: " << text.toStdString();
  EXPECT_GE(readout->contentsRect().height(), needed.height()) << text.toStdString();
  window_.frameImages().setMinimumWidth(0);
  window_.frameImages().setMaximumWidth(QWIDGETSIZE_MAX);
  readout->setFont(QFont());
}

TEST_F(StudioWindowTest, ShortcutListHasTheMenusKeysAndThePlayButtons) {
  const auto* help = window_.findChild<ShortcutsHelpReaction*>();
  ASSERT_NE(help, nullptr);
  const QStringList rows = help->rows();
  for (const char* row : {"F1\tKeyboard Shortcuts", "PgDown\tNext Frame", "Space\tPlay / pause",
                          "Tab\tNext Box", "Shift+Tab\tPrevious Box", "Ctrl+Shift+Z, Ctrl+Y\tRedo",
                          "Ctrl+Tab\tLeave 3D View (Next Field)"})
    EXPECT_TRUE(rows.contains(row)) << row << "\n" << rows.join('\n').toStdString();
  for (const QString& row : rows) EXPECT_FALSE(row.contains("Backtab")) << row.toStdString();
}

// The dialog shows both columns whole: the keys of the longest row left the
// action names cut off in a fixed-width dialog.
TEST_F(StudioWindowTest, ShortcutDialogShowsEveryKeyAndActionWhole) {
  const auto* help = window_.findChild<ShortcutsHelpReaction*>();
  ASSERT_NE(help, nullptr);
  const std::unique_ptr<QDialog> dialog = help->createDialog();
  dialog->show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(dialog.get()));
  QApplication::processEvents();
  auto* table = dialog->findChild<QTableWidget*>();
  ASSERT_NE(table, nullptr);
  EXPECT_EQ(table->horizontalScrollBar()->maximum(), 0) << "a column is cut off";
  const QFontMetrics metrics(table->font());
  for (int row = 0; row < table->rowCount(); ++row)
    for (int column = 0; column < 2; ++column) {
      const QString text = table->item(row, column)->text();
      EXPECT_LE(metrics.horizontalAdvance(text), table->columnWidth(column)) << text.toStdString();
    }
  dialog->close();
}

TEST_F(StudioWindowTest, SceneHasOnePointPerValidDepthPixel) {
  ASSERT_TRUE(openTiny());
  for (int frame = 0; frame < test::kTinyFrames; ++frame) {
    window_.controller().setCurrentFrame(frame);
    const size_t expected = test::countValidDepth(tiny_.depths[static_cast<size_t>(frame)]);
    EXPECT_EQ(window_.sceneView().framePointCount(), expected) << "frame " << frame;
  }
  // The frames differ on purpose, so a stale cloud would be caught above.
  EXPECT_NE(test::countValidDepth(tiny_.depths[0]), test::countValidDepth(tiny_.depths[2]));
}

TEST_F(StudioWindowTest, FramePanesShowColourDepthAndLabels) {
  ASSERT_TRUE(openTiny());
  const FrameImagesView& images = window_.frameImages();
  EXPECT_EQ(images.colorPane().image().size(), QSize(test::kTinyWidth, test::kTinyHeight));
  EXPECT_EQ(images.depthPane().image().size(), QSize(test::kTinyWidth, test::kTinyHeight));
  const QImage& labels = images.labelPane().image();
  ASSERT_EQ(labels.size(), QSize(test::kTinyWidth, test::kTinyHeight));
  // Inside the square the label colour dominates the blend over the colour image.
  const QColor inside = labels.pixelColor(80, 60);
  EXPECT_GT(inside.red(), inside.green());
  EXPECT_GT(inside.blue(), inside.green());

  const auto& legend = images.labelLegend().entries();
  ASSERT_EQ(legend.size(), 2u);
  EXPECT_EQ(legend[0].name, "square_box");
  EXPECT_EQ(legend[0].color, QColor(230, 60, 160));
  EXPECT_EQ(legend[1].name, "blue_cup");
}

TEST_F(StudioWindowTest, BrokenSequenceIsReportedAndTheOpenOneKept) {
  ASSERT_TRUE(openTiny());
  window_.controller().setCurrentFrame(1);

  const auto broken = temp_ / "broken";
  std::filesystem::create_directories(broken);
  std::ofstream(broken / "sequence.json") << R"({"format": "labeloctomap-sequence", "version": 1,
    "camera": {"width": "wide"}, "frames": 7})";
  EXPECT_FALSE(window_.controller().openSequence(qPath(broken)));
  ASSERT_EQ(errors_.size(), 1u);
  EXPECT_TRUE(errors_[0].message.contains("sequence.json")) << errors_[0].message.toStdString();

  EXPECT_FALSE(window_.controller().openSequence(qPath(temp_ / "no_such_folder")));
  ASSERT_EQ(errors_.size(), 2u);
  EXPECT_TRUE(errors_[1].message.contains("no_such_folder")) << errors_[1].message.toStdString();

  EXPECT_EQ(window_.controller().sequenceName(), "tiny_shelf");
  EXPECT_EQ(window_.controller().currentFrame(), 1);
  EXPECT_EQ(window_.timeline().slider().maximum(), test::kTinyFrames - 1);
}

TEST_F(StudioWindowTest, MissingFrameFileIsReportedOnceAndShowsNothing) {
  std::filesystem::remove(tiny_.folder / "depth_1.png");
  ASSERT_TRUE(openTiny());
  // The frame's error, reported once the window shows the frame
  // (recording_open_test.cpp); the fusion stops at it with an error of its own.
  const auto frame_errors = [&] {
    std::vector<ReportedError> found;
    for (const auto& error : errors_)
      if (error.title.startsWith("Cannot load frame")) found.push_back(error);
    return found;
  };
  window_.controller().setCurrentFrame(1);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !frame_errors().empty(); }, 5'000));
  ASSERT_EQ(frame_errors().size(), 1u);
  EXPECT_TRUE(frame_errors()[0].message.contains("depth_1.png"))
      << frame_errors()[0].message.toStdString();
  EXPECT_EQ(window_.controller().currentFrameData(), nullptr);
  EXPECT_EQ(window_.sceneView().framePointCount(), 0u);

  window_.controller().setCurrentFrame(0);
  window_.controller().setCurrentFrame(1);
  QTest::qWait(50);
  EXPECT_EQ(frame_errors().size(), 1u);
}

TEST_F(StudioWindowTest, RememberedAsRecentAndOpenedByDrop) {
  ASSERT_TRUE(openTiny());
  ASSERT_FALSE(window_.recentSequences().paths().isEmpty());
  EXPECT_EQ(std::filesystem::path(window_.recentSequences().paths().front().toStdString()),
            std::filesystem::absolute(tiny_.folder));

  const auto other = test::writeTinySequence(temp_ / "dropped_shelf");
  QMimeData mime;
  mime.setUrls({QUrl::fromLocalFile(qPath(other.folder))});
  QDragEnterEvent enter(QPoint(40, 40), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&window_, &enter);
  EXPECT_TRUE(enter.isAccepted());
  QDropEvent drop(QPointF(40, 40), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&window_, &drop);
  // Opened just after the drop event has been answered.
  EXPECT_TRUE(
      QTest::qWaitFor([&] { return window_.controller().sequenceName() == "dropped_shelf"; }));
  EXPECT_EQ(window_.controller().sequenceName(), "dropped_shelf");
  EXPECT_TRUE(errors_.empty());

  // The same sequence opened by its sequence.json is one entry, first again.
  window_.controller().setDiscardGuard([] { return true; });
  ASSERT_TRUE(window_.controller().openSequence(qPath(tiny_.folder / "sequence.json")));
  const QStringList recent = window_.recentSequences().paths();
  ASSERT_GE(recent.size(), 2);
  EXPECT_EQ(std::filesystem::path(recent.front().toStdString()),
            std::filesystem::canonical(tiny_.folder));
  EXPECT_EQ(recent.count(recent.front()), 1);
  EXPECT_EQ(std::count_if(recent.begin(), recent.end(),
                          [&](const QString& path) {
                            return QFileInfo(path).canonicalFilePath() ==
                                   QFileInfo(qPath(tiny_.folder)).canonicalFilePath();
                          }),
            1)
      << recent.join('\n').toStdString();
}

// The views still show the open sequence's frame while the new one is being
// set up (its boxes choose the label of the heat map before its first frame
// is shown): they must not read the freed sequence then.
TEST_F(StudioWindowTest, OpensASequenceWhoseBoxesChooseAnotherLabel) {
  ASSERT_TRUE(openTiny());
  ASSERT_EQ(window_.session().selectedLabel(), test::kSquareLabel);
  for (int round = 0; round < 3; ++round) {
    const auto other = test::writeTinySequence(temp_ / ("cup_shelf" + std::to_string(round)));
    Annotations boxes;
    GroundTruthBox cup;
    cup.label = 2;
    cup.name = "blue_cup";
    cup.box.center = {0.1, 0.1, 0.6};
    cup.box.size = {0.05, 0.05, 0.05};
    boxes.boxes.push_back(cup);
    saveAnnotations(boxes, other.folder / "annotations.json");
    ASSERT_TRUE(window_.controller().openSequence(qPath(other.folder)));
    EXPECT_EQ(window_.session().selectedLabel(), 2);
    ASSERT_TRUE(openTiny());
    EXPECT_EQ(window_.session().selectedLabel(), test::kSquareLabel);
  }
  EXPECT_TRUE(errors_.empty());
}

// README says ROS bags open like sequences; dropping one must too.
TEST_F(StudioWindowTest, DroppedRosBagIsAccepted) {
  // Whether a drag of `file` onto the window is taken as a sequence.
  const auto accepted = [&](const std::filesystem::path& file) {
    QMimeData mime;
    mime.setUrls({QUrl::fromLocalFile(qPath(file))});
    const bool named = SequenceDropHandler::droppedSequencePath(&mime) == qPath(file);
    QDragEnterEvent enter(QPoint(40, 40), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&window_, &enter);
    EXPECT_EQ(enter.isAccepted(), named) << file;
    return named;
  };
  // A bag; other files are still refused, and so are JSON files that are no
  // sequence (boxes); a sequence.json under another name is one.
  const struct {
    const char* name;
    const char* content;
    bool sequence;
  } files[] = {
      {"recording.bag", "#ROSBAG V2.0\n", true},
      {"notes.txt", "notes\n", false},
      {"annotations.json", "{\"format\": \"labeloctomap-annotations\", \"boxes\": []}\n", false},
      {"shelf-copy.json", "{\n  \"format\": \"labeloctomap-sequence\",\n  \"version\": 1\n}\n",
       true}};
  for (const auto& file : files) {
    std::ofstream(temp_ / file.name) << file.content;
    EXPECT_EQ(accepted(temp_ / file.name), file.sequence) << file.name;
  }
}

bool isNear(QRgb pixel, const Rgb& color, int tolerance) {
  return std::abs(qRed(pixel) - color[0]) <= tolerance &&
         std::abs(qGreen(pixel) - color[1]) <= tolerance &&
         std::abs(qBlue(pixel) - color[2]) <= tolerance;
}

TEST_F(StudioWindowTest, ScreenshotShowsTheLabelledCloud) {
  ASSERT_TRUE(openTiny());
  window_.controller().setCurrentFrame(1);
  const QImage shot = captureWindow(window_, window_.sceneView());
  ASSERT_FALSE(shot.isNull());
  shot.save(LOM_UI_SCREENSHOT_PATH);
  const auto temp_png = temp_ / "shot.png";
  ASSERT_TRUE(shot.save(qPath(temp_png)));
  const QImage reloaded(qPath(temp_png));
  ASSERT_EQ(reloaded.size(), shot.size());

  bool uniform = true;
  for (int y = 0; y < shot.height() && uniform; y += 7)
    for (int x = 0; x < shot.width() && uniform; x += 7)
      uniform = shot.pixel(x, y) == shot.pixel(0, 0);
  EXPECT_FALSE(uniform);

  const QRect scene_area(window_.sceneView().mapTo(&window_, QPoint(0, 0)),
                         window_.sceneView().size());
  ASSERT_TRUE(shot.rect().contains(scene_area));
  size_t label_pixels = 0, dark_pixels = 0;
  for (int y = scene_area.top(); y <= scene_area.bottom(); ++y)
    for (int x = scene_area.left(); x <= scene_area.right(); ++x) {
      const QRgb pixel = shot.pixel(x, y);
      if (isNear(pixel, test::kSquareColor, 12)) ++label_pixels;
      if (qGray(pixel) < 8) ++dark_pixels;
    }
  const auto area = static_cast<size_t>(scene_area.width()) * scene_area.height();
  EXPECT_GT(label_pixels, 200u) << "the labelled square is not visible in the 3D view";
  EXPECT_LT(dark_pixels, area / 2) << "the 3D view is mostly black";
}

}  // namespace
}  // namespace lom::ui
