// labeloctomap-studio run as a program: screenshot mode and its errors.
#include <gtest/gtest.h>

#include <QImage>
#include <QProcess>
#include <filesystem>

#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace {

struct StudioRun {
  int exit_code = -1;
  QString err;
};

StudioRun runStudio(const QStringList& arguments) {
  QProcess studio;
  studio.start(LOM_STUDIO_PATH, arguments);
  if (!studio.waitForFinished(120000)) {
    studio.kill();
    return {};
  }
  return {studio.exitStatus() == QProcess::NormalExit ? studio.exitCode() : -1,
          QString::fromLocal8Bit(studio.readAllStandardError())};
}

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

}  // namespace
