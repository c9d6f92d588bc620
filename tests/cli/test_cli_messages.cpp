// Messages of failures and notes: each names the file and the option at fault and says what
// was expected, in the product's own terms (no raw library text, no internal field names).
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "cli_scene_fixture.hpp"
#include "lom/label_map.hpp"
#include "lom/objects.hpp"
#include "lom/sequence.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::q;
using lom::test::runCli;
using lom::test::TempDir;

class CliMessageTest : public lom::test::CliSceneTest {};

TEST_F(CliMessageTest, RunningOutOfMemoryIsReportedPlainly) {
  if (lom::test::kAddressSanitizer)
    GTEST_SKIP() << "built with AddressSanitizer: allocations cannot be made to fail with "
                    "ulimit -v (its shadow memory needs terabytes of address space)";
  TempDir out;
  // 2 mm voxels need more than 600 MB here; the program itself starts in less.
  // Each frame's memory check lets the frame through with a --frame-memory
  // far above the limit, so the allocations fail part way.
  const auto r = runCli("fuse " + q(scene()) + " --out " + q(out / "m.ot") +
                            " --resolution 0.002 --max-range 2 --frame-memory 100 --quiet",
                        {600 * 1024, 120});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("labeloctomap fuse: out of memory while running"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(scene().string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("a coarser --resolution or a shorter --max-range"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("std::bad_alloc"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(out.path()));

  // By default the frame is checked against what the limit leaves, and
  // refused before its update streams and nodes are allocated.
  const auto checked = runCli("fuse " + q(scene()) + " --out " + q(out / "m.ot") +
                                  " --resolution 0.002 --max-range 2 --quiet",
                              {600 * 1024, 120});
  EXPECT_EQ(checked.exit_code, 1) << checked.err;
  EXPECT_NE(checked.err.find("sequence.json: frames[0].depth: expected rays that cross few enough "
                             "voxels to fuse in the "),
            std::string::npos)
      << checked.err;
  EXPECT_NE(checked.err.find(" of memory available (at most "), std::string::npos) << checked.err;
  EXPECT_TRUE(fs::is_empty(out.path()));
}

TEST_F(CliMessageTest, WriteFailuresNameTheOutput) {
  // /proc takes no new files, not even from root.
  auto r = runCli("export " + q(map()) + " --format pcd --out /proc/lom-test-voxels.pcd");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/proc/lom-test-voxels.pcd: output path: expected a folder where files "
                       "can be created"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find(": :"), std::string::npos) << r.err;
  r = runCli("export " + q(map()) + " --format ply --per-label --out /proc/lom-test-meshes");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/proc/lom-test-meshes: output path: expected a folder"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("filesystem error"), std::string::npos) << r.err;
}

// A folder where no file can be written is refused before any work, for a
// file output and for a folder output alike (/proc/sys takes no new file,
// not even from root).
TEST_F(CliMessageTest, AnUnwritableOutputFolderIsRefusedBeforeAnyWork) {
  if (::access("/proc/sys", W_OK) == 0) GTEST_SKIP() << "/proc/sys is writable here";
  auto r = runCli("fuse " + q(scene()) + " --out /proc/sys/lom-test.ot");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/proc/sys/lom-test.ot: --out: expected a folder where files can be "
                       "written, found folder /proc/sys: "),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.out.find("fused"), std::string::npos) << r.out;
  r = runCli("score " + q(scene()) + " --annotations " + q(scene() / "annotations.json") +
             " --out /proc/sys/lom-test-report");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("--out: expected a folder where files can be written"), std::string::npos)
      << r.err;
}

// An empty map exported as an octree, and a .ot file that is not a map, are
// blamed on the input map with the map reader's words.
TEST_F(CliMessageTest, EmptyAndBrokenMapsAreNamedAsTheInput) {
  TempDir out;
  lom::LabelMap(lom::LabelMap::load(map()).labels()).save(out / "empty.ot");
  for (const char* format : {"ot", "bt"}) {
    const auto r = runCli("export " + q(out / "empty.ot") + " --format " + format + " --out " +
                          q(out / (std::string("copy.") + format)));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find((out / "empty.ot").string() + ": map: expected at least one known voxel"),
              std::string::npos)
        << r.err;
  }
  std::ofstream(out / "nothing.ot").close();
  const auto info = runCli("info " + q(out / "nothing.ot"));
  EXPECT_EQ(info.exit_code, 1) << info.err;
  EXPECT_NE(info.err.find("nothing.ot: header"), std::string::npos) << info.err;
  EXPECT_EQ(info.err.find("JSON"), std::string::npos) << info.err;
  EXPECT_FALSE(fs::exists(out / "copy.ot"));
}

// Messages whose wording used to mislead: an empty path named nowhere, a
// range that excluded a refused value, numbers taken for a file name.
TEST_F(CliMessageTest, MessagesSayWhatWasWrongInTheCallersTerms) {
  TempDir out;
  auto r = runCli("fuse '' --out " + q(out / "m.ot"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("found an empty path ('')"), std::string::npos) << r.err;
  r = runCli("import frames " + q(scene()) + " --out " + q(out / "s") + " --every 0");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--every expects an integer from 1 to"), std::string::npos) << r.err;
  r = runCli("import frames " + q(scene()) + " --out " + q(out / "s") +
             " --intrinsics nan,519,325.5,253.5");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("expected finite numbers"), std::string::npos) << r.err;
  r = runCli("plan " + q(map()) + " --target " + target() +
             " --approach 1,0,0 --min-cluster-voxels 0");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--min-cluster-voxels expects an integer from 1 to"), std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::is_empty(out.path()));
}

TEST_F(CliMessageTest, AnEmptyLabelSelectionNamesTheMapAndTheOption) {
  TempDir out;
  const auto present = counts();
  int empty = 1;
  while (present.count(empty)) ++empty;
  const auto r = runCli("export " + q(map()) + " --labels " + std::to_string(empty) +
                        " --format ply --out " + q(out / "b.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(map().string() + ": --labels: expected labels with occupied voxels"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("label " + std::to_string(empty) + " ("), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("b.ply"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(out.path()));
}

TEST_F(CliMessageTest, ObjectsOfABackgroundOnlyMapSayWhatIsThere) {
  TempDir out;
  // With the background as the only candidate, every occupied voxel is background.
  auto r = runCli("fuse " + q(scene()) + " --candidates 0 --out " + q(out / "bg.ot") + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const size_t background = lom::LabelMap::load(out / "bg.ot").occupiedCountPerLabel().at(0);
  r = runCli("export " + q(out / "bg.ot") + " --format objects --out " + q(out / "objects.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find((out / "bg.ot").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(std::to_string(background) + " occupied voxels, all of the background"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--labels 0"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "objects.json"));
  r = runCli("export " + q(out / "bg.ot") + " --format objects --labels 0 --out " +
             q(out / "objects.json"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(CliMessageTest, PlanOnAMapWithoutObjectLabelsSaysSo) {
  TempDir out;
  lom::LabelMap background(
      lom::LabelSet(std::vector<lom::LabelInfo>{{0, "__background__", {0, 0, 0}}}));
  lom::OrientedBox box;
  box.center = {0.0, 0.0, 0.05};
  box.size = {0.1, 0.1, 0.1};
  lom::rasterizeBox(background, box, 0);
  background.save(out / "background.ot");
  const auto r = runCli("plan " + q(out / "background.ot") + " --target 0 --approach 1,0,0");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find((out / "background.ot").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("only label is the background"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("1..0"), std::string::npos) << r.err;
}

TEST_F(CliMessageTest, InfoDescribesAMapAndValidateSaysItIsOne) {
  auto r = runCli("info " + q(map()));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("resolution:       0.01 m"), std::string::npos) << r.out;
  // The fused frames' cameras, recorded in the map (the generated scene has z up).
  EXPECT_NE(r.out.find("camera views:     " +
                       std::to_string(lom::loadSequence(scene()).frames.size()) + ", mean up ("),
            std::string::npos)
      << r.out;
  size_t occupied = 0;
  for (const auto& [label, count] : counts()) occupied += count;
  EXPECT_NE(r.out.find("occupied voxels:  " + std::to_string(occupied)), std::string::npos)
      << r.out;
  EXPECT_EQ(r.err.find("JSON"), std::string::npos) << r.err;
  r = runCli("validate " + q(map()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("found a map file"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("JSON"), std::string::npos) << r.out;
}

TEST_F(CliMessageTest, BinaryOctreeExportLeavesStderrQuiet) {
  TempDir out;
  const auto r = runCli("export " + q(map()) + " --format bt --out " + q(out / "map.bt"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_TRUE(fs::exists(out / "map.bt"));
}

TEST_F(CliMessageTest, PlanSaysWhenItGuessedTheApproach) {
  const auto present = counts();
  const std::string target = std::to_string(std::prev(present.end())->first);
  // A fused map records its cameras: their viewing direction, nothing guessed.
  auto r = runCli("plan " + q(map()) + " --target " + target);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("guessed"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("mean viewing direction of the map's cameras"), std::string::npos) << r.out;
  r = runCli("plan " + q(map()) + " --target " + target + " --sequence " + q(scene()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("guessed"), std::string::npos) << r.err;
  // A map made without cameras: the direction is guessed, and the note says so.
  TempDir out;
  lom::LabelMap drawn(lom::LabelMap::load(map()).labels());
  lom::OrientedBox object, free_space;
  object.center = {0.3, 0.0, 0.05};
  object.size = {0.1, 0.1, 0.1};
  free_space.center = {-0.25, 0.0, 0.1};
  free_space.size = {0.5, 0.4, 0.25};
  lom::rasterizeBox(drawn, object, std::stoi(target));
  lom::rasterizeFreeBox(drawn, free_space);
  drawn.save(out / "drawn.ot");
  r = runCli("plan " + q(out / "drawn.ot") + " --target " + target);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("note: the approach direction was guessed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--sequence SEQ"), std::string::npos) << r.err;
}

}  // namespace

namespace {

// A recording that `labeloctomap import` reads, given where a sequence is
// expected: the error says what it is and which command converts it.
TEST(CliRecordingTest, RecordingsGivenAsSequencesNameTheImportThatConvertsThem) {
  TempDir dir;
  const fs::path dataset = dir / "room scan";  // a quaternion-pose folder, with a space
  fs::create_directories(dataset / "depth");
  std::ofstream(dataset / "pose.txt") << "0 0 0 0 0 0 1\n";
  const auto folder = runCli("info " + q(dataset));
  EXPECT_EQ(folder.exit_code, 1) << folder.err;
  // It stores no camera: the commands given name the intrinsics they need.
  EXPECT_NE(folder.err.find("found no such file; the folder is a quaternion-pose folder (depth/, "
                            "pose.txt): convert it with `labeloctomap import quaternion '" +
                            dataset.string() +
                            "' --intrinsics fx,fy,cx,cy --out SEQ` "
                            "(`labeloctomap-studio --intrinsics fx,fy,cx,cy '" +
                            dataset.string() +
                            "'` opens it as it is; the folder stores no camera intrinsics)"),
            std::string::npos)
      << folder.err;
  // With an intrinsics file, no option.
  std::ofstream(dataset / "intrinsics.txt") << "500 0 320\n0 500 240\n0 0 1\n";
  const auto with_camera = runCli("info " + q(dataset));
  EXPECT_NE(with_camera.err.find("`labeloctomap import quaternion '" + dataset.string() +
                                 "' --out SEQ` (`labeloctomap-studio '" + dataset.string() +
                                 "'` opens it as it is)"),
            std::string::npos)
      << with_camera.err;

  const fs::path bag = dir / "rec.bag";
  std::ofstream(bag) << "#ROSBAG V2.0\n";
  TempDir out;
  const auto file = runCli("fuse " + q(bag) + " --out " + q(out / "m.ot"));
  EXPECT_EQ(file.exit_code, 1) << file.err;
  EXPECT_NE(file.err.find("found a ROS bag file: convert it with `labeloctomap import rosbag " +
                          bag.string() + " --out SEQ`"),
            std::string::npos)
      << file.err;
  EXPECT_TRUE(fs::is_empty(out.path()));

  // A folder that is neither: the plain message, no suggestion.
  fs::create_directories(dir / "empty");
  const auto plain = runCli("info " + q(dir / "empty"));
  EXPECT_EQ(plain.exit_code, 1);
  EXPECT_NE(plain.err.find("found no such file\n"), std::string::npos) << plain.err;
}

}  // namespace
