// Fusing a generated shelf-bin scene labels each object's voxels correctly.
#include <gtest/gtest.h>

#include <map>

#include "lom/fusion.hpp"
#include "lom/synth.hpp"
#include "test_support.hpp"

namespace {

constexpr int kTransparentLabel = 9;  // dasani_water_bottle: no depth, so no voxels

struct BoxContents {
  size_t own = 0;    // occupied voxels of the object's label inside its box
  size_t other = 0;  // occupied voxels of other object labels inside its box
};

class FuseSyntheticTest : public ::testing::TestWithParam<double> {};

TEST_P(FuseSyntheticTest, ObjectsVoxelsCarryTheirLabel) {
  const double resolution = GetParam();
  lom::test::TempDir dir;
  lom::SynthOptions options;
  options.seed = 11;
  options.objects = 6;
  options.frames = 6;
  options.views = 3;
  options.width = 320;
  options.height = 240;
  const lom::SynthScene scene = lom::writeSyntheticScene(options, dir.path());
  const lom::Sequence sequence = lom::loadSequence(dir.path());

  lom::FusionOptions fusion;
  fusion.map.resolution = resolution;
  const lom::LabelMap map = lom::fuseSequence(sequence, fusion);

  // Voxel centres within half a voxel of the box count as inside: the box
  // surface cuts through the voxels holding the object's surface points.
  std::map<int, BoxContents> contents;
  map.forEachOccupied([&](const lom::OccupiedVoxel& voxel) {
    for (const auto& gt : scene.annotations.boxes) {
      if (!gt.box.contains(voxel.center, 0.5 * voxel.size)) continue;
      if (voxel.label == gt.label)
        ++contents[gt.label].own;
      else if (voxel.label != 0)
        ++contents[gt.label].other;
    }
  });
  for (const auto& gt : scene.annotations.boxes) {
    if (gt.label == kTransparentLabel) continue;
    const BoxContents& c = contents[gt.label];
    SCOPED_TRACE(gt.name);
    // Every visible object is mapped ...
    EXPECT_GE(c.own, 10u);
    // ... and inside its box its own label clearly dominates the other objects'
    // labels; look-alike confusion and boundary mixing of the simulated segmenter
    // leave a minority of wrong voxels.
    EXPECT_GE(c.own, 4 * c.other) << "own " << c.own << " other " << c.other;
  }
  // Voxels of object labels are mostly inside the box of that object.
  for (const auto& gt : scene.annotations.boxes) {
    if (gt.label == kTransparentLabel) continue;
    const auto voxels = map.voxelsOfLabel(gt.label);
    size_t inside = 0;
    for (const auto& key : voxels)
      if (gt.box.contains(map.centerOf(key), resolution)) ++inside;
    SCOPED_TRACE(gt.name);
    ASSERT_FALSE(voxels.empty());
    EXPECT_GE(static_cast<double>(inside) / voxels.size(), 0.7);
  }
}

INSTANTIATE_TEST_SUITE_P(Resolutions, FuseSyntheticTest, ::testing::Values(0.01, 0.02));

}  // namespace
