// What the window says and offers once a recording (a dataset folder the
// studio converts) or a sequence is open: the conversion's warnings on every
// open, file dialogs that start beside the recording rather than in the
// import cache, recordings named in Open Recent by their own names, and a
// frame that cannot be loaded reported once the window shows that frame.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QDir>
#include <QFileDialog>
#include <QMenu>
#include <QPushButton>
#include <QSettings>
#include <QSlider>
#include <QStatusBar>
#include <QTest>
#include <QTimer>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "lom/sequence.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/open_map_reaction.hpp"
#include "lom/ui/recent_sequences.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "lom/ui/timeline_widget.hpp"
#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

namespace fs = std::filesystem;

QString qPath(const fs::path& path) { return QString::fromStdString(path.string()); }

// The tiny sequence as a TUM RGB-D folder (depth.txt, rgb.txt without
// images, groundtruth.txt): a folder name without freiburg1/2/3 gets the
// benchmark's default intrinsics, which the import warns about.
void writeTumLayout(const test::TinySequence& tiny, const fs::path& folder) {
  const Sequence sequence = loadSequence(tiny.folder);
  fs::create_directories(folder / "depth");
  std::ofstream depth_list(folder / "depth.txt");
  std::ofstream truth(folder / "groundtruth.txt");
  truth.precision(17);
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", 100.0 + 0.1 * static_cast<double>(i));
    const std::string name = std::string("depth/") + stamp + ".png";
    writeDepthPng(folder / name, loadFrame(sequence, i).depth, 1.0 / 5000.0);
    depth_list << stamp << " " << name << "\n";
    const Eigen::Isometry3d& pose = sequence.frames[i].T_world_camera;
    const Eigen::Quaterniond q(pose.linear());
    truth << stamp << " " << pose.translation().x() << " " << pose.translation().y() << " "
          << pose.translation().z() << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w()
          << "\n";
  }
  std::ofstream(folder / "rgb.txt") << "# no colour images\n";
}

class RecordingOpenTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tiny_ = test::writeTinySequence(temp_ / "tiny_shelf");
    window_.setErrorReporter([this](const QString& title, const QString& message) {
      errors_ << title + ": " + message;
    });
    window_.setWarningReporter([this](const QString& title, const QString& message) {
      warnings_ << title + ": " + message;
    });
    window_.setRecoveryOffer([](const QString&) { return false; });
    window_.setMapDiscardQuestion([](const QString&) { return true; });  // see unsaved_map_test.cpp
    window_.resize(1280, 800);
    window_.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&window_));
  }

  SequenceController& controller() { return window_.controller(); }

  test::TempDir temp_;
  test::TinySequence tiny_;
  MainWindow window_;
  QStringList errors_;
  QStringList warnings_;
};

// A recording whose conversion warns (the TUM default intrinsics here; a bag
// whose camera pose comes from /tf_static alone, in the core's tests) says so
// on every open, fresh or from the import cache, as `labeloctomap import`
// does; a recording whose conversion has nothing to warn about says nothing.
TEST_F(RecordingOpenTest, AConversionsWarningsAreShownOnEveryOpen) {
  const fs::path tum = temp_ / "tum_room";
  writeTumLayout(tiny_, tum);
  for (int open = 0; open < 2; ++open) {
    SCOPED_TRACE(open == 0 ? "converted" : "from the cache");
    warnings_.clear();
    ASSERT_TRUE(controller().openSequence(qPath(tum))) << errors_.join('\n').toStdString();
    EXPECT_EQ(controller().frameCount(), test::kTinyFrames);
    const QStringList said = warnings_.filter("Check the conversion");
    ASSERT_EQ(said.size(), 1) << warnings_.join('\n').toStdString();
    EXPECT_TRUE(said[0].contains("The conversion of tum_room warns")) << said[0].toStdString();
    EXPECT_TRUE(said[0].contains("the benchmark's default intrinsics fx = fy = 525"))
        << said[0].toStdString();
    EXPECT_TRUE(said[0].contains(QString(kImportNotesFile))) << said[0].toStdString();
    ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
  }
  warnings_.clear();
  const fs::path frames = temp_ / "frames_room";
  test::writeFramesLayout(tiny_, frames);
  ASSERT_TRUE(controller().openSequence(qPath(frames)));
  EXPECT_TRUE(warnings_.filter("Check the conversion").isEmpty())
      << warnings_.join('\n').toStdString();
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
}

// Export report… and Open Map… start beside a converted recording, where the
// user keeps its files, not inside the hidden import cache its sequence is in.
TEST_F(RecordingOpenTest, DialogsForOutputsStartBesideTheRecording) {
  const fs::path recordings = temp_ / "recordings";
  test::writeFramesLayout(tiny_, recordings / "room_frames");
  ASSERT_TRUE(controller().openSequence(qPath(recordings / "room_frames")));
  ASSERT_TRUE(controller().isConverted());
  ASSERT_NE(fs::path(controller().sequence().root).parent_path(), recordings);
  EXPECT_EQ(controller().outputFolder(), qPath(recordings));

  QAction* open_map = window_.findAction("Open Map…");
  ASSERT_NE(open_map, nullptr);
  auto* reaction = open_map->findChild<OpenMapReaction*>();
  ASSERT_NE(reaction, nullptr);
  QString map_folder;
  reaction->setChooser([&](const QString& start) {
    map_folder = start;
    return QString();
  });
  open_map->trigger();
  EXPECT_EQ(map_folder, qPath(recordings));

  // The report's folder dialog, answered by leaving it.
  QString report_folder;
  QTimer answer;
  answer.setInterval(20);
  QObject::connect(&answer, &QTimer::timeout, [&] {
    for (QWidget* widget : QApplication::topLevelWidgets())
      if (auto* dialog = qobject_cast<QFileDialog*>(widget); dialog && dialog->isVisible()) {
        report_folder = dialog->directory().absolutePath();
        QMetaObject::invokeMethod(dialog, "reject", Qt::QueuedConnection);
      }
  });
  answer.start();
  auto& export_button = const_cast<QPushButton&>(window_.evaluationPanel().exportButton());
  emit export_button.clicked();  // whether or not there are scores to export yet
  answer.stop();
  EXPECT_EQ(report_folder, qPath(recordings));

  // A sequence's dialogs start beside its folder, as before.
  ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
  EXPECT_EQ(controller().outputFolder(), qPath(temp_.path()));
}

// A recording converted with --labels (its boxes name those labels) opened
// again without them (Open Recent in a session started on another sequence)
// is converted with the same labels, and the status bar says so; labels
// given for the session take precedence.
TEST_F(RecordingOpenTest, ARecordingOpenedAgainKeepsTheLabelsItWasConvertedWith) {
  const fs::path frames = temp_ / "labelled_room";
  test::writeFramesLayout(tiny_, frames);
  const ImportOptions plain = controller().importOptions();
  auto labelSet = [](const std::vector<std::string>& names) {
    std::vector<LabelInfo> labels;
    for (const std::string& name : names) {
      LabelInfo label;
      label.id = static_cast<int>(labels.size());
      label.name = name;
      label.color = {static_cast<std::uint8_t>(40 * labels.size()), 200, 10};
      labels.push_back(label);
    }
    return LabelSet(labels);
  };
  ImportOptions labelled = plain;
  labelled.labels = labelSet({"__background__", "mug", "bowl"});
  controller().setImportOptions(labelled);
  ASSERT_TRUE(controller().openSequence(qPath(frames))) << errors_.join('\n').toStdString();
  ASSERT_EQ(controller().sequence().labels, *labelled.labels);

  controller().setImportOptions(plain);  // a later session without --labels
  ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
  window_.statusBar()->clearMessage();
  window_.resize(900, window_.height());  // narrower than the note
  QTest::qWait(50);
  ASSERT_TRUE(controller().openSequence(qPath(frames))) << errors_.join('\n').toStdString();
  EXPECT_EQ(controller().sequence().labels, *labelled.labels);
  EXPECT_TRUE(window_.statusBar()->currentMessage().contains(
      "labelled_room was converted with the labels it was converted with before"))
      << window_.statusBar()->currentMessage().toStdString();
  // Wider than the status bar: its whole text is the tooltip.
  const QString note = window_.statusBar()->currentMessage();
  ASSERT_GT(window_.statusBar()->fontMetrics().horizontalAdvance(note),
            window_.statusBar()->width())
      << "the test needs a note wider than the status bar";
  EXPECT_EQ(window_.statusBar()->toolTip(), note);
  window_.statusBar()->showMessage("Short");
  EXPECT_EQ(window_.statusBar()->toolTip(), QString());

  ImportOptions other = plain;
  other.labels = labelSet({"__background__", "cup"});
  controller().setImportOptions(other);
  ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
  ASSERT_TRUE(controller().openSequence(qPath(frames))) << errors_.join('\n').toStdString();
  EXPECT_EQ(controller().sequence().labels, *other.labels);
  controller().setImportOptions(plain);
  ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
  ASSERT_TRUE(controller().openSequence(qPath(frames)));
  EXPECT_EQ(controller().sequence().labels, *other.labels);  // the last conversion's

  // The same recording reached through a symbolic link is the same recording.
  const fs::path link = temp_ / "linked_room";
  fs::create_directory_symlink(frames, link);
  ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
  ASSERT_TRUE(controller().openSequence(qPath(link))) << errors_.join('\n').toStdString();
  EXPECT_EQ(controller().sequence().labels, *other.labels);
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
}

// Open Recent names a bag by its file name (its folder may hold many bags)
// and a sequence by its folder's name, given as the folder or as its
// sequence.json.
TEST_F(RecordingOpenTest, OpenRecentNamesABagByItsFileName) {
  fs::create_directories(temp_ / "bags");
  const fs::path bag = temp_ / "bags" / "kitchen.bag";
  std::ofstream(bag) << "#ROSBAG V2.0\n";
  QSettings().setValue("recentSequences", QStringList{qPath(bag), qPath(tiny_.folder),
                                                      qPath(tiny_.folder / "sequence.json")});
  QMenu* recent = nullptr;
  for (QMenu* menu : window_.findChildren<QMenu*>())
    if (menu->title().remove('&') == "Open Recent") recent = menu;
  ASSERT_NE(recent, nullptr);
  emit recent->aboutToShow();
  QStringList names;
  for (QAction* action : recent->actions())
    if (!action->isSeparator()) names << action->text().remove('&');
  QSettings().remove("recentSequences");
  ASSERT_GE(names.size(), 3) << names.join('\n').toStdString();
  EXPECT_TRUE(names[0].startsWith("1 kitchen.bag  (")) << names[0].toStdString();
  EXPECT_TRUE(names[1].startsWith("2 tiny_shelf  (")) << names[1].toStdString();
  EXPECT_TRUE(names[2].startsWith("3 tiny_shelf  (")) << names[2].toStdString();
}

// A frame whose files cannot be read: while the message box waits for an
// answer, the window already shows that frame (status bar, slider), not the
// one before it, which its frame field no longer names.
TEST_F(RecordingOpenTest, AFrameThatCannotBeLoadedIsReportedOnceTheWindowShowsIt) {
  window_.session().setAutoFuse(false);  // a fusion would stop at the frame too, with its own error
  ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
  const Sequence& sequence = controller().sequence();
  const fs::path depth = sequence.pathOf(sequence.frames[2].depth);
  fs::resize_file(depth, fs::file_size(depth) / 2);
  controller().setCurrentFrame(1);
  const QString status_before = window_.statusText();
  struct Seen {
    QString title;
    int frame = -1;
    int slider = -1;
    QString status;
  };
  std::vector<Seen> seen;
  window_.setErrorReporter([&](const QString& title, const QString&) {
    seen.push_back({title, controller().currentFrame(), window_.timeline().slider().value(),
                    window_.statusText()});
  });
  controller().setCurrentFrame(2);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !seen.empty(); }, 5'000));
  QTest::qWait(50);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].title, "Cannot load frame 3 (frames[2])");
  EXPECT_EQ(seen[0].frame, 2);
  EXPECT_EQ(seen[0].slider, 2);
  EXPECT_NE(seen[0].status, status_before) << seen[0].status.toStdString();
  EXPECT_EQ(seen[0].status, window_.statusText());
  // Reported once, not on every pass over the frame.
  controller().setCurrentFrame(1);
  controller().setCurrentFrame(2);
  QTest::qWait(50);
  EXPECT_EQ(seen.size(), 1u);
}

}  // namespace
}  // namespace lom::ui
