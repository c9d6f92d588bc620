// Hand-computed log-odds for short hit/miss sequences (docs/fusion.md).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "lom/error.hpp"
#include "lom/fusion.hpp"

namespace {

using lom::CameraIntrinsics;
using lom::DepthImage;
using lom::FrameEvidence;
using lom::LabelMap;
using lom::MapParameters;
using lom::ProbabilityImage;

double logitOf(double p) { return std::log(p / (1.0 - p)); }
double probOf(double l) { return 1.0 - 1.0 / (1.0 + std::exp(l)); }

lom::LabelSet threeLabels() {
  return lom::LabelSet({{0, "__background__", {0, 0, 0}}, {1, "book", {128, 0, 0}},
                        {2, "cup", {0, 128, 0}}});
}

// A camera of `width` x 1 pixels whose rays all go (almost exactly) along +z:
// the huge focal length keeps every pixel in the voxel column of the origin.
CameraIntrinsics pencilCamera(int width) {
  CameraIntrinsics camera;
  camera.width = width;
  camera.height = 1;
  camera.fx = camera.fy = 1e6;
  camera.cx = (width - 1) / 2.0;
  camera.cy = 0.0;
  return camera;
}

// The origin sits at a voxel centre (x, y) so rays run along the voxel column.
Eigen::Isometry3d poseAtVoxelCentre() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.005, 0.005, 0.005);
  return T;
}

struct Pixel {
  float depth;
  std::vector<float> proba;  // one value per label
};

// Which integration path the current test runs (every rule must hold for both).
lom::IntegrationPath g_path = lom::IntegrationPath::Reference;

class FusionRulesTest : public ::testing::TestWithParam<lom::IntegrationPath> {
 protected:
  void SetUp() override { g_path = GetParam(); }
};

lom::FrameStats integrate(LabelMap& map, const std::vector<Pixel>& pixels,
                          const std::optional<std::vector<int>>& candidates = std::nullopt) {
  const int width = static_cast<int>(pixels.size());
  DepthImage depth{width, 1, {}};
  ProbabilityImage proba;
  proba.width = width;
  proba.height = 1;
  proba.channels = map.numLabels();
  for (int k = 0; k < map.numLabels(); ++k) proba.channel_labels.push_back(k);
  for (const auto& p : pixels) {
    depth.metres.push_back(p.depth);
    proba.values.insert(proba.values.end(), p.proba.begin(), p.proba.end());
  }
  FrameEvidence evidence(map.numLabels(), &proba, nullptr, candidates, 0.9);
  lom::IntegrationOptions options;
  options.path = g_path;
  return lom::integrateFrame(map, pencilCamera(width), poseAtVoxelCentre(), depth, evidence, options);
}

// Centre of the voxel the pixel at depth d lands in (origin z = 0.005).
Eigen::Vector3d at(double z) { return {0.005, 0.005, z}; }

const double kMin = logitOf(0.12);
const double kMax = logitOf(0.97);
const double kMiss = logitOf(0.3);

TEST_P(FusionRulesTest, OneHitGivesLogitOfEachLabelClampedBelow) {
  LabelMap map(threeLabels());
  integrate(map, {{0.5, {0.7f, 0.2f, 0.1f}}});
  const auto state = map.voxelAt(at(0.505));
  ASSERT_TRUE(state.known);
  EXPECT_TRUE(state.occupied);
  EXPECT_EQ(state.label, 0);
  EXPECT_NEAR(state.probabilities[0], 0.7, 1e-6);
  EXPECT_NEAR(state.probabilities[1], 0.2, 1e-6);
  // logit(0.1) = -2.197 is below logit(0.12): clamped.
  EXPECT_NEAR(state.probabilities[2], 0.12, 1e-6);
}

// What holds the point: the voxel's own centre and edge, not the point asked.
TEST_P(FusionRulesTest, AVoxelsStateNamesItsCentreAndSize) {
  LabelMap map(threeLabels());
  integrate(map, {{0.5, {0.7f, 0.2f, 0.1f}}});
  const auto state = map.voxelAt(Eigen::Vector3d(0.0071, 0.0012, 0.5093));
  ASSERT_TRUE(state.known);
  EXPECT_NEAR((state.center - at(0.505)).norm(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(state.size, 0.01);
  EXPECT_FALSE(map.voxelAt(at(0.705)).known);
  EXPECT_EQ(map.voxelAt(at(0.705)).size, 0.0);
}

TEST_P(FusionRulesTest, TwoFramesAddLogOdds) {
  LabelMap map(threeLabels());
  integrate(map, {{0.5, {0.2f, 0.7f, 0.1f}}});
  integrate(map, {{0.5, {0.3f, 0.6f, 0.1f}}});
  const auto state = map.voxelAt(at(0.505));
  EXPECT_EQ(state.label, 1);
  EXPECT_NEAR(state.probabilities[1], probOf(logitOf(0.7) + logitOf(0.6)), 1e-6);
  EXPECT_NEAR(state.probabilities[0], probOf(std::max(kMin, logitOf(0.2) + logitOf(0.3))), 1e-6);
}

TEST_P(FusionRulesTest, ClampsAtTheUpperBound) {
  LabelMap map(threeLabels());
  for (int i = 0; i < 3; ++i) integrate(map, {{0.5, {0.01f, 0.98f, 0.01f}}});
  const auto state = map.voxelAt(at(0.505));
  EXPECT_NEAR(state.probabilities[1], 0.97, 1e-6);
  // Then one strongly contradicting view lowers it from the clamped value, not from 3 x logit(0.98).
  integrate(map, {{0.5, {0.5f, 0.05f, 0.45f}}});
  EXPECT_NEAR(map.voxelAt(at(0.505)).probabilities[1], probOf(kMax + logitOf(0.05)), 1e-6);
}

TEST_P(FusionRulesTest, MissesLowerEveryLabelUntilTheLowerClamp) {
  LabelMap map(threeLabels());
  integrate(map, {{0.5, {0.7f, 0.2f, 0.1f}}});
  auto state = map.voxelAt(at(0.255));
  ASSERT_TRUE(state.known);
  EXPECT_FALSE(state.occupied);
  for (float p : state.probabilities) EXPECT_NEAR(p, 0.3, 1e-6);
  integrate(map, {{0.5, {0.7f, 0.2f, 0.1f}}});
  state = map.voxelAt(at(0.255));
  for (float p : state.probabilities) EXPECT_NEAR(p, probOf(2 * kMiss), 1e-6);
  integrate(map, {{0.5, {0.7f, 0.2f, 0.1f}}});
  state = map.voxelAt(at(0.255));
  for (float p : state.probabilities) EXPECT_NEAR(p, 0.12, 1e-6);  // 3 x -0.847 < -1.992
  // The voxel behind the hit was never observed.
  EXPECT_FALSE(map.voxelAt(at(0.515)).known);
}

TEST_P(FusionRulesTest, AMissOnAnOccupiedVoxelLowersEveryLabel) {
  LabelMap map(threeLabels());
  integrate(map, {{0.5, {0.1f, 0.8f, 0.1f}}});
  integrate(map, {{0.9, {1.f, 0.f, 0.f}}});  // the ray now passes through the earlier hit
  const auto state = map.voxelAt(at(0.505));
  EXPECT_NEAR(state.probabilities[1], probOf(logitOf(0.8) + kMiss), 1e-6);
  EXPECT_NEAR(state.probabilities[0], probOf(std::max(kMin, kMin + kMiss)), 1e-6);
}

TEST_P(FusionRulesTest, ThresholdBoundaryCountsAsOccupied) {
  LabelMap map(threeLabels());
  integrate(map, {{0.5, {0.5f, 0.3f, 0.2f}}});
  auto state = map.voxelAt(at(0.505));
  EXPECT_NEAR(state.probabilities[0], 0.5, 1e-6);
  EXPECT_TRUE(state.occupied);  // max_k p_k >= 0.5
  map.setOccupancyThreshold(0.51);
  EXPECT_FALSE(map.voxelAt(at(0.505)).occupied);
  EXPECT_TRUE(map.occupiedCountPerLabel().empty());
  map.setOccupancyThreshold(0.5);
  EXPECT_EQ(map.occupiedCountPerLabel().at(0), 1u);
}

// A probability equal to the threshold is "at" it, also where its float
// log-odds fall a unit in the last place below the threshold's: a voxel seen
// once with p = 0.9 (a label image's confidence) was free at threshold 0.9.
TEST_P(FusionRulesTest, AProbabilityEqualToTheThresholdIsOccupiedWhateverItsRounding) {
  for (const double threshold : {0.65, 0.9, 0.95, 0.96}) {
    SCOPED_TRACE(threshold);
    const auto p = static_cast<float>(threshold);
    LabelMap map(threeLabels());
    integrate(map, {{0.5, {0.5f * (1.0f - p), p, 0.5f * (1.0f - p)}}});
    map.setOccupancyThreshold(threshold);
    EXPECT_TRUE(map.voxelAt(at(0.505)).occupied);
    EXPECT_EQ(map.occupiedCountPerLabel().count(1), 1u);
    map.setOccupancyThreshold(threshold + 1e-4);  // above it: free
    EXPECT_FALSE(map.voxelAt(at(0.505)).occupied);
  }
}

TEST_P(FusionRulesTest, TiesGoToTheLowerLabelId) {
  LabelMap map(threeLabels());
  integrate(map, {{0.5, {0.1f, 0.6f, 0.6f}}});
  EXPECT_EQ(map.voxelAt(at(0.505)).label, 1);
  LabelMap map2(threeLabels());
  integrate(map2, {{0.5, {0.6f, 0.6f, 0.1f}}});
  EXPECT_EQ(map2.voxelAt(at(0.505)).label, 0);
}

TEST_P(FusionRulesTest, SeveralPixelsInOneVoxelEachContribute) {
  LabelMap map(threeLabels());
  const auto stats = integrate(map, {{0.5, {0.1f, 0.7f, 0.2f}}, {0.501f, {0.1f, 0.7f, 0.2f}}});
  EXPECT_EQ(stats.hit_voxels, 1u);
  EXPECT_NEAR(map.voxelAt(at(0.505)).probabilities[1], probOf(2 * logitOf(0.7)), 1e-6);
  EXPECT_NEAR(map.voxelAt(at(0.505)).probabilities[2], probOf(std::max(kMin, 2 * logitOf(0.2))),
              1e-6);
}

TEST_P(FusionRulesTest, AVoxelHitInAFrameIsNotMissedInThatFrame) {
  LabelMap map(threeLabels());
  // The second pixel's ray passes through the voxel the first pixel hits.
  const auto stats = integrate(map, {{0.5, {0.1f, 0.7f, 0.2f}}, {0.8, {0.1f, 0.2f, 0.7f}}});
  EXPECT_EQ(stats.hit_voxels, 2u);
  EXPECT_NEAR(map.voxelAt(at(0.505)).probabilities[1], 0.7, 1e-6);
  EXPECT_NEAR(map.voxelAt(at(0.805)).probabilities[2], 0.7, 1e-6);
  // A voxel crossed by both rays is missed once, not twice.
  for (float p : map.voxelAt(at(0.305)).probabilities) EXPECT_NEAR(p, 0.3, 1e-6);
}

TEST_P(FusionRulesTest, BeyondMaxRangeOnlyMissesUpToMaxRange) {
  MapParameters parameters;
  parameters.max_range = 1.0;
  LabelMap map(threeLabels(), parameters);
  const auto stats = integrate(map, {{1.5, {0.1f, 0.8f, 0.1f}}});
  EXPECT_EQ(stats.hit_voxels, 0u);
  EXPECT_FALSE(map.voxelAt(at(1.505)).known);
  EXPECT_NEAR(map.voxelAt(at(0.905)).probabilities[0], 0.3, 1e-6);
  EXPECT_FALSE(map.voxelAt(at(1.205)).known);
  // Unlimited range (<= 0) hits the far point.
  parameters.max_range = 0.0;
  LabelMap unlimited(threeLabels(), parameters);
  integrate(unlimited, {{1.5, {0.1f, 0.8f, 0.1f}}});
  EXPECT_EQ(unlimited.voxelAt(at(1.505)).label, 1);
  EXPECT_TRUE(unlimited.voxelAt(at(1.505)).occupied);
}

// With an unlimited range the farthest depth sets the rays' length: a frame
// whose rays would cross more voxels than the limit is refused before
// anything is integrated, naming the depth; a limited range cuts such rays
// instead, and a limit of 0 lets them through.
TEST_P(FusionRulesTest, UnlimitedRangeRefusesRaysLongerThanTheLimit) {
  MapParameters parameters;
  parameters.max_range = 0.0;
  LabelMap map(threeLabels(), parameters);
  try {
    integrate(map, {{0.5, {0.1f, 0.8f, 0.1f}}, {12.0, {0.1f, 0.8f, 0.1f}}});
    FAIL() << "a depth 1200 voxels away was fused with an unlimited range";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "depth");
    EXPECT_NE(e.problem().found.find("12.00 m"), std::string::npos) << e.what();
    EXPECT_NE(e.problem().found.find("1200 voxels"), std::string::npos) << e.what();
    EXPECT_NE(e.problem().expected.find("within 10 m"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(map.voxelAt(at(0.505)).known);  // nothing of the frame was integrated
  EXPECT_EQ(integrate(map, {{9.9, {0.1f, 0.8f, 0.1f}}}).hit_voxels, 1u);  // 990 voxels

  parameters.max_range = 5.0;
  LabelMap limited(threeLabels(), parameters);
  integrate(limited, {{12.0, {0.1f, 0.8f, 0.1f}}});
  EXPECT_NEAR(limited.voxelAt(at(4.005)).probabilities[1], 0.3, 1e-6);

  parameters.max_range = 0.0;
  LabelMap unbounded(threeLabels(), parameters);
  const int width = 1;
  DepthImage depth{width, 1, {12.0f}};
  ProbabilityImage proba{1, 1, 3, {0, 1, 2}, {0.1f, 0.8f, 0.1f}, {}};
  FrameEvidence evidence(3, &proba, nullptr, std::nullopt, 0.9);
  lom::IntegrationOptions options;
  options.path = g_path;
  options.max_voxels_per_ray = 0.0;
  lom::integrateFrame(unbounded, pencilCamera(width), poseAtVoxelCentre(), depth, evidence,
                      options);
  EXPECT_EQ(unbounded.voxelAt(at(12.005)).label, 1);
}

// IntegrationOptions::frame_memory_limit_bytes: a frame whose rays cross more
// voxels than the limit takes (kFusionBytesPerCrossedVoxel each) is refused
// before it changes the map, naming the depth, the voxels and the memory; one
// that fits is fused. The fast path checks (the reference path does not).
void refuseAFrameWhoseRaysCrossMoreVoxelsThanTheLimitTakes() {
  LabelMap map(threeLabels());
  const int width = 2;
  DepthImage depth{width, 1, {0.5f, 0.5f}};  // rays of 50 voxels along z
  ProbabilityImage proba{width, 1, 3, {0, 1, 2}, {0.1f, 0.8f, 0.1f, 0.1f, 0.8f, 0.1f}, {}};
  FrameEvidence evidence(3, &proba, nullptr, std::nullopt, 0.9);
  lom::IntegrationOptions options;
  options.path = lom::IntegrationPath::Fast;
  options.frame_memory_limit_bytes = 40 * lom::kFusionBytesPerCrossedVoxel;
  try {
    lom::integrateFrame(map, pencilCamera(width), poseAtVoxelCentre(), depth, evidence, options);
    FAIL() << "a frame crossing 50 voxels was fused in the memory of 40";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "depth");
    EXPECT_NE(e.problem().found.find("rays crossing 50 voxels, 50 of them new to the map"),
              std::string::npos)
        << e.what();
    EXPECT_NE(e.problem().expected.find("of memory allowed per frame"), std::string::npos)
        << e.what();
    EXPECT_NE(e.problem().expected.find("coarser voxels or a shorter max range"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(map.voxelAt(at(0.505)).known);  // nothing of the frame was integrated
  EXPECT_FALSE(map.voxelAt(at(0.205)).known);

  options.frame_memory_limit_bytes =
      60 * lom::kFusionBytesPerCrossedVoxel;  // both rays cross the same 50
  lom::integrateFrame(map, pencilCamera(width), poseAtVoxelCentre(), depth, evidence, options);
  EXPECT_EQ(map.voxelAt(at(0.505)).label, 1);
  EXPECT_TRUE(map.voxelAt(at(0.205)).known);

  // The same frame again: its voxels are in the map now and take only their
  // place in the update streams, so the limit that refused it lets it through.
  options.frame_memory_limit_bytes = 40 * lom::kFusionBytesPerCrossedVoxel;
  EXPECT_NO_THROW(
      lom::integrateFrame(map, pencilCamera(width), poseAtVoxelCentre(), depth, evidence, options));

  options.frame_memory_limit_bytes = 0.0;  // the memory available: a frame this small fits
  lom::integrateFrame(map, pencilCamera(width), poseAtVoxelCentre(), depth, evidence, options);
}

// IntegrationOptions::cancelled: asked before the frame and between its
// phases; a frame cancelled at any of them leaves the map as it was, and the
// next frame fuses as if the cancelled one had never started.
TEST(FrameCancel, AFrameCancelledBetweenItsPhasesLeavesTheMapAsItWas) {
  const int width = 2;
  DepthImage depth{width, 1, {0.5f, 0.7f}};
  ProbabilityImage proba{width, 1, 3, {0, 1, 2}, {0.1f, 0.8f, 0.1f, 0.2f, 0.2f, 0.6f}, {}};
  FrameEvidence evidence(3, &proba, nullptr, std::nullopt, 0.9);
  lom::IntegrationOptions plain;
  plain.path = lom::IntegrationPath::Fast;
  LabelMap expected(threeLabels());
  lom::integrateFrame(expected, pencilCamera(width), poseAtVoxelCentre(), depth, evidence, plain);
  const auto expectSameMap = [&](const LabelMap& map) {
    for (const double z : {0.205, 0.505, 0.705}) {
      const auto voxel = map.voxelAt(at(z));
      const auto wanted = expected.voxelAt(at(z));
      EXPECT_EQ(voxel.known, wanted.known) << z;
      EXPECT_EQ(voxel.label, wanted.label) << z;
      for (size_t k = 0; k < 3; ++k)
        EXPECT_EQ(voxel.probabilities[k], wanted.probabilities[k]) << z << " label " << k;
    }
  };
  // Asked before the frame, after the rays, after the memory check (when it
  // runs: a limit given), after the update streams and after their merge.
  for (const auto& [limit, asks] : {std::pair{0.0, 4}, std::pair{1e12, 5}}) {
    for (int cancel_at = 1; cancel_at <= asks + 1; ++cancel_at) {
      SCOPED_TRACE("limit " + std::to_string(limit) + ", cancelled at ask " +
                   std::to_string(cancel_at));
      LabelMap map(threeLabels());
      int asked = 0;
      lom::IntegrationOptions options = plain;
      options.frame_memory_limit_bytes = limit;
      options.cancelled = [&] { return ++asked == cancel_at; };
      bool cancelled = false;
      try {
        lom::integrateFrame(map, pencilCamera(width), poseAtVoxelCentre(), depth, evidence,
                            options);
      } catch (const lom::FrameCancelled&) {
        cancelled = true;
      }
      if (cancel_at > asks) {  // asked every time and never told to stop: fused
        EXPECT_FALSE(cancelled);
        EXPECT_EQ(asked, asks);
        expectSameMap(map);
        continue;
      }
      ASSERT_TRUE(cancelled);
      EXPECT_EQ(map.numNodes(), 0u) << "the cancelled frame changed the map";
      lom::integrateFrame(map, pencilCamera(width), poseAtVoxelCentre(), depth, evidence, plain);
      expectSameMap(map);
    }
  }
}

// On a thread of its own: the stream buffers a frame may reuse are the
// thread's own from its earlier frames (none here), not whatever the tests
// before left in the main thread's (their size depended on how those tests'
// rays were shared out between the threads, so the refusal came and went).
TEST(FrameMemoryLimit, RefusesAFrameWhoseRaysCrossMoreVoxelsThanTheLimitTakes) {
  std::thread(refuseAFrameWhoseRaysCrossMoreVoxelsThanTheLimitTakes).join();
}

// Rays of two threads crossing the same voxels count them once: the check
// is the same for every thread count and every way the rows are shared out
// (a sum over the threads refused frames at random near the limit).
TEST(FrameMemoryLimit, VoxelsMarkedByBothThreadsCountOnce) {
  CameraIntrinsics camera = pencilCamera(1);
  camera.height = 4;
  camera.cy = 1.5;  // four rows, every ray along the same column of voxels
  DepthImage depth{1, 4, {0.5f, 0.5f, 0.5f, 0.5f}};
  ProbabilityImage proba{1, 4, 3, {0, 1, 2}, std::vector<float>(12, 0.1f), {}};
  for (size_t i = 1; i < 12; i += 3) proba.values[i] = 0.8f;
  FrameEvidence evidence(3, &proba, nullptr, std::nullopt, 0.9);
  for (int threads : {1, 2, 4}) {
    SCOPED_TRACE(threads);
    LabelMap map(threeLabels());
    lom::IntegrationOptions options;
    options.path = lom::IntegrationPath::Fast;
    options.threads = threads;
    options.frame_memory_limit_bytes = 60 * lom::kFusionBytesPerCrossedVoxel;  // 50 crossed
    EXPECT_NO_THROW(
        lom::integrateFrame(map, camera, poseAtVoxelCentre(), depth, evidence, options));
    EXPECT_EQ(map.voxelAt(at(0.505)).label, 1);
  }
}

// In a child process: limits the address space to 64 MiB more than it uses,
// and exits with 0 when availableMemoryBytes keeps within what that leaves.
[[noreturn]] void exitWithAvailableMemoryUnderALimit() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0;
  statm >> pages;
  const double room = 64.0 * 1024 * 1024;
  const auto limit = static_cast<rlim_t>(pages * static_cast<double>(sysconf(_SC_PAGESIZE)) + room);
  rlimit address_space{};
  address_space.rlim_cur = address_space.rlim_max = limit;
  if (setrlimit(RLIMIT_AS, &address_space) != 0) std::exit(3);
  const std::optional<double> available = lom::availableMemoryBytes();
  std::exit(available && *available <= room && *available > 0.0 ? 0 : 4);
}

// Under a limit on the address space (ulimit -v), no more memory is available
// than the limit leaves (checked in a child process, whose limit ends with it).
TEST(FrameMemoryLimit, AvailableMemoryKeepsWithinTheAddressSpaceLimit) {
  const std::optional<double> unlimited = lom::availableMemoryBytes();
  ASSERT_TRUE(unlimited) << "/proc/meminfo gave no MemAvailable";
  EXPECT_GT(*unlimited, 64.0 * 1024 * 1024);
  // Re-executed rather than forked: earlier tests in the same run leave the
  // fusion's worker threads, and a fork of a threaded process may crash.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(exitWithAvailableMemoryUnderALimit(), ::testing::ExitedWithCode(0), "");
}

TEST_P(FusionRulesTest, CandidatesZeroOtherLabelsAndRenormalise) {
  LabelMap map(threeLabels());
  integrate(map, {{0.5, {0.5f, 0.3f, 0.2f}}}, std::vector<int>{1, 2});
  const auto state = map.voxelAt(at(0.505));
  EXPECT_EQ(state.label, 1);
  EXPECT_NEAR(state.probabilities[1], 0.6, 1e-6);
  EXPECT_NEAR(state.probabilities[2], 0.4, 1e-6);
  EXPECT_NEAR(state.probabilities[0], 0.12, 1e-6);
}

TEST_P(FusionRulesTest, CandidatesWithNoMassBecomeUniform) {
  ProbabilityImage proba{1, 1, 3, {0, 1, 2}, {1.f, 0.f, 0.f}, {}};
  FrameEvidence evidence(3, &proba, nullptr, std::vector<int>{1, 2}, 0.9);
  float p[3];
  EXPECT_FALSE(evidence.probabilities(0, 0, p));  // no probability for any candidate
  EXPECT_FLOAT_EQ(p[0], 0.f);
  EXPECT_FLOAT_EQ(p[1], 0.5f);
  EXPECT_FLOAT_EQ(p[2], 0.5f);
  // Such a pixel has no label to project (not the lower of the tied candidates).
  EXPECT_EQ(evidence.argmax(0, 0), -1);
  // A pixel with some probability for a candidate has its argmax.
  ProbabilityImage some{1, 1, 3, {0, 1, 2}, {0.9f, 0.f, 0.1f}, {}};
  FrameEvidence with_mass(3, &some, nullptr, std::vector<int>{1, 2}, 0.9);
  EXPECT_TRUE(with_mass.probabilities(0, 0, p));
  EXPECT_FLOAT_EQ(p[2], 1.f);
  EXPECT_EQ(with_mass.argmax(0, 0), 2);
}

TEST_P(FusionRulesTest, ZeroAndOneProbabilitiesGiveFiniteLogOdds) {
  ProbabilityImage proba{1, 1, 3, {0, 1, 2}, {0.f, 1.f, 0.f}, {}};
  FrameEvidence evidence(3, &proba, nullptr, std::nullopt, 0.9);
  float l[3];
  evidence.logOdds(0, 0, l);
  for (float v : l) EXPECT_TRUE(std::isfinite(v));
  EXPECT_GT(l[1], 10.f);
  EXPECT_LT(l[0], -10.f);
}

TEST_P(FusionRulesTest, LabelImageBecomesOneHotWithConfidence) {
  lom::LabelImage label{2, 1, {2, 0}};
  FrameEvidence evidence(3, nullptr, &label, std::nullopt, 0.9);
  float p[3];
  evidence.probabilities(0, 0, p);
  EXPECT_FLOAT_EQ(p[2], 0.9f);
  EXPECT_FLOAT_EQ(p[0], 0.05f);
  EXPECT_FLOAT_EQ(p[1], 0.05f);
  EXPECT_EQ(evidence.argmax(1, 0), 0);
}

TEST_P(FusionRulesTest, UnlistedChannelsHaveProbabilityZero) {
  // Channels for labels 0 and 2 only: label 1 gets 0.
  ProbabilityImage proba{1, 1, 2, {0, 2}, {0.25f, 0.75f}, {}};
  FrameEvidence evidence(3, &proba, nullptr, std::nullopt, 0.9);
  float p[3];
  evidence.probabilities(0, 0, p);
  EXPECT_FLOAT_EQ(p[0], 0.25f);
  EXPECT_FLOAT_EQ(p[1], 0.f);
  EXPECT_FLOAT_EQ(p[2], 0.75f);
}

TEST_P(FusionRulesTest, RejectsBadParametersAndMismatchedInputs) {
  MapParameters bad;
  bad.p_miss = 1.0;
  EXPECT_THROW(LabelMap(threeLabels(), bad), lom::Error);
  bad = {};
  bad.resolution = 0.0;
  EXPECT_THROW(LabelMap(threeLabels(), bad), lom::Error);
  bad = {};
  bad.clamp_min = 0.9;
  bad.clamp_max = 0.5;
  EXPECT_THROW(LabelMap(threeLabels(), bad), lom::Error);

  ProbabilityImage proba{1, 1, 3, {0, 1, 7}, {0.2f, 0.3f, 0.5f}, {}};
  try {
    FrameEvidence evidence(3, &proba, nullptr, std::nullopt, 0.9);
    FAIL() << "expected an error for label 7";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "proba_labels");
    EXPECT_NE(std::string(e.what()).find("7"), std::string::npos);
  }
  ProbabilityImage ok{2, 1, 3, {0, 1, 2}, std::vector<float>(6, 0.3f), {}};
  FrameEvidence evidence(3, &ok, nullptr, std::nullopt, 0.9);
  LabelMap map(threeLabels());
  DepthImage depth{3, 1, {0.5f, 0.5f, 0.5f}};
  EXPECT_THROW(lom::integrateFrame(map, pencilCamera(3), poseAtVoxelCentre(), depth, evidence),
               lom::Error);
}

INSTANTIATE_TEST_SUITE_P(BothPaths, FusionRulesTest,
                         ::testing::Values(lom::IntegrationPath::Reference,
                                           lom::IntegrationPath::Fast),
                         [](const auto& info) {
                           return info.param == lom::IntegrationPath::Fast ? "Fast" : "Reference";
                         });

}  // namespace
