// How much of a frame lies beyond max range (fusion keeps only free space
// there): countDepthRanges must agree with fusion pixel by pixel, and
// fuseSequence reports the counts so that callers can warn.
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
  camera.width = 5;
  camera.height = 4;
  camera.fx = 2.0;
  camera.fy = 2.5;
  camera.cx = 2.0;
  camera.cy = 1.5;
  return camera;
}

// Depths spread around 1 m of distance from the camera, with invalid pixels.
lom::DepthImage spreadDepths(const lom::CameraIntrinsics& camera) {
  lom::DepthImage depth{camera.width, camera.height, {}};
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u)
      depth.metres.push_back(0.55f + 0.05f * static_cast<float>(u + 2 * v));
  depth.metres[0] = 0.0f;
  depth.metres[1] = std::numeric_limits<float>::quiet_NaN();
  depth.metres[2] = std::numeric_limits<float>::infinity();
  depth.metres[3] = -1.0f;
  return depth;
}

TEST(DepthRangesTest, CountsMeasuredPixelsFartherThanMaxRangeFromTheCamera) {
  const lom::CameraIntrinsics camera = smallCamera();
  const lom::DepthImage depth = spreadDepths(camera);
  size_t measured = 0, beyond = 0;
  double farthest = 0.0;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const float z = depth.at(u, v);
      if (!(z > 0.0f) || !std::isfinite(z)) continue;
      const double distance = camera.backProject(u, v, z).norm();
      ++measured;
      beyond += distance > 1.0 ? 1 : 0;
      farthest = std::max(farthest, distance);
    }
  ASSERT_GT(beyond, 3u);
  ASSERT_LT(beyond, measured - 3);
  const lom::DepthRanges ranges = lom::countDepthRanges(camera, depth, 1.0);
  EXPECT_EQ(ranges.measured, measured);
  EXPECT_EQ(ranges.measured, 16u);
  EXPECT_EQ(ranges.beyond, beyond);
  EXPECT_NEAR(ranges.farthest, farthest, 1e-12);
  // Max range <= 0 is unlimited: nothing is beyond.
  EXPECT_EQ(lom::countDepthRanges(camera, depth, 0.0).beyond, 0u);
  EXPECT_EQ(lom::countDepthRanges(camera, depth, 100.0).beyond, 0u);
}

TEST(DepthRangesTest, AgreesWithFusionPixelByPixel) {
  // Each pixel alone in a frame: fusion gives it a hit exactly when it is within range.
  const lom::CameraIntrinsics camera = smallCamera();
  const lom::DepthImage all = spreadDepths(camera);
  const lom::LabelSet labels({{0, "bg", {0, 0, 0}}, {1, "thing", {1, 1, 1}}});
  const lom::LabelImage label{camera.width, camera.height,
                              std::vector<std::uint16_t>(all.metres.size(), 1)};
  const lom::FrameEvidence evidence(2, nullptr, &label, std::nullopt, 0.9);
  for (const auto path : {lom::IntegrationPath::Reference, lom::IntegrationPath::Fast}) {
    for (size_t i = 4; i < all.metres.size(); ++i) {
      lom::DepthImage one{camera.width, camera.height, std::vector<float>(all.metres.size(), 0.0f)};
      one.metres[i] = all.metres[i];
      lom::MapParameters parameters;
      parameters.max_range = 1.0;
      lom::LabelMap map(labels, parameters);
      lom::IntegrationOptions options;
      options.path = path;
      const lom::FrameStats stats =
          lom::integrateFrame(map, camera, Eigen::Isometry3d::Identity(), one, evidence, options);
      const lom::DepthRanges ranges = lom::countDepthRanges(camera, one, 1.0);
      EXPECT_EQ(stats.valid_pixels, 1u);
      EXPECT_EQ(ranges.measured, 1u);
      EXPECT_EQ(stats.hit_voxels, 1u - ranges.beyond) << "pixel " << i;
    }
  }
}

TEST(DepthRangesTest, FuseSequenceReportsPixelsBeyondMaxRange) {
  lom::test::TempDir dir;
  const lom::CameraIntrinsics camera = smallCamera();
  fs::create_directories(dir / "depth");
  fs::create_directories(dir / "label");
  lom::Sequence sequence;
  sequence.root = dir.path();
  sequence.labels = lom::LabelSet({{0, "bg", {0, 0, 0}}, {1, "thing", {1, 1, 1}}});
  sequence.camera = camera;
  lom::DepthImage depth = spreadDepths(camera);
  for (float& z : depth.metres)
    if (!std::isfinite(z) || z < 0.0f) z = 0.0f;
  for (int i = 0; i < 2; ++i) {
    lom::FrameRecord frame;
    frame.depth = "depth/" + std::to_string(i) + ".png";
    frame.label = "label/" + std::to_string(i) + ".png";
    lom::writeDepthPng(dir / frame.depth, depth, camera.depth_scale);
    lom::writeLabelPng(dir / frame.label,
                       {camera.width, camera.height, std::vector<std::uint16_t>(20, 1)});
    sequence.frames.push_back(frame);
  }
  lom::saveSequence(sequence, dir.path());
  const lom::Sequence loaded = lom::loadSequence(dir.path());
  const lom::DepthRanges expected =
      lom::countDepthRanges(camera, lom::loadFrame(loaded, 0).depth, 1.0);
  ASSERT_GT(expected.beyond, 0u);

  lom::FusionOptions options;
  options.map.max_range = 1.0;
  std::vector<lom::FusionProgress> reports;
  (void)lom::fuseSequence(loaded, options, [&](const lom::FusionProgress& progress) {
    reports.push_back(progress);
    return true;
  });
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_EQ(reports[0].stats.beyond_range_pixels, expected.beyond);
  EXPECT_NEAR(reports[0].stats.farthest_range, expected.farthest, 1e-12);
  EXPECT_EQ(reports[1].totals.beyond_range_pixels, 2 * expected.beyond);
  EXPECT_EQ(reports[1].totals.valid_pixels, 2 * expected.measured);
  EXPECT_EQ(reports[1].totals.valid_pixels,
            reports[0].stats.valid_pixels + reports[1].stats.valid_pixels);
  EXPECT_NEAR(reports[1].totals.farthest_range, expected.farthest, 1e-12);
}

// "Most depths beyond max range" counts against every measured depth: a depth
// beyond max range may also lie outside the map's extent (not among the
// valid pixels), and one far depth beside one mapped one is half, not all.
TEST(DepthRangesTest, MostDepthsBeyondMaxRangeCountsDepthsOutsideTheMap) {
  lom::FrameStats totals;
  totals.valid_pixels = 1;
  totals.outside_map_pixels = 1;
  totals.beyond_range_pixels = 1;  // the one outside the map
  EXPECT_EQ(lom::measuredPixels(totals), 2u);
  EXPECT_FALSE(lom::mostDepthsBeyondMaxRange(totals, 1.0));
  totals.beyond_range_pixels = 2;
  EXPECT_TRUE(lom::mostDepthsBeyondMaxRange(totals, 1.0));
  EXPECT_FALSE(lom::mostDepthsBeyondMaxRange(totals, 0.0));  // unlimited range
}

TEST(SuggestedResolution, RaysCrossAtMost250VoxelsInStepsOfFiveMillimetres) {
  EXPECT_DOUBLE_EQ(lom::suggestedResolutionForRange(10.0, 0.01), 0.04);
  EXPECT_DOUBLE_EQ(lom::suggestedResolutionForRange(10.0, 0.005), 0.04);
  EXPECT_DOUBLE_EQ(lom::suggestedResolutionForRange(2.0, 0.005), 0.01);    // 8 mm, rounded up
  EXPECT_DOUBLE_EQ(lom::suggestedResolutionForRange(1.25, 0.005), 0.005);  // exactly 250
  EXPECT_DOUBLE_EQ(lom::suggestedResolutionForRange(1.0, 0.01), 0.01);     // never finer than asked
  EXPECT_DOUBLE_EQ(lom::suggestedResolutionForRange(20.0, 0.1), 0.1);
  // Never coarser than fusion takes: past 250 m the rays get longer instead.
  EXPECT_DOUBLE_EQ(lom::suggestedResolutionForRange(600.0, 0.01), lom::kMaxFusionResolution);
}

}  // namespace
