// labeloctomap fuse / export end to end on a generated sequence.
#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <string>

#include "cli_scene_fixture.hpp"
#include "lom/fusion.hpp"
#include "lom/images.hpp"
#include "lom/label_map.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace {

using lom::test::runCli;
using lom::test::TempDir;

class CliFuseTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new TempDir();
    const auto r = runCli("synth --out '" + (scene_->path() / "scene").string() +
                          "' --seed 5 --objects 4 --frames 4 --views 3 --width 160 --height 120");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete scene_;
    scene_ = nullptr;
  }
  static std::string scene() { return "'" + (scene_->path() / "scene").string() + "'"; }
  static TempDir* scene_;
};
TempDir* CliFuseTest::scene_ = nullptr;

TEST_F(CliFuseTest, FusesAndPrintsASummary) {
  TempDir out;
  const auto map_path = out / "map.ot";
  const auto r = runCli("fuse " + scene() + " --out '" + map_path.string() + "' --resolution 0.02");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("fused 4 frames"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("occupied voxels"), std::string::npos);
  EXPECT_NE(r.out.find("__background__"), std::string::npos);
  // The run's peak memory, at least the map's own bytes (printed in KiB above it).
  const auto map_line = r.out.find("map: resolution");
  const auto peak_line = r.out.find("memory: peak resident ");
  ASSERT_NE(map_line, std::string::npos) << r.out;
  ASSERT_NE(peak_line, std::string::npos) << r.out;
  const auto kib_end = r.out.find(" KiB\n", map_line);
  const long map_kib = std::stol(r.out.substr(r.out.rfind(' ', kib_end - 1) + 1));
  const long peak_mib = std::stol(r.out.substr(peak_line + 22));
  EXPECT_GT(peak_mib, 0);
  EXPECT_GE(peak_mib * 1024 + 512, map_kib) << r.out;
  const lom::LabelMap map = lom::LabelMap::load(map_path);
  EXPECT_DOUBLE_EQ(map.parameters().resolution, 0.02);
  EXPECT_EQ(map.numLabels(), 40);
  EXPECT_FALSE(map.occupiedCountPerLabel().empty());
}

TEST_F(CliFuseTest, FrameRangeAndCandidatesAreApplied) {
  TempDir out;
  const auto r = runCli("fuse " + scene() + " --out '" + (out / "m.ot").string() +
                        "' --resolution 0.02 --frames 1:3 --candidates 0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("fused 2 frames"), std::string::npos) << r.out;
  const auto counts = lom::LabelMap::load(out / "m.ot").occupiedCountPerLabel();
  ASSERT_EQ(counts.size(), 1u);  // only the background can win
  EXPECT_EQ(counts.begin()->first, 0);
}

// --start-from: frames fused into a map fused earlier give the map of all the
// frames fused at once, with the earlier map's parameters.
TEST_F(CliFuseTest, FramesFusedIntoAnEarlierMapGiveTheMapOfAllTheFrames) {
  TempDir out;
  const std::string fine = " --resolution 0.02 --max-range 1.5 --p-miss 0.35";
  ASSERT_EQ(
      runCli("fuse " + scene() + " --frames 0:2 --out '" + (out / "first.ot").string() + "'" + fine)
          .exit_code,
      0);
  const auto r =
      runCli("fuse " + scene() + " --frames 2: --start-from '" + (out / "first.ot").string() +
             "' --out '" + (out / "both.ot").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("fused 2 frames"), std::string::npos) << r.out;
  ASSERT_EQ(
      runCli("fuse " + scene() + " --out '" + (out / "all.ot").string() + "'" + fine).exit_code, 0);
  EXPECT_EQ(lom::test::slurp(out / "both.ot"), lom::test::slurp(out / "all.ot"));
  const lom::LabelMap both = lom::LabelMap::load(out / "both.ot");
  EXPECT_DOUBLE_EQ(both.parameters().resolution, 0.02);
  EXPECT_DOUBLE_EQ(both.parameters().p_miss, 0.35);
  // --threshold is the result's; the earlier map is left as it was.
  const std::string first = lom::test::slurp(out / "first.ot");
  ASSERT_EQ(runCli("fuse " + scene() + " --frames 2: --threshold 0.6 --start-from '" +
                   (out / "first.ot").string() + "' --out '" + (out / "t.ot").string() + "'")
                .exit_code,
            0);
  EXPECT_DOUBLE_EQ(lom::LabelMap::load(out / "t.ot").parameters().occupancy_threshold, 0.6);
  EXPECT_EQ(lom::test::slurp(out / "first.ot"), first);
}

// Fusing into a map the frames it was fused from counts them twice: a warning
// (the map records its camera views); other frames are not warned about.
TEST_F(CliFuseTest, FusingTheSameFramesAgainIsWarnedAbout) {
  TempDir out;
  const std::string first = (out / "first.ot").string();
  ASSERT_EQ(runCli("fuse " + scene() + " --frames 0:2 --quiet --out '" + first + "'").exit_code, 0);
  const auto again = runCli("fuse " + scene() + " --frames 0:2 --quiet --start-from '" + first +
                            "' --out '" + (out / "twice.ot").string() + "'");
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("warning: " + first +
                           " was fused from these very frames already, it seems (it records as "
                           "many camera views as they are, looking the same ways): fusing them "
                           "again counts each of their observations twice"),
            std::string::npos)
      << again.err;
  const auto other = runCli("fuse " + scene() + " --frames 2: --quiet --start-from '" + first +
                            "' --out '" + (out / "both.ot").string() + "'");
  EXPECT_EQ(other.exit_code, 0) << other.err;
  EXPECT_EQ(other.err.find("warning:"), std::string::npos) << other.err;

  // Frames that include the map's (a continuation started from the first
  // frame again): the warning names the map's frames and the range to fuse.
  const auto all = runCli("fuse " + scene() + " --quiet --start-from '" + first + "' --out '" +
                          (out / "all.ot").string() + "'");
  EXPECT_EQ(all.exit_code, 0) << all.err;
  EXPECT_NE(all.err.find("warning: " + first +
                         " was fused from frames 0:2 of these already, it seems (it records as "
                         "many camera views as they are, looking the same ways): fusing them "
                         "again counts each of their observations twice, which makes the map "
                         "surer than the data are; leave them out with --frames 2: "),
            std::string::npos)
      << all.err;
  // A map of middle frames: the frames before them, and those after.
  const std::string middle = (out / "middle.ot").string();
  ASSERT_EQ(runCli("fuse " + scene() + " --frames 1:3 --quiet --out '" + middle + "'").exit_code,
            0);
  const auto around = runCli("fuse " + scene() + " --quiet --start-from '" + middle + "' --out '" +
                             (out / "around.ot").string() + "'");
  EXPECT_NE(around.err.find("was fused from frames 1:3 of these already"), std::string::npos)
      << around.err;
  EXPECT_NE(around.err.find("leave them out with --frames 0:1 (and fuse the frames after them "
                            "too)"),
            std::string::npos)
      << around.err;
}

// A map fused with --candidates is continued with the same candidates unless
// --candidates says otherwise: the same map as all its frames fused at once.
TEST_F(CliFuseTest, AMapFusedWithCandidatesIsContinuedWithThem) {
  TempDir out;
  const std::string first = (out / "first.ot").string();
  ASSERT_EQ(
      runCli("fuse " + scene() + " --frames 0:2 --candidates 0,1 --quiet --out '" + first + "'")
          .exit_code,
      0);
  const auto r = runCli("fuse " + scene() + " --frames 2: --start-from '" + first + "' --out '" +
                        (out / "both.ot").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("note: fusing with the candidates " + first +
                       " was fused with (0,1), as it records"),
            std::string::npos)
      << r.err;
  ASSERT_EQ(runCli("fuse " + scene() + " --candidates 0,1 --quiet --out '" +
                   (out / "all.ot").string() + "'")
                .exit_code,
            0);
  EXPECT_EQ(lom::test::slurp(out / "both.ot"), lom::test::slurp(out / "all.ot"));
  EXPECT_EQ(lom::LabelMap::load(out / "both.ot").fusedCandidates().labels,
            (std::vector<int>{0, 1}));
  // --candidates chooses others: the record widens to both, no note.
  const auto wider = runCli("fuse " + scene() + " --frames 2: --candidates 0,2 --start-from '" +
                            first + "' --out '" + (out / "wider.ot").string() + "'");
  ASSERT_EQ(wider.exit_code, 0) << wider.err;
  EXPECT_EQ(wider.err.find("note: fusing with the candidates"), std::string::npos) << wider.err;
  EXPECT_EQ(lom::LabelMap::load(out / "wider.ot").fusedCandidates().labels,
            (std::vector<int>{0, 1, 2}));
}

// A map to start from holds its own settings; fuse takes only those its
// options could give (a map written elsewhere or edited may hold any).
TEST_F(CliFuseTest, StartingFromAMapWithSettingsFuseWouldRefuseIsRefused) {
  TempDir out;
  const lom::LabelSet labels = lom::loadSequence(scene_->path() / "scene").labels;
  const auto refused = [&](const std::string& name, const lom::MapParameters& parameters,
                           const std::string& field) {
    lom::LabelMap map(labels, parameters);
    map.save(out / name);
    const auto r = runCli("fuse " + scene() + " --start-from '" + (out / name).string() +
                          "' --out '" + (out / "x.ot").string() + "'");
    EXPECT_EQ(r.exit_code, 1) << name << "\n" << r.err;
    EXPECT_NE(r.err.find(name + ": " + field + ": expected"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out / "x.ot"));
  };
  lom::MapParameters p_miss;
  p_miss.p_miss = 0.7;
  refused("p_miss.ot", p_miss, "p_miss");
  lom::MapParameters coarse;
  coarse.resolution = 5.0;
  coarse.max_range = 10.0;
  refused("coarse.ot", coarse, "resolution");
  lom::MapParameters threshold;
  threshold.occupancy_threshold = 0.99;
  refused("threshold.ot", threshold, "occupancy_threshold");
}

// 9 m of 9 mm voxels is 1000 voxels, within the limit, however the division rounds.
TEST_F(CliFuseTest, RaysOfExactlyTheLimitAreTaken) {
  TempDir out;
  for (const char* pair :
       {"--resolution 0.009 --max-range 9", "--resolution 0.7 --max-range 700"}) {
    const auto r = runCli("fuse " + scene() + " --frames 0:1 --quiet " + pair + " --out '" +
                          (out / "x.ot").string() + "'");
    EXPECT_EQ(r.exit_code, 0) << pair << "\n" << r.err;
  }
  const auto r =
      runCli("fuse " + scene() + " --frames 0:1 --resolution 0.009 --max-range 9.01 --out '" +
             (out / "y.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
}

TEST_F(CliFuseTest, StartingFromAnUnusableMapIsRefusedBeforeAnyWork) {
  TempDir out;
  ASSERT_EQ(runCli("fuse " + scene() + " --frames 0:1 --resolution 0.02 --out '" +
                   (out / "first.ot").string() + "'")
                .exit_code,
            0);
  const std::string first = "'" + (out / "first.ot").string() + "'";
  // The map's own parameters cannot be changed.
  auto r = runCli("fuse " + scene() + " --start-from " + first + " --resolution 0.01 --out '" +
                  (out / "x.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--resolution cannot be given with --start-from"), std::string::npos)
      << r.err;
  // The result never replaces the map it starts from.
  r = runCli("fuse " + scene() + " --start-from " + first + " --out " + first);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the map to start from"), std::string::npos) << r.err;
  // A map of another label set.
  lom::LabelMap other(lom::LabelSet({{0, "floor", {1, 2, 3}}}), lom::MapParameters{});
  other.save(out / "other.ot");
  r = runCli("fuse " + scene() + " --start-from '" + (out / "other.ot").string() + "' --out '" +
             (out / "x.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("other.ot: labels: expected 40 labels (the sequence's), found 1 label\n"),
            std::string::npos)
      << r.err;
  // No map at all.
  r = runCli("fuse " + scene() + " --start-from '" + (out / "none.ot").string() + "' --out '" +
             (out / "x.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("none.ot"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "x.ot"));
}

TEST_F(CliFuseTest, ExportWritesAPcdThatPclReads) {
  TempDir out;
  ASSERT_EQ(runCli("fuse " + scene() + " --out '" + (out / "m.ot").string() + "' --resolution 0.02")
                .exit_code,
            0);
  const auto r = runCli("export '" + (out / "m.ot").string() + "' --voxels '" +
                        (out / "v.pcd").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  pcl::PCLPointCloud2 cloud;
  ASSERT_EQ(pcl::io::loadPCDFile((out / "v.pcd").string(), cloud), 0);
  std::vector<std::string> fields;
  for (const auto& f : cloud.fields) fields.push_back(f.name);
  for (const char* name : {"x", "y", "z", "label", "probability", "rgb"})
    EXPECT_NE(std::find(fields.begin(), fields.end(), name), fields.end()) << name;
  const lom::LabelMap map = lom::LabelMap::load(out / "m.ot");
  size_t occupied = 0;
  for (const auto& [label, count] : map.occupiedCountPerLabel()) occupied += count;
  EXPECT_EQ(static_cast<size_t>(cloud.width) * cloud.height, occupied);
}

TEST_F(CliFuseTest, BadInputGivesAClearErrorAndNoOutput) {
  TempDir out;
  auto r = runCli("fuse " + scene() + " --out '" + (out / "m.ot").string() + "' --p-miss 1.5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--p-miss"), std::string::npos) << r.err;
  r = runCli("fuse " + scene() + " --out '" + (out / "nofolder" / "m.ot").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("nofolder"), std::string::npos) << r.err;
  r = runCli("fuse " + scene() + " --out '" + (out / "m.ot").string() + "' --candidates 0,99");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("99"), std::string::npos) << r.err;
  r = runCli("fuse '" + (out / "nothing").string() + "' --out '" + (out / "m.ot").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(std::filesystem::is_empty(out.path()));

  // A map file of another kind.
  std::ofstream(out / "not-a-map.ot") << "# Octomap OcTree file\nid OcTree\nsize 1\nres 0.1\ndata\n";
  r = runCli("export '" + (out / "not-a-map.ot").string() + "' --voxels '" +
             (out / "v.pcd").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("LabelOcTree"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "v.pcd"));
}

// Every depth 0 (no measurement): an empty map would only make every later
// command fail, so fuse says why and writes nothing.
TEST_F(CliFuseTest, FramesWithoutAnyValidDepthAreAnErrorAndWriteNothing) {
  TempDir out;
  const auto copy = out / "scene";
  std::filesystem::copy(scene_->path() / "scene", copy, std::filesystem::copy_options::recursive);
  for (const auto& entry : std::filesystem::directory_iterator(copy / "depth"))
    lom::writeDepthPng(entry.path(), lom::DepthImage{160, 120, std::vector<float>(160 * 120, 0.f)},
                       0.001);
  const auto r = runCli("fuse '" + copy.string() + "' --out '" + (out / "m.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("sequence.json: depth: expected frames with valid depths"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("none in the 4 frames fused"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "m.ot"));
}

TEST_F(CliFuseTest, WrongChannelCountNamesTheFrameAndField) {
  TempDir out;
  const auto copy = out / "scene";
  std::filesystem::copy(scene_->path() / "scene", copy, std::filesystem::copy_options::recursive);
  // Drop one entry of frame 2's proba_labels: the .npy keeps its channels.
  std::ifstream in(copy / "sequence.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  size_t at = 0;
  for (int frame = 0; frame <= 2; ++frame) at = text.find("\"proba_labels\"", at + 1);
  ASSERT_NE(at, std::string::npos);
  const size_t open = text.find('[', at);
  const size_t comma = text.find(',', open);
  text.erase(open + 1, comma - open);  // removes the first label id and its comma
  std::ofstream(copy / "sequence.json") << text;

  const auto r = runCli("fuse '" + copy.string() + "' --out '" + (out / "m.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("frames[2]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("proba"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("channel"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "m.ot"));
}

// A copy of the scene with every camera moved `shift` metres along x.
std::filesystem::path shiftedScene(const TempDir& out, const std::filesystem::path& scene,
                                   double shift) {
  const auto copy = out / "scene";
  lom::test::copyWithCamerasShifted(scene, copy, shift);
  return copy;
}

// 327.4 m out, the cameras lie inside the map's 327.68 m at 1 cm, but some of
// what they see does not: the map is fused, and fuse says how much it left out.
TEST_F(CliFuseTest, DepthsOutsideTheMapAreAWarningWithTheCountAndTheExtent) {
  TempDir out;
  const auto copy = shiftedScene(out, scene_->path() / "scene", 327.4);
  const auto r = runCli("fuse '" + copy.string() + "' --out '" + (out / "m.ot").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string warning = "warning: " + (copy / "sequence.json").string() + ": ";
  const auto at = r.err.find(warning);
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" measured depth pixels (", at), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("lie outside the map's extent, 327.68 m either side of the origin on each "
                       "axis at 0.01 m voxels: the map leaves them out",
                       at),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("a coarser --resolution extends the map (0.02 m voxels reach 655.36 m)", at),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(std::filesystem::exists(out / "m.ot"));
  // Where the map holds everything, no such warning.
  const auto coarse = runCli("fuse '" + copy.string() + "' --out '" + (out / "c.ot").string() +
                             "' --resolution 0.02");
  ASSERT_EQ(coarse.exit_code, 0) << coarse.err;
  EXPECT_EQ(coarse.err.find("outside the map's extent"), std::string::npos) << coarse.err;
}

// Focal lengths far too short (a mistake such as one in metres for one in
// pixels) put the depths farther than any range fusion takes: the max-range
// warning points at the intrinsics instead of suggesting options fuse refuses.
TEST_F(CliFuseTest, DepthsBeyondAnyRangeFusionTakesPointAtTheIntrinsics) {
  TempDir out;
  const auto copy = out / "scene";
  std::filesystem::copy(scene_->path() / "scene", copy, std::filesystem::copy_options::recursive);
  lom::Sequence sequence = lom::loadSequence(copy);
  // About 2 km out at the image's edges: inside the extent of 10 cm voxels (3276.8 m).
  sequence.camera.fx = sequence.camera.fy = 0.03;
  for (auto& frame : sequence.frames) frame.camera.reset();
  lom::saveSequence(sequence, copy);
  const auto r = runCli("fuse '" + copy.string() + "' --resolution 0.1 --out '" +
                        (out / "m.ot").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto at = r.err.find("were beyond the max range of 1 m");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_NE(r.err.find("The depths reach farther than 1000 m, beyond any max range fusion takes", at),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("check camera.fx, camera.fy, camera.cx, camera.cy and camera.depth_scale in " +
                           (copy / "sequence.json").string(),
                       at),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("--max-range inf"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(" inf m"), std::string::npos) << r.err;

  // Depths of a few hundred metres can be fused with 1 m voxels, in rays
  // longer than the 250 voxels the suggestion otherwise keeps to: it says so,
  // and that such depths point at the intrinsics too.
  sequence.camera.fx = sequence.camera.fy = 0.2;
  lom::saveSequence(sequence, copy);
  const auto far =
      runCli("fuse '" + copy.string() + "' --frames 0:1 --out '" + (out / "far.ot").string() + "'");
  ASSERT_EQ(far.exit_code, 0) << far.err;
  EXPECT_NE(far.err.find("--resolution 1 to map them (1 m voxels, the coarsest fusion takes, "
                         "and rays of "),
            std::string::npos)
      << far.err;
  EXPECT_NE(far.err.find("suggest wrong camera intrinsics or depth scale"), std::string::npos)
      << far.err;
  EXPECT_EQ(far.err.find("rays of at most 250 voxels"), std::string::npos) << far.err;
}

// Depths beyond max range are a warning when they are most of the valid
// pixels, a note (same words) from a fifth of them, and nothing below.
TEST_F(CliFuseTest, DepthsBeyondMaxRangeAreNotedFromAFifthAndWarnedFromAHalf) {
  TempDir out;
  const lom::Sequence sequence = lom::loadSequence(scene_->path() / "scene");
  std::vector<lom::DepthImage> depths;
  for (size_t i = 0; i < sequence.frames.size(); ++i)
    depths.push_back(lom::loadFrame(sequence, i).depth);
  int notes = 0;
  for (int cm = 50; cm <= 100; cm += 5) {
    const double range = cm / 100.0;
    size_t valid = 0, beyond = 0;
    for (size_t i = 0; i < depths.size(); ++i) {
      const lom::DepthRanges ranges = lom::countDepthRanges(sequence.cameraOf(i), depths[i], range);
      valid += ranges.measured;
      beyond += ranges.beyond;
    }
    const double share = static_cast<double>(beyond) / static_cast<double>(valid);
    const auto r = runCli("fuse '" + (scene_->path() / "scene").string() + "' --max-range " +
                          std::to_string(range) + " --out '" + (out / "m.ot").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const bool warned = r.err.find("warning: ") != std::string::npos &&
                        r.err.find("were beyond the max range") != std::string::npos;
    const bool noted = r.err.find("note: ") != std::string::npos &&
                       r.err.find("were beyond the max range") != std::string::npos;
    SCOPED_TRACE(std::to_string(range) + " m: " + std::to_string(share));
    EXPECT_EQ(warned, share > 0.5) << r.err;
    EXPECT_EQ(noted, share >= 0.2 && share <= 0.5) << r.err;
    notes += noted;
    if (noted) {  // --quiet leaves out every note; a warning stays
      const auto quiet =
          runCli("fuse '" + (scene_->path() / "scene").string() + "' --max-range " +
                 std::to_string(range) + " --quiet --out '" + (out / "m.ot").string() + "'");
      EXPECT_EQ(quiet.err.find("note: "), std::string::npos) << quiet.err;
    }
  }
  EXPECT_GT(notes, 0) << "no max range of the scene gave a note";
}

// A map continued with --start-from keeps its own max range and resolution
// (fuse refuses both options then): the advice says to fuse again without it.
TEST_F(CliFuseTest, AdviceAfterStartFromSaysToFuseAgainWithoutIt) {
  TempDir out;
  const std::string scene_path = "'" + (scene_->path() / "scene").string() + "'";
  ASSERT_EQ(runCli("fuse " + scene_path + " --max-range 0.5 --frames 0:1 --out '" +
                   (out / "first.ot").string() + "'")
                .exit_code,
            0);
  const auto r =
      runCli("fuse " + scene_path + " --frames 1: --start-from '" + (out / "first.ot").string() +
             "' --out '" + (out / "all.ot").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("were beyond the max range of 0.5 m"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fuse again without --start-from (whose map keeps its own max range and "
                       "resolution), with --max-range "),
            std::string::npos)
      << r.err;
  // Without --start-from the advice is the plain one.
  const auto plain =
      runCli("fuse " + scene_path + " --max-range 0.5 --out '" + (out / "plain.ot").string() + "'");
  EXPECT_NE(plain.err.find("; fuse with --max-range "), std::string::npos) << plain.err;
}

// A map records the world frame of the poses fused into it: frames of another
// frame are not fused into it, nor is it scored against boxes of another
// frame; info shows it.
TEST_F(CliFuseTest, AMapOfAnotherWorldFrameIsRefusedByStartFromAndScore) {
  TempDir out;
  const auto copy = out / "odom_scene";
  std::filesystem::copy(scene_->path() / "scene", copy, std::filesystem::copy_options::recursive);
  lom::Sequence sequence = lom::loadSequence(copy);
  sequence.frame_id = "odom";
  lom::saveSequence(sequence, copy);
  const std::string odom_map = "'" + (out / "odom.ot").string() + "'";
  ASSERT_EQ(runCli("fuse '" + copy.string() + "' --frames 0:1 --quiet --out " + odom_map).exit_code,
            0);
  const auto info = runCli("info " + odom_map);
  EXPECT_NE(info.out.find("world frame:      odom (the frame its fused poses were in)\n"),
            std::string::npos)
      << info.out;

  const auto into = runCli("fuse " + scene() + " --frames 1: --start-from " + odom_map +
                           " --out '" + (out / "mixed.ot").string() + "'");
  EXPECT_NE(into.exit_code, 0);
  EXPECT_NE(into.err.find((out / "odom.ot").string()), std::string::npos) << into.err;
  EXPECT_NE(into.err.find("world frame"), std::string::npos) << into.err;
  EXPECT_NE(into.err.find("\"world\""), std::string::npos) << into.err;
  EXPECT_NE(into.err.find("\"odom\""), std::string::npos) << into.err;
  EXPECT_FALSE(std::filesystem::exists(out / "mixed.ot"));

  const auto score = runCli("score " + scene() + " --annotations '" +
                            (scene_->path() / "scene" / "annotations.json").string() + "' --map " +
                            odom_map + " --out '" + (out / "report").string() + "'");
  EXPECT_NE(score.exit_code, 0);
  EXPECT_NE(score.err.find("world frame"), std::string::npos) << score.err;
  EXPECT_NE(score.err.find("\"odom\", the frame the map's fused poses were in"), std::string::npos)
      << score.err;
  EXPECT_FALSE(std::filesystem::exists(out / "report"));

  // Frames of its own world frame fuse into it.
  const auto same = runCli("fuse '" + copy.string() + "' --frames 1: --quiet --start-from " +
                           odom_map + " --out '" + (out / "both.ot").string() + "'");
  EXPECT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(lom::LabelMap::load(out / "both.ot").worldFrame().frame_id, "odom");
}

// The frame memory check charges nodes only for voxels a miss adds them
// for: a frame fused again into the map that holds it crosses known voxels
// and saturated free space (merged leaves a miss leaves as they are), and
// takes only its streams.
TEST_F(CliFuseTest, AFrameOverKnownSpaceIsChargedOnlyItsStreams) {
  TempDir out;
  const std::string first = "'" + (out / "all.ot").string() + "'";
  ASSERT_EQ(runCli("fuse " + scene() + " --out " + first + " --quiet").exit_code, 0);
  const auto probe = runCli("fuse " + scene() + " --frames 0:1 --start-from " + first +
                            " --frame-memory 0.000001 --out '" + (out / "b.ot").string() + "'");
  ASSERT_EQ(probe.exit_code, 1) << probe.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      probe.err, m, std::regex("rays crossing ([0-9]+) voxels, ([0-9]+) of them new to the map")))
      << probe.err;
  const double crossed = std::stod(m[1].str()), fresh = std::stod(m[2].str());
  EXPECT_LT(fresh * 10.0, crossed) << "most of what the frame crosses is in the map already";
  // A limit between what its streams take and what it would take as new voxels.
  const double bytes =
      crossed * lom::kFusionStreamBytesPerCrossedVoxel +
      fresh * (lom::kFusionBytesPerCrossedVoxel - lom::kFusionStreamBytesPerCrossedVoxel) + 4096.0;
  ASSERT_LT(bytes, crossed * lom::kFusionBytesPerCrossedVoxel);
  char gib[64];
  std::snprintf(gib, sizeof gib, "%.12f", bytes / (1024.0 * 1024.0 * 1024.0));
  const auto r = runCli("fuse " + scene() + " --frames 0:1 --start-from " + first +
                        " --frame-memory " + gib + " --out '" + (out / "b.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// 400 m out, the cameras lie outside the map: fuse fails at once, naming the
// first such frame's pose and the extent, and writes nothing.
// --frame-memory: a frame whose rays cross more voxels than the memory given
// takes is refused, naming the frame's depth, before anything is written; the
// option takes GiB above 0.
TEST_F(CliFuseTest, AFrameNeedingMoreThanTheFrameMemoryIsAnErrorAndWritesNothing) {
  TempDir out;
  const auto map_path = out / "m.ot";
  const auto r =
      runCli("fuse " + scene() + " --out '" + map_path.string() + "' --frame-memory 0.001");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("sequence.json: frames[0].depth: expected rays that cross few enough voxels "
                       "to fuse in the 1 MiB of memory allowed per frame (at most 8948 new voxels "
                       "of 0.01 m, about 120 bytes each, or 22370 the map holds already); coarser "
                       "voxels or a shorter max range cross fewer, found rays crossing "),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(map_path));

  const auto coarse = runCli("fuse " + scene() + " --out '" + map_path.string() +
                             "' --frame-memory 0.05 --resolution 0.02");
  EXPECT_EQ(coarse.exit_code, 0) << coarse.err;
  EXPECT_TRUE(std::filesystem::exists(map_path));

  for (const char* bad : {"0", "-1"}) {
    const auto refused = runCli("fuse " + scene() + " --out '" + (out / "n.ot").string() +
                                "' --frame-memory " + bad);
    EXPECT_EQ(refused.exit_code, 2) << bad << ": " << refused.err;
    EXPECT_NE(refused.err.find("option --frame-memory expects the memory a frame may take"),
              std::string::npos)
        << refused.err;
  }
}

TEST_F(CliFuseTest, CameraOutsideTheMapIsAnErrorNamingThePose) {
  TempDir out;
  const auto copy = shiftedScene(out, scene_->path() / "scene", 400.0);
  const auto r = runCli("fuse '" + copy.string() + "' --out '" + (out / "m.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find((copy / "sequence.json").string() +
                       ": frames[0].pose: expected a camera position inside the map's extent, "
                       "327.68 m either side of the origin on each axis at 0.01 m voxels"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("(voxels of 0.013 m or more hold this one), found the camera at (399."),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("every depth pixel"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "m.ot"));
}

// One camera at 1e20 m: that frame is named, not the next one as a jump.
TEST_F(CliFuseTest, OneCameraFarOutIsNamedItself) {
  TempDir out;
  const auto copy = out / "scene";
  std::filesystem::copy(scene_->path() / "scene", copy, std::filesystem::copy_options::recursive);
  lom::Sequence sequence = lom::loadSequence(copy);
  sequence.frames[0].T_world_camera.translation().x() = 1e20;
  lom::saveSequence(sequence, copy);
  const auto r = runCli("fuse '" + copy.string() + "' --out '" + (out / "m.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("frames[0].pose: expected a camera position inside the map's extent"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("a wrong pose?"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("frames[1]"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("will span"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "m.ot"));
}

// Intrinsics that throw every point far out: the depths were measured, so the
// error says they lie outside the map and points at the intrinsics, rather
// than calling them 0 or invalid.
TEST_F(CliFuseTest, EveryPointOutsideTheMapIsNotCalledInvalid) {
  TempDir out;
  const auto copy = out / "scene";
  std::filesystem::copy(scene_->path() / "scene", copy, std::filesystem::copy_options::recursive);
  lom::Sequence sequence = lom::loadSequence(copy);
  sequence.camera.fx = 1e-300;
  lom::saveSequence(sequence, copy);
  const auto r = runCli("fuse '" + copy.string() + "' --out '" + (out / "m.ot").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.find("every depth pixel is 0"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sequence.json: depth: expected depth points inside the map's extent, "
                       "327.68 m either side"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("none in the 4 frames fused: all "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("check camera.fx"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "m.ot"));
}

}  // namespace
