// What the Picked Voxel panel says of a voxel: the labels with evidence by
// probability (ties by label id, as the argmax breaks them), the labels left
// at the lowest probability as one line instead of a few of them picked at
// random as runners-up, and "no map" apart from "never observed".
#include <gtest/gtest.h>

#include "lom/ui/map_snapshot.hpp"
#include "lom/ui/picked_voxel_view.hpp"

namespace lom::ui {
namespace {

LabelSet labelsNamed(const std::vector<std::string>& names) {
  std::vector<LabelInfo> labels;
  for (size_t i = 0; i < names.size(); ++i) labels.push_back({static_cast<int>(i), names[i], {}});
  return LabelSet(labels);
}

VoxelState occupied(std::vector<float> probabilities) {
  VoxelState voxel;
  voxel.known = true;
  voxel.occupied = true;
  voxel.probabilities = std::move(probabilities);
  voxel.label =
      static_cast<int>(std::max_element(voxel.probabilities.begin(), voxel.probabilities.end()) -
                       voxel.probabilities.begin());
  return voxel;
}

QStringList linesOf(const QString& text) { return text.split('\n').mid(1); }

TEST(PickedVoxelText, LabelsAtTheLowestProbabilityAreOneLine) {
  const LabelSet labels = labelsNamed({"bg", "bear", "book", "cup", "duck", "egg"});
  const QString text = PickedVoxelView::describe(
      Eigen::Vector3d::Zero(), occupied({0.12f, 0.97f, 0.12f, 0.5f, 0.12f, 0.12f}), labels);
  EXPECT_EQ(linesOf(text), (QStringList{"Occupied: label 1 bear", "  0.970  1 bear",
                                        "  0.500  3 cup", "  0.120  4 other labels"}))
      << text.toStdString();
}

TEST(PickedVoxelText, TiesAreListedByLabelIdAndTheRestCounted) {
  const LabelSet labels = labelsNamed({"a", "b", "c", "d", "e", "f", "g", "h", "i"});
  const QString text = PickedVoxelView::describe(
      Eigen::Vector3d::Zero(), occupied({0.12f, 0.4f, 0.9f, 0.4f, 0.4f, 0.4f, 0.4f, 0.4f, 0.3f}),
      labels);
  EXPECT_EQ(linesOf(text), (QStringList{"Occupied: label 2 c", "  0.900  2 c", "  0.400  1 b",
                                        "  0.400  3 d", "  0.400  4 e", "  0.400  5 f",
                                        "  …  3 more above 0.120", "  0.120  0 a"}))
      << text.toStdString();
}

TEST(PickedVoxelText, AFreeVoxelWithoutEvidenceForAnyLabelSaysSo) {
  VoxelState free = occupied(std::vector<float>(40, 0.12f));
  free.occupied = false;
  const QString text = PickedVoxelView::describe(Eigen::Vector3d::Zero(), free,
                                                 labelsNamed(std::vector<std::string>(40, "x")));
  EXPECT_EQ(linesOf(text), (QStringList{"Free: label 0 x", "  0.120  all 40 labels alike"}))
      << text.toStdString();
}

// The voxel described is named by its centre and size (after a re-fusion at
// another resolution it is not the one first clicked), and centres print
// exactly at any resolution.
TEST(PickedVoxelText, TheVoxelDescribedIsNamedByItsCentreAndSize) {
  const LabelSet labels = labelsNamed({"bg", "bear"});
  VoxelState coarse = occupied({0.12f, 0.97f});
  coarse.center = Eigen::Vector3d(0.15, -0.03, 0.05);
  coarse.size = 0.02;
  QString text = PickedVoxelView::describe(Eigen::Vector3d(0.155, -0.035, 0.055), coarse, labels);
  EXPECT_TRUE(
      text.startsWith("Point (0.155, -0.035, 0.055)\nVoxel of 2 cm centred at (0.150, "
                      "-0.030, 0.050)\nOccupied: label 1 bear"))
      << text.toStdString();
  VoxelState fine = coarse;
  fine.center = Eigen::Vector3d(0.1225, -0.0375, 0.0025);
  fine.size = 0.005;
  text = PickedVoxelView::describe(fine.center, fine, labels);
  EXPECT_TRUE(text.startsWith(
      "Point (0.1225, -0.0375, 0.0025)\nVoxel of 0.5 cm centred at (0.1225, -0.0375, 0.0025)"))
      << text.toStdString();
  EXPECT_EQ(coordinateDecimals(0.01), 3);
  EXPECT_EQ(coordinateDecimals(0.005), 4);
  EXPECT_EQ(coordinateDecimals(0.0025), 5);
  EXPECT_EQ(coordinateDecimals(0.02), 3);
  EXPECT_EQ(coordinateDecimals(0.0), 3);
}

TEST(PickedVoxelText, NoMapIsNotANeverObservedVoxel) {
  const LabelSet labels = labelsNamed({"bg", "bear"});
  const VoxelState unknown;
  EXPECT_TRUE(PickedVoxelView::describe(Eigen::Vector3d::Zero(), unknown, labels)
                  .contains("Unknown voxel (never observed)."));
  const QString none =
      PickedVoxelView::describe(Eigen::Vector3d::Zero(), unknown, labels, 32, false);
  EXPECT_TRUE(none.contains("No map yet")) << none.toStdString();
  EXPECT_FALSE(none.contains("never observed")) << none.toStdString();
}

}  // namespace
}  // namespace lom::ui
