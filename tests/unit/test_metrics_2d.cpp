// The paper's 2D segmentation metrics on confusion matrices worked out by hand.
#include <gtest/gtest.h>

#include "lom/metrics_2d.hpp"

namespace {

// Values below are ratios of small integers; only rounding of the divisions remains.
constexpr double kTight = 1e-12;

lom::ConfusionMatrix fromRows(const std::vector<std::vector<std::uint64_t>>& rows) {
  lom::ConfusionMatrix m(static_cast<int>(rows.size()));
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = 0; j < rows[i].size(); ++j) m.add(static_cast<int>(i), static_cast<int>(j), rows[i][j]);
  return m;
}

TEST(Metrics2d, HandMadeConfusionMatrix) {
  // Rows: true class, columns: predicted class. Class 2 is absent from the
  // ground truth but predicted 9 times; it is not one of the n_cl classes.
  const lom::ConfusionMatrix m = fromRows({
      {50, 2, 3, 5},  // t_0 = 60
      {4, 30, 6, 0},  // t_1 = 40
      {0, 0, 0, 0},   // t_2 = 0
      {1, 0, 0, 9},   // t_3 = 10
  });
  // Column sums (predicted): 55, 32, 9, 14.
  const lom::Metrics2d metrics = m.metrics();
  EXPECT_EQ(metrics.pixels, 110u);
  EXPECT_EQ(metrics.classes, 3);
  EXPECT_NEAR(metrics.pixel_accuracy, 89.0 / 110.0, kTight);
  EXPECT_NEAR(metrics.mean_accuracy, (50.0 / 60.0 + 30.0 / 40.0 + 9.0 / 10.0) / 3.0, kTight);
  // IU_i = n_ii / (t_i + sum_j n_ji - n_ii): 50/65, 30/42, 9/15.
  EXPECT_NEAR(metrics.mean_iu, (50.0 / 65.0 + 30.0 / 42.0 + 9.0 / 15.0) / 3.0, kTight);
  EXPECT_NEAR(metrics.fw_iu, (60.0 * 50.0 / 65.0 + 40.0 * 30.0 / 42.0 + 10.0 * 9.0 / 15.0) / 110.0, kTight);
}

TEST(Metrics2d, PerfectPredictionScoresOne) {
  lom::ConfusionMatrix m(5);
  m.add(0, 0, 1000);
  m.add(3, 3, 20);
  m.add(4, 4, 7);
  const lom::Metrics2d metrics = m.metrics();
  EXPECT_EQ(metrics.classes, 3);
  EXPECT_DOUBLE_EQ(metrics.pixel_accuracy, 1.0);
  EXPECT_DOUBLE_EQ(metrics.mean_accuracy, 1.0);
  EXPECT_DOUBLE_EQ(metrics.mean_iu, 1.0);
  EXPECT_DOUBLE_EQ(metrics.fw_iu, 1.0);
}

TEST(Metrics2d, UnlabelledPixelsAreIgnoredAndMergeAdds) {
  lom::ConfusionMatrix a(2);
  a.add(0, 0, 3);
  a.add(-1, 0, 100);  // no ground truth
  a.add(1, 2, 100);   // not a label of the set
  lom::ConfusionMatrix b(2);
  b.add(1, 0, 1);
  b.add(1, 1, 1);
  a.merge(b);
  EXPECT_EQ(a.total(), 5u);
  EXPECT_EQ(a.at(1, 0), 1u);
  const lom::Metrics2d metrics = a.metrics();
  EXPECT_NEAR(metrics.pixel_accuracy, 4.0 / 5.0, kTight);
  EXPECT_NEAR(metrics.mean_accuracy, (1.0 + 0.5) / 2.0, kTight);
  // IU_0 = 3 / (3 + 4 - 3), IU_1 = 1 / (2 + 1 - 1).
  EXPECT_NEAR(metrics.mean_iu, (3.0 / 4.0 + 1.0 / 2.0) / 2.0, kTight);
  EXPECT_THROW(a.merge(lom::ConfusionMatrix(3)), std::invalid_argument);
}

TEST(Metrics2d, EmptyMatrixScoresZero) {
  const lom::Metrics2d metrics = lom::ConfusionMatrix(4).metrics();
  EXPECT_EQ(metrics.pixels, 0u);
  EXPECT_EQ(metrics.classes, 0);
  EXPECT_EQ(metrics.pixel_accuracy, 0.0);
  EXPECT_EQ(metrics.mean_iu, 0.0);
}

}  // namespace
