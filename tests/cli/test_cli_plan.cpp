// labeloctomap plan end to end: table, plan.json, approach sources, errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "lom/label_map.hpp"
#include "lom/objects.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace {

using lom::test::runCli;
using lom::test::TempDir;
using Json = nlohmann::json;

using lom::test::slurp;

std::string quoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

lom::OrientedBox aabb(const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  lom::OrientedBox box;
  box.center = 0.5 * (low + high);
  box.size = high - low;
  return box;
}

class CliPlanTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = new TempDir();
    {
      // The target (19) at the back of the bin, 8 in front of it, 30 in front of 8,
      // 13 behind it; free space in front of the bin where the cameras looked through.
      lom::LabelMap map(lom::apc2016Labels());
      lom::rasterizeBox(map, aabb({0.30, -0.05, 0.0}, {0.40, 0.05, 0.10}), 19);
      lom::rasterizeBox(map, aabb({0.16, -0.05, 0.0}, {0.24, 0.05, 0.09}), 8);
      lom::rasterizeBox(map, aabb({0.02, -0.03, 0.0}, {0.08, 0.03, 0.12}), 30);
      lom::rasterizeBox(map, aabb({0.45, -0.05, 0.0}, {0.55, 0.05, 0.10}), 13);
      lom::rasterizeFreeBox(map, aabb({-0.50, -0.20, 0.0}, {0.0, 0.20, 0.25}));
      map.save(root_->path() / "bin.ot");
    }
    {
      lom::LabelMap map(lom::apc2016Labels());  // no free space, no target
      lom::rasterizeBox(map, aabb({0.16, -0.05, 0.0}, {0.24, 0.05, 0.09}), 8);
      map.save(root_->path() / "no_target.ot");
    }
    {
      // Cameras looking along -y: the bin is seen from the side, so nothing hides 19.
      lom::Sequence sequence;
      sequence.labels = lom::apc2016Labels();
      lom::FrameRecord frame;
      frame.depth = "depth/000000.png";
      frame.T_world_camera.linear() =
          Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
      sequence.frames.push_back(frame);
      frame.depth = "depth/000001.png";
      sequence.frames.push_back(frame);
      std::filesystem::create_directories(root_->path() / "side" / "depth");
      // Their depths: a wall half a metre away, where the map has nothing.
      lom::DepthImage wall;
      wall.width = sequence.camera.width;
      wall.height = sequence.camera.height;
      wall.metres.assign(static_cast<size_t>(wall.width) * static_cast<size_t>(wall.height), 0.5f);
      for (const auto& recorded : sequence.frames)
        lom::writeDepthPng(root_->path() / "side" / recorded.depth, wall,
                           sequence.camera.depth_scale);
      lom::saveSequence(sequence, root_->path() / "side");
    }
  }
  static void TearDownTestSuite() {
    delete root_;
    root_ = nullptr;
  }
  static std::filesystem::path path(const std::string& name) { return root_->path() / name; }
  static std::string map() { return quoted(path("bin.ot")); }
  static TempDir* root_;
};
TempDir* CliPlanTest::root_ = nullptr;

TEST_F(CliPlanTest, PrintsTheTableAndWritesThePlan) {
  TempDir out;
  const auto r = runCli("plan " + map() + " --target 19 --approach 1,0,0 --out " + quoted(out / "plan.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("   1  remove  30 rolodex_jumbo_pencil_cup"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("   2  remove  8 creativity_chenille_stems"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("   3  pick    19 i_am_a_bunny_book"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wrote"), std::string::npos) << r.out;

  const Json plan = Json::parse(slurp(out / "plan.json"));
  EXPECT_EQ(plan["format"], "labeloctomap-plan");
  EXPECT_EQ(plan["map"], path("bin.ot").string());
  EXPECT_EQ(plan["approach"]["source"], "given");
  EXPECT_EQ(plan["occluders"], Json::array({"30", "8"}));
  ASSERT_EQ(plan["steps"].size(), 3u);
  EXPECT_EQ(plan["steps"][0]["object"], "30");
  EXPECT_EQ(plan["steps"][0]["placement"]["where"], "outside");
  EXPECT_EQ(plan["steps"][2]["action"], "pick");
  EXPECT_DOUBLE_EQ(plan["steps"][2]["grasp"]["position"][0].get<double>(), 0.30);
  // Nothing is left behind next to the plan.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(out.path()), {}), 1);
  EXPECT_DOUBLE_EQ(plan["occupancy_threshold"].get<double>(), 0.5);  // the map's own
}

// --occluders centroid: the paper's rule, recorded in plan.json; the default
// (path) is recorded too, and anything else is a usage error.
TEST_F(CliPlanTest, OccludersCentroidTakesThePapersRule) {
  TempDir out;
  const auto path_rule =
      runCli("plan " + map() + " --target 19 --approach 1,0,0 --out " + quoted(out / "path.json"));
  ASSERT_EQ(path_rule.exit_code, 0) << path_rule.err;
  const auto centroid =
      runCli("plan " + map() + " --target 19 --approach 1,0,0 --occluders centroid --out " +
             quoted(out / "centroid.json"));
  ASSERT_EQ(centroid.exit_code, 0) << centroid.err;
  const Json by_path = Json::parse(slurp(out / "path.json"));
  const Json by_centroid = Json::parse(slurp(out / "centroid.json"));
  EXPECT_EQ(by_path["options"]["occluder_rule"], "path");
  EXPECT_EQ(by_centroid["options"]["occluder_rule"], "centroid");
  // Every object whose centroid is in front of the target's, and only those.
  std::map<std::string, double> depth;
  double target_depth = 0.0;
  for (const Json& object : by_centroid["objects"]) {
    const double x = object["centroid"][0].get<double>();
    depth[object["id"].get<std::string>()] = x;
    if (object["id"] == by_centroid["target"]["object"]) target_depth = x;
  }
  std::set<std::string> expected, removed;
  for (const auto& [id, x] : depth)
    if (x < target_depth) expected.insert(id);
  for (const Json& id : by_centroid["occluders"]) removed.insert(id.get<std::string>());
  EXPECT_EQ(removed, expected);
  EXPECT_GE(removed.size(), by_path["occluders"].size());
  // The table says which rule chose them.
  EXPECT_NE(centroid.out.find("in the way (centroid nearer the cameras than the target's, the "
                              "paper's rule)"),
            std::string::npos)
      << centroid.out;
  EXPECT_NE(path_rule.out.find("in the way (in the target's path along the approach)"),
            std::string::npos)
      << path_rule.out;

  const auto bad = runCli("plan " + map() + " --target 19 --approach 1,0,0 --occluders box");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--occluders expects path"), std::string::npos) << bad.err;
}

// --threshold reads the map as the studio's Threshold does; plan.json says
// which threshold the objects were read at.
TEST_F(CliPlanTest, ThresholdReadsTheMapAtAnotherProbability) {
  TempDir out;
  const std::string plan = "plan " + map() + " --target 19 --approach 1,0,0 --out " +
                           quoted(out / "plan.json") + " --threshold ";
  const auto surer = runCli(plan + "0.7");
  ASSERT_EQ(surer.exit_code, 0) << surer.err;
  EXPECT_DOUBLE_EQ(Json::parse(slurp(out / "plan.json"))["occupancy_threshold"].get<double>(), 0.7);
  // The objects' voxels (probability 0.9) are not occupied at 0.95.
  const auto none = runCli(plan + "0.95");
  EXPECT_EQ(none.exit_code, 1) << none.err;
  EXPECT_NE(none.err.find("which has no occupied voxel"), std::string::npos) << none.err;
  const auto above = runCli(plan + "0.99");
  EXPECT_EQ(above.exit_code, 2) << above.err;
  EXPECT_NE(above.err.find("option --threshold expects at most 0.97"), std::string::npos)
      << above.err;
}

TEST_F(CliPlanTest, TargetByNameAndApproachFromTheMapsFreeSpace) {
  TempDir out;
  const auto r = runCli("plan " + map() + " --target i_am_a_bunny_book --out " + quoted(out / "plan.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("free space"), std::string::npos) << r.out;
  const Json plan = Json::parse(slurp(out / "plan.json"));
  EXPECT_EQ(plan["target"]["label"], 19);
  EXPECT_EQ(plan["approach"]["source"], "free-space");
  EXPECT_GT(plan["approach"]["direction"][0].get<double>(), 0.95);
  EXPECT_EQ(plan["occluders"], Json::array({"30", "8"}));
  // The map was built without cameras: its boxes stand on +z, said.
  EXPECT_NE(r.err.find("note: " + path("bin.ot").string() +
                       " does not record which way up its cameras were"),
            std::string::npos)
      << r.err;
}

TEST_F(CliPlanTest, SequenceGivesTheMeanViewingDirection) {
  TempDir out;
  const auto r = runCli("plan " + map() + " --target 19 --sequence " + quoted(path("side")) + " --out " +
                        quoted(out / "plan.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json plan = Json::parse(slurp(out / "plan.json"));
  EXPECT_EQ(plan["approach"]["source"], "sequence");
  EXPECT_NEAR(plan["approach"]["direction"][1].get<double>(), -1.0, 1e-9);
  EXPECT_TRUE(plan["occluders"].empty());
  EXPECT_EQ(plan["steps"].size(), 1u);
  // The sequence's depths are not where the map's voxels are: planned, with a warning.
  EXPECT_NE(
      r.err.find("warning: " + path("bin.ot").string() + ": only 0% of the sequence's depths"),
      std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("The approach from --sequence may point anywhere."), std::string::npos)
      << r.err;
  // Its cameras' up stands in for the up the map does not record.
  EXPECT_EQ(r.err.find("does not record which way up"), std::string::npos) << r.err;
}

TEST_F(CliPlanTest, WithoutApproachTheMapsRecordedCamerasGiveIt) {
  TempDir out;
  // The same map, fused (as it were) by cameras looking along -y, as the side sequence.
  lom::LabelMap map = lom::LabelMap::load(path("bin.ot"));
  const Eigen::Matrix3d looking_along_minus_y =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  ASSERT_LT((looking_along_minus_y.col(2) - Eigen::Vector3d(0, -1, 0)).norm(), 1e-12);
  map.noteCameraView(looking_along_minus_y);
  map.noteCameraView(looking_along_minus_y);
  map.save(out / "viewed.ot");
  const auto r = runCli("plan " + quoted(out / "viewed.ot") + " --target 19 --out " +
                        quoted(out / "plan.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("guessed"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("mean viewing direction of the map's cameras"), std::string::npos) << r.out;
  const Json plan = Json::parse(slurp(out / "plan.json"));
  EXPECT_EQ(plan["approach"]["source"], "map-cameras");
  EXPECT_NEAR(plan["approach"]["direction"][1].get<double>(), -1.0, 1e-9);
  EXPECT_TRUE(plan["occluders"].empty());
}

TEST_F(CliPlanTest, EmptyBinCandidatesAndAllClusters) {
  TempDir out;
  const auto r = runCli("plan " + map() +
                        " --target 19 --approach 1,0,0 --empty-bin 0,0.6,0.1,0.4,0.3,0.2"
                        " --candidates 30,8,rolodex_jumbo_pencil_cup --all-clusters --out " +
                        quoted(out / "plan.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json plan = Json::parse(slurp(out / "plan.json"));
  EXPECT_EQ(plan["objects"].size(), 3u);  // 8, 19 (the target is always kept), 30; not 13
  for (const Json& object : plan["objects"])  // named as objects.json names them too
    EXPECT_EQ(object["cluster_voxels"], object["voxels"]);
  EXPECT_EQ(plan["options"]["all_clusters"], true);
  // Each candidate once (30 was given by id and by name), the target among
  // them, in ascending order.
  EXPECT_EQ(plan["options"]["candidates"], Json::array({8, 19, 30}));
  for (int k = 0; k < 2; ++k) {
    const auto& placement = plan["steps"][k]["placement"];
    ASSERT_EQ(placement["where"], "bin") << k;
    const double y = placement["position"][1].get<double>();
    EXPECT_NEAR(y, 0.6, 1e-9);
  }
  EXPECT_NE(r.out.find("bin "), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("not empty"), std::string::npos) << r.err;  // nothing of the map there

  // A bin over the objects (given in the wrong place): placed all the same,
  // with a warning naming what the map has in it.
  const auto over =
      runCli("plan " + map() + " --target 19 --approach 1,0,0 --empty-bin 0.2,0,0.05,0.16,0.2,0.1");
  ASSERT_EQ(over.exit_code, 0) << over.err;
  EXPECT_NE(over.err.find("warning: --empty-bin 0.2,0,0.05,0.16,0.2,0.1 holds "), std::string::npos)
      << over.err;
  // 8's block, 0.16 to 0.24 by 0.1 by 0.09 m at 1 cm: 8 x 10 x 9 voxels.
  EXPECT_NE(over.err.find("occupied voxels of objects in " + path("bin.ot").string() +
                          " (8 (creativity_chenille_stems): 720"),
            std::string::npos)
      << over.err;
  EXPECT_NE(over.err.find("it is not empty there"), std::string::npos) << over.err;
}

TEST_F(CliPlanTest, UnknownTargetLabelFailsNamingTheMap) {
  for (const std::string target : {"99", "no_such_object", "0"}) {
    const auto r = runCli("plan " + map() + " --target " + target + " --approach 1,0,0");
    EXPECT_EQ(r.exit_code, 1) << target << r.out;
    EXPECT_NE(r.err.find(path("bin.ot").string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--target"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("expected"), std::string::npos) << r.err;
  }
}

// Leading zeros are no part of a label id, however many there are.
TEST_F(CliPlanTest, TargetIdsWithLeadingZerosNameTheirLabel) {
  for (const std::string target : {"019", "0000019", "00000000019"}) {
    TempDir out;
    const auto r = runCli("plan " + map() + " --target " + target + " --approach 1,0,0 --out " +
                          quoted(out / "plan.json"));
    ASSERT_EQ(r.exit_code, 0) << target << ": " << r.err;
    EXPECT_EQ(Json::parse(slurp(out / "plan.json"))["target"]["label"], 19) << target;
  }
  const auto background = runCli("plan " + map() + " --target 0000 --approach 1,0,0");
  EXPECT_EQ(background.exit_code, 1);
  EXPECT_NE(background.err.find("the background"), std::string::npos) << background.err;
}

TEST_F(CliPlanTest, TargetWithoutVoxelsFails) {
  const auto r = runCli("plan " + quoted(path("no_target.ot")) + " --target 19 --approach 1,0,0");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no_target.ot"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no occupied voxel"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("i_am_a_bunny_book"), std::string::npos) << r.err;
}

TEST_F(CliPlanTest, WithoutFreeSpaceAnApproachIsNeeded) {
  const auto r = runCli("plan " + quoted(path("no_target.ot")) + " --target 8");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--approach"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--sequence"), std::string::npos) << r.err;
}

TEST_F(CliPlanTest, BadOptionsAreUsageErrors) {
  for (const std::string bad :
       {"--approach 1,2", "--approach 0,0,0", "--approach a,b,c", "--approach 1,0,0,",
        "--empty-bin 0,0,0,1,1", "--empty-bin 0,0,0,1,-1,1", "--min-cluster-voxels 0",
        "--cluster-tolerance 0", "--approach 1,0,0 --sequence x", "--frobnicate 3",
        "--candidates 8,", "--candidates ,8", "--candidates 8,,19", "--candidates ''"}) {
    const auto r = runCli("plan " + map() + " --target 19 " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.err;
    EXPECT_NE(r.err.find("usage: labeloctomap plan"), std::string::npos) << r.err;
  }
  const auto r = runCli("plan " + map() + " --target 19 --approach 1,2");
  EXPECT_NE(r.err.find("--approach"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("x,y,z"), std::string::npos) << r.err;
  const auto missing = runCli("plan " + map());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("--target"), std::string::npos) << missing.err;
}

TEST_F(CliPlanTest, MissingFilesFailNamingThem) {
  TempDir out;
  auto r = runCli("plan " + quoted(out / "absent.ot") + " --target 19 --approach 1,0,0");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("absent.ot"), std::string::npos) << r.err;
  r = runCli("plan " + map() + " --target 19 --sequence " + quoted(out / "no_sequence"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no_sequence"), std::string::npos) << r.err;
  r = runCli("plan " + map() + " --target 19 --approach 1,0,0 --out " +
             quoted(out / "no_folder" / "plan.json"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no_folder"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
}

}  // namespace
