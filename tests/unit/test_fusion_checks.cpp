// The checks of fusion settings that the command line and the studio share.
#include <gtest/gtest.h>

#include "lom/frame_range.hpp"
#include "lom/fusion.hpp"

namespace {

lom::LabelSet threeLabels() {
  return lom::LabelSet(
      {{0, "__background__", {0, 0, 0}}, {1, "book", {128, 0, 0}}, {2, "cup", {0, 128, 0}}});
}

// `fuse --frames` and the studio's Frames field read ranges alike.
TEST(FrameRanges, ReadAToBAsFramesAToBMinusOneAndAbsentEndsAsTheSequenceEnds) {
  struct Case {
    const char* text;
    size_t first, end;
  };
  for (const Case& c : {Case{"2:5", 2, 5}, Case{" 7 : ", 7, lom::kToTheEnd}, Case{":3", 0, 3},
                        Case{"  ", 0, lom::kToTheEnd}}) {
    const auto range = lom::parseFrameRange(c.text);
    ASSERT_TRUE(range) << c.text;
    EXPECT_EQ(range->first, c.first) << c.text;
    EXPECT_EQ(range->end, c.end) << c.text;
  }
  // The text of a range reads back as it.
  for (const char* text : {"2:5", "7:", "0:3", "0:1"}) {
    const auto range = lom::parseFrameRange(text);
    ASSERT_TRUE(range) << text;
    EXPECT_EQ(lom::frameRangeText(*range), text);
  }
  EXPECT_EQ(lom::frameRangeText(*lom::parseFrameRange(":3")), "0:3");
  EXPECT_EQ(lom::frameRangeText({}), "");
}

TEST(FrameRanges, OtherTextsSayWhatARangeMustBe) {
  const auto expected = [](const char* text) {
    std::string what;
    EXPECT_FALSE(lom::parseFrameRange(text, &what)) << text;
    return what;
  };
  EXPECT_EQ(expected("5"), "A:B (first frame, end frame exclusive), A: or :B");
  EXPECT_EQ(expected("-1:3"), "non-negative frame indices A:B");
  EXPECT_EQ(expected("1:+3"), "non-negative frame indices A:B");
  EXPECT_EQ(expected("1 2:3"), "non-negative frame indices A:B");
  EXPECT_EQ(expected("1:2:3"), "non-negative frame indices A:B");
  EXPECT_EQ(expected("3:3"), "an end frame B after the first frame A");
  EXPECT_EQ(expected("4:2"), "an end frame B after the first frame A");
  EXPECT_EQ(expected("0:99999999999999999999"),
            "frame indices of at most 9223372036854775807 (frame index 99999999999999999999 is "
            "too large)");
  // The largest index itself is a frame index.
  EXPECT_TRUE(lom::parseFrameRange("9223372036854775806:9223372036854775807"));
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
