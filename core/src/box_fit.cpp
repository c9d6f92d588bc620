#include "lom/box_fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace lom {

namespace {

// OctoMap's key of the voxel whose lower corner is at the origin (tree_max_val at depth 16).
constexpr int kKeyOrigin = 32768;

// Neighbour keys may step a little outside 0..65535; the bias keeps them distinct and positive.
std::uint64_t pack(int x, int y, int z) {
  constexpr int kBias = 1 << 10;
  return (static_cast<std::uint64_t>(x + kBias) << 42) | (static_cast<std::uint64_t>(y + kBias) << 21) |
         static_cast<std::uint64_t>(z + kBias);
}

struct Extent {
  Eigen::Matrix3d axes;  // columns: box axes in world
  Eigen::Vector3d low, high;
  [[nodiscard]] double volume() const { return (high - low).prod(); }
};

// Extent along `axes` of all voxel cubes (each cube reaches 0.5 * edge * sum|a_i| along axis a).
Extent enclose(const std::vector<Eigen::Vector3d>& centers, const Eigen::Matrix3d& axes,
               double resolution) {
  Extent extent{axes, Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()),
                Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity())};
  const Eigen::Vector3d reach = 0.5 * resolution * axes.cwiseAbs().colwise().sum().transpose();
  for (const auto& c : centers) {
    const Eigen::Vector3d projected = axes.transpose() * c;
    extent.low = extent.low.cwiseMin(projected - reach);
    extent.high = extent.high.cwiseMax(projected + reach);
  }
  return extent;
}

}  // namespace

Eigen::Vector3d voxelCenter(const VoxelKey& key, double resolution) {
  return {(static_cast<int>(key.x) - kKeyOrigin + 0.5) * resolution,
          (static_cast<int>(key.y) - kKeyOrigin + 0.5) * resolution,
          (static_cast<int>(key.z) - kKeyOrigin + 0.5) * resolution};
}

std::vector<VoxelKey> largestCluster(const std::vector<VoxelKey>& keys, double tolerance_voxels) {
  if (keys.empty()) return {};
  std::vector<VoxelKey> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());

  const int reach = std::max(1, static_cast<int>(std::floor(tolerance_voxels)));
  std::vector<std::array<int, 3>> offsets;
  for (int dx = -reach; dx <= reach; ++dx)
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dz = -reach; dz <= reach; ++dz) {
        const int squared = dx * dx + dy * dy + dz * dz;
        // 26-neighbours (touching by a face, an edge or a corner) are always
        // connected, whatever the tolerance.
        const bool touching = std::abs(dx) <= 1 && std::abs(dy) <= 1 && std::abs(dz) <= 1;
        if (squared > 0 && (touching || squared <= tolerance_voxels * tolerance_voxels))
          offsets.push_back({dx, dy, dz});
      }

  std::unordered_map<std::uint64_t, size_t> index_of;
  index_of.reserve(sorted.size() * 2);
  for (size_t i = 0; i < sorted.size(); ++i) index_of.emplace(pack(sorted[i].x, sorted[i].y, sorted[i].z), i);

  // Flood fill in key order: the first cluster found of a given size holds the smallest key.
  std::vector<int> cluster_of(sorted.size(), -1);
  std::vector<size_t> stack;
  int best = -1;
  size_t best_size = 0;
  int cluster = 0;
  for (size_t seed = 0; seed < sorted.size(); ++seed) {
    if (cluster_of[seed] >= 0) continue;
    size_t size = 0;
    cluster_of[seed] = cluster;
    stack.push_back(seed);
    while (!stack.empty()) {
      const VoxelKey key = sorted[stack.back()];
      stack.pop_back();
      ++size;
      for (const auto& d : offsets) {
        const auto it = index_of.find(pack(key.x + d[0], key.y + d[1], key.z + d[2]));
        if (it == index_of.end() || cluster_of[it->second] >= 0) continue;
        cluster_of[it->second] = cluster;
        stack.push_back(it->second);
      }
    }
    if (size > best_size) {
      best_size = size;
      best = cluster;
    }
    ++cluster;
  }
  std::vector<VoxelKey> result;
  result.reserve(best_size);
  for (size_t i = 0; i < sorted.size(); ++i)
    if (cluster_of[i] == best) result.push_back(sorted[i]);
  return result;
}

OrientedBox fitOrientedBox(const std::vector<VoxelKey>& keys, double resolution) {
  if (keys.empty()) throw std::invalid_argument("fitOrientedBox: no voxels");
  std::vector<Eigen::Vector3d> centers;
  centers.reserve(keys.size());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& key : keys) {
    centers.push_back(voxelCenter(key, resolution));
    mean += centers.back();
  }
  mean /= static_cast<double>(centers.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& c : centers) covariance += (c - mean) * (c - mean).transpose();

  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d principal = solver.eigenvectors();
  // A right-handed frame, so that it is a rotation.
  if (principal.determinant() < 0) principal.col(2) = -principal.col(2);

  // PCA axes of a nearly cubic or symmetric object are arbitrary; the axis-aligned
  // box often fits voxel data (itself axis-aligned) better, so the smaller one wins.
  const Extent along_principal = enclose(centers, principal, resolution);
  const Extent along_world = enclose(centers, Eigen::Matrix3d::Identity(), resolution);
  const Extent& best = along_principal.volume() < along_world.volume() ? along_principal : along_world;

  OrientedBox box;
  box.size = best.high - best.low;
  box.center = best.axes * (0.5 * (best.low + best.high));
  box.rotation = Eigen::Quaterniond(best.axes).normalized();
  return box;
}

}  // namespace lom
