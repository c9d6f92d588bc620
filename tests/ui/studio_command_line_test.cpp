// labeloctomap-studio run as a program: screenshot mode and its errors.
#include <gtest/gtest.h>

#include <QFileInfo>
#include <QImage>
#include <QProcess>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "lom/annotations.hpp"
#include "lom/sequence.hpp"
#include "lom/ui/annotation_files.hpp"
#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace {

struct StudioRun {
  int exit_code = -1;  // -1 also for a crash
  QString err;
  QString out;
};

StudioRun runStudio(const QStringList& arguments, const QProcessEnvironment& environment =
                                                      QProcessEnvironment::systemEnvironment()) {
  QProcess studio;
  studio.setProcessEnvironment(environment);
  studio.start(LOM_STUDIO_PATH, arguments);
  if (!studio.waitForFinished(120000)) {
    studio.kill();
    return {};
  }
  return {studio.exitStatus() == QProcess::NormalExit ? studio.exitCode() : -1,
          QString::fromLocal8Bit(studio.readAllStandardError()),
          QString::fromLocal8Bit(studio.readAllStandardOutput())};
}

// As on a server or in CI without X: no display of any kind.
QProcessEnvironment withoutDisplay() {
  QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
  environment.remove("DISPLAY");
  environment.remove("WAYLAND_DISPLAY");
  environment.remove("QT_QPA_PLATFORM");
  return environment;
}

using lom::test::slurp;

QString qPath(const std::filesystem::path& path) { return QString::fromStdString(path.string()); }

TEST(StudioCommandLine, ScreenshotWritesAPictureOfTheWindow) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  const auto out = temp / "window.png";
  const StudioRun run = runStudio({"--screenshot", qPath(out), "--frame", "2", qPath(tiny.folder)});
  ASSERT_EQ(run.exit_code, 0) << run.err.toStdString();
  const QImage shot(qPath(out));
  ASSERT_FALSE(shot.isNull());
  EXPECT_GE(shot.width(), 800);
}

// A 5 cm box of `label` in front of the tiny sequence's camera.
lom::Annotations oneBox(int label, const char* name) {
  lom::Annotations boxes;
  lom::GroundTruthBox box;
  box.label = label;
  box.name = name;
  box.box.center = {0.1, 0.0, 0.6};
  box.box.size = {0.05, 0.05, 0.05};
  boxes.boxes.push_back(box);
  return boxes;
}

// Boxes of a label the sequence lacks are kept and reported: a warning on
// stderr, not a failure; and taking a picture is not a session to reopen, so
// the Recent list stays as it was.
TEST(StudioCommandLine, ScreenshotWarnsAboutUnknownLabelsAndLeavesTheRecentListAlone) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  lom::saveAnnotations(oneBox(99, "mystery"), tiny.folder / "annotations.json");
  QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
  environment.insert("XDG_CONFIG_HOME", qPath(temp / "config"));
  const auto out = temp / "window.png";
  const StudioRun run = runStudio({"--screenshot", qPath(out), qPath(tiny.folder)}, environment);
  EXPECT_EQ(run.exit_code, 0) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("warning: Boxes with unknown labels")) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("label 99")) << run.err.toStdString();
  EXPECT_FALSE(QImage(qPath(out)).isNull());
  std::string settings;
  if (std::filesystem::exists(temp / "config"))
    for (const auto& entry : std::filesystem::recursive_directory_iterator(temp / "config"))
      if (entry.is_regular_file()) settings += slurp(entry.path());
  EXPECT_EQ(settings.find("recentSequences"), std::string::npos) << settings;
}

// Unsaved boxes left by a session that ended are neither asked about (no one
// is there to answer) nor dropped: the next interactive session offers them.
TEST(StudioCommandLine, ScreenshotLeavesTheBoxRecoveryFileForTheNextSession) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  // Where the studio keeps its recovery files under this XDG_DATA_HOME.
  const QString name =
      QFileInfo(lom::ui::BoxesAutosave::recoveryPath(qPath(tiny.folder))).fileName();
  const auto recovery =
      temp / "data" / "LabelOctoMap" / "LabelOctoMap Studio" / "recovery" / name.toStdString();
  std::filesystem::create_directories(recovery.parent_path());
  lom::saveAnnotations(oneBox(1, "square_box"), recovery);
  const std::string before = slurp(recovery);
  QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
  environment.insert("XDG_DATA_HOME", qPath(temp / "data"));
  const auto out = temp / "window.png";
  const StudioRun run = runStudio({"--screenshot", qPath(out), qPath(tiny.folder)}, environment);
  EXPECT_EQ(run.exit_code, 0) << run.err.toStdString();
  EXPECT_FALSE(QImage(qPath(out)).isNull());
  ASSERT_TRUE(std::filesystem::exists(recovery));
  EXPECT_EQ(slurp(recovery), before);
}

// Under a number format with decimal commas (German here) the studio still
// reads a recording's "615.19" as the files mean it: Qt sets the C library's
// locale from the environment, which the studio undoes for numbers. The
// locale is built into the test's own folder (no system locale needed), and
// the test is skipped where Debian's locale sources are missing.
TEST(StudioCommandLine, AGermanNumberFormatStillReadsTheRecordingsDecimalPoints) {
  lom::test::TempDir temp;
  std::filesystem::create_directories(temp / "locales");
  const std::string build = "localedef -i de_DE -f UTF-8 '" + (temp / "locales").string() +
                            "/de_DE.UTF-8' >/dev/null 2>&1";
  if (std::system(build.c_str()) != 0)
    GTEST_SKIP() << "no de_DE locale could be built (Debian's locales package holds its source)";
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  lom::test::writeFramesLayout(tiny, temp / "recording");  // converted when opened
  QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
  environment.insert("LOCPATH", qPath(temp / "locales"));
  environment.insert("LC_ALL", "de_DE.UTF-8");
  const auto out = temp / "window.png";
  const StudioRun run =
      runStudio({"--screenshot", qPath(out), qPath(temp / "recording")}, environment);
  EXPECT_EQ(run.exit_code, 0) << run.err.toStdString();
  // Every frame converted: none left out for a pose it could not read.
  EXPECT_FALSE(run.err.contains("could not be converted")) << run.err.toStdString();
  EXPECT_FALSE(QImage(qPath(out)).isNull());
}

// The picture never replaces a file of the sequence it shows.
TEST(StudioCommandLine, ScreenshotRefusesToReplaceAFileOfTheSequence) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  const lom::Sequence sequence = lom::loadSequence(tiny.folder);
  const auto colour = sequence.pathOf(sequence.frames[0].color);
  const std::string before = slurp(colour);
  const StudioRun run = runStudio({"--screenshot", qPath(colour), qPath(tiny.folder)});
  EXPECT_EQ(run.exit_code, 2) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("would replace the input")) << run.err.toStdString();
  EXPECT_EQ(slurp(colour), before);
}

TEST(StudioCommandLine, BrokenSequenceExitsWithItsMessage) {
  lom::test::TempDir temp;
  const StudioRun run =
      runStudio({"--screenshot", qPath(temp / "x.png"), qPath(temp / "missing_sequence")});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_TRUE(run.err.contains("missing_sequence")) << run.err.toStdString();
  EXPECT_FALSE(std::filesystem::exists(temp / "x.png"));
}

TEST(StudioCommandLine, FrameOutOfRangeIsAUsageError) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  const StudioRun run =
      runStudio({"--screenshot", qPath(temp / "x.png"), "--frame", "9", qPath(tiny.folder)});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_TRUE(run.err.contains("--frame 9")) << run.err.toStdString();
}

TEST(StudioCommandLine, AScreenshotNameWithoutAnImageFormatIsAUsageError) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  for (const char* name : {"shot.txt", "shot"}) {
    const StudioRun run = runStudio({"--screenshot", qPath(temp / name), qPath(tiny.folder)});
    EXPECT_EQ(run.exit_code, 2) << name << run.err.toStdString();
    EXPECT_TRUE(run.err.contains("image format such as .png")) << run.err.toStdString();
    EXPECT_FALSE(std::filesystem::exists(temp / name)) << name;
  }
}

TEST(StudioCommandLine, HelpAndVersionNeedNoDisplay) {
  const StudioRun help = runStudio({"--help"}, withoutDisplay());
  EXPECT_EQ(help.exit_code, 0) << help.err.toStdString();
  EXPECT_TRUE(help.out.contains("--screenshot")) << help.out.toStdString();
  EXPECT_TRUE(help.out.contains("--intrinsics")) << help.out.toStdString();
  const StudioRun version = runStudio({"--version"}, withoutDisplay());
  EXPECT_EQ(version.exit_code, 0) << version.err.toStdString();
  EXPECT_TRUE(version.out.startsWith("labeloctomap-studio ")) << version.out.toStdString();
}

TEST(StudioCommandLine, WithoutADisplayItSaysHowToGetOneAndExits3) {
  lom::test::TempDir temp;
  const auto out = temp / "x.png";
  for (const QStringList& arguments :
       {QStringList{"--screenshot", qPath(out), "--demo"}, QStringList{}}) {
    const StudioRun run = runStudio(arguments, withoutDisplay());
    EXPECT_EQ(run.exit_code, 3) << run.err.toStdString();
    EXPECT_TRUE(run.err.contains("DISPLAY is not set")) << run.err.toStdString();
    EXPECT_TRUE(run.err.contains("xvfb-run")) << run.err.toStdString();
  }
  // Qt's offscreen platform would start, but with an empty 3D view.
  QProcessEnvironment offscreen = withoutDisplay();
  offscreen.insert("QT_QPA_PLATFORM", "offscreen");
  const StudioRun run = runStudio({"--screenshot", qPath(out), "--demo"}, offscreen);
  EXPECT_EQ(run.exit_code, 3) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("offscreen")) << run.err.toStdString();
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A display without GLX (ssh -X to a server with indirect GLX off): the 3D
// view would stay black under VTK's OpenGL errors; the studio says why and
// exits 3 instead, as without a display.
TEST(StudioCommandLine, ADisplayWithoutGlxIsRefusedWithTheReason) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian's xvfb package)";
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  const auto out = temp / "window.png";
  QProcess studio;
  studio.start("xvfb-run", {"-a", "-s", "-screen 0 640x480x24 -extension GLX", LOM_STUDIO_PATH,
                            "--screenshot", qPath(out), qPath(tiny.folder)});
  ASSERT_TRUE(studio.waitForFinished(120000));
  const QString err = QString::fromLocal8Bit(studio.readAllStandardError());
  EXPECT_EQ(studio.exitCode(), 3) << err.toStdString();
  EXPECT_TRUE(err.contains("gives no OpenGL context drawn on this machine")) << err.toStdString();
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(StudioCommandLine, MistakesInTheCallExit2EvenWithoutADisplay) {
  for (const QStringList& arguments :
       {QStringList{"--no-such-option"}, QStringList{"--frame", "-1", "seq"},
        QStringList{"--intrinsics", "1,2,3", "seq"}, QStringList{"a", "b"},
        QStringList{"--resolution", "abc", "seq"}, QStringList{"--resolution", "5", "seq"},
        QStringList{"--max-range", "-1", "seq"}, QStringList{"--max-range", "30", "seq"}}) {
    const StudioRun run = runStudio(arguments, withoutDisplay());
    EXPECT_EQ(run.exit_code, 2) << arguments.join(' ').toStdString() << ": "
                                << run.err.toStdString();
    EXPECT_TRUE(run.err.contains("usage:")) << run.err.toStdString();
  }
}

TEST(StudioCommandLine, UnreadableFrameExits1WithoutAPicture) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  std::filesystem::remove(tiny.folder / "depth_0.png");
  const auto out = temp / "x.png";
  const StudioRun run = runStudio({"--screenshot", qPath(out), qPath(tiny.folder)});
  EXPECT_EQ(run.exit_code, 1) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("depth_0.png")) << run.err.toStdString();
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(StudioCommandLine, FusionStoppedExits1WithoutAPicture) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  std::ofstream(tiny.folder / "depth_2.png", std::ios::trunc) << "not a png";
  const auto out = temp / "x.png";
  const StudioRun run = runStudio({"--screenshot", qPath(out), "--fuse", qPath(tiny.folder)});
  EXPECT_EQ(run.exit_code, 1) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("Fusion stopped")) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("depth_2.png")) << run.err.toStdString();
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A screenshot that could not be written is found before the sequence is
// opened and fused, not after.
TEST(StudioCommandLine, AScreenshotInAMissingFolderIsAUsageError) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  const StudioRun run = runStudio(
      {"--screenshot", qPath(temp / "nowhere" / "shot.png"), "--fuse", qPath(tiny.folder)});
  EXPECT_EQ(run.exit_code, 2) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("expected a file in an existing, writable folder"))
      << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("nowhere does not exist")) << run.err.toStdString();
  EXPECT_FALSE(run.err.contains("fused")) << run.err.toStdString();
  const StudioRun folder = runStudio({"--screenshot", qPath(temp.path()), qPath(tiny.folder)});
  EXPECT_EQ(folder.exit_code, 2) << folder.err.toStdString();
}

TEST(StudioCommandLine, FailedScreenshotLeavesTheExistingFileAlone) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  const auto out = temp / "shot.png";
  std::ofstream(out) << "an earlier file";
  // The picture cannot be written: files may not grow beyond 4 KiB (ulimit -f,
  // as a batch system sets it: the studio must not be killed by the signal).
  StudioRun run;
  {
    const lom::test::FileSizeLimit limit(4096, /*ignore_signal=*/false);
    run = runStudio({"--screenshot", qPath(out), qPath(tiny.folder)});
  }
  EXPECT_EQ(run.exit_code, 1) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("shot.png")) << run.err.toStdString();
  EXPECT_TRUE(run.err.contains("file-size limit")) << run.err.toStdString();
  EXPECT_EQ(slurp(out), "an earlier file");
  // Nothing else is left in the folder (no temporary file).
  size_t entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(temp.path())) {
    (void)entry;
    ++entries;
  }
  EXPECT_EQ(entries, 2u);  // seq/ and the file
}

// A dataset layout without stored intrinsics (pose.txt, color/N.png,
// depth/N.pgm) opens when the studio is given them.
TEST(StudioCommandLine, DatasetFolderNeedingIntrinsicsOpensWithTheOption) {
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  const QString room = qPath(lom::test::sharedDataDir() / "kinect-room-5");
  lom::test::TempDir temp;
  const auto out = temp / "room.png";
  const StudioRun without = runStudio({"--screenshot", qPath(out), room});
  EXPECT_EQ(without.exit_code, 1) << without.err.toStdString();
  EXPECT_TRUE(without.err.contains("labeloctomap-studio --intrinsics"))
      << without.err.toStdString();
  EXPECT_FALSE(std::filesystem::exists(out));

  const StudioRun with =
      runStudio({"--screenshot", qPath(out), "--intrinsics", "518,519,325.5,253.5", room});
  EXPECT_EQ(with.exit_code, 0) << with.err.toStdString();
  EXPECT_FALSE(QImage(qPath(out)).isNull());
}

// The fusion settings come from the command line too: a room fused at the
// default 1 m range maps almost nothing, which a picture run says on stderr
// (the Fusion panel's Re-fuse button cannot be pressed there); with the
// room's range and a coarser voxel it maps the room. A sequence's own labels
// are not renamed by --labels (it names a converted recording's ids).
TEST(StudioCommandLine, FusionSettingsAndTheirWarningsOnTheCommandLine) {
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  const QString room = qPath(lom::test::sharedDataDir() / "kinect-room-5");
  lom::test::TempDir temp;
  const auto out = temp / "room.png";
  const StudioRun near = runStudio(
      {"--screenshot", qPath(out), "--fuse", "--intrinsics", "518,519,325.5,253.5", room});
  ASSERT_EQ(near.exit_code, 0) << near.err.toStdString();
  EXPECT_TRUE(near.err.contains("warning: ")) << near.err.toStdString();
  EXPECT_TRUE(near.err.contains("of the depths lay beyond the max range of 1.00 m"))
      << near.err.toStdString();
  EXPECT_TRUE(near.err.contains("Give --max-range")) << near.err.toStdString();
  const StudioRun far =
      runStudio({"--screenshot", qPath(out), "--fuse", "--intrinsics", "518,519,325.5,253.5",
                 "--max-range", "4", "--resolution", "0.02", room});
  ASSERT_EQ(far.exit_code, 0) << far.err.toStdString();
  EXPECT_FALSE(far.err.contains("beyond the max range")) << far.err.toStdString();

  const auto tiny = lom::test::writeTinySequence(temp / "seq");
  std::ofstream(temp / "labels.txt") << "__background__\nmug\n";
  const StudioRun labelled = runStudio({"--screenshot", qPath(temp / "tiny.png"), "--labels",
                                        qPath(temp / "labels.txt"), qPath(tiny.folder)});
  ASSERT_EQ(labelled.exit_code, 0) << labelled.err.toStdString();
  EXPECT_TRUE(labelled.err.contains("note: --labels is not used")) << labelled.err.toStdString();
  // The built-in set by name, as `labeloctomap import --labels apc2016` takes it.
  const StudioRun builtin = runStudio(
      {"--screenshot", qPath(temp / "tiny.png"), "--labels", "apc2016", qPath(tiny.folder)});
  EXPECT_EQ(builtin.exit_code, 0) << builtin.err.toStdString();
  EXPECT_TRUE(builtin.err.contains("note: --labels is not used")) << builtin.err.toStdString();
  const StudioRun missing = runStudio({"--screenshot", qPath(temp / "tiny.png"), "--labels",
                                       qPath(temp / "none.txt"), qPath(tiny.folder)});
  EXPECT_EQ(missing.exit_code, 1) << missing.err.toStdString();
  EXPECT_TRUE(missing.err.contains("none.txt")) << missing.err.toStdString();
}

}  // namespace
