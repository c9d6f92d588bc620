// Euclidean clustering of voxels and oriented boxes fitted to them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>

#include "lom/box_fit.hpp"
#include "lom/error.hpp"
#include "lom/iou.hpp"
#include "lom/objects.hpp"

namespace {

constexpr double kEdge = 0.01;
constexpr int kOrigin = 32768;

lom::VoxelKey key(int i, int j, int k) {
  return {static_cast<std::uint16_t>(kOrigin + i), static_cast<std::uint16_t>(kOrigin + j),
          static_cast<std::uint16_t>(kOrigin + k)};
}

std::vector<lom::VoxelKey> block(int i0, int i1, int j0, int j1, int k0, int k1) {
  std::vector<lom::VoxelKey> keys;
  for (int i = i0; i < i1; ++i)
    for (int j = j0; j < j1; ++j)
      for (int k = k0; k < k1; ++k) keys.push_back(key(i, j, k));
  return keys;
}

// The key of the voxel holding point p.
lom::VoxelKey keyAt(const Eigen::Vector3d& p) {
  return key(static_cast<int>(std::floor(p.x() / kEdge)),
             static_cast<int>(std::floor(p.y() / kEdge)),
             static_cast<int>(std::floor(p.z() / kEdge)));
}

// The voxels of a box's faces that a camera at `camera` sees (a depth camera
// maps only those): what a fused map holds of an object.
std::vector<lom::VoxelKey> seenSurface(const lom::OrientedBox& box, const Eigen::Vector3d& camera) {
  std::vector<lom::VoxelKey> keys;
  const Eigen::Matrix3d axes = box.rotation.toRotationMatrix();
  const double step = kEdge / 4;
  for (int axis = 0; axis < 3; ++axis)
    for (const int sign : {-1, 1}) {
      const Eigen::Vector3d normal = sign * axes.col(axis);
      const Eigen::Vector3d face = box.center + 0.5 * box.size[axis] * normal;
      if (normal.dot(camera - face) <= 0.0) continue;
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      for (double u = -0.5 * box.size[a]; u <= 0.5 * box.size[a]; u += step)
        for (double v = -0.5 * box.size[b]; v <= 0.5 * box.size[b]; v += step) {
          Eigen::Vector3d local = Eigen::Vector3d::Zero();
          local[axis] = sign * 0.4999 * box.size[axis];
          local[a] = u;
          local[b] = v;
          keys.push_back(keyAt(box.center + axes * local));
        }
    }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// The voxels whose centres lie inside a box.
std::vector<lom::VoxelKey> solid(const lom::OrientedBox& box) {
  std::vector<lom::VoxelKey> keys;
  const double reach = 0.5 * box.size.norm();
  const int lo_i = static_cast<int>(std::floor((box.center.x() - reach) / kEdge));
  const int lo_j = static_cast<int>(std::floor((box.center.y() - reach) / kEdge));
  const int lo_k = static_cast<int>(std::floor((box.center.z() - reach) / kEdge));
  const int n = static_cast<int>(std::ceil(2 * reach / kEdge)) + 1;
  for (int i = lo_i; i <= lo_i + n; ++i)
    for (int j = lo_j; j <= lo_j + n; ++j)
      for (int k = lo_k; k <= lo_k + n; ++k)
        if (box.contains(lom::voxelCenter(key(i, j, k), kEdge))) keys.push_back(key(i, j, k));
  return keys;
}

lom::OrientedBox boxOf(const Eigen::Vector3d& center, const Eigen::Vector3d& size,
                       const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  lom::OrientedBox box;
  box.center = center;
  box.size = size;
  box.rotation = Eigen::Quaterniond(rotation);
  return box;
}

Eigen::Matrix3d yawed(double degrees) {
  return Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Degrees between a box's z and `up`.
double tiltDegrees(const lom::OrientedBox& box, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = box.rotation * Eigen::Vector3d::UnitZ();
  return std::acos(std::clamp(z.dot(up.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// Degrees between the footprints' sides of two level boxes (modulo a quarter turn).
double yawErrorDegrees(const lom::OrientedBox& a, const lom::OrientedBox& b) {
  const Eigen::Vector3d xa = a.rotation * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d xb = b.rotation * Eigen::Vector3d::UnitX();
  const double difference =
      std::abs(std::atan2(xa.y(), xa.x()) - std::atan2(xb.y(), xb.x())) * 180.0 / M_PI;
  const double quarter = std::fmod(difference, 90.0);
  return std::min(quarter, 90.0 - quarter);
}

TEST(BoxFit, LargestClusterDropsOutliers) {
  std::vector<lom::VoxelKey> keys = block(0, 3, 0, 3, 0, 3);  // 27 voxels
  keys.push_back(key(20, 0, 0));
  keys.push_back(key(21, 0, 0));
  const auto cluster = lom::largestCluster(keys, 2.0);
  EXPECT_EQ(cluster, block(0, 3, 0, 3, 0, 3));
}

TEST(BoxFit, ToleranceDecidesWhatIsConnected) {
  // Two 2x2x2 blocks whose nearest centres are 3 voxels apart, and a larger third one far away.
  std::vector<lom::VoxelKey> keys = block(0, 2, 0, 2, 0, 2);
  const auto second = block(4, 6, 0, 2, 0, 2);
  keys.insert(keys.end(), second.begin(), second.end());
  const auto far = block(40, 43, 0, 2, 0, 2);  // 12 voxels
  keys.insert(keys.end(), far.begin(), far.end());
  EXPECT_EQ(lom::largestCluster(keys, 2.0).size(), 12u);
  EXPECT_EQ(lom::largestCluster(keys, 3.0).size(), 16u);
  // Diagonal neighbours (distance sqrt(3)) are connected at the smallest tolerance used.
  EXPECT_EQ(lom::largestCluster({key(0, 0, 0), key(1, 1, 1), key(2, 2, 2)}, 2.0).size(), 3u);
  EXPECT_TRUE(lom::largestCluster({}, 2.0).empty());
}

TEST(BoxFit, TouchingVoxelsAreConnectedAtAnyTolerance) {
  // Sharing a face, an edge (distance sqrt 2) or only a corner (sqrt 3).
  for (double tolerance : {0.5, 1.0, 1.5}) {
    SCOPED_TRACE(tolerance);
    EXPECT_EQ(lom::largestCluster({key(0, 0, 0), key(1, 0, 0)}, tolerance).size(), 2u);
    EXPECT_EQ(lom::largestCluster({key(0, 0, 0), key(1, 1, 0)}, tolerance).size(), 2u);
    EXPECT_EQ(lom::largestCluster({key(0, 0, 0), key(1, 1, 1)}, tolerance).size(), 2u);
    // Voxels that do not touch stay apart below their distance.
    EXPECT_EQ(lom::largestCluster({key(0, 0, 0), key(2, 0, 0)}, tolerance).size(), 1u);
  }
  EXPECT_EQ(lom::largestCluster({key(0, 0, 0), key(2, 0, 0)}, 2.0).size(), 2u);
}

// The clusters by their definition: every pair of voxels compared, joined
// when touching or within the tolerance; largest first, ties by smallest key.
std::vector<std::vector<lom::VoxelKey>> clustersByPairs(std::vector<lom::VoxelKey> keys,
                                                        double tolerance) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<size_t> parent(keys.size());
  std::iota(parent.begin(), parent.end(), size_t{0});
  const auto root = [&](size_t i) {
    while (parent[i] != i) i = parent[i];
    return i;
  };
  for (size_t i = 0; i < keys.size(); ++i)
    for (size_t j = i + 1; j < keys.size(); ++j) {
      const int dx = keys[i].x - keys[j].x, dy = keys[i].y - keys[j].y, dz = keys[i].z - keys[j].z;
      const bool touching = std::abs(dx) <= 1 && std::abs(dy) <= 1 && std::abs(dz) <= 1;
      if (touching || dx * dx + dy * dy + dz * dz <= tolerance * tolerance)
        parent[root(i)] = root(j);
    }
  std::map<size_t, std::vector<lom::VoxelKey>> by_root;
  for (size_t i = 0; i < keys.size(); ++i) by_root[root(i)].push_back(keys[i]);
  std::vector<std::vector<lom::VoxelKey>> clusters;
  for (auto& [r, members] : by_root) clusters.push_back(std::move(members));
  std::sort(clusters.begin(), clusters.end(), [](const auto& a, const auto& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return clusters;
}

TEST(BoxFit, ClustersMatchTheirDefinitionOnRandomSets) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 30; ++trial) {
    SCOPED_TRACE(trial);
    // Sparse sets give many clusters of equal sizes (the tie rule); some
    // near the ends of the key range, whose neighbours fall outside it.
    std::uniform_int_distribution<int> coordinate(0, 13);
    const double tolerance =
        std::vector<double>{0.5, 1.5, 2.0, 2.9, 4.0}[static_cast<size_t>(trial % 5)];
    std::vector<lom::VoxelKey> keys;
    for (int i = 0; i < 60; ++i) {
      const int x = coordinate(rng), y = coordinate(rng), z = coordinate(rng);
      if (trial % 3 == 2)
        keys.push_back({static_cast<std::uint16_t>(x), static_cast<std::uint16_t>(65535 - y),
                        static_cast<std::uint16_t>(z)});
      else
        keys.push_back(key(x, y, z));
    }
    const auto expected = clustersByPairs(keys, tolerance);
    EXPECT_EQ(lom::voxelClusters(keys, tolerance), expected);
    EXPECT_EQ(lom::largestCluster(keys, tolerance), expected.front());
    // Objects keep the clusters of at least the minimum size, in the same order.
    std::vector<std::vector<lom::VoxelKey>> at_least_two;
    for (const auto& c : expected)
      if (c.size() >= 2) at_least_two.push_back(c);
    EXPECT_EQ(lom::euclideanClusters(keys, tolerance, 2), at_least_two);
  }
}

TEST(BoxFit, BulkLeavesOutPartsSmallerThanItsLimit) {
  std::vector<lom::VoxelKey> keys = block(0, 3, 0, 3, 0, 3);          // 27 voxels
  const std::vector<lom::VoxelKey> wall = block(10, 11, 0, 8, 0, 1);  // 8 in a row: kept
  keys.insert(keys.end(), wall.begin(), wall.end());
  const std::vector<lom::VoxelKey> speck = {key(200, 0, 0), key(201, 1, 1)};  // corner to corner
  keys.insert(keys.end(), speck.begin(), speck.end());
  keys.push_back(key(-300, 5, 5));
  std::vector<lom::VoxelKey> expected = block(0, 3, 0, 3, 0, 3);
  expected.insert(expected.end(), wall.begin(), wall.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(lom::bulkVoxels(keys), expected);
  EXPECT_EQ(lom::bulkVoxels(keys, 27), block(0, 3, 0, 3, 0, 3));
  // No part that large: every voxel is kept, sorted.
  std::vector<lom::VoxelKey> all = keys;
  std::sort(all.begin(), all.end());
  EXPECT_EQ(lom::bulkVoxels(keys, 28), all);
  EXPECT_TRUE(lom::bulkVoxels({}).empty());
}

TEST(BoxFit, ToleranceOutsideItsRangeIsRefused) {
  const std::vector<lom::VoxelKey> keys{key(0, 0, 0), key(3, 0, 0)};
  for (const double bad : {-1.0, 20.5, 1e30, std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    SCOPED_TRACE(bad);
    EXPECT_THROW((void)lom::largestCluster(keys, bad), std::invalid_argument);
    EXPECT_THROW((void)lom::voxelClusters(keys, bad), std::invalid_argument);
  }
  // The largest tolerance allowed reaches across 20 voxel edges.
  EXPECT_EQ(
      lom::voxelClusters({key(0, 0, 0), key(20, 0, 0), key(40, 1, 0)}, lom::kMaxClusterTolerance)
          .size(),
      2u);
}

TEST(BoxFit, AxisAlignedBlockIsFittedExactly) {
  lom::OrientedBox truth;  // voxels [0, 5) x [0, 3) x [0, 2)
  truth.center = {0.025, 0.015, 0.01};
  truth.size = {0.05, 0.03, 0.02};
  const lom::OrientedBox fitted = lom::fitOrientedBox(block(0, 5, 0, 3, 0, 2), kEdge);
  EXPECT_NEAR(lom::boxIoU(fitted, truth), 1.0, 1e-9);
}

TEST(BoxFit, RotatedObjectGetsARotatedBox) {
  // Voxels whose centres lie in a long thin box turned 30 degrees about z.
  lom::OrientedBox truth;
  truth.center = {0.0, 0.0, 0.05};
  truth.size = {0.40, 0.06, 0.10};
  truth.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()));
  std::vector<lom::VoxelKey> keys;
  for (int i = -30; i < 30; ++i)
    for (int j = -30; j < 30; ++j)
      for (int k = 0; k < 10; ++k)
        if (truth.contains(lom::voxelCenter(key(i, j, k), kEdge))) keys.push_back(key(i, j, k));
  ASSERT_GT(keys.size(), 1000u);
  const lom::OrientedBox fitted = lom::fitOrientedBox(keys, kEdge);
  // The box encloses the voxel cubes, so it reaches past the object by under a
  // voxel on each side; the axis-aligned box of the same voxels is far worse.
  lom::OrientedBox axis_aligned;
  Eigen::Vector3d low = Eigen::Vector3d::Constant(1e9), high = Eigen::Vector3d::Constant(-1e9);
  for (const auto& k : keys) {
    low = low.cwiseMin(lom::voxelCenter(k, kEdge) - Eigen::Vector3d::Constant(kEdge / 2));
    high = high.cwiseMax(lom::voxelCenter(k, kEdge) + Eigen::Vector3d::Constant(kEdge / 2));
  }
  axis_aligned.center = (low + high) / 2;
  axis_aligned.size = high - low;
  EXPECT_GT(lom::boxIoU(fitted, truth), 0.7);
  EXPECT_LT(lom::boxIoU(axis_aligned, truth), 0.3);
  EXPECT_LT(fitted.volume(), axis_aligned.volume());

  int longest = 0;
  fitted.size.maxCoeff(&longest);
  const Eigen::Vector3d fitted_long = fitted.rotation * Eigen::Vector3d::Unit(longest);
  EXPECT_GT(std::abs(fitted_long.dot(truth.rotation * Eigen::Vector3d::UnitX())), std::cos(3.0 * M_PI / 180.0));
  // Every voxel, reaching half an edge from its centre along the box's axes,
  // is inside the fitted box, but for sparse end layers (the tips of the
  // turned object's voxelised ends), at most 5% of the voxels at each end.
  const Eigen::Matrix3d axes = fitted.rotation.toRotationMatrix();
  size_t outside = 0;
  for (const auto& k : keys) {
    const Eigen::Vector3d local = axes.transpose() * (lom::voxelCenter(k, kEdge) - fitted.center);
    const Eigen::Vector3d excess =
        local.cwiseAbs() + Eigen::Vector3d::Constant(kEdge / 2) - fitted.size / 2;
    if (excess.maxCoeff() > 1e-12) ++outside;
    EXPECT_LT(excess.maxCoeff(), 2 * kEdge) << "a trimmed layer is at the box's end";
  }
  EXPECT_LE(outside, 4 * (keys.size() / 20));
}

// The fitted box's frame is canonical: z nearest the world's up (pointing
// up), x nearest the world's x (pointing +x), so that box edits act as their
// names say; a block aligned with the world gets the axis-aligned box.
// In a recording whose world is its first camera, up is not +z: a box fitted
// with the map's up stands along it, so that its height is the object's.
TEST(BoxFit, TheCanonicalFrameFollowsTheUpItIsGiven) {
  // A bottle 8 cm tall along -y (the camera's up), 3 cm across.
  const std::vector<lom::VoxelKey> keys = block(0, 3, -8, 0, 0, 3);
  const Eigen::Vector3d up(0.0, -1.0, 0.0);
  const lom::OrientedBox standing = lom::fitOrientedBox(keys, kEdge, up);
  const Eigen::Matrix3d axes = standing.rotation.toRotationMatrix();
  EXPECT_GT(axes.col(2).dot(up), 0.999) << "box z is the map's up";
  EXPECT_GT(axes.col(0).x(), 0.999) << "box x is the world's x, level";
  EXPECT_NEAR(standing.size.z(), 0.08, 1e-9) << "its height is the bottle's";
  EXPECT_TRUE(standing.center.isApprox(Eigen::Vector3d(0.015, -0.04, 0.015), 1e-9));
  // The same box as with world +z, only its axes named otherwise.
  const lom::OrientedBox world_z = lom::fitOrientedBox(keys, kEdge);
  EXPECT_NEAR(world_z.size.z(), 0.03, 1e-9);
  EXPECT_NEAR(world_z.volume(), standing.volume(), 1e-12);
  EXPECT_TRUE(world_z.center.isApprox(standing.center, 1e-12));
  // A tilted up picks the axis nearest it.
  const Eigen::Vector3d tilted = Eigen::Vector3d(0.3, -1.0, 0.4).normalized();
  EXPECT_NEAR(lom::fitOrientedBox(keys, kEdge, tilted).size.z(), 0.08, 1e-9);

  const Eigen::Matrix3d level = lom::levelRotation(up).toRotationMatrix();
  EXPECT_TRUE(level.col(2).isApprox(up, 1e-12));
  EXPECT_TRUE(level.col(0).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_NEAR(level.determinant(), 1.0, 1e-12);
  // Up along x: the level x is the world's y.
  EXPECT_TRUE(lom::levelRotation(Eigen::Vector3d::UnitX())
                  .toRotationMatrix()
                  .col(0)
                  .isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_THROW((void)lom::levelRotation(Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW((void)lom::fitOrientedBox(keys, kEdge, Eigen::Vector3d(std::nan(""), 0, 1)),
               std::invalid_argument);
}

TEST(BoxFit, FittedBoxesHaveACanonicalFrame) {
  // A flat plate (1 voxel thick) turned 30 degrees about z: PCA orders its
  // axes thinnest first, which made box x the world's up.
  lom::OrientedBox plate;
  plate.center = {0.0, 0.0, 0.005};
  plate.size = {0.30, 0.20, 0.01};
  plate.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()));
  std::vector<lom::VoxelKey> keys;
  for (int i = -30; i < 30; ++i)
    for (int j = -30; j < 30; ++j)
      if (plate.contains(lom::voxelCenter(key(i, j, 0), kEdge))) keys.push_back(key(i, j, 0));
  const lom::OrientedBox fitted = lom::fitOrientedBox(keys, kEdge);
  const Eigen::Matrix3d axes = fitted.rotation.toRotationMatrix();
  EXPECT_GT(axes(2, 2), 0.999) << "box z is the world's up";
  EXPECT_GT(axes(0, 0), 0.0) << "box x points +x";
  EXPECT_NEAR(fitted.size.z(), 0.01, 1e-9);
  EXPECT_GT(fitted.size.x(), fitted.size.y()) << "the long side along x, as the plate lies";
  EXPECT_NEAR(std::atan2(axes(1, 0), axes(0, 0)), M_PI / 6, 3.0 * M_PI / 180.0);
  // Blocks aligned with the world: the axis-aligned box, unrotated, every time.
  for (int w = 1; w <= 6; ++w)
    for (int h = 1; h <= 6; ++h) {
      std::vector<lom::VoxelKey> block;
      for (int i = 0; i < w; ++i)
        for (int j = 0; j < h; ++j)
          for (int k = 0; k < 2; ++k) block.push_back(key(1000 + i, 7 + j, k));
      const lom::OrientedBox box = lom::fitOrientedBox(block, kEdge);
      EXPECT_TRUE(box.rotation.isApprox(Eigen::Quaterniond::Identity(), 1e-9)) << w << "x" << h;
      EXPECT_NEAR((box.size - Eigen::Vector3d(w, h, 2) * kEdge).norm(), 0.0, 1e-9) << w << "x" << h;
    }
}

TEST(BoxFit, TightenedBoxEnclosesTheVoxelsInsideItAndNoMore) {
  constexpr double r = 0.01;
  // A 3x2x1 block of voxels from the origin, and one voxel far away.
  std::vector<Eigen::Vector3d> centres;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j) centres.emplace_back((i + 0.5) * r, (j + 0.5) * r, 0.5 * r);
  centres.emplace_back(0.205, 0.005, 0.005);
  lom::OrientedBox rough;  // 5 cm around the block, not reaching the far voxel
  rough.center = {0.015, 0.01, 0.005};
  rough.size = {0.1, 0.1, 0.1};
  const auto tight = lom::tightenBox(rough, centres, r);
  ASSERT_TRUE(tight.has_value());
  EXPECT_NEAR((tight->center - Eigen::Vector3d(0.015, 0.01, 0.005)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((tight->size - Eigen::Vector3d(0.03, 0.02, 0.01)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(tight->rotation.isApprox(rough.rotation));
  // A voxel whose centre lies outside the box is left out, even if its cube
  // reaches in; one whose centre is inside is held, but the box never grows
  // past the sides drawn (which here cut the outer columns' cubes).
  lom::OrientedBox partial = rough;
  partial.size.x() =
      0.02 +
      2 * 0.0004;  // centre at 0.015, x from 0.0046: the first column's centres (0.005) inside
  partial.center.x() = 0.015;
  const auto cut = lom::tightenBox(partial, centres, r);
  ASSERT_TRUE(cut.has_value());
  EXPECT_NEAR(cut->size.x(), 0.0208, 1e-12) << "the three columns, within the sides drawn";
  EXPECT_NEAR(cut->size.y(), 0.02, 1e-12) << "pulled in where the block ends inside";
  partial.size.x() = 0.019;  // x from 0.0055 to 0.0245: only the middle column's centres
  EXPECT_NEAR(lom::tightenBox(partial, centres, r)->size.x(), 0.01, 1e-12);
  // A rotated box keeps its rotation and encloses each cube along its own axes.
  lom::OrientedBox turned;
  turned.center = {0.005, 0.005, 0.005};
  turned.size = {0.05, 0.05, 0.05};
  turned.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()));
  const auto one = lom::tightenBox(turned, {Eigen::Vector3d(0.005, 0.005, 0.005)}, r);
  ASSERT_TRUE(one.has_value());
  EXPECT_NEAR(one->size.x(), r * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(one->size.y(), r * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(one->size.z(), r, 1e-12);
  EXPECT_TRUE(one->rotation.isApprox(turned.rotation));
  // A rotated box over a slab larger than it: tightening again changes
  // nothing (holding whole cubes used to grow the box at every press).
  std::vector<Eigen::Vector3d> slab;
  for (int i = -20; i < 20; ++i)
    for (int j = -20; j < 20; ++j)
      for (int k = 0; k < 3; ++k) slab.emplace_back((i + 0.5) * r, (j + 0.5) * r, (k + 0.5) * r);
  lom::OrientedBox over = turned;
  over.center = {0.0, 0.0, 0.015};
  over.size = {0.1, 0.1, 0.1};
  const auto first = lom::tightenBox(over, slab, r);
  ASSERT_TRUE(first.has_value());
  const auto second = lom::tightenBox(*first, slab, r);
  ASSERT_TRUE(second.has_value());
  EXPECT_NEAR((second->size - first->size).norm(), 0.0, 1e-12);
  EXPECT_NEAR((second->center - first->center).norm(), 0.0, 1e-12);
  EXPECT_LE(first->size.x(), 0.1 + 1e-12);
  // Nothing inside: no box.
  rough.center = {1.0, 1.0, 1.0};
  EXPECT_FALSE(lom::tightenBox(rough, centres, r).has_value());
}

TEST(BoxFit, FinestCentresSplitPrunedLeaves) {
  const std::vector<lom::OccupiedVoxel> leaves = {
      {Eigen::Vector3d(0.02, 0.02, 0.02), 0.04, 1, 0.9f},  // 4x4x4 voxels
      {Eigen::Vector3d(0.105, 0.005, 0.005), 0.01, 2, 0.9f}};
  const auto all = lom::finestVoxelCentres(leaves, 0.01);
  ASSERT_EQ(all.size(), 65u);
  EXPECT_NEAR((all.front() - Eigen::Vector3d(0.005, 0.005, 0.005)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((all[63] - Eigen::Vector3d(0.035, 0.035, 0.035)).norm(), 0.0, 1e-12);
  EXPECT_EQ(lom::finestVoxelCentres(leaves, 0.01, 2).size(), 1u);
  EXPECT_TRUE(lom::finestVoxelCentres(leaves, 0.01, 3).empty());
  EXPECT_TRUE(lom::finestVoxelCentres(leaves, 0.0).empty());
  // A leaf standing for more voxels than a map lists (512^3 here) is refused, not allocated.
  const std::vector<lom::OccupiedVoxel> huge = {{Eigen::Vector3d::Zero(), 5.12, 1, 0.9f}};
  EXPECT_THROW((void)lom::finestVoxelCentres(huge, 0.01), lom::Error);
  EXPECT_TRUE(lom::finestVoxelCentres(huge, 0.01, 2).empty()) << "another label's leaves are not counted";
}

// Surfaces seen from one side pull the principal axes of an upright object
// off its up by several degrees, and a world-aligned box ignored its yaw:
// the fitted box stands level with up, turned to the object's footprint.
TEST(BoxFit, BoxesStandLevelAndTurnToTheFootprint) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  for (const double yaw : {0.0, 15.0, 30.0, 45.0, 60.0}) {
    SCOPED_TRACE("yaw " + std::to_string(yaw));
    // An upright 16x6x22 cm box on the floor, seen from the side and above.
    const lom::OrientedBox truth =
        boxOf(Eigen::Vector3d(0.2, 0.0, 0.11), Eigen::Vector3d(0.16, 0.06, 0.22), yawed(yaw));
    const lom::OrientedBox fitted =
        lom::fitOrientedBox(seenSurface(truth, Eigen::Vector3d(-0.4, -0.1, 0.45)), kEdge, up);
    EXPECT_LT(tiltDegrees(fitted, up), 1e-3);
    EXPECT_LT(yawErrorDegrees(fitted, truth), 2.5);
    EXPECT_NEAR(fitted.size.z(), 0.22, 1.5 * kEdge);
    EXPECT_GT(lom::boxIoU(fitted, truth), 0.6);
  }
  // A solid block turned 15 degrees: its turn, not the world's axes.
  const lom::OrientedBox turned =
      boxOf(Eigen::Vector3d(0.0, 0.0, 0.05), Eigen::Vector3d(0.20, 0.12, 0.10), yawed(15.0));
  const lom::OrientedBox fitted = lom::fitOrientedBox(solid(turned), kEdge);
  EXPECT_LT(yawErrorDegrees(fitted, turned), 1.5);
  EXPECT_GT(lom::boxIoU(fitted, turned), 0.8);
}

// A world that is the first camera's frame (up tilted by its pitch) gets the
// box of a z-up world, turned with it: the fit depends on the scene and its
// up, not on how the world's axes lie.
TEST(BoxFit, TheBoxTurnsWithTheWorld) {
  const lom::OrientedBox truth =
      boxOf(Eigen::Vector3d(0.2, 0.0, 0.04), Eigen::Vector3d(0.10, 0.09, 0.08), yawed(30.0));
  const Eigen::Vector3d camera(-0.4, 0.0, 0.35);
  const lom::OrientedBox level =
      lom::fitOrientedBox(seenSurface(truth, camera), kEdge, Eigen::Vector3d::UnitZ());
  for (const double pitch : {20.0, 35.0}) {
    SCOPED_TRACE("pitch " + std::to_string(pitch));
    // The scene seen from a camera pitched down, in that camera's frame
    // (x right, y down, z forward), shifted off the voxel grid.
    const Eigen::Matrix3d world =
        Eigen::AngleAxisd(pitch * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix() *
        Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Vector3d shift(0.0013, 0.0021, 0.6);
    lom::OrientedBox moved = truth;
    moved.center = world * truth.center + shift;
    moved.rotation = Eigen::Quaterniond(world * truth.rotation.toRotationMatrix());
    const Eigen::Vector3d up = world * Eigen::Vector3d::UnitZ();
    const lom::OrientedBox fitted =
        lom::fitOrientedBox(seenSurface(moved, world * camera + shift), kEdge, up);
    EXPECT_LT(tiltDegrees(fitted, up), 1e-3);
    // Back in the z-up world: the same box, within a voxel.
    lom::OrientedBox back = fitted;
    back.center = world.transpose() * (fitted.center - shift);
    back.rotation = Eigen::Quaterniond(world.transpose() * fitted.rotation.toRotationMatrix());
    EXPECT_LT((back.center - level.center).norm(), kEdge);
    // The voxels of a tilted grid spread the top face over a few layers: the
    // height grows by about a voxel, the footprint by less.
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_NEAR(back.size[axis], level.size[axis], 1.5 * kEdge);
    // Both yaws are the object's (a footprint this near a square leaves a few
    // degrees of play).
    EXPECT_LT(yawErrorDegrees(back, truth), 4.0);
    EXPECT_LT(yawErrorDegrees(level, truth), 4.0);
    EXPECT_NEAR(lom::boxIoU(fitted, moved), lom::boxIoU(level, truth), 0.1);
  }
}

// An object that lies tilted (a board leaning at 40 degrees) keeps a tilted
// box: the level box of it is several times larger.
TEST(BoxFit, AnObjectLyingTiltedGetsATiltedBox) {
  const Eigen::Matrix3d leaning =
      Eigen::AngleAxisd(40.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const lom::OrientedBox board =
      boxOf(Eigen::Vector3d(0.0, 0.0, 0.15), Eigen::Vector3d(0.40, 0.10, 0.03), leaning);
  const lom::OrientedBox fitted = lom::fitOrientedBox(solid(board), kEdge);
  EXPECT_NEAR(tiltDegrees(fitted, Eigen::Vector3d::UnitZ()), 40.0, 2.0);
  EXPECT_GT(lom::boxIoU(fitted, board), 0.6);
}

// Voxels of the label under the plane objects rest on (its mask's edge
// projected onto the floor below) do not stretch the box downwards, unless
// they are most of the label's voxels.
TEST(BoxFit, VoxelsUnderTheSupportAreLeftOut) {
  std::vector<lom::VoxelKey> keys = block(0, 8, 0, 6, 0, 4);   // resting on z = 0
  for (int i = 0; i < 8; ++i) keys.push_back(key(i, -1, -2));  // under the floor
  lom::LevelPlane floor;
  floor.normal = Eigen::Vector3d::UnitZ();
  floor.offset = 0.0;
  const lom::OrientedBox without = lom::fitOrientedBox(keys, kEdge);
  EXPECT_NEAR(without.size.z(), 0.06, 1e-9) << "no support: every voxel is enclosed";
  const lom::OrientedBox fitted = lom::fitOrientedBox(keys, kEdge, floor.normal, floor);
  EXPECT_NEAR(fitted.size.z(), 0.04, 1e-9);
  EXPECT_NEAR(fitted.center.z(), 0.02, 1e-9);
  EXPECT_NEAR(fitted.size.y(), 0.06, 1e-9);
  // A voxel layer of the floor itself (within an edge of the plane) is kept.
  lom::LevelPlane lower = floor;
  lower.offset = -0.012;
  EXPECT_NEAR(lom::fitOrientedBox(keys, kEdge, floor.normal, lower).size.z(), 0.06, 1e-9);
  // An object that lies under the plane (a table top taken for the support) keeps its box.
  lom::LevelPlane table = floor;
  table.offset = 0.5;
  EXPECT_NEAR(lom::fitOrientedBox(keys, kEdge, floor.normal, table).size.z(), 0.06, 1e-9);
}

// Sparse end layers are trimmed: a chain of stray voxels two edges apart,
// which the cluster tolerance joins to the object, does not triple its
// height; a tiny object and a thin one keep every voxel.
TEST(BoxFit, SparseEndLayersAreTrimmedButNeverMostOfAnObject) {
  std::vector<lom::VoxelKey> keys = block(0, 10, 0, 10, 0, 10);
  const std::vector<lom::VoxelKey> body = keys;
  for (int step = 1; step <= 5; ++step) keys.push_back(key(5, 5, 9 + 2 * step));
  ASSERT_EQ(lom::largestCluster(keys, 2.0).size(), keys.size()) << "the chain joins the object";
  const lom::OrientedBox fitted = lom::fitOrientedBox(keys, kEdge);
  EXPECT_NEAR(fitted.size.z(), 0.10, 1e-9);
  EXPECT_NEAR(lom::boxIoU(fitted, lom::fitOrientedBox(body, kEdge)), 1.0, 1e-9);
  // A stray at a corner trims along each axis alike.
  std::vector<lom::VoxelKey> corner = body;
  corner.push_back(key(11, 11, 11));
  EXPECT_NEAR(lom::boxIoU(lom::fitOrientedBox(corner, kEdge), lom::fitOrientedBox(body, kEdge)),
              1.0, 1e-9);
  // A few voxels: all kept.
  const std::vector<lom::VoxelKey> tiny{key(0, 0, 0), key(1, 0, 0), key(2, 0, 0), key(4, 0, 0),
                                        key(6, 0, 0)};
  EXPECT_NEAR(lom::fitOrientedBox(tiny, kEdge).size.x(), 0.07, 1e-9);
  // A rod one voxel across, its every layer as sparse as its ends: all kept.
  const std::vector<lom::VoxelKey> rod = block(0, 1, 0, 1, 0, 40);
  EXPECT_NEAR(lom::fitOrientedBox(rod, kEdge).size.z(), 0.40, 1e-9);
  // A pyramid's tip layers are sparse: at most 5% of its voxels go.
  std::vector<lom::VoxelKey> pyramid;
  for (int k = 0; k < 10; ++k)
    for (int i = k; i < 20 - k; ++i)
      for (int j = k; j < 20 - k; ++j) pyramid.push_back(key(i, j, k));
  const lom::OrientedBox peak = lom::fitOrientedBox(pyramid, kEdge);
  size_t inside = 0;
  for (const auto& k : pyramid)
    if (peak.contains(lom::voxelCenter(k, kEdge), 1e-9)) ++inside;
  EXPECT_GE(inside, pyramid.size() - pyramid.size() / 20 * 2);
}

TEST(BoxFit, NoVoxelsIsAnError) {
  EXPECT_THROW((void)lom::fitOrientedBox({}, kEdge), std::invalid_argument);
}

}  // namespace
