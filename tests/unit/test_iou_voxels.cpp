// Voxel cubes against oriented boxes, and the IU_3d of voxel sets.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "lom/box_fit.hpp"
#include "lom/evaluation.hpp"
#include "lom/iou.hpp"
#include "lom/score_breakdown.hpp"

namespace {

using lom::OrientedBox;

constexpr double kEdge = 0.01;

OrientedBox tiltedBox() {
  OrientedBox b;
  b.center = {0.113, -0.047, 0.052};
  b.size = {0.083, 0.051, 0.037};
  b.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.6, Eigen::Vector3d(0.3, -0.5, 1.0).normalized()));
  return b;
}

// Fraction of `samples` uniform points of the voxel inside the box, as a volume,
// with its standard error.
std::pair<double, double> monteCarloVolume(const OrientedBox& box, const Eigen::Vector3d& voxel_center,
                                           int samples, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(-0.5 * kEdge, 0.5 * kEdge);
  int inside = 0;
  for (int i = 0; i < samples; ++i)
    inside += box.contains(voxel_center + Eigen::Vector3d(offset(rng), offset(rng), offset(rng)));
  const double voxel = kEdge * kEdge * kEdge;
  const double fraction = static_cast<double>(inside) / samples;
  return {fraction * voxel, std::sqrt(fraction * (1 - fraction) / samples) * voxel};
}

TEST(IouVoxelVolume, PartialVoxelsAgreeWithMonteCarlo) {
  const OrientedBox box = tiltedBox();
  const lom::VoxelBoxIntersector intersector(box, kEdge);
  const Eigen::Matrix3d axes = box.rotation.toRotationMatrix();
  const Eigen::Vector3d half = 0.5 * box.size;
  // Voxels centred on a box corner, on an edge and on a face: each is cut.
  const std::vector<Eigen::Vector3d> centers = {
      box.center + axes * half,
      box.center + axes * Eigen::Vector3d(half.x(), -half.y(), 0.0),
      box.center + axes * Eigen::Vector3d(0.0, 0.0, -half.z()) + Eigen::Vector3d(0.001, 0.002, 0.0),
  };
  unsigned seed = 1;
  for (const auto& center : centers) {
    const double exact = intersector.volume(center);
    ASSERT_GT(exact, 0.0);
    ASSERT_LT(exact, kEdge * kEdge * kEdge);
    const auto [estimate, standard_error] = monteCarloVolume(box, center, 1000000, seed++);
    // Five standard errors: a correct implementation fails with probability < 1e-6.
    EXPECT_NEAR(exact, estimate, 5 * standard_error) << "voxel at " << center.transpose();
  }
}

TEST(IouVoxelVolume, VoxelsTilingSpaceAddUpToTheBoxVolume) {
  // Every voxel of a grid around the box: their exact shares must sum to the
  // box's volume, whichever path (inside, outside, clipped) each one took.
  const OrientedBox box = tiltedBox();
  const lom::VoxelBoxIntersector intersector(box, kEdge);
  double total = 0.0;
  int clipped = 0;
  for (int i = -10; i <= 30; ++i)
    for (int j = -20; j <= 15; ++j)
      for (int k = -10; k <= 20; ++k) {
        const double v = intersector.volume(Eigen::Vector3d((i + 0.5) * kEdge, (j + 0.5) * kEdge, (k + 0.5) * kEdge));
        total += v;
        clipped += v > 0.0 && v < kEdge * kEdge * kEdge;
      }
  EXPECT_GT(clipped, 100);
  EXPECT_NEAR(total, box.volume(), 1e-10 * box.volume());
}

TEST(IouVoxelVolume, FastPathsAndCentres) {
  OrientedBox box;
  box.center = {0, 0, 0};
  box.size = {0.1, 0.1, 0.1};
  const lom::VoxelBoxIntersector intersector(box, kEdge);
  EXPECT_DOUBLE_EQ(intersector.volume({0.005, 0.005, 0.005}), kEdge * kEdge * kEdge);
  EXPECT_DOUBLE_EQ(intersector.volume({0.5, 0.0, 0.0}), 0.0);
  // Centred on a face: half inside.
  EXPECT_NEAR(intersector.volume({0.05, 0.0, 0.0}), 0.5 * kEdge * kEdge * kEdge, 1e-18);
  EXPECT_TRUE(intersector.centerInside({0.049, 0.0, 0.0}));
  EXPECT_FALSE(intersector.centerInside({0.051, 0.0, 0.0}));
}

// Keys of the voxels with lower corner (i, j, k) * edge for i in [i0, i1) etc.
std::vector<lom::VoxelKey> block(int i0, int i1, int j0, int j1, int k0, int k1) {
  std::vector<lom::VoxelKey> keys;
  for (int i = i0; i < i1; ++i)
    for (int j = j0; j < j1; ++j)
      for (int k = k0; k < k1; ++k)
        keys.push_back({static_cast<std::uint16_t>(32768 + i), static_cast<std::uint16_t>(32768 + j),
                        static_cast<std::uint16_t>(32768 + k)});
  return keys;
}

TEST(IouVoxelSets, GridAlignedBoxes) {
  OrientedBox box;  // exactly the voxels [0, 4) x [0, 2) x [0, 3)
  box.center = {0.02, 0.01, 0.015};
  box.size = {0.04, 0.02, 0.03};
  for (lom::IouMode mode : {lom::IouMode::Exact, lom::IouMode::Center}) {
    EXPECT_NEAR(lom::voxelIou(block(0, 4, 0, 2, 0, 3), kEdge, box, mode), 1.0, 1e-9);
    // Half of the box predicted, nothing else: v_tp = v_pred = v_gt / 2.
    EXPECT_NEAR(lom::voxelIou(block(0, 2, 0, 2, 0, 3), kEdge, box, mode), 0.5, 1e-9);
    // The box and as much again outside it: IU = 1/2.
    EXPECT_NEAR(lom::voxelIou(block(0, 8, 0, 2, 0, 3), kEdge, box, mode), 0.5, 1e-9);
    EXPECT_EQ(lom::voxelIou({}, kEdge, box, mode), 0.0);
  }
}

// Voxels wholly inside a much larger box: their summed shares must not come
// out above their own volume (a false positive below zero in the report).
TEST(IouVoxelSets, OverlapNeverExceedsEitherVolume) {
  OrientedBox box;
  box.center = {0.123, -0.456, 0.789};
  box.size = {1.5, 1.5, 1.5};
  box.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  for (const double edge : {0.01, 0.0073, 0.02}) {
    const std::vector<lom::VoxelKey> voxels = block(5, 14, -50, -43, 70, 81);
    for (lom::IouMode mode : {lom::IouMode::Exact, lom::IouMode::Center}) {
      const lom::IouVolumes v = lom::voxelIouVolumes(voxels, edge, box, mode);
      ASSERT_GT(v.true_positive, 0.0) << edge;
      EXPECT_LE(v.true_positive, v.predicted) << edge;
      EXPECT_GE(v.falsePositive(), 0.0) << edge;
      EXPECT_GE(v.falseNegative(), 0.0) << edge;
    }
  }
  // A box the size of everything: the overlap is the voxels', never more.
  box.size = {1e5, 1e5, 1e5};
  const lom::IouVolumes huge =
      lom::voxelIouVolumes(block(0, 3, 0, 3, 0, 3), kEdge, box, lom::IouMode::Exact);
  EXPECT_GE(huge.falsePositive(), 0.0);
}

TEST(IouVoxelSets, VolumesAreTheTermsOfTheScore) {
  OrientedBox box;  // shifted by a quarter voxel along x, as below
  box.center = {0.02 + 0.0025, 0.01, 0.015};
  box.size = {0.04, 0.02, 0.03};
  const double voxel = kEdge * kEdge * kEdge;
  const auto voxels = block(0, 4, 0, 2, 0, 3);
  const lom::IouVolumes exact = lom::voxelIouVolumes(voxels, kEdge, box, lom::IouMode::Exact);
  EXPECT_NEAR(exact.predicted, 24 * voxel, 1e-15);
  EXPECT_NEAR(exact.ground_truth, 24 * voxel, 1e-15);
  // The column of voxels at x = 0 is a quarter outside: 6 voxels x 1/4.
  EXPECT_NEAR(exact.true_positive, 22.5 * voxel, 1e-15);
  EXPECT_NEAR(exact.falsePositive(), 1.5 * voxel, 1e-15);
  EXPECT_NEAR(exact.falseNegative(), 1.5 * voxel, 1e-15);
  EXPECT_EQ(exact.iou(), lom::voxelIou(voxels, kEdge, box, lom::IouMode::Exact));
  const lom::IouVolumes centre = lom::voxelIouVolumes(voxels, kEdge, box, lom::IouMode::Center);
  EXPECT_NEAR(centre.true_positive, 24 * voxel, 1e-15);
  EXPECT_NEAR(centre.falseNegative(), 0.0, 1e-15);
  EXPECT_EQ(lom::voxelIouVolumes({}, kEdge, box, lom::IouMode::Exact).iou(), 0.0);

  // Each voxel's share, in the centres' order: the first column 3/4, the rest whole.
  std::vector<Eigen::Vector3d> centres;
  for (const auto& key : voxels) centres.push_back(lom::voxelCenter(key, kEdge));
  const std::vector<double> shares =
      lom::voxelSharesInBox(centres, kEdge, box, lom::IouMode::Exact);
  ASSERT_EQ(shares.size(), voxels.size());
  for (size_t i = 0; i < voxels.size(); ++i)
    EXPECT_NEAR(shares[i], voxels[i].x == 32768 ? 0.75 : 1.0, 1e-12) << i;
  const Eigen::Vector3d far_away(1.0, 1.0, 1.0);
  EXPECT_EQ(lom::voxelSharesInBox({far_away}, kEdge, box, lom::IouMode::Center),
            std::vector<double>{0.0});
}

TEST(IouVoxelSets, ExactAndCentreModesDifferOnShiftedBoxes) {
  OrientedBox box;  // shifted by a quarter voxel along x: voxels straddle its faces
  box.center = {0.02 + 0.0025, 0.01, 0.015};
  box.size = {0.04, 0.02, 0.03};
  const auto voxels = block(0, 4, 0, 2, 0, 3);
  // Exact: v_tp = 3.75/4 of the voxels; union = 4.25/4 -> 15/17.
  EXPECT_NEAR(lom::voxelIou(voxels, kEdge, box, lom::IouMode::Exact), 15.0 / 17.0, 1e-9);
  // Centres: all 24 centres are inside, so the IU is v_pred / v_gt = 1.
  EXPECT_NEAR(lom::voxelIou(voxels, kEdge, box, lom::IouMode::Center), 1.0, 1e-9);
}

// In centre mode the box is counted as the grid voxels whose centres are in
// it, as the prediction is: a box thinner than a voxel still holds a layer of
// them, and the score counts them against that layer, not against the
// thinner box (which gave a true positive below the voxels inside and a
// false negative below zero). The report and the breakdown agree.
TEST(IouVoxelSets, CentreModeCountsTheBoxInGridVoxels) {
  OrientedBox box;  // 10 x 10 voxels, 0.93 of a voxel thick, on the layer z = 0
  box.center = {0.05, 0.05, 0.005};
  box.size = {0.1, 0.1, 0.0093};
  const double voxel = kEdge * kEdge * kEdge;
  std::vector<lom::VoxelKey> voxels = block(0, 10, 0, 10, 0, 1);
  for (const lom::VoxelKey& above : block(0, 10, 0, 1, 1, 2)) voxels.push_back(above);
  const lom::IouVolumes v = lom::voxelIouVolumes(voxels, kEdge, box, lom::IouMode::Center);
  EXPECT_NEAR(v.ground_truth, 100 * voxel, 1e-15);
  EXPECT_NEAR(v.true_positive, 100 * voxel, 1e-15);
  EXPECT_NEAR(v.falsePositive(), 10 * voxel, 1e-15);
  EXPECT_NEAR(v.falseNegative(), 0.0, 1e-15);
  EXPECT_NEAR(v.iou(), 100.0 / 110.0, 1e-12);
  const lom::ScoreBreakdown breakdown = lom::scoreBreakdown(
      voxels, kEdge, lom::GroundTruthBox{32, "mailer", box}, lom::IouMode::Center);
  EXPECT_EQ(breakdown.inside, 100u);
  EXPECT_EQ(breakdown.outside, 10u);
  EXPECT_EQ(breakdown.volumes.iou(), v.iou());
  EXPECT_EQ(breakdown.volumes.ground_truth, v.ground_truth);
  // Exact mode keeps the box's own volume.
  EXPECT_NEAR(lom::voxelIouVolumes(voxels, kEdge, box, lom::IouMode::Exact).ground_truth,
              93 * voxel, 1e-15);
}

// A box thinner than a voxel that lies between two layers of voxel centres
// (here z from 0.0082 to 0.0122, between the centres at 0.005 and 0.015)
// holds no centre itself; centre mode takes it one voxel thick, so it holds
// the one layer nearest to it, and that layer mapped scores 1, not 0.
TEST(IouVoxelSets, CentreModeGivesABoxBetweenCentrePlanesItsNearestLayer) {
  OrientedBox box;
  box.center = {0.05, 0.05, 0.0102};
  box.size = {0.1, 0.1, 0.004};
  const double voxel = kEdge * kEdge * kEdge;
  const lom::VoxelBoxIntersector intersector(box, kEdge);
  EXPECT_EQ(intersector.centresInside(), 100.0);
  EXPECT_TRUE(intersector.centerInside({0.005, 0.005, 0.015}));
  EXPECT_FALSE(intersector.centerInside({0.005, 0.005, 0.005}));
  EXPECT_FALSE(intersector.centerInside({0.005, 0.005, 0.025}));
  const std::vector<lom::VoxelKey> layer = block(0, 10, 0, 10, 1, 2);
  const lom::IouVolumes v = lom::voxelIouVolumes(layer, kEdge, box, lom::IouMode::Center);
  EXPECT_NEAR(v.ground_truth, 100 * voxel, 1e-15);
  EXPECT_NEAR(v.true_positive, 100 * voxel, 1e-15);
  EXPECT_NEAR(v.iou(), 1.0, 1e-12);
  EXPECT_EQ(lom::voxelIou(block(0, 10, 0, 10, 0, 1), kEdge, box, lom::IouMode::Center), 0.0);
  // Tilted by 30 degrees about x, the thin box still holds a voxel centre in
  // every grid column it crosses.
  box.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitX()));
  const lom::VoxelBoxIntersector tilted(box, kEdge);
  for (int i = 1; i < 9; ++i)
    for (int j = 1; j < 8; ++j) {
      int held = 0;
      for (int k = -10; k < 10; ++k)
        held += tilted.centerInside({(i + 0.5) * kEdge, (j + 0.5) * kEdge, (k + 0.5) * kEdge});
      EXPECT_GE(held, 1) << "column " << i << ", " << j;
    }
}

// The count of grid centres inside a box, column by column, is the count of a
// test of every centre of the box's surroundings.
TEST(IouVoxelSets, CentresInsideCountsEveryGridCentreTheTestAccepts) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<OrientedBox> boxes = {tiltedBox()};
  for (int i = 0; i < 12; ++i) {
    OrientedBox b;
    b.center = {0.3 * unit(rng), 0.3 * unit(rng), 0.3 * unit(rng)};
    b.size = {0.005 + 0.1 * std::abs(unit(rng)), 0.005 + 0.1 * std::abs(unit(rng)),
              0.003 + 0.05 * std::abs(unit(rng))};
    b.rotation = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng)).normalized();
    if (i % 4 == 0)
      b.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(unit(rng), Eigen::Vector3d::UnitZ()));
    if (i % 4 == 1) b.rotation = Eigen::Quaterniond::Identity();
    boxes.push_back(b);
  }
  for (const double edge : {kEdge, 0.0073}) {
    for (size_t n = 0; n < boxes.size(); ++n) {
      const OrientedBox& box = boxes[n];
      const lom::VoxelBoxIntersector intersector(box, edge);
      const double reach = 0.5 * box.size.norm() + 2 * edge;
      double brute = 0.0;
      auto index = [&](double x) { return static_cast<long>(std::floor(x / edge)); };
      for (long i = index(box.center.x() - reach); i <= index(box.center.x() + reach); ++i)
        for (long j = index(box.center.y() - reach); j <= index(box.center.y() + reach); ++j)
          for (long k = index(box.center.z() - reach); k <= index(box.center.z() + reach); ++k)
            brute += intersector.centerInside(
                Eigen::Vector3d((i + 0.5) * edge, (j + 0.5) * edge, (k + 0.5) * edge));
      EXPECT_EQ(intersector.centresInside(), brute) << "box " << n << ", edge " << edge;
      EXPECT_GT(brute, 0.0) << "box " << n;
    }
  }
  // A box wider than any object is counted by its volume, in no time.
  OrientedBox field;
  field.size = {400.0, 300.0, 0.5};
  EXPECT_NEAR(lom::VoxelBoxIntersector(field, kEdge).centresInside(),
              field.volume() / (kEdge * kEdge * kEdge), 1.0);
}

}  // namespace
