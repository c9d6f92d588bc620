// A room-scale recording fused with the default max range (1 m) keeps almost
// nothing: fusion reports how many depths were beyond max range and `fuse`
// warns, suggesting a max range that covers the depths. Skipped with a
// message when the recording is absent.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "lom/fusion.hpp"
#include "lom/import.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom {
namespace {

namespace fs = std::filesystem;

struct ProgramRun {
  int exit_code = -1;
  std::string err;
};

// Runs the labeloctomap program with `args`, keeping its standard error.
ProgramRun runProgram(const std::string& args, const test::TempDir& dir) {
  const fs::path err = dir / "stderr.txt";
  const std::string command = std::string("'") + LOM_CLI_PATH + "' " + args + " >/dev/null 2>'" +
                              err.string() + "' </dev/null";
  const int status = std::system(command.c_str());
  ProgramRun run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err);
  std::stringstream text;
  text << in.rdbuf();
  run.err = text.str();
  return run;
}

Sequence importKinectRoom(const test::TempDir& dir) {
  ImportOptions options;
  options.intrinsics = parseIntrinsics("518,519,325.5,253.5");
  const ImportReport report = importSource(
      SourceKind::Quaternion, test::sharedDataDir() / "kinect-room-5", dir / "seq", options);
  EXPECT_EQ(report.frames_written, 5u);
  return loadSequence(dir / "seq");
}

FrameStats fusedTotals(const Sequence& sequence, double max_range, double resolution) {
  FusionOptions options;
  options.map.max_range = max_range;
  options.map.resolution = resolution;
  FrameStats totals;
  (void)fuseSequence(sequence, options, [&](const FusionProgress& progress) {
    totals = progress.totals;
    return true;
  });
  return totals;
}

TEST(MaxRangeRealData, KinectRoomDepthsAreMostlyBeyondTheDefaultMaxRange) {
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  test::TempDir dir;
  const Sequence sequence = importKinectRoom(dir);
  const FrameStats totals = fusedTotals(sequence, MapParameters{}.max_range, 0.05);
  std::cout << "[ ranges    ] kinect-room-5: " << totals.beyond_range_pixels << " of "
            << totals.valid_pixels << " valid pixels beyond 1 m, farthest " << totals.farthest_range
            << " m\n";
  ASSERT_GT(totals.valid_pixels, 500000u);
  EXPECT_GT(static_cast<double>(totals.beyond_range_pixels),
            0.9 * static_cast<double>(totals.valid_pixels));
  EXPECT_GT(totals.farthest_range, 4.0);
  EXPECT_LT(totals.farthest_range, 12.0);  // a Kinect measures no farther

  const FrameStats covered = fusedTotals(sequence, std::ceil(totals.farthest_range), 0.05);
  EXPECT_EQ(covered.beyond_range_pixels, 0u);
  EXPECT_EQ(covered.valid_pixels, totals.valid_pixels);
}

TEST(MaxRangeRealData, FuseWarnsWhenMostDepthsAreBeyondMaxRange) {
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  if (!fs::exists(LOM_CLI_PATH)) GTEST_SKIP() << "the program " << LOM_CLI_PATH << " is not built";
  test::TempDir dir;
  (void)importKinectRoom(dir);
  const std::string sequence = "'" + (dir / "seq").string() + "'";
  const ProgramRun cut = runProgram(
      "fuse " + sequence + " --resolution 0.05 --out '" + (dir / "cut.ot").string() + "'", dir);
  EXPECT_EQ(cut.exit_code, 0) << cut.err;
  EXPECT_NE(cut.err.find("warning: "), std::string::npos) << cut.err;
  EXPECT_NE(cut.err.find("beyond the max range of 1 m"), std::string::npos) << cut.err;
  EXPECT_NE(cut.err.find("fuse with --max-range 10 to map them\n"), std::string::npos)
      << cut.err;  // 5 cm voxels are coarse enough for 10 m
  // At 5 mm a 10 m ray would cross 2,000 voxels: the suggestion coarsens them.
  const ProgramRun fine =
      runProgram("fuse " + sequence + " --resolution 0.005 --frames 0:1 --out '" +
                     (dir / "fine.ot").string() + "'",
                 dir);
  EXPECT_EQ(fine.exit_code, 0) << fine.err;
  EXPECT_NE(fine.err.find("fuse with --max-range 10 --resolution 0.04 to map them (rays of at "
                          "most 250 voxels"),
            std::string::npos)
      << fine.err;

  const ProgramRun whole =
      runProgram("fuse " + sequence + " --resolution 0.05 --max-range 10 --out '" +
                     (dir / "whole.ot").string() + "'",
                 dir);
  EXPECT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_EQ(whole.err.find("warning"), std::string::npos) << whole.err;
}

// The camera matrix of quarter-size images: its rays fan out too wide and run
// long, and the depths seem beyond max range; fuse warns about the camera and
// says that the range is not what to change.
TEST(MaxRangeRealData, WrongIntrinsicsComeBeforeTheMaxRangeAdvice) {
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  if (!fs::exists(LOM_CLI_PATH)) GTEST_SKIP() << "the program " << LOM_CLI_PATH << " is not built";
  test::TempDir dir;
  ImportOptions options;
  options.intrinsics = parseIntrinsics("129.5,129.75,81.4,63.4");  // 518,519,325.5,253.5 / 4
  (void)importSource(SourceKind::Quaternion, test::sharedDataDir() / "kinect-room-5", dir / "seq",
                     options);
  const ProgramRun run =
      runProgram("fuse '" + (dir / "seq").string() + "' --resolution 0.05 --frames 0:1 --out '" +
                     (dir / "quarter.ot").string() + "'",
                 dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("camera: the principal point cx = 81.4, cy = 63.4 lies at 13 % and 13 %"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("beyond the max range"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("(but the camera's intrinsics look wrong, warned above: correct them "
                         "before changing --max-range)"),
            std::string::npos)
      << run.err;
}

}  // namespace
}  // namespace lom
