// The score breakdown: each voxel of a box's label counted inside, partly
// inside or outside the box as IU_3d counts it, from keys or from occupied
// leaves (pruned ones split), with the volumes that make the score.
#include <gtest/gtest.h>

#include <cmath>

#include "lom/box_fit.hpp"
#include "lom/score_breakdown.hpp"

namespace {

constexpr double kEdge = 0.01;

lom::GroundTruthBox boxOfLabel3() {
  lom::GroundTruthBox box;
  box.label = 3;
  // x from 0 to 0.014: a first layer of voxels inside, 40 % of the second.
  box.box.center = Eigen::Vector3d(0.007, 0.01, 0.01);
  box.box.size = Eigen::Vector3d(0.014, 0.02, 0.02);
  return box;
}

TEST(ScoreBreakdown, PrunedLeavesAreSplitAndOtherLabelsLeftOut) {
  std::vector<lom::OccupiedVoxel> leaves;
  leaves.push_back({Eigen::Vector3d(0.01, 0.01, 0.01), 0.02, 3, 0.9f});  // 2x2x2 voxels
  leaves.push_back({Eigen::Vector3d(0.105, 0.005, 0.005), 0.01, 3, 0.9f});
  leaves.push_back({Eigen::Vector3d(0.205, 0.005, 0.005), 0.01, 4, 0.9f});  // another label
  const lom::GroundTruthBox box = boxOfLabel3();
  const lom::ScoreBreakdown exact = lom::scoreBreakdown(leaves, kEdge, box, lom::IouMode::Exact);
  ASSERT_EQ(exact.centres.size(), 9u);
  ASSERT_EQ(exact.shares.size(), 9u);
  EXPECT_EQ(exact.label, 3);
  EXPECT_EQ(exact.inside, 4u);   // x in [0, 0.01]
  EXPECT_EQ(exact.partly, 4u);   // x in [0.01, 0.02]: 40 % inside
  EXPECT_EQ(exact.outside, 1u);  // the single voxel at x = 0.1
  for (size_t i = 0; i < exact.centres.size(); ++i) {
    const double x = exact.centres[i].x();
    EXPECT_NEAR(exact.shares[i], x < 0.01 ? 1.0 : x < 0.02 ? 0.4 : 0.0, 1e-9) << x;
  }
  EXPECT_NEAR(exact.volumes.true_positive, 5.6e-6, 1e-15);
  EXPECT_NEAR(exact.volumes.predicted, 9e-6, 1e-15);
  EXPECT_NEAR(exact.volumes.ground_truth, 5.6e-6, 1e-15);
  EXPECT_NEAR(exact.volumes.iou(), 5.6 / 9.0, 1e-9);

  const lom::ScoreBreakdown centre = lom::scoreBreakdown(leaves, kEdge, box, lom::IouMode::Center);
  EXPECT_EQ(centre.inside, 4u);  // centres at x = 0.005; those at 0.015 lie outside
  EXPECT_EQ(centre.partly, 0u);
  EXPECT_EQ(centre.outside, 5u);
}

TEST(ScoreBreakdown, KeysGiveTheScoresVolumes) {
  std::vector<lom::VoxelKey> keys;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j)
      keys.push_back(
          {static_cast<std::uint16_t>(32768 + i), static_cast<std::uint16_t>(32768 + j), 32768});
  const lom::GroundTruthBox box = boxOfLabel3();
  for (const lom::IouMode mode : {lom::IouMode::Exact, lom::IouMode::Center}) {
    const lom::ScoreBreakdown breakdown = lom::scoreBreakdown(keys, kEdge, box, mode);
    const lom::IouVolumes scored = lom::voxelIouVolumes(keys, kEdge, box.box, mode);
    EXPECT_EQ(breakdown.centres.size(), keys.size());
    EXPECT_EQ(breakdown.centres.front(), lom::voxelCenter(keys.front(), kEdge));
    EXPECT_NEAR(breakdown.volumes.true_positive, scored.true_positive, 1e-15);
    EXPECT_NEAR(breakdown.volumes.iou(), scored.iou(), 1e-12);
  }
  EXPECT_TRUE(lom::scoreBreakdown(std::vector<lom::VoxelKey>{}, kEdge, box, lom::IouMode::Exact)
                  .centres.empty());
}

TEST(ScoreBreakdown, ColoursBlendFromRedOutsideThroughAmberToGreenInside) {
  const lom::Rgb inside{40, 200, 70}, half{255, 180, 0}, outside{230, 45, 45};
  EXPECT_EQ(lom::scoreShareColour(1.0), inside);
  EXPECT_EQ(lom::scoreShareColour(0.5), half);
  EXPECT_EQ(lom::scoreShareColour(0.0), outside);
  EXPECT_EQ(lom::scoreShareColour(0.75), (lom::Rgb{148, 190, 35}));  // half way from amber to green
  EXPECT_EQ(lom::scoreShareColour(0.25), (lom::Rgb{243, 113, 23}));  // half way from red to amber
  // Nearly inside is nearly green, nearly outside nearly red, but never quite.
  EXPECT_NE(lom::scoreShareColour(0.98), inside);
  EXPECT_LE(std::abs(lom::scoreShareColour(0.98)[0] - inside[0]), 10);
  EXPECT_NE(lom::scoreShareColour(0.02), outside);
  EXPECT_LE(std::abs(lom::scoreShareColour(0.02)[1] - outside[1]), 11);
  EXPECT_EQ(lom::scoreShareColour(std::nan("")), outside);
}

}  // namespace
