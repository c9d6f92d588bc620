// The checks of fusion settings that the command line and the studio share.
#include <gtest/gtest.h>

#include "lom/fusion.hpp"

namespace {

lom::LabelSet threeLabels() {
  return lom::LabelSet(
      {{0, "__background__", {0, 0, 0}}, {1, "book", {128, 0, 0}}, {2, "cup", {0, 128, 0}}});
}

TEST(FusionChecks, RaysOfAtMost1000VoxelsPass) {
  EXPECT_FALSE(lom::checkRayLength(2.0, 0.002));  // 1000 voxels, the limit itself
  EXPECT_FALSE(lom::checkRayLength(10.0, 0.01));
  EXPECT_FALSE(lom::checkRayLength(1.0, 0.005));
}

TEST(FusionChecks, LongerRaysNameTheirLengthRoundedUpAndTheLimit) {
  const auto rays = lom::checkRayLength(5.0, 0.002);
  ASSERT_TRUE(rays);
  EXPECT_DOUBLE_EQ(rays->voxels, 2500.0);
  EXPECT_DOUBLE_EQ(rays->limit, lom::kMaxFusionVoxelsPerRay);
  // 3 m at 2.9 mm: 1034.48 voxels, so a ray crosses 1035.
  const auto rounded = lom::checkRayLength(3.0, 0.0029);
  ASSERT_TRUE(rounded);
  EXPECT_DOUBLE_EQ(rounded->voxels, 1035.0);
  // Just over the limit counts: 1000.5 voxels.
  ASSERT_TRUE(lom::checkRayLength(2.001, 0.002));
  EXPECT_DOUBLE_EQ(lom::checkRayLength(2.001, 0.002)->voxels, 1001.0);
}

TEST(FusionChecks, AnUnlimitedRangeIsLeftToTheDepths) {
  EXPECT_FALSE(lom::checkRayLength(0.0, 0.002));
  EXPECT_FALSE(lom::checkRayLength(-1.0, 0.002));
}

TEST(FusionChecks, CandidatesMustBeLabelsOfTheSequence) {
  const lom::LabelSet labels = threeLabels();
  EXPECT_FALSE(lom::checkCandidates(std::nullopt, labels));
  EXPECT_FALSE(lom::checkCandidates(std::vector<int>{}, labels));
  EXPECT_FALSE(lom::checkCandidates(std::vector<int>{0, 1, 2}, labels));

  const auto unknown = lom::checkCandidates(std::vector<int>{0, 3, 2, 99}, labels);
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->label, 3);  // the first, in the order given
  EXPECT_EQ(unknown->label_count, 3);

  const auto negative = lom::checkCandidates(std::vector<int>{-1}, labels);
  ASSERT_TRUE(negative);
  EXPECT_EQ(negative->label, -1);

  const auto none = lom::checkCandidates(std::vector<int>{0}, lom::LabelSet{});
  ASSERT_TRUE(none);
  EXPECT_EQ(none->label_count, 0);
}

}  // namespace
