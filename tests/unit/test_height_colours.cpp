// Height colours: the ramp's ends and middle, and heights measured along any up.
#include <gtest/gtest.h>

#include <cmath>

#include "lom/height_colours.hpp"

namespace {

TEST(HeightColours, RampRunsFromBlueThroughGreenToRed) {
  EXPECT_EQ(lom::heightRampColour(0.0), (lom::Rgb{49, 54, 149}));
  EXPECT_EQ(lom::heightRampColour(0.5), (lom::Rgb{102, 189, 99}));
  EXPECT_EQ(lom::heightRampColour(1.0), (lom::Rgb{215, 48, 39}));
  // Half way between the first two stops.
  EXPECT_EQ(lom::heightRampColour(0.125), (lom::Rgb{59, 111, 175}));
}

TEST(HeightColours, ShadedViewsDrawTheBackgroundGreyAndBlackLabelsDarkGrey) {
  // One rule for the studio's 3D view and legend and `labeloctomap render`.
  const lom::LabelSet labels(
      {{0, "__background__", {0, 0, 0}}, {1, "cup", {200, 30, 30}}, {2, "black_box", {0, 0, 0}}});
  EXPECT_EQ(lom::shadedLabelColour(labels, 0), (lom::Rgb{150, 150, 160}));
  EXPECT_EQ(lom::shadedLabelColour(labels, 1), (lom::Rgb{200, 30, 30}));
  EXPECT_EQ(lom::shadedLabelColour(labels, 2), (lom::Rgb{96, 96, 96}));
  EXPECT_EQ(lom::shadedLabelColour(labels, 7), (lom::Rgb{255, 0, 255}));
  // The background is grey whatever its palette colour.
  const lom::LabelSet coloured({{0, "floor", {10, 120, 10}}, {1, "cup", {200, 30, 30}}});
  EXPECT_EQ(lom::shadedLabelColour(coloured, 0), lom::kShadedBackgroundColour);
}

TEST(HeightColours, RampClampsOutOfRangeAndNaN) {
  EXPECT_EQ(lom::heightRampColour(-3.0), lom::heightRampColour(0.0));
  EXPECT_EQ(lom::heightRampColour(7.0), lom::heightRampColour(1.0));
  EXPECT_EQ(lom::heightRampColour(std::nan("")), lom::heightRampColour(0.0));
}

TEST(HeightColours, SpanningMapsLowestToBlueAndHighestToRed) {
  // y down, as in a camera frame: up is -y; the point with the smallest y is the highest.
  const std::vector<Eigen::Vector3d> points{{0, 1.0, 0}, {5, -1.0, 2}, {0, 0.0, 9}};
  const auto colours = lom::HeightColours::spanning(points, {0, -2.0, 0});
  EXPECT_DOUBLE_EQ(colours.fraction(points[0]), 0.0);
  EXPECT_DOUBLE_EQ(colours.fraction(points[1]), 1.0);
  EXPECT_DOUBLE_EQ(colours.fraction(points[2]), 0.5);
  EXPECT_EQ(colours.colour(points[0]), lom::heightRampColour(0.0));
  EXPECT_EQ(colours.colour(points[1]), lom::heightRampColour(1.0));
  EXPECT_DOUBLE_EQ(colours.fraction({0, -3.0, 0}), 1.0);  // beyond the range: clamped
}

TEST(HeightColours, ManyPointsSpanTheFirstToTheNinetyNinthPercentile) {
  // 1,000 points at heights 0..999 along z, and two strays far away.
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 1000; ++i) points.emplace_back(0, 0, i);
  points.emplace_back(0, 0, -1e6);
  points.emplace_back(0, 0, 1e6);
  const auto colours = lom::HeightColours::spanning(points, Eigen::Vector3d::UnitZ());
  // 1,002 heights: the 10th lowest is 8, the 10th highest 991.
  EXPECT_DOUBLE_EQ(colours.fraction({0, 0, 8}), 0.0);
  EXPECT_DOUBLE_EQ(colours.fraction({0, 0, 991}), 1.0);
  EXPECT_DOUBLE_EQ(colours.fraction({0, 0, 499.5}), 0.5);
  EXPECT_DOUBLE_EQ(colours.fraction({0, 0, -1e6}), 0.0);
  // Below the minimum every point counts.
  points.resize(lom::HeightColours::kPercentileMinimum - 1);
  const auto few = lom::HeightColours::spanning(points, Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(few.fraction({0, 0, 0}), 0.0);
  EXPECT_DOUBLE_EQ(few.fraction({0, 0, 198}), 1.0);
}

TEST(HeightColours, FlatOrEmptySetGetsTheMiddleColour) {
  const auto flat = lom::HeightColours::spanning({{0, 0, 1}, {4, 4, 1}}, Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(flat.fraction({2, 2, 1}), 0.5);
  const auto empty = lom::HeightColours::spanning({}, Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(empty.fraction({0, 0, 0}), 0.5);
}

TEST(HeightColours, ZeroUpMeansPlusZ) {
  const lom::HeightColours colours({0, 0, 0}, 0.0, 2.0);
  EXPECT_EQ(colours.up(), Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(colours.fraction({9, 9, 1.0}), 0.5);
}

}  // namespace
