// The single-view projection baseline the studio shows beside the map: only
// points the map can hold, wherever the pose puts the camera.
#include "lom/ui/projection_voxels.hpp"

#include <gtest/gtest.h>

#include "lom/sequence.hpp"
#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

constexpr int kCupLabel = 2;  // the tiny sequence's cup, right of the square

size_t countOf(const MapSnapshot& snapshot, int label) {
  const auto it = snapshot.counts.find(label);
  return it == snapshot.counts.end() ? 0 : it->second;
}

bool insideExtent(const MapSnapshot& snapshot) {
  for (const OccupiedVoxel& voxel : snapshot.voxels)
    if (!insideMapExtent(voxel.center, snapshot.resolution)) return false;
  return true;
}

TEST(ProjectionVoxels, PointsOutsideTheMapsExtentAreLeftOutAsFusionLeavesThemOut) {
  test::TempDir dir;
  test::writeTinySequence(dir / "tiny");
  Sequence sequence = loadSequence(dir / "tiny");
  const FrameData frame = loadFrame(sequence, 0);
  FusionOptions options;
  options.map.resolution = 0.01;
  options.map.max_range = 2.0;  // every labelled pixel of the tiny sequence

  const MapSnapshot near = projectionVoxels(sequence, 0, frame, options);
  ASSERT_GT(countOf(near, test::kSquareLabel), 0u);
  ASSERT_GT(countOf(near, kCupLabel), 0u);
  EXPECT_TRUE(insideExtent(near));

  // The camera 15 cm inside the extent's edge: the square (at most 11 cm to
  // either side) stays inside, the cup (18 to 32 cm to the right) lies beyond.
  sequence.frames[0].T_world_camera.translation().x() = mapExtent(0.01) - 0.15;
  const MapSnapshot edge = projectionVoxels(sequence, 0, frame, options);
  EXPECT_GT(countOf(edge, test::kSquareLabel), 0u);
  EXPECT_EQ(countOf(edge, kCupLabel), 0u);
  EXPECT_TRUE(insideExtent(edge));

  // Far beyond the extent (and beyond any integer's range of cells): nothing.
  for (const double x : {1e30, -1e300}) {
    sequence.frames[0].T_world_camera.translation().x() = x;
    EXPECT_TRUE(projectionVoxels(sequence, 0, frame, options).empty()) << x;
  }
}

}  // namespace
}  // namespace lom::ui
