// The map's extent (OctoMap's 16-bit keys: 32768 voxels either side of the
// origin on each axis): fusion refuses a camera outside it, and counts the
// depth pixels whose points fall outside, which the map cannot hold.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "lom/fusion.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

lom::CameraIntrinsics smallCamera() {
  lom::CameraIntrinsics camera;
  camera.width = 6;
  camera.height = 4;
  camera.fx = 4.0;
  camera.fy = 4.0;
  camera.cx = 2.5;
  camera.cy = 1.5;
  return camera;
}

// A camera at `x` on the x axis, looking along +x.
Eigen::Isometry3d lookingAlongX(double x) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return pose;
}

// Near columns at 0.1 m, far ones at 1 m, and two pixels without a measurement.
lom::DepthImage nearAndFar(const lom::CameraIntrinsics& camera) {
  lom::DepthImage depth{camera.width, camera.height, {}};
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) depth.metres.push_back(u < 2 ? 0.1f : 1.0f);
  depth.metres[0] = 0.0f;
  depth.metres[7] = std::numeric_limits<float>::quiet_NaN();
  return depth;
}

const lom::LabelSet& twoLabels() {
  static const lom::LabelSet labels({{0, "bg", {0, 0, 0}}, {1, "thing", {1, 1, 1}}});
  return labels;
}

TEST(MapExtentTest, IsTheKeyRangeOfTheGrid) {
  EXPECT_DOUBLE_EQ(lom::mapExtent(0.01), 327.68);
  EXPECT_DOUBLE_EQ(lom::mapExtent(0.002), 65.536);
  EXPECT_TRUE(lom::insideMapExtent({327.67, 0.0, 0.0}, 0.01));
  EXPECT_FALSE(lom::insideMapExtent({327.68, 0.0, 0.0}, 0.01));
  EXPECT_TRUE(lom::insideMapExtent({-327.68, 0.0, 0.0}, 0.01));
  EXPECT_FALSE(lom::insideMapExtent({0.0, -327.69, 0.0}, 0.01));
  EXPECT_FALSE(lom::insideMapExtent({0.0, 0.0, 65.6}, 0.002));
  EXPECT_FALSE(lom::insideMapExtent({1e20, 0.0, 0.0}, 1.0));
  EXPECT_EQ(lom::describeMapExtent(0.01),
            "327.68 m either side of the origin on each axis at 0.01 m voxels");
}

TEST(MapExtentTest, ResolutionForReachIsTheFinestWholeMillimetreThatHoldsIt) {
  EXPECT_DOUBLE_EQ(lom::resolutionForReach(1.0), 0.001);
  EXPECT_DOUBLE_EQ(lom::resolutionForReach(65.3), 0.002);
  EXPECT_DOUBLE_EQ(lom::resolutionForReach(327.4), 0.01);
  EXPECT_DOUBLE_EQ(lom::resolutionForReach(327.68), 0.011);  // 327.68 m is just outside at 1 cm
  for (const double reach : {3.0, 65.536, 100.0, 327.68, 5000.0}) {
    const double resolution = lom::resolutionForReach(reach);
    EXPECT_TRUE(lom::insideMapExtent({reach, -reach, reach}, resolution)) << reach;
    EXPECT_FALSE(lom::insideMapExtent({reach, 0.0, 0.0}, resolution - 0.001)) << reach;
  }
  EXPECT_TRUE(std::isinf(lom::resolutionForReach(1e20)));
}

TEST(MapExtentTest, IntegrateFrameRefusesACameraOutsideTheMap) {
  const lom::CameraIntrinsics camera = smallCamera();
  const lom::DepthImage depth = nearAndFar(camera);
  const lom::LabelImage label{camera.width, camera.height,
                              std::vector<std::uint16_t>(depth.metres.size(), 1)};
  const lom::FrameEvidence evidence(2, nullptr, &label, std::nullopt, 0.9);
  for (const auto path : {lom::IntegrationPath::Reference, lom::IntegrationPath::Fast}) {
    lom::LabelMap map(twoLabels(), lom::MapParameters{});
    lom::IntegrationOptions options;
    options.path = path;
    try {
      (void)lom::integrateFrame(map, camera, lookingAlongX(400.0), depth, evidence, options);
      ADD_FAILURE() << "a camera at 400 m was fused into a map of 1 cm voxels";
    } catch (const lom::Error& e) {
      EXPECT_EQ(e.problem().field, "pose");
      EXPECT_NE(e.problem().expected.find("327.68 m either side of the origin"), std::string::npos)
          << e.what();
      EXPECT_NE(e.problem().expected.find("voxels of 0.013 m or more"), std::string::npos)
          << e.what();
      EXPECT_NE(e.problem().found.find("(400, 0, 0) m"), std::string::npos) << e.what();
    }
    EXPECT_EQ(map.numLeaves(), 0u);
  }
}

// Camera 0.28 m inside the extent: the near columns' points lie inside, the
// far ones' (1 m away) outside. Both paths keep the same pixels, and the
// frame's stats count the others instead of passing them for invalid.
TEST(MapExtentTest, PixelsOutsideTheMapAreCountedAndLeftOutByBothPaths) {
  const lom::CameraIntrinsics camera = smallCamera();
  const lom::DepthImage depth = nearAndFar(camera);
  const Eigen::Isometry3d pose = lookingAlongX(327.4);
  size_t inside = 0, outside = 0;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const float z = depth.at(u, v);
      if (!(z > 0.0f)) continue;
      const Eigen::Vector3d p = pose * camera.backProject(u, v, z);
      (p.x() < 327.68 ? inside : outside) += 1;
    }
  ASSERT_GT(inside, 3u);
  ASSERT_GT(outside, 3u);

  const lom::LabelImage label{camera.width, camera.height,
                              std::vector<std::uint16_t>(depth.metres.size(), 1)};
  const lom::FrameEvidence evidence(2, nullptr, &label, std::nullopt, 0.9);
  lom::MapParameters parameters;
  parameters.max_range = 2.0;
  std::vector<lom::FrameStats> stats;
  std::vector<size_t> leaves;
  for (const auto path : {lom::IntegrationPath::Reference, lom::IntegrationPath::Fast}) {
    lom::LabelMap map(twoLabels(), parameters);
    lom::IntegrationOptions options;
    options.path = path;
    lom::FrameStats frame = lom::integrateFrame(map, camera, pose, depth, evidence, options);
    lom::noteDepthRanges(frame, camera, depth, parameters.max_range);
    EXPECT_EQ(frame.valid_pixels, inside);
    EXPECT_EQ(frame.outside_map_pixels, outside);
    stats.push_back(frame);
    leaves.push_back(map.numLeaves());
  }
  EXPECT_EQ(stats[0].hit_voxels, stats[1].hit_voxels);
  EXPECT_EQ(stats[0].miss_voxels, stats[1].miss_voxels);
  EXPECT_EQ(leaves[0], leaves[1]);

  lom::FrameStats totals;
  lom::addFrameStats(totals, stats[0]);
  lom::addFrameStats(totals, stats[1]);
  EXPECT_EQ(totals.outside_map_pixels, 2 * outside);
}

// A sequence of two small frames written to `dir`, the second camera at `x`.
lom::Sequence twoFrames(const fs::path& dir, double x) {
  const lom::CameraIntrinsics camera = smallCamera();
  fs::create_directories(dir / "depth");
  fs::create_directories(dir / "label");
  lom::Sequence sequence;
  sequence.root = dir;
  sequence.labels = twoLabels();
  sequence.camera = camera;
  lom::DepthImage depth = nearAndFar(camera);
  depth.metres[7] = 0.0f;  // PNG has no NaN
  for (int i = 0; i < 2; ++i) {
    lom::FrameRecord frame;
    frame.depth = "depth/" + std::to_string(i) + ".png";
    frame.label = "label/" + std::to_string(i) + ".png";
    frame.T_world_camera = lookingAlongX(i == 1 ? x : 0.0);
    lom::writeDepthPng(dir / frame.depth, depth, camera.depth_scale);
    lom::writeLabelPng(dir / frame.label, {camera.width, camera.height,
                                           std::vector<std::uint16_t>(depth.metres.size(), 1)});
    sequence.frames.push_back(frame);
  }
  lom::saveSequence(sequence, dir);
  return lom::loadSequence(dir);
}

TEST(MapExtentTest, FuseSequenceNamesTheFrameWhoseCameraIsOutsideBeforeFusingAny) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = twoFrames(dir.path(), 400.0);
  size_t fused = 0;
  try {
    (void)lom::fuseSequence(sequence, lom::FusionOptions{}, [&](const lom::FusionProgress&) {
      ++fused;
      return true;
    });
    ADD_FAILURE() << "a camera at 400 m was fused into a map of 1 cm voxels";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().file, (dir / "sequence.json").string());
    EXPECT_EQ(e.problem().field, "frames[1].pose");
    EXPECT_NE(e.problem().expected.find("327.68 m either side"), std::string::npos) << e.what();
  }
  EXPECT_EQ(fused, 0u);
  // At 2 cm voxels the map reaches 655.36 m: it holds that camera.
  lom::FusionOptions coarse;
  coarse.map.resolution = 0.02;
  EXPECT_NO_THROW((void)lom::fuseSequence(sequence, coarse));
  // Frames left out by the range are not checked.
  lom::FusionOptions first_only;
  first_only.last_frame = 1;
  EXPECT_NO_THROW((void)lom::fuseSequence(sequence, first_only));
}

TEST(MapExtentTest, CamerasOutsideEveryMapAreProblemsAndOutsideTheFinestAWarning) {
  lom::Sequence sequence;
  sequence.root = "/data/seq";
  for (const double x : {0.0, 100.0, 1e20, 70.0, 0.5}) {
    lom::FrameRecord frame;
    frame.T_world_camera.translation() = Eigen::Vector3d(x, 0.0, 1.0);
    sequence.frames.push_back(frame);
  }
  const lom::CameraExtentCheck check = lom::checkCameraExtents(sequence);
  ASSERT_EQ(check.problems.size(), 1u);
  EXPECT_EQ(check.problems[0].file, "/data/seq/sequence.json");
  EXPECT_EQ(check.problems[0].field, "frames[2].pose");
  EXPECT_NE(
      check.problems[0].expected.find("32768 m either side of the origin on each axis at 1 m"),
      std::string::npos)
      << check.problems[0].message();
  EXPECT_NE(check.problems[0].found.find("1e+20"), std::string::npos)
      << check.problems[0].message();
  EXPECT_NE(check.warning.find("frames[1].pose and 1 other frame:"), std::string::npos)
      << check.warning;
  EXPECT_NE(check.warning.find("65.536 m either side"), std::string::npos) << check.warning;
  EXPECT_NE(check.warning.find("voxels of 0.004 m or more"), std::string::npos) << check.warning;

  sequence.frames.erase(sequence.frames.begin() + 1, sequence.frames.begin() + 4);
  const lom::CameraExtentCheck near = lom::checkCameraExtents(sequence);
  EXPECT_TRUE(near.problems.empty());
  EXPECT_TRUE(near.warning.empty());
}

}  // namespace
