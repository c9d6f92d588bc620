// The boxes' files: an unreadable annotations.json is never overwritten
// unasked, the boxes of a converted recording outlive its import cache entry,
// recovery files follow the sequence (however its path is typed) and the
// state of the boxes in memory, unknown labels are reported, and a replaced
// file keeps its permissions.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <QAction>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QImage>
#include <QOpenGLWidget>
#include <QProcess>
#include <QStandardPaths>
#include <QStatusBar>
#include <QSysInfo>
#include <QTest>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "dialog_answerer.hpp"
#include "lom/annotations.hpp"
#include "lom/ui/annotation_files.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/box_file_reaction.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/save_screenshot_reaction.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

namespace fs = std::filesystem;

QString qPath(const fs::path& path) { return QString::fromStdString(path.string()); }

using lom::test::slurp;

GroundTruthBox boxOf(int label, const std::string& name) {
  GroundTruthBox box;
  box.label = label;
  box.name = name;
  box.box.center = {0.1, 0.0, 0.6};
  box.box.size = {0.05, 0.05, 0.05};
  return box;
}

// Opens `path` in `window` and waits for the offer of its unsaved boxes,
// which comes once the switch to it has finished.
bool openInto(MainWindow& window, const QString& path) {
  const bool opened = window.controller().openSequence(path);
  EXPECT_TRUE(QTest::qWaitFor([&] { return !window.autosave().isOfferPending(); }, 10'000));
  return opened;
}

class BoxFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tiny_ = lom::test::writeTinySequence(temp_ / "tiny_shelf");
    window_.setErrorReporter([this](const QString& title, const QString& message) {
      errors_ << title + ": " + message;
    });
    window_.setWarningReporter([this](const QString& title, const QString& message) {
      warnings_ << title + ": " + message;
    });
    window_.setRecoveryOffer([this](const QString& file) {
      offered_ << file;
      return accept_offer_;
    });
    window_.setMapDiscardQuestion([](const QString&) { return true; });  // see unsaved_map_test.cpp
    window_.session().setAutoFuse(false);
    window_.resize(1280, 800);
    window_.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&window_));
  }
  void TearDown() override { boxes().undoStack().setClean(); }

  AnnotationsModel& boxes() { return window_.session().annotations(); }
  // Another studio: a live process that holds the lock of `recovery` (as
  // QLockFile writes it: pid, program, host).
  static bool holdInAnotherProcess(const QString& recovery, QProcess& other) {
    QDir().mkpath(QFileInfo(recovery).path());
    other.start("sleep", {"60"});
    if (!other.waitForStarted()) return false;
    QFile lock(recovery + ".lock");
    if (!lock.open(QIODevice::WriteOnly)) return false;
    lock.write(QByteArray::number(other.processId()) + "\n/usr/bin/sleep\n" +
               QSysInfo::machineHostName().toUtf8() + "\n");
    return true;
  }
  // Another program writes one box (label 3) to `file`; returns its bytes.
  static std::string writeTheirBoxes(const fs::path& file) {
    Annotations theirs;
    theirs.boxes.push_back(boxOf(3, "red_mug"));
    saveAnnotations(theirs, file);
    return slurp(file);
  }
  bool open(const fs::path& path) { return openInto(window_, qPath(path)); }

  lom::test::TempDir temp_;
  lom::test::TinySequence tiny_;
  MainWindow window_;
  QStringList errors_;
  QStringList warnings_;
  QStringList offered_;
  bool accept_offer_ = false;
};

TEST_F(BoxFilesTest, UnreadableBoxesFileIsOnlyReplacedAfterAnExplicitConfirmation) {
  const fs::path file = tiny_.folder / "annotations.json";
  std::ofstream(file) << "{\"format\": \"labeloctomap-annotations\", \"boxes\": [ {\"label\": ";
  const std::string before = slurp(file);
  ASSERT_TRUE(open(tiny_.folder));
  ASSERT_FALSE(errors_.isEmpty());
  EXPECT_TRUE(errors_.front().contains("annotations.json")) << errors_.front().toStdString();
  EXPECT_EQ(boxes().boxCount(), 0);
  EXPECT_EQ(QFileInfo(boxes().unreadablePath()), QFileInfo(qPath(file)));
  boxes().addBox(boxOf(1, "square_box"));
  QAction* save = window_.findAction("Save Boxes");
  ASSERT_NE(save, nullptr);

  {  // Ctrl+S asks, naming the file and why it could not be read; Cancel keeps it.
    test::DialogAnswerer answer("Cancel");
    save->trigger();
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions.front().contains(QDir::toNativeSeparators(qPath(file))));
    EXPECT_TRUE(answer.questions.front().contains(boxes().unreadableError()));
    EXPECT_FALSE(boxes().unreadableError().isEmpty());
  }
  EXPECT_EQ(slurp(file), before);
  EXPECT_TRUE(boxes().isDirty());

  {  // Save As… proposes a free name beside it; the unreadable file stays as it was.
    test::DialogAnswerer answer("Save As", qPath(tiny_.folder / "annotations-2.json"));
    save->trigger();
    ASSERT_EQ(answer.proposed_files.size(), 1);
    EXPECT_EQ(QFileInfo(answer.proposed_files.front()).fileName(), "annotations-2.json");
  }
  EXPECT_EQ(slurp(file), before);
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(loadAnnotations(tiny_.folder / "annotations-2.json").boxes.size(), 1u);

  // Later saves go to the new file without asking.
  boxes().addBox(boxOf(2, "blue_cup"));
  {
    test::DialogAnswerer answer("Cancel");
    save->trigger();
    EXPECT_TRUE(answer.questions.isEmpty());
  }
  EXPECT_EQ(slurp(file), before);
  EXPECT_EQ(loadAnnotations(tiny_.folder / "annotations-2.json").boxes.size(), 2u);

  // Choosing the unreadable file in Save Boxes As… still asks.
  auto* save_as = window_.findAction("Save Boxes As…")->findChild<BoxFileReaction*>();
  ASSERT_NE(save_as, nullptr);
  {
    test::DialogAnswerer answer("Cancel");
    save_as->saveTo(qPath(file));
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions.front().contains(boxes().unreadableError()));
  }
  EXPECT_EQ(slurp(file), before);
}

// The name chosen through the question's Save As… is checked like any other:
// the sequence's own files are never written.
TEST_F(BoxFilesTest, SaveAsFromTheUnreadableFileQuestionNeverWritesASequenceFile) {
  const fs::path file = tiny_.folder / "annotations.json";
  std::ofstream(file) << "not json at all";
  const fs::path sequence_json = tiny_.folder / "sequence.json";
  const std::string sequence_before = slurp(sequence_json);
  ASSERT_TRUE(open(tiny_.folder));
  errors_.clear();
  boxes().addBox(boxOf(1, "square_box"));
  {  // "Yes": the file dialog's own question about replacing an existing file.
    test::DialogAnswerer answer("Save As|Yes", qPath(sequence_json));
    window_.findAction("Save Boxes")->trigger();
    ASSERT_EQ(answer.proposed_files.size(), 1);
  }
  EXPECT_EQ(slurp(sequence_json), sequence_before);
  EXPECT_TRUE(boxes().isDirty());
  ASSERT_EQ(errors_.size(), 1);
  EXPECT_TRUE(errors_.front().contains("is a file of the sequence"))
      << errors_.front().toStdString();
}

TEST_F(BoxFilesTest, UnreadableBoxesFileStaysProtectedAfterAYamlImport) {
  const fs::path file = tiny_.folder / "annotations.json";
  std::ofstream(file) << "not json at all";
  const std::string before = slurp(file);
  ASSERT_TRUE(open(tiny_.folder));
  std::ofstream(temp_ / "boxes.yaml")
      << "boxes:\n  - dimensions: [0.05, 0.05, 0.05]\n    position: [0.1, 0.0, 0.6]\n"
         "    orientation: [0, 0, 0, 1]\n    name: object_1\n";
  ASSERT_TRUE(importYamlBoxes(window_.session(), qPath(temp_ / "boxes.yaml")).isEmpty());
  ASSERT_EQ(boxes().boxCount(), 1);
  {  // Ctrl+S still asks before replacing the file that could not be read.
    test::DialogAnswerer answer("Cancel");
    window_.findAction("Save Boxes")->trigger();
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions.front().contains(boxes().unreadableError()));
  }
  EXPECT_EQ(slurp(file), before);
}

TEST_F(BoxFilesTest, NeitherBoxesNorScreenshotsAreSavedOverTheSequencesFiles) {
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(1, "square_box"));
  const std::string sequence_json = slurp(tiny_.folder / "sequence.json");
  auto* save_as = window_.findAction("Save Boxes As…")->findChild<BoxFileReaction*>();
  ASSERT_NE(save_as, nullptr);
  save_as->saveTo(qPath(tiny_.folder / "." / "sequence.json"));  // under another name too
  ASSERT_EQ(errors_.size(), 1);
  EXPECT_TRUE(errors_.front().contains("is a file of the sequence"))
      << errors_.front().toStdString();
  EXPECT_EQ(slurp(tiny_.folder / "sequence.json"), sequence_json);
  EXPECT_TRUE(boxes().isDirty());

  // Nor over another sequence's files: its sequence.json, its boxes, its frames.
  const fs::path other = temp_ / "other_sequence";
  lom::test::writeTinySequence(other);
  std::ofstream(other / "annotations.json") << "{}";
  for (const fs::path& file :
       {other / "sequence.json", other / "annotations.json", other / "color_0.png"}) {
    errors_.clear();
    const std::string kept = slurp(file);
    save_as->saveTo(qPath(file));
    ASSERT_EQ(errors_.size(), 1) << file;
    EXPECT_TRUE(errors_.front().contains("is a file of the sequence"))
        << errors_.front().toStdString();
    EXPECT_EQ(slurp(file), kept) << file;
  }
  EXPECT_TRUE(boxes().isDirty());
  // The open sequence's own boxes file is where they are saved.
  errors_.clear();
  save_as->saveTo(qPath(tiny_.folder / "annotations.json"));
  EXPECT_TRUE(errors_.empty()) << errors_.front().toStdString();
  EXPECT_FALSE(boxes().isDirty());
  boxes().addBox(boxOf(1, "square_box"));
  errors_.clear();

  // A frame's colour image is a PNG, as a screenshot is.
  auto* screenshot = window_.findAction("Save Screenshot…")->findChild<SaveScreenshotReaction*>();
  ASSERT_NE(screenshot, nullptr);
  const fs::path colour = tiny_.folder / "color_0.png";
  ASSERT_TRUE(fs::exists(colour));
  const std::string pixels = slurp(colour);
  EXPECT_TRUE(screenshot->saveTo(qPath(colour)).contains("is a file of the sequence"));
  EXPECT_EQ(slurp(colour), pixels);
  // Another sequence's colour image too.
  EXPECT_TRUE(
      screenshot->saveTo(qPath(other / "color_0.png")).contains("is a file of the sequence"));
  // Anywhere else the picture is written.
  EXPECT_TRUE(screenshot->saveTo(qPath(temp_ / "window.png")).isEmpty());
  EXPECT_TRUE(fs::exists(temp_ / "window.png"));

  // The 3D view alone: the same rules, a picture the size of the view.
  auto* view = window_.findAction("Save 3D View…")->findChild<SaveScreenshotReaction*>();
  ASSERT_NE(view, nullptr);
  EXPECT_TRUE(view->saveTo(qPath(colour)).contains("is a file of the sequence"));
  EXPECT_EQ(slurp(colour), pixels);
  ASSERT_TRUE(view->saveTo(qPath(temp_ / "view.png")).isEmpty());
  const QImage window_picture(qPath(temp_ / "window.png")), view_picture(qPath(temp_ / "view.png"));
  // The view's drawing, inside its focus frame.
  const QWidget* drawing = window_.sceneView().findChild<QOpenGLWidget*>();
  ASSERT_NE(drawing, nullptr);
  const qreal ratio = drawing->devicePixelRatioF();
  EXPECT_EQ(view_picture.size(), drawing->size() * ratio);
  EXPECT_LT(view_picture.width(), window_picture.width());
  // What the window's picture shows where the 3D view is.
  const QPoint corner = drawing->mapTo(&window_, QPoint(0, 0)) * ratio;
  for (const QPoint at :
       {QPoint(5, 5), QPoint(view_picture.width() / 2, view_picture.height() / 2)})
    EXPECT_EQ(view_picture.pixel(at), window_picture.pixel(corner + at)) << at.x() << "," << at.y();
}

TEST_F(BoxFilesTest, UnreadableBoxesFileIsReplacedWhenTheUserConfirms) {
  const fs::path file = tiny_.folder / "annotations.json";
  std::ofstream(file) << "not json at all";
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(1, "square_box"));
  test::DialogAnswerer answer("Overwrite");
  window_.findAction("Save Boxes")->trigger();
  EXPECT_EQ(answer.questions.size(), 1);
  EXPECT_EQ(loadAnnotations(file).boxes.size(), 1u);
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_TRUE(boxes().unreadablePath().isEmpty());
}

// The import cache entry of a recording is rebuilt whenever a file of the
// recording that its import reads changes; its boxes must not go with it.
TEST_F(BoxFilesTest, BoxesOfAConvertedRecordingSurviveAChangeOfItsFolder) {
  const fs::path source = temp_ / "frames_layout";
  lom::test::writeFramesLayout(tiny_, source);
  ASSERT_TRUE(open(source)) << errors_.join('\n').toStdString();
  ASSERT_TRUE(window_.controller().isConverted());
  const fs::path first_cache = window_.session().sequence()->root;
  boxes().addBox(boxOf(1, "square_box"));
  window_.findAction("Save Boxes")->trigger();
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
  ASSERT_FALSE(boxes().isDirty());
  const QString saved = boxes().path();
  EXPECT_FALSE(saved.startsWith(qPath(first_cache))) << saved.toStdString();
  EXPECT_TRUE(saved.startsWith(QStandardPaths::writableLocation(QStandardPaths::AppDataLocation)))
      << saved.toStdString();

  // A file the import reads is written again (the same camera matrix).
  std::ofstream(source / "intrinsics.K.txt", std::ios::app) << "\n";
  ASSERT_TRUE(open(source));
  EXPECT_NE(window_.session().sequence()->root, first_cache);  // a new cache entry
  EXPECT_EQ(boxes().boxCount(), 1);
  EXPECT_EQ(boxes().path(), saved);
  // Opened by another spelling of its path, it is the same recording.
  ASSERT_TRUE(open(fs::path(qPath(source).toStdString() + "/")));
  EXPECT_EQ(boxes().boxCount(), 1);
}

TEST_F(BoxFilesTest, BoxesInTheImportCacheMoveToTheStudiosOwnFolder) {
  const fs::path source = temp_ / "frames_layout";
  lom::test::writeFramesLayout(tiny_, source);
  ASSERT_TRUE(open(source));
  // Where boxes of converted recordings used to be saved.
  const fs::path legacy = window_.session().sequence()->root / "annotations.json";
  Annotations old;
  old.boxes.push_back(boxOf(2, "blue_cup"));
  saveAnnotations(old, legacy);

  ASSERT_TRUE(open(source));
  ASSERT_EQ(boxes().boxCount(), 1);
  EXPECT_EQ(boxes().box(0).label, 2);
  const QString durable = perSourceFile("annotations", qPath(source));
  EXPECT_TRUE(durable.startsWith(QStandardPaths::writableLocation(QStandardPaths::AppDataLocation)))
      << durable.toStdString();
  EXPECT_EQ(boxesFileOf(window_.controller()), durable);
  EXPECT_EQ(boxes().path(), durable);
  ASSERT_TRUE(QFileInfo::exists(durable));
  EXPECT_EQ(loadAnnotations(durable.toStdString()).boxes.size(), 1u);
  EXPECT_TRUE(fs::exists(legacy));  // copied, not moved: nothing is lost if the copy is
}

TEST_F(BoxFilesTest, RecoveryFileDoesNotDependOnHowThePathIsTyped) {
  const QString folder = qPath(tiny_.folder);
  const QString expected = BoxesAutosave::recoveryPath(folder);
  EXPECT_TRUE(QFileInfo(expected).fileName().startsWith("tiny_shelf-")) << expected.toStdString();
  EXPECT_EQ(BoxesAutosave::recoveryPath(folder + "/"), expected);
  EXPECT_EQ(BoxesAutosave::recoveryPath(folder + "/sequence.json"), expected);
  EXPECT_EQ(BoxesAutosave::recoveryPath(folder + "/../tiny_shelf/."), expected);
  const fs::path link = temp_ / "linked_shelf";
  fs::create_directory_symlink(tiny_.folder, link);
  EXPECT_EQ(BoxesAutosave::recoveryPath(qPath(link)), expected);

  // Unsaved boxes of the folder opened with a trailing slash are offered back
  // when it is opened through its sequence.json.
  ASSERT_TRUE(window_.controller().openSequence(folder + "/"));
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  ASSERT_TRUE(QFileInfo::exists(expected));
  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  QStringList offered;
  next.setRecoveryOffer([&](const QString& file) {
    offered << file;
    return false;
  });
  next.session().setAutoFuse(false);
  ASSERT_TRUE(openInto(next, folder + "/sequence.json"));
  EXPECT_EQ(offered, QStringList{expected});
}

// Boxes opened from another file, restored after the studio was killed, are
// saved to that file again, not over the sequence's own annotations.json.
TEST_F(BoxFilesTest, RestoredBoxesAreSavedWhereTheyCameFrom) {
  Annotations own;
  own.boxes.push_back(boxOf(2, "blue_cup"));
  saveAnnotations(own, tiny_.folder / "annotations.json");
  const std::string own_before = slurp(tiny_.folder / "annotations.json");
  Annotations other;
  other.boxes.push_back(boxOf(1, "square_box"));
  saveAnnotations(other, temp_ / "other.json");
  ASSERT_TRUE(open(tiny_.folder));
  ASSERT_EQ(loadBoxes(window_.session(), qPath(temp_ / "other.json")), QString());
  GroundTruthBox moved = boxes().box(0);
  moved.box.center.x() += 0.01;
  boxes().setBox(0, moved, "Edit box");
  window_.autosave().writeNow();
  ASSERT_TRUE(QFileInfo::exists(window_.autosave().currentRecoveryPath()));

  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  next.setWarningReporter([](const QString&, const QString&) {});
  next.setRecoveryOffer([](const QString&) { return true; });
  next.session().setAutoFuse(false);
  ASSERT_TRUE(openInto(next, qPath(tiny_.folder)));
  AnnotationsModel& restored = next.session().annotations();
  ASSERT_EQ(restored.boxCount(), 1);
  EXPECT_TRUE(restored.isDirty());
  EXPECT_EQ(QFileInfo(restored.path()), QFileInfo(qPath(temp_ / "other.json")));
  next.findAction("Save Boxes")->trigger();
  EXPECT_FALSE(restored.isDirty());
  EXPECT_EQ(slurp(tiny_.folder / "annotations.json"), own_before);
  const Annotations saved = loadAnnotations(temp_ / "other.json");
  ASSERT_EQ(saved.boxes.size(), 1u);
  EXPECT_DOUBLE_EQ(saved.boxes.front().box.center.x(), moved.box.center.x());
}

// Boxes opened from beside another sequence's sequence.json are that
// sequence's ground truth: they become this sequence's unsaved boxes, and
// Save Boxes writes this sequence's file, never theirs.
TEST_F(BoxFilesTest, BoxesOfAnotherSequenceAreSavedAsThisSequencesBoxes) {
  const lom::test::TinySequence other = lom::test::writeTinySequence(temp_ / "other_shelf");
  Annotations theirs;
  theirs.boxes.push_back(boxOf(1, "square_box"));
  saveAnnotations(theirs, other.folder / "annotations.json");
  const std::string theirs_before = slurp(other.folder / "annotations.json");
  ASSERT_TRUE(open(tiny_.folder));
  warnings_.clear();
  ASSERT_EQ(loadBoxes(window_.session(), qPath(other.folder / "annotations.json")), QString());
  ASSERT_EQ(boxes().boxCount(), 1);
  EXPECT_TRUE(boxes().isDirty());
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join('\n').toStdString();
  EXPECT_TRUE(warnings_.front().contains("Boxes of another sequence"))
      << warnings_.front().toStdString();
  GroundTruthBox moved = boxes().box(0);
  moved.box.center.x() += 0.01;
  boxes().setBox(0, moved, "Edit box");
  window_.findAction("Save Boxes")->trigger();
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(slurp(other.folder / "annotations.json"), theirs_before);
  const Annotations saved = loadAnnotations(tiny_.folder / "annotations.json");
  ASSERT_EQ(saved.boxes.size(), 1u);
  EXPECT_DOUBLE_EQ(saved.boxes.front().box.center.x(), moved.box.center.x());

  // A file of this sequence's own folder is edited in place, as before.
  ASSERT_EQ(loadBoxes(window_.session(), qPath(tiny_.folder / "annotations.json")), QString());
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(QFileInfo(boxes().path()), QFileInfo(qPath(tiny_.folder / "annotations.json")));
}

// A recovery file that cannot be read is named in a message and kept aside,
// not dropped without a word after the user asked to restore it.
TEST_F(BoxFilesTest, AnUnreadableRecoveryFileIsReportedAndKept) {
  const QString recovery = BoxesAutosave::recoveryPath(qPath(tiny_.folder));
  QDir().mkpath(QFileInfo(recovery).path());
  {
    QFile file(recovery);
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
    file.write(
        "{\"format\": \"labeloctomap-annotations\", \"boxes\": [{\"label\": 1, "
        "\"center\": [0.1, 0.2]}]}");
  }
  accept_offer_ = true;
  ASSERT_TRUE(open(tiny_.folder));
  EXPECT_EQ(offered_.size(), 1);
  ASSERT_FALSE(warnings_.isEmpty());
  EXPECT_TRUE(warnings_.back().startsWith("Boxes not restored")) << warnings_.back().toStdString();
  EXPECT_TRUE(warnings_.back().contains(recovery + ".unreadable"))
      << warnings_.back().toStdString();
  EXPECT_FALSE(QFileInfo::exists(recovery));
  EXPECT_TRUE(QFileInfo::exists(recovery + ".unreadable"));
  EXPECT_FALSE(boxes().isDirty());
  QFile::remove(recovery + ".unreadable");
}

// A box file opened with the item for the other kind says which item reads it.
TEST_F(BoxFilesTest, ABoxFileOfTheOtherKindNamesTheItemThatReadsIt) {
  ASSERT_TRUE(open(tiny_.folder));
  const fs::path yaml = temp_ / "boxes.yaml";
  std::ofstream(yaml) << "- name: object_1\n  center: [0.1, 0.0, 0.6]\n";
  Annotations json_boxes;
  json_boxes.boxes.push_back(boxOf(1, "square_box"));
  saveAnnotations(json_boxes, temp_ / "boxes.json");
  const QString yaml_error = loadBoxes(window_.session(), qPath(yaml));
  EXPECT_TRUE(yaml_error.contains("read with File ▸ Import YAML Boxes"))
      << yaml_error.toStdString();
  const QString json_error = importYamlBoxes(window_.session(), qPath(temp_ / "boxes.json"));
  EXPECT_TRUE(json_error.contains("read with File ▸ Open Boxes")) << json_error.toStdString();
  // Files of the right kind that are broken get no such hint.
  std::ofstream(temp_ / "broken.json") << "{";
  EXPECT_FALSE(loadBoxes(window_.session(), qPath(temp_ / "broken.json")).contains("▸"));
}

TEST_F(BoxFilesTest, RecoveryFileGoesWhenTheBoxesAreCleanAgain) {
  ASSERT_TRUE(open(tiny_.folder));
  const QString recovery = window_.autosave().currentRecoveryPath();
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  ASSERT_TRUE(QFileInfo::exists(recovery));
  boxes().undoStack().undo();  // back to the saved state
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_FALSE(QFileInfo::exists(recovery));

  // Open Boxes… replaces the unsaved boxes: their recovery file goes too.
  Annotations other;
  other.boxes.push_back(boxOf(2, "blue_cup"));
  saveAnnotations(other, temp_ / "other.json");
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  ASSERT_TRUE(QFileInfo::exists(recovery));
  {
    test::DialogAnswerer answer("Discard", qPath(temp_ / "other.json"));
    window_.findAction("Open Boxes…")->trigger();
    EXPECT_EQ(answer.questions.size(), 1);
  }
  ASSERT_EQ(boxes().boxCount(), 1);
  EXPECT_EQ(boxes().box(0).label, 2);
  EXPECT_FALSE(QFileInfo::exists(recovery));

  // Nothing stale is offered when the sequence opens again.
  accept_offer_ = true;
  ASSERT_TRUE(open(tiny_.folder));
  EXPECT_TRUE(offered_.isEmpty()) << offered_.join(", ").toStdString();
}

// A recovery copy that cannot be written (a full disk; here a folder in its
// place) is said once, not at every retry; once a copy is written again, a
// later failure is said again.
TEST_F(BoxFilesTest, ARecoveryCopyThatCannotBeWrittenIsSaidOnce) {
  ASSERT_TRUE(open(tiny_.folder));
  const QString recovery = window_.autosave().currentRecoveryPath();
  ASSERT_FALSE(recovery.isEmpty());
  ASSERT_TRUE(QDir().mkpath(recovery));
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join("\n").toStdString();
  EXPECT_TRUE(warnings_.front().startsWith("Unsaved boxes not backed up: "))
      << warnings_.front().toStdString();
  EXPECT_TRUE(warnings_.front().contains(recovery)) << warnings_.front().toStdString();
  window_.autosave().writeNow();
  EXPECT_EQ(warnings_.size(), 1);
  ASSERT_TRUE(QDir(recovery).removeRecursively());
  window_.autosave().writeNow();
  EXPECT_TRUE(QFileInfo(recovery).isFile());
  EXPECT_EQ(warnings_.size(), 1);
  ASSERT_TRUE(QFile::remove(recovery));
  ASSERT_TRUE(QDir().mkpath(recovery));
  boxes().addBox(boxOf(2, "blue_cup"));
  window_.autosave().writeNow();
  EXPECT_EQ(warnings_.size(), 2);
  ASSERT_TRUE(QDir(recovery).removeRecursively());
}

TEST_F(BoxFilesTest, RecoveryFileStaysWhenTheOtherSequenceFailsToOpen) {
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  const QString recovery = window_.autosave().currentRecoveryPath();
  ASSERT_TRUE(QFileInfo::exists(recovery));
  {
    // Said before the unsaved boxes are asked about: nothing to discard them for.
    test::DialogAnswerer answer("Discard");
    EXPECT_FALSE(open(temp_ / "no_such_sequence"));
    EXPECT_TRUE(answer.questions.isEmpty()) << answer.questions.join('\n').toStdString();
    EXPECT_EQ(errors_.size(), 1);
  }
  EXPECT_TRUE(boxes().isDirty());  // still the boxes being worked on
  EXPECT_TRUE(QFileInfo::exists(recovery));

  // Once another sequence has really replaced them, their recovery file goes.
  const auto other = lom::test::writeTinySequence(temp_ / "other_shelf");
  {
    test::DialogAnswerer answer("Discard");
    ASSERT_TRUE(open(other.folder));
  }
  EXPECT_FALSE(QFileInfo::exists(recovery));
}

TEST_F(BoxFilesTest, BoxesWithUnknownLabelsAreReportedByFileAndIndex) {
  Annotations annotations;
  annotations.boxes.push_back(boxOf(1, "square_box"));
  annotations.boxes.push_back(boxOf(999, "mystery"));
  saveAnnotations(annotations, tiny_.folder / "annotations.json");
  ASSERT_TRUE(open(tiny_.folder));
  EXPECT_EQ(boxes().boxCount(), 2);  // kept, so they can be fixed
  // A warning, not an error: the sequence and the other boxes are usable.
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join('\n').toStdString();
  EXPECT_TRUE(warnings_.front().contains("annotations.json")) << warnings_.front().toStdString();
  EXPECT_TRUE(warnings_.front().contains("boxes[1]")) << warnings_.front().toStdString();
  EXPECT_TRUE(warnings_.front().contains("999")) << warnings_.front().toStdString();

  warnings_.clear();
  saveAnnotations(annotations, temp_ / "other.json");
  EXPECT_EQ(loadBoxes(window_.session(), qPath(temp_ / "other.json")), QString());
  ASSERT_EQ(warnings_.size(), 1);
  EXPECT_TRUE(warnings_.front().contains("other.json: boxes[1]"))
      << warnings_.front().toStdString();

  // A box of the background is no object either (score refuses it); saving
  // such boxes keeps them and says at once that score will refuse the file.
  annotations.boxes.push_back(boxOf(0, "__background__"));
  saveAnnotations(annotations, tiny_.folder / "annotations.json");
  warnings_.clear();
  ASSERT_TRUE(open(tiny_.folder));
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join('\n').toStdString();
  EXPECT_TRUE(warnings_.front().contains("boxes[2]: label 0 is the background, not an object"))
      << warnings_.front().toStdString();
  warnings_.clear();
  GroundTruthBox moved = boxes().box(0);
  moved.box.center.x() += 0.01;
  boxes().setBox(0, moved, "move");  // something to save
  window_.findAction("Save Boxes")->trigger();
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(loadAnnotations(tiny_.folder / "annotations.json").boxes.size(), 3u);
  ASSERT_EQ(warnings_.filter("Saved with labels the sequence lacks").size(), 1)
      << warnings_.join('\n').toStdString();
  EXPECT_TRUE(warnings_.front().contains("`labeloctomap score` refuses the file"))
      << warnings_.front().toStdString();
  EXPECT_TRUE(warnings_.front().contains("boxes[1]: label 999")) << warnings_.front().toStdString();
}

// Restoring a recovery copy of boxes whose unknown labels were just reported
// (the file's own) says nothing new; labels the file did not have are reported.
TEST_F(BoxFilesTest, RestoredBoxesRepeatNoWarningTheirFileAlreadyGave) {
  Annotations annotations;
  annotations.frame_id = "base";
  annotations.boxes.push_back(boxOf(1, "square_box"));
  annotations.boxes.push_back(boxOf(999, "mystery"));
  saveAnnotations(annotations, tiny_.folder / "annotations.json");
  ASSERT_TRUE(open(tiny_.folder));
  GroundTruthBox moved = boxes().box(0);
  moved.box.center.x() += 0.01;
  boxes().setBox(0, moved, "Edit box");
  window_.autosave().writeNow();
  ASSERT_TRUE(QFileInfo::exists(window_.autosave().currentRecoveryPath()));

  const auto reopen = [&](QStringList& seen) {
    auto next = std::make_unique<MainWindow>();
    next->setErrorReporter([](const QString&, const QString&) {});
    next->setWarningReporter(
        [&seen](const QString& title, const QString& message) { seen << title + ": " + message; });
    next->setRecoveryOffer([](const QString&) { return true; });
    next->setMapDiscardQuestion([](const QString&) { return true; });
    next->session().setAutoFuse(false);
    EXPECT_TRUE(openInto(*next, qPath(tiny_.folder)));
    EXPECT_EQ(next->session().annotations().boxCount(), static_cast<int>(annotations.boxes.size()));
    EXPECT_TRUE(next->session().annotations().isDirty());
    return next;
  };
  {
    QStringList seen;
    auto next = reopen(seen);
    EXPECT_EQ(seen.filter("Boxes with unknown labels").size(), 1) << seen.join('\n').toStdString();
    EXPECT_EQ(seen.filter("Boxes in another frame").size(), 1) << seen.join('\n').toStdString();
    next->session().annotations().undoStack().setClean();
  }

  // A label the file does not have, added since: the restored boxes say so.
  boxes().addBox(boxOf(777, "stranger"));
  window_.autosave().writeNow();
  annotations.boxes.push_back(boxOf(777, "stranger"));
  QStringList seen;
  auto next = reopen(seen);
  const QStringList unknown = seen.filter("Boxes with unknown labels");
  ASSERT_EQ(unknown.size(), 2) << seen.join('\n').toStdString();
  EXPECT_TRUE(unknown.back().contains("777")) << unknown.back().toStdString();
  EXPECT_EQ(seen.filter("Boxes in another frame").size(), 1) << seen.join('\n').toStdString();
  next->session().annotations().undoStack().setClean();
}

TEST_F(BoxFilesTest, BoxesOfAnotherFrameAreAWarningThatSaysHowTheyAreRead) {
  Annotations annotations;
  annotations.frame_id = "base";
  annotations.boxes.push_back(boxOf(1, "square_box"));
  saveAnnotations(annotations, tiny_.folder / "annotations.json");
  ASSERT_TRUE(open(tiny_.folder));
  EXPECT_EQ(boxes().boxCount(), 1);
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join('\n').toStdString();
  const std::string frame = window_.controller().sequence().frame_id;
  EXPECT_TRUE(warnings_.front().contains(QString::fromStdString(
      "annotations.json: frame_id is \"base\", the sequence's frame is \"" + frame + "\"")))
      << warnings_.front().toStdString();
  // Boxes in the sequence's own frame say nothing.
  warnings_.clear();
  annotations.frame_id = frame;
  saveAnnotations(annotations, temp_ / "same.json");
  EXPECT_EQ(loadBoxes(window_.session(), qPath(temp_ / "same.json")), QString());
  EXPECT_TRUE(warnings_.isEmpty()) << warnings_.join('\n').toStdString();
}

TEST_F(BoxFilesTest, TheUnsavedBoxesQuestionOffersToSaveThemFirst) {
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(1, "square_box"));
  {  // Opening another boxes file: Save writes these first, then opens it.
    Annotations other;
    other.boxes.push_back(boxOf(2, "blue_cup"));
    saveAnnotations(other, temp_ / "other.json");
    test::DialogAnswerer answer("Save", qPath(temp_ / "other.json"));
    window_.findAction("Open Boxes…")->trigger();
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions.front().contains("Save them first?"));
  }
  EXPECT_EQ(loadAnnotations(tiny_.folder / "annotations.json").boxes.front().label, 1);
  ASSERT_EQ(boxes().boxCount(), 1);
  EXPECT_EQ(boxes().box(0).label, 2);

  // Closing: Save writes them and the window closes.
  boxes().addBox(boxOf(1, "square_box"));
  test::DialogAnswerer answer("Save");
  EXPECT_TRUE(window_.close());
  EXPECT_EQ(loadAnnotations(temp_ / "other.json").boxes.size(), 2u);
  EXPECT_FALSE(boxes().isDirty());
}

// A pose 50 m off: the sequence opens, with a warning naming the frame.
TEST_F(BoxFilesTest, CameraJumpsAreAWarningWhenTheSequenceOpens) {
  lom::Sequence sequence = lom::loadSequence(tiny_.folder);
  sequence.frames[1].T_world_camera.translation() += Eigen::Vector3d(0.0, 50.0, 0.0);
  lom::saveSequence(sequence, tiny_.folder);
  ASSERT_TRUE(open(tiny_.folder));
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join('\n').toStdString();
  EXPECT_TRUE(warnings_.front().startsWith("Camera jumps: frames[1].pose"))
      << warnings_.front().toStdString();
}

// Focal lengths in metres instead of pixels: the sequence opens, with a
// warning naming the camera and its field of view.
TEST_F(BoxFilesTest, ImplausibleIntrinsicsAreAWarningWhenTheSequenceOpens) {
  lom::Sequence sequence = lom::loadSequence(tiny_.folder);
  sequence.camera.fx = sequence.camera.fy = 0.002;
  sequence.camera.cx = 0.5 * (sequence.camera.width - 1);
  sequence.camera.cy = 0.5 * (sequence.camera.height - 1);
  for (auto& frame : sequence.frames) frame.camera.reset();
  lom::saveSequence(sequence, tiny_.folder);
  ASSERT_TRUE(open(tiny_.folder));
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join('\n').toStdString();
  EXPECT_TRUE(warnings_.front().startsWith("Unusual camera intrinsics: camera: fx = 0.002, fy = 0.002"))
      << warnings_.front().toStdString();
  EXPECT_TRUE(warnings_.front().contains("check the camera in sequence.json"))
      << warnings_.front().toStdString();
}

TEST_F(BoxFilesTest, SavingKeepsThePermissionsOfTheFileItReplaces) {
  Annotations annotations;
  annotations.boxes.push_back(boxOf(1, "square_box"));
  const fs::path file = tiny_.folder / "annotations.json";
  saveAnnotations(annotations, file);
  fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(2, "blue_cup"));
  window_.findAction("Save Boxes")->trigger();
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(loadAnnotations(file).boxes.size(), 2u);
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::mask,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

// Boxes read from a file (imported, restored) and then replaced by another
// file's boxes are clean: Qt's clear() of an empty undo stack kept the
// "never clean" state, so the new boxes showed as unsaved.
TEST_F(BoxFilesTest, BoxesReplacedAfterAnImportAreClean) {
  ASSERT_TRUE(open(tiny_.folder));
  Annotations imported;
  imported.boxes.push_back(boxOf(1, "square_box"));
  boxes().reset(imported, QString());
  boxes().undoStack().resetClean();  // as Import YAML Boxes… and a restore leave them
  ASSERT_TRUE(boxes().isDirty());
  Annotations other;
  other.boxes.push_back(boxOf(2, "blue_cup"));
  boxes().reset(other, qPath(temp_ / "other.json"));
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_FALSE(window_.isWindowModified());
  // An edit and its undo are clean again.
  GroundTruthBox moved = boxes().box(0);
  moved.box.center.x() += 0.01;
  boxes().setBox(0, moved, "Edit box");
  EXPECT_TRUE(boxes().isDirty());
  boxes().undoStack().undo();
  EXPECT_FALSE(boxes().isDirty());
}

// An edit that changes nothing is no step: the boxes stay saved.
TEST_F(BoxFilesTest, EditsThatChangeNothingLeaveTheBoxesSaved) {
  Annotations own;
  GroundTruthBox tiny_box = boxOf(1, "square_box");
  tiny_box.box.size.z() = 0.001;  // under the smallest size a shrink leaves
  own.boxes.push_back(tiny_box);
  saveAnnotations(own, tiny_.folder / "annotations.json");
  ASSERT_TRUE(open(tiny_.folder));
  ASSERT_FALSE(boxes().isDirty());
  boxes().select(0);
  boxes().setBox(0, boxes().box(0), "Change box label");
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(boxes().undoStack().count(), 0);
  window_.findAction("Shrink Box Height (z)")->trigger();
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_DOUBLE_EQ(boxes().box(0).box.size.z(), 0.001) << "a shrink never grows a box";
  window_.findAction("Grow Box Height (z)")->trigger();
  EXPECT_TRUE(boxes().isDirty());
  EXPECT_GT(boxes().box(0).box.size.z(), 0.001);
}

// Tab and Shift+Tab in the 3D view step through the boxes. Shift+Tab comes
// as Backtab with Shift: a Shift+Backtab shortcut never fired.
TEST_F(BoxFilesTest, TabAndShiftTabInTheSceneStepThroughTheBoxes) {
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(1, "square_box"));
  boxes().addBox(boxOf(2, "blue_cup"));
  boxes().select(0);
  QWidget* scene = &window_.sceneView();
  QWidget* view = scene;
  for (QWidget* child : scene->findChildren<QWidget*>())
    if (child->focusPolicy() != Qt::NoFocus) view = child;
  window_.activateWindow();
  QApplication::setActiveWindow(&window_);
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
  view->setFocus();
  QApplication::processEvents();
  ASSERT_TRUE(QApplication::focusWidget() == scene ||
              scene->isAncestorOf(QApplication::focusWidget()));
  QTest::keyClick(QApplication::focusWidget(), Qt::Key_Tab);
  EXPECT_EQ(boxes().selected(), 1);
  QTest::keyClick(QApplication::focusWidget(), Qt::Key_Backtab, Qt::ShiftModifier);
  EXPECT_EQ(boxes().selected(), 0);

  // Ctrl+Tab and Ctrl+Shift+Tab take the focus out of the view (Tab alone
  // never could, with boxes to step through), and select no other box.
  const auto inScene = [&] {
    QWidget* focus = QApplication::focusWidget();
    return focus == scene || scene->isAncestorOf(focus);
  };
  // The focused view is framed in the highlight colour (else the window's).
  const auto frameColour = [&] { return scene->grab().toImage().pixelColor(0, 0); };
  EXPECT_EQ(frameColour(), scene->palette().color(QPalette::Highlight));
  QTest::keyClick(QApplication::focusWidget(), Qt::Key_Tab, Qt::ControlModifier);
  EXPECT_FALSE(inScene());
  EXPECT_EQ(frameColour(), scene->palette().color(QPalette::Window));
  EXPECT_NE(QApplication::focusWidget(), nullptr);
  EXPECT_EQ(boxes().selected(), 0);
  view->setFocus();
  QApplication::processEvents();
  ASSERT_TRUE(inScene());
  QTest::keyClick(QApplication::focusWidget(), Qt::Key_Backtab,
                  Qt::ControlModifier | Qt::ShiftModifier);
  EXPECT_FALSE(inScene());
  EXPECT_EQ(boxes().selected(), 0);
}

// A studio ended with unsaved boxes of a sequence that was then moved: its
// copy is found by the old path, never offered again; the next studio keeps
// it as a plain boxes file and says where, once.
TEST_F(BoxFilesTest, TheCopyOfASequenceMovedAwayIsKeptAndSaidWhere) {
  const fs::path old_folder = temp_ / "before_the_move";
  lom::test::writeTinySequence(old_folder);
  ASSERT_TRUE(open(old_folder));
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  const QString recovery = window_.autosave().currentRecoveryPath();
  ASSERT_TRUE(QFileInfo::exists(recovery));
  const std::string copy = slurp(recovery.toStdString());
  boxes().undoStack().undo();  // the copy goes; it is put back below, as a crash leaves it
  ASSERT_FALSE(QFileInfo::exists(recovery));
  ASSERT_TRUE(open(tiny_.folder));
  fs::rename(old_folder, temp_ / "after_the_move");
  std::ofstream(recovery.toStdString(), std::ios::binary) << copy;

  // As a studio does when it opens its first sequence.
  warnings_.clear();
  window_.autosave().keepOrphanedCopies();
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join("\n").toStdString();
  EXPECT_TRUE(warnings_.front().startsWith("Unsaved boxes of a sequence not found: "))
      << warnings_.front().toStdString();
  EXPECT_TRUE(
      warnings_.front().contains(qPath(fs::weakly_canonical(temp_.path()) / "before_the_move")))
      << warnings_.front().toStdString();
  const QString kept = BoxesAutosave::declinedPath(recovery);
  EXPECT_TRUE(warnings_.front().contains(kept)) << warnings_.front().toStdString();
  EXPECT_FALSE(QFileInfo::exists(recovery));
  EXPECT_FALSE(QFileInfo::exists(recovery + ".lock"));
  ASSERT_TRUE(QFileInfo::exists(kept));
  EXPECT_EQ(loadAnnotations(fs::path(kept.toStdString())).boxes.size(), 1u);
  EXPECT_TRUE(offered_.isEmpty());
  // Said once: kept, it is no longer looked at.
  window_.autosave().keepOrphanedCopies();
  EXPECT_EQ(warnings_.size(), 1) << warnings_.join("\n").toStdString();
  // The copy of the open sequence, and of one still there, are left alone.
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  ASSERT_TRUE(QFileInfo::exists(window_.autosave().currentRecoveryPath()));
  window_.autosave().keepOrphanedCopies();
  EXPECT_EQ(warnings_.size(), 1) << warnings_.join("\n").toStdString();
  EXPECT_TRUE(QFileInfo::exists(window_.autosave().currentRecoveryPath()));
  QFile::remove(kept);
}

// A declined recovery copy is not offered again, and not deleted either.
TEST_F(BoxFilesTest, ADeclinedRecoveryCopyIsKept) {
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  const QString recovery = window_.autosave().currentRecoveryPath();
  ASSERT_TRUE(QFileInfo::exists(recovery));
  const std::string copy = slurp(recovery.toStdString());
  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  int offers = 0;
  next.setRecoveryOffer([&](const QString&) {
    ++offers;
    return false;
  });
  next.session().setAutoFuse(false);
  ASSERT_TRUE(openInto(next, qPath(tiny_.folder)));
  EXPECT_EQ(offers, 1);
  EXPECT_FALSE(QFileInfo::exists(recovery));
  const QString declined = BoxesAutosave::declinedPath(recovery);
  ASSERT_TRUE(QFileInfo::exists(declined));
  // A plain boxes file: what Open Boxes… and `labeloctomap score` read.
  const Annotations kept = loadAnnotations(declined.toStdString());
  ASSERT_EQ(kept.boxes.size(), 1u);
  EXPECT_EQ(kept.boxes[0].name, "square_box");
  EXPECT_NE(copy.find("square_box"), std::string::npos);
  ASSERT_TRUE(openInto(next, qPath(tiny_.folder)));
  EXPECT_EQ(offers, 1) << "not offered again";
  // Declined again after another session: the earlier copy stays beside the new one.
  const std::string first_kept = slurp(declined.toStdString());
  std::ofstream(recovery.toStdString()) << copy;  // another session left unsaved boxes
  ASSERT_TRUE(openInto(next, qPath(tiny_.folder)));
  EXPECT_EQ(offers, 2);
  EXPECT_EQ(slurp(declined.toStdString()), first_kept);
  QString second = declined;
  second.chop(5);
  second += "-2.json";
  EXPECT_TRUE(QFileInfo::exists(second)) << second.toStdString();
}

// A declined copy opened with Open Boxes… (where the question said it stays)
// is recovered work for this sequence: unsaved, and Save Boxes writes the
// sequence's file (it showed the boxes as saved and wrote them back into the
// hidden recovery folder).
TEST_F(BoxFilesTest, ADeclinedRecoveryCopyOpenedIsSavedToTheSequencesFile) {
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  const QString recovery = window_.autosave().currentRecoveryPath();
  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  QStringList warnings;
  next.setWarningReporter([&](const QString&, const QString& text) { warnings << text; });
  next.setRecoveryOffer([](const QString&) { return false; });
  next.session().setAutoFuse(false);
  ASSERT_TRUE(openInto(next, qPath(tiny_.folder)));
  const QString declined = BoxesAutosave::declinedPath(recovery);
  ASSERT_TRUE(QFileInfo::exists(declined));
  const std::string copy = slurp(declined.toStdString());
  EXPECT_TRUE(loadBoxes(next.session(), declined).isEmpty());
  AnnotationsModel& model = next.session().annotations();
  ASSERT_EQ(model.boxCount(), 1);
  EXPECT_TRUE(model.isDirty()) << "recovered boxes shown as saved";
  EXPECT_TRUE(next.isWindowModified());
  ASSERT_FALSE(warnings.isEmpty());
  EXPECT_TRUE(warnings.back().contains("recovery copy")) << warnings.back().toStdString();
  next.findAction("Save Boxes")->trigger();
  EXPECT_FALSE(model.isDirty());
  const Annotations saved = loadAnnotations(tiny_.folder / "annotations.json");
  ASSERT_EQ(saved.boxes.size(), 1u);
  EXPECT_EQ(saved.boxes[0].name, "square_box");
  EXPECT_EQ(slurp(declined.toStdString()), copy) << "the copy is left as it is";
}

// Restored boxes older than their file on disk: Save would replace newer
// boxes, so the restore says so.
TEST_F(BoxFilesTest, RestoringBoxesOlderThanTheirFileWarns) {
  Annotations own;
  own.boxes.push_back(boxOf(2, "blue_cup"));
  saveAnnotations(own, tiny_.folder / "annotations.json");
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  const QString recovery = window_.autosave().currentRecoveryPath();
  ASSERT_TRUE(QFileInfo::exists(recovery));
  // Someone else writes the file after the copy was made.
  QTest::qWait(20);
  own.boxes.push_back(boxOf(1, "square_box"));
  saveAnnotations(own, tiny_.folder / "annotations.json");
  fs::last_write_time(tiny_.folder / "annotations.json",
                      fs::last_write_time(recovery.toStdString()) + std::chrono::seconds(5));
  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  QStringList warnings;
  next.setWarningReporter(
      [&](const QString& title, const QString& message) { warnings << title + ": " + message; });
  next.setRecoveryOffer([](const QString&) { return true; });
  next.session().setAutoFuse(false);
  ASSERT_TRUE(openInto(next, qPath(tiny_.folder)));
  EXPECT_EQ(next.session().annotations().boxCount(), 2);  // the restored boxes
  ASSERT_EQ(warnings.size(), 1) << warnings.join("\n").toStdString();
  EXPECT_TRUE(warnings.front().contains("older than their file")) << warnings.front().toStdString();
  EXPECT_TRUE(warnings.front().contains("Save Boxes As")) << warnings.front().toStdString();
  next.session().annotations().undoStack().setClean();
}

// While another sequence opens, a warning about its boxes runs an event loop:
// a box fitted to the previous sequence's map must not land in the new one.
TEST_F(BoxFilesTest, ABoxFittedToThePreviousMapStaysOutOfTheNextSequence) {
  const auto other = lom::test::writeTinySequence(temp_ / "other_shelf");
  Annotations warned;
  warned.frame_id = "base";  // not the sequence's frame: a warning when it loads
  saveAnnotations(warned, other.folder / "annotations.json");
  window_.session().setAutoFuse(true);
  ASSERT_TRUE(open(tiny_.folder));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.session().worker().isFusing(); }, 60000));
  QTest::qWait(100);
  window_.session().setAutoFuse(false);
  window_.session().setSelectedLabel(lom::test::kSquareLabel);
  int warned_count = 0;
  window_.setWarningReporter([&](const QString&, const QString&) {
    ++warned_count;
    QTest::qWait(800);  // the user reads the warning: its event loop runs
  });
  window_.findAction("Add Box from Label Voxels")->trigger();  // fitted in the background
  ASSERT_TRUE(open(other.folder));
  QTest::qWait(300);
  EXPECT_GE(warned_count, 1);
  EXPECT_EQ(boxes().boxCount(), 0) << "a box fitted to the first sequence's map was added";
  EXPECT_FALSE(boxes().isDirty());
}

// ... nor may the autosave write the boxes shown then (the new sequence's) to
// the previous sequence's recovery file, to be offered back with it.
TEST_F(BoxFilesTest, TheAutosaveNeverWritesBoxesToAnotherSequencesRecoveryFile) {
  const auto other = lom::test::writeTinySequence(temp_ / "other_shelf");
  Annotations warned;
  warned.frame_id = "base";
  saveAnnotations(warned, other.folder / "annotations.json");
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(2, "blue_cup"));  // unsaved boxes of the first sequence
  window_.autosave().writeNow();
  const QString first_recovery = window_.autosave().currentRecoveryPath();
  ASSERT_TRUE(QFileInfo::exists(first_recovery));
  int warned_count = 0;
  window_.setWarningReporter([&](const QString&, const QString&) {
    ++warned_count;
    // The autosave's minute ends while the warning is up, with unsaved boxes shown.
    boxes().addBox(boxOf(1, "square_box"));
    window_.autosave().writeNow();
  });
  {
    test::DialogAnswerer answer("Discard");
    ASSERT_TRUE(open(other.folder));
  }
  EXPECT_GE(warned_count, 1);
  EXPECT_FALSE(QFileInfo::exists(first_recovery))
      << "the first sequence's copy holds the other's boxes";
}
// Another program (or another studio) that wrote the boxes file since the
// studio read or saved it: Save Boxes asks before replacing that.
TEST_F(BoxFilesTest, BoxesChangedOnDiskAreNotReplacedUnasked) {
  const fs::path file = tiny_.folder / "annotations.json";
  Annotations first;
  first.boxes.push_back(boxOf(1, "square_box"));
  saveAnnotations(first, file);
  ASSERT_TRUE(open(tiny_.folder));
  ASSERT_EQ(boxes().boxCount(), 1);
  boxes().addBox(boxOf(2, "blue_cup"));
  const std::string their_bytes = writeTheirBoxes(file);
  {
    test::DialogAnswerer answer("Cancel");
    window_.findAction("Save Boxes")->trigger();
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions[0].contains("was changed on disk"))
        << answer.questions[0].toStdString();
  }
  EXPECT_EQ(slurp(file), their_bytes);
  EXPECT_TRUE(boxes().isDirty());
  {
    test::DialogAnswerer answer("Replace");
    window_.findAction("Save Boxes")->trigger();
    EXPECT_EQ(answer.questions.size(), 1);
  }
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(loadAnnotations(file).boxes.size(), 2u);
  // Saved here since: the next save asks nothing.
  boxes().addBox(boxOf(3, "red_mug"));
  {
    test::DialogAnswerer answer("Cancel");
    window_.findAction("Save Boxes")->trigger();
    EXPECT_TRUE(answer.questions.isEmpty());
  }
  EXPECT_EQ(loadAnnotations(file).boxes.size(), 3u);
  EXPECT_TRUE(errors_.isEmpty()) << errors_.join('\n').toStdString();
}

TEST_F(BoxFilesTest, ABoxesFileMadeElsewhereSinceTheSequenceOpenedIsNotReplacedUnasked) {
  const fs::path file = tiny_.folder / "annotations.json";
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(2, "blue_cup"));
  const std::string their_bytes = writeTheirBoxes(file);
  {
    // Save As… proposes a free name beside it; cancelling the file dialog saves nothing.
    test::DialogAnswerer answer("Save As");
    window_.findAction("Save Boxes")->trigger();
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions[0].contains("was made by another program"))
        << answer.questions[0].toStdString();
    ASSERT_EQ(answer.proposed_files.size(), 1);
    EXPECT_TRUE(answer.proposed_files[0].endsWith("annotations-2.json"))
        << answer.proposed_files[0].toStdString();
  }
  EXPECT_EQ(slurp(file), their_bytes);
  EXPECT_TRUE(boxes().isDirty());
}

// A sequence folder moved or deleted while open is not made again by Save
// Boxes: the boxes stay unsaved, and the error says where they were to go.
TEST_F(BoxFilesTest, SavingIntoAVanishedSequenceFolderFailsAndKeepsTheBoxes) {
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(2, "blue_cup"));
  fs::rename(tiny_.folder, temp_ / "moved_shelf");
  window_.findAction("Save Boxes")->trigger();
  EXPECT_FALSE(fs::exists(tiny_.folder)) << "the vanished folder was made again";
  EXPECT_FALSE(fs::exists(temp_ / "moved_shelf" / "annotations.json"));
  ASSERT_EQ(errors_.size(), 1);
  EXPECT_TRUE(errors_[0].contains("annotations.json")) << errors_[0].toStdString();
  EXPECT_TRUE(boxes().isDirty());
}

// A studio in another process has the sequence open: this one neither
// offers, writes nor removes that studio's recovery copy, and says why.
TEST_F(BoxFilesTest, ASecondStudioOnTheSequenceLeavesTheFirstsRecoveryCopyAlone) {
  const QString recovery = BoxesAutosave::recoveryPath(qPath(tiny_.folder));
  QDir().mkpath(QFileInfo(recovery).path());
  QProcess other;
  ASSERT_TRUE(holdInAnotherProcess(recovery, other));
  Annotations theirs;
  theirs.boxes.push_back(boxOf(3, "red_mug"));
  saveAnnotations(theirs, fs::path(recovery.toStdString()));
  const std::string their_copy = slurp(fs::path(recovery.toStdString()));
  accept_offer_ = true;

  ASSERT_TRUE(open(tiny_.folder));
  EXPECT_TRUE(offered_.isEmpty()) << "the other studio's copy was offered";
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join('\n').toStdString();
  EXPECT_TRUE(warnings_[0].contains(QString("process %1").arg(other.processId())))
      << warnings_[0].toStdString();
  EXPECT_TRUE(window_.autosave().currentRecoveryPath().isEmpty());
  boxes().addBox(boxOf(2, "blue_cup"));
  window_.autosave().writeNow();
  window_.findAction("Save Boxes")->trigger();
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(slurp(fs::path(recovery.toStdString())), their_copy);
  other.kill();
  other.waitForFinished();

  // The other studio gone (killed: its lock stays behind), the next autosave
  // takes the copies over, keeping the one it left as a plain boxes file.
  warnings_.clear();
  boxes().addBox(boxOf(1, "square_box"));
  window_.autosave().writeNow();
  EXPECT_EQ(window_.autosave().currentRecoveryPath(), recovery);
  ASSERT_EQ(warnings_.size(), 1) << warnings_.join('\n').toStdString();
  EXPECT_TRUE(warnings_[0].startsWith("Unsaved boxes of another studio"))
      << warnings_[0].toStdString();
  const fs::path declined(BoxesAutosave::declinedPath(recovery).toStdString());
  ASSERT_TRUE(fs::exists(declined));
  ASSERT_EQ(loadAnnotations(declined).boxes.size(), 1u);
  EXPECT_EQ(loadAnnotations(declined).boxes[0].label, 3);
  EXPECT_TRUE(QFileInfo::exists(recovery)) << "this window's own copy";
  fs::remove(declined);
}

// Boxes taken from elsewhere (another sequence's file, a YAML import) are
// saved to the sequence's file without a question while it is as it was.
TEST_F(BoxFilesTest, ImportedBoxesReplaceAnUnchangedFileWithoutAQuestion) {
  const auto other = lom::test::writeTinySequence(temp_ / "other_shelf");
  Annotations theirs;
  theirs.boxes.push_back(boxOf(3, "red_mug"));
  saveAnnotations(theirs, other.folder / "annotations.json");
  Annotations own;
  own.boxes.push_back(boxOf(1, "square_box"));
  saveAnnotations(own, tiny_.folder / "annotations.json");
  ASSERT_TRUE(open(tiny_.folder));
  {
    test::DialogAnswerer answer("Discard", qPath(other.folder / "annotations.json"));
    window_.findAction("Open Boxes…")->trigger();
  }
  ASSERT_TRUE(boxes().isDirty());
  {
    test::DialogAnswerer answer("Cancel");
    window_.findAction("Save Boxes")->trigger();
    EXPECT_TRUE(answer.questions.isEmpty()) << answer.questions.join('\n').toStdString();
  }
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_EQ(loadAnnotations(tiny_.folder / "annotations.json").boxes.at(0).label, 3);
}

// A studio ended with unsaved boxes after another program changed their
// file: restored, the boxes still do not replace that change unasked.
TEST_F(BoxFilesTest, RestoredBoxesStillAskBeforeReplacingAFileChangedBeforeTheCrash) {
  const fs::path file = tiny_.folder / "annotations.json";
  Annotations own;
  own.boxes.push_back(boxOf(1, "square_box"));
  saveAnnotations(own, file);
  ASSERT_TRUE(open(tiny_.folder));
  boxes().addBox(boxOf(2, "blue_cup"));
  Annotations theirs;
  theirs.boxes = {boxOf(3, "red_mug"), boxOf(2, "blue_cup"), boxOf(1, "square_box")};
  saveAnnotations(theirs, file);
  window_.autosave().writeNow();  // then the studio is killed

  MainWindow next;
  next.setErrorReporter([](const QString&, const QString&) {});
  next.setWarningReporter([](const QString&, const QString&) {});
  next.setRecoveryOffer([](const QString&) { return true; });
  next.setMapDiscardQuestion([](const QString&) { return true; });
  next.session().setAutoFuse(false);
  ASSERT_TRUE(openInto(next, qPath(tiny_.folder)));
  ASSERT_EQ(next.session().annotations().boxCount(), 2) << "the restored boxes";
  {
    test::DialogAnswerer answer("Cancel");
    next.findAction("Save Boxes")->trigger();
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions[0].contains("was changed on disk"))
        << answer.questions[0].toStdString();
  }
  EXPECT_EQ(loadAnnotations(file).boxes.size(), 3u);
  next.session().annotations().undoStack().setClean();
}

// A screenshot written says where it went, as the exports do.
TEST_F(BoxFilesTest, ASavedScreenshotIsNamedInTheStatusBar) {
  ASSERT_TRUE(open(tiny_.folder));
  const fs::path shot = temp_ / "shot.png";
  {
    test::DialogAnswerer answer("Cancel", qPath(shot));
    window_.findAction("Save Screenshot…")->trigger();
  }
  ASSERT_TRUE(fs::exists(shot));
  const QString message = window_.statusBar()->currentMessage();
  EXPECT_TRUE(message.startsWith("Saved ") && message.contains("shot.png"))
      << message.toStdString();
}

// Locked out of one sequence, the studio opens another whose boxes file
// cannot be read; the autosave's minute ends while that error is up. The
// other sequence's recovery copy is still offered, not taken for the other
// studio's leftover.
TEST_F(BoxFilesTest, ALockedOutStudioOpeningAnotherSequenceOffersThatOnesCopy) {
  QProcess other;
  ASSERT_TRUE(holdInAnotherProcess(BoxesAutosave::recoveryPath(qPath(tiny_.folder)), other));
  ASSERT_TRUE(open(tiny_.folder));
  ASSERT_TRUE(window_.autosave().currentRecoveryPath().isEmpty()) << "locked out";
  const auto next = lom::test::writeTinySequence(temp_ / "next_shelf");
  std::ofstream(next.folder / "annotations.json") << "{ not json";
  const QString next_recovery = BoxesAutosave::recoveryPath(qPath(next.folder));
  Annotations left;
  left.boxes.push_back(boxOf(2, "blue_cup"));
  saveAnnotations(left, fs::path(next_recovery.toStdString()));  // a crash's copy
  window_.setErrorReporter([this](const QString& title, const QString& message) {
    errors_ << title + ": " + message;
    window_.autosave().writeNow();
  });
  accept_offer_ = true;
  ASSERT_TRUE(open(next.folder));
  EXPECT_EQ(offered_, QStringList{next_recovery});
  EXPECT_FALSE(QFileInfo::exists(BoxesAutosave::declinedPath(next_recovery)));
  for (const QString& warning : warnings_)
    EXPECT_FALSE(warning.startsWith("Unsaved boxes of another studio")) << warning.toStdString();
  other.kill();
  other.waitForFinished();
}

}  // namespace
}  // namespace lom::ui
