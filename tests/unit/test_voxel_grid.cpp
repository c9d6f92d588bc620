// The voxel-grid traversal that every fusion path uses, checked against OctoMap.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include <octomap/OcTree.h>

#include "voxel_grid.hpp"

namespace {

using lom::grid::Grid;
using lom::grid::Key;

std::vector<Key> ourRay(const Grid& g, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  std::vector<Key> keys;
  lom::grid::traverseRay(g, a, b,
                         [&](std::uint16_t x, std::uint16_t y, std::uint16_t z) { keys.push_back({x, y, z}); });
  return keys;
}

TEST(VoxelGridTest, KeysAndCentresMatchOctomap) {
  octomap::OcTree tree(0.01);
  const Grid g(0.01);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-2.0, 2.0);
  for (int i = 0; i < 10000; ++i) {
    const Eigen::Vector3d p(coord(rng), coord(rng), coord(rng));
    Key key;
    ASSERT_TRUE(g.keyOf(p, key));
    const octomap::OcTreeKey ok = tree.coordToKey(p.x(), p.y(), p.z());
    EXPECT_EQ(key[0], ok[0]);
    EXPECT_EQ(key[1], ok[1]);
    EXPECT_EQ(key[2], ok[2]);
    EXPECT_DOUBLE_EQ(g.centerOf(key[0]), tree.keyToCoord(ok[0]));
  }
}

TEST(VoxelGridTest, AxisAlignedRayVisitsEveryVoxelBeforeTheEnd) {
  const Grid g(0.1);
  const auto keys = ourRay(g, {0.05, 0.05, 0.05}, {0.05, 0.05, 0.55});
  ASSERT_EQ(keys.size(), 5u);  // z voxels 0..4; voxel 5 holds the end point
  for (size_t i = 0; i < keys.size(); ++i) {
    EXPECT_EQ(keys[i][0], lom::grid::kKeyOffset);
    EXPECT_EQ(keys[i][2], lom::grid::kKeyOffset + static_cast<int>(i));
  }
  EXPECT_TRUE(ourRay(g, {0.01, 0.01, 0.01}, {0.02, 0.02, 0.02}).empty());
}

TEST(VoxelGridTest, ConsecutiveVoxelsAreFaceNeighbours) {
  const Grid g(0.01);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coord(-0.6, 0.6);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d a(coord(rng), coord(rng), coord(rng));
    const Eigen::Vector3d b(coord(rng), coord(rng), coord(rng));
    const auto keys = ourRay(g, a, b);
    for (size_t j = 1; j < keys.size(); ++j) {
      int manhattan = 0;
      for (int d = 0; d < 3; ++d) manhattan += std::abs(keys[j][d] - keys[j - 1][d]);
      ASSERT_EQ(manhattan, 1);
    }
  }
}

// The traversal agrees with OctoMap's own computeRayKeys except, rarely, where
// a ray passes within rounding distance of a voxel edge or corner.
TEST(VoxelGridTest, AgreesWithOctomapsRayKeys) {
  octomap::OcTree tree(0.01);
  const Grid g(0.01);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-0.5, 0.5);
  size_t total = 0, differing = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d a(coord(rng), coord(rng), coord(rng));
    const Eigen::Vector3d b(coord(rng), coord(rng), coord(rng));
    std::set<std::array<int, 3>> ours, theirs;
    for (const auto& k : ourRay(g, a, b)) ours.insert({k[0], k[1], k[2]});
    octomap::KeyRay ray;
    ASSERT_TRUE(tree.computeRayKeys(octomap::point3d(a.x(), a.y(), a.z()),
                                    octomap::point3d(b.x(), b.y(), b.z()), ray));
    for (const auto& k : ray) theirs.insert({k[0], k[1], k[2]});
    total += theirs.size();
    for (const auto& k : theirs) differing += ours.count(k) == 0;
  }
  ASSERT_GT(total, 50000u);
  // OctoMap works on float endpoints, this grid on doubles: the sets may differ
  // in a handful of voxels out of ~100k.
  EXPECT_LT(static_cast<double>(differing) / total, 1e-3);
}

}  // namespace
