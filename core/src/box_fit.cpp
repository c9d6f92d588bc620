#include "lom/box_fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "lom/error.hpp"
#include "voxel_index.hpp"

namespace lom {

namespace {

// OctoMap's key of the voxel whose lower corner is at the origin (tree_max_val at depth 16).
constexpr int kKeyOrigin = 32768;

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

std::vector<std::vector<VoxelKey>> voxelClusters(const std::vector<VoxelKey>& keys,
                                                 double tolerance_voxels) {
  if (!(tolerance_voxels >= 0.0 && tolerance_voxels <= kMaxClusterTolerance))
    throw std::invalid_argument(
        "voxel clusters: the tolerance must be a number of voxel edges from 0 to " +
        std::to_string(static_cast<int>(kMaxClusterTolerance)) + ", got " +
        std::to_string(tolerance_voxels));
  if (keys.empty()) return {};
  static_assert(kMaxClusterTolerance <= VoxelIndex::kMargin,
                "neighbour queries stay within the index's margin");
  const int reach = std::max(1, static_cast<int>(std::floor(tolerance_voxels)));
  std::vector<VoxelIndex::Cell> offsets;
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

  // Flood fill by rank (the index's order: neighbours are mostly in the brick
  // of the last query); each cluster's keys are then sorted.
  const VoxelIndex index(keys);
  const std::vector<VoxelIndex::Cell>& cells = index.cells();
  constexpr std::uint32_t kUnset = ~std::uint32_t{0};
  std::vector<std::uint32_t> cluster_of(cells.size(), kUnset);
  std::vector<std::vector<VoxelKey>> clusters;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < cells.size(); ++seed) {
    if (cluster_of[seed] != kUnset) continue;
    const auto cluster = static_cast<std::uint32_t>(clusters.size());
    std::vector<VoxelKey> members;
    cluster_of[seed] = cluster;
    stack.push_back(seed);
    while (!stack.empty()) {
      const VoxelIndex::Cell c = cells[stack.back()];
      stack.pop_back();
      members.push_back({static_cast<std::uint16_t>(c[0]), static_cast<std::uint16_t>(c[1]),
                         static_cast<std::uint16_t>(c[2])});
      for (const auto& d : offsets) {
        const std::uint32_t rank = index.rankOf({c[0] + d[0], c[1] + d[1], c[2] + d[2]});
        if (rank == VoxelIndex::kAbsent || cluster_of[rank] != kUnset) continue;
        cluster_of[rank] = cluster;
        stack.push_back(rank);
      }
    }
    std::sort(members.begin(), members.end());
    clusters.push_back(std::move(members));
  }
  // Largest first; among equal sizes, the one holding the smallest key first.
  std::sort(clusters.begin(), clusters.end(),
            [](const std::vector<VoxelKey>& a, const std::vector<VoxelKey>& b) {
              return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
            });
  return clusters;
}

std::vector<VoxelKey> bulkVoxels(const std::vector<VoxelKey>& keys, size_t min_part_voxels) {
  std::vector<VoxelKey> bulk;
  for (const auto& part : voxelClusters(keys, 1.0))
    if (part.size() >= min_part_voxels) bulk.insert(bulk.end(), part.begin(), part.end());
  if (bulk.empty()) bulk = keys;
  std::sort(bulk.begin(), bulk.end());
  bulk.erase(std::unique(bulk.begin(), bulk.end()), bulk.end());
  return bulk;
}

std::vector<VoxelKey> largestCluster(const std::vector<VoxelKey>& keys, double tolerance_voxels) {
  std::vector<std::vector<VoxelKey>> clusters = voxelClusters(keys, tolerance_voxels);
  return clusters.empty() ? std::vector<VoxelKey>{} : std::move(clusters.front());
}

namespace {

// The unit up and the level references of the canonical frame: x (the
// world's x made perpendicular to up, or its y when up is along x) and y (up x
// that x), which breaks ties of the x sign.
struct LevelFrame {
  Eigen::Vector3d up, x, y;
};

LevelFrame levelFrame(const Eigen::Vector3d& up) {
  const double length = up.norm();
  if (!up.allFinite() || !(length > 1e-12))
    throw std::invalid_argument("box frame: up must be a finite, non-zero direction");
  LevelFrame frame;
  frame.up = up / length;
  for (const Eigen::Vector3d world : {Eigen::Vector3d(Eigen::Vector3d::UnitX()),
                                      Eigen::Vector3d(Eigen::Vector3d::UnitY())}) {
    frame.x = world - world.dot(frame.up) * frame.up;
    if (frame.x.norm() > 1e-6) break;
  }
  frame.x.normalize();
  frame.y = frame.up.cross(frame.x);
  return frame;
}

}  // namespace

Eigen::Quaterniond levelRotation(const Eigen::Vector3d& up) {
  const LevelFrame frame = levelFrame(up);
  Eigen::Matrix3d axes;
  axes.col(0) = frame.x;
  axes.col(1) = frame.y;
  axes.col(2) = frame.up;
  return Eigen::Quaterniond(axes).normalized();
}

OrientedBox fitOrientedBox(const std::vector<VoxelKey>& keys, double resolution,
                           const Eigen::Vector3d& up_direction) {
  if (keys.empty()) throw std::invalid_argument("fitOrientedBox: no voxels");
  const LevelFrame level = levelFrame(up_direction);
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
  // PCA must be smaller by more than rounding: for blocks aligned with the
  // world the two volumes are equal, and rounding decided.
  const Extent& best = along_principal.volume() < along_world.volume() * (1.0 - 1e-9)
                           ? along_principal
                           : along_world;

  OrientedBox box;
  box.center = best.axes * (0.5 * (best.low + best.high));
  // The same box in a predictable frame (PCA orders its axes by spread and
  // picks their signs at random): z is the axis nearest up, pointing up; x
  // the one of the other two nearest the level x, pointing along it (so yaw
  // lies in (-90, 90] degrees); y = z x x. Box edits (move up, grow the
  // height, yaw) then act as their names say.
  const Eigen::Vector3d size = best.high - best.low;
  const Eigen::Vector3d along_up = best.axes.transpose() * level.up;
  const Eigen::Vector3d along_x = best.axes.transpose() * level.x;
  int zi = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(along_up[i]) > std::abs(along_up[zi])) zi = i;
  const int a = (zi + 1) % 3, b = (zi + 2) % 3;
  const bool a_is_x = std::abs(along_x[a]) > std::abs(along_x[b]) ||
                      (std::abs(along_x[a]) == std::abs(along_x[b]) && a < b);
  const int xi = a_is_x ? a : b, yi = a_is_x ? b : a;
  Eigen::Vector3d z = best.axes.col(zi);
  if (z.dot(level.up) < 0.0) z = -z;
  Eigen::Vector3d x = best.axes.col(xi);
  const double x_along = x.dot(level.x);
  if (x_along < 0.0 || (x_along == 0.0 && x.dot(level.y) < 0.0)) x = -x;
  Eigen::Matrix3d axes;
  axes.col(0) = x;
  axes.col(1) = z.cross(x);
  axes.col(2) = z;
  box.size = Eigen::Vector3d(size[xi], size[yi], size[zi]);
  box.rotation = Eigen::Quaterniond(axes).normalized();
  return box;
}

std::vector<Eigen::Vector3d> finestVoxelCentres(const std::vector<OccupiedVoxel>& leaves,
                                                double resolution, std::optional<int> label) {
  std::vector<Eigen::Vector3d> centres;
  if (!(resolution > 0.0)) return centres;
  auto perEdge = [resolution](const OccupiedVoxel& leaf) {
    return std::max(1L, std::lround(leaf.size / resolution));
  };
  double total = 0.0;
  for (const OccupiedVoxel& leaf : leaves)
    if (!label || leaf.label == *label) total += std::pow(static_cast<double>(perEdge(leaf)), 3.0);
  if (total > static_cast<double>(kMaxExpandedVoxels))
    throw Error("(map)", "voxels",
                "at most " + std::to_string(kMaxExpandedVoxels) +
                    " voxels at the map's resolution (occupied leaves larger than a voxel stand "
                    "for all their voxels)",
                std::to_string(static_cast<unsigned long long>(total)) + " voxels");
  centres.reserve(static_cast<size_t>(total));
  for (const OccupiedVoxel& leaf : leaves) {
    if (label && leaf.label != *label) continue;
    const int per_edge = static_cast<int>(perEdge(leaf));
    const Eigen::Vector3d first =
        leaf.center - Eigen::Vector3d::Constant(0.5 * leaf.size - 0.5 * resolution);
    for (int i = 0; i < per_edge; ++i)
      for (int j = 0; j < per_edge; ++j)
        for (int k = 0; k < per_edge; ++k)
          centres.push_back(first + resolution * Eigen::Vector3d(i, j, k));
  }
  return centres;
}

std::optional<OrientedBox> tightenBox(const OrientedBox& box,
                                      const std::vector<Eigen::Vector3d>& voxel_centres,
                                      double resolution) {
  const Eigen::Matrix3d R =
      box.rotation.normalized().toRotationMatrix();  // box axes (columns) in the world
  // Half the extent of an axis-aligned cube along each box axis.
  const Eigen::Vector3d reach = 0.5 * resolution * R.cwiseAbs().colwise().sum().transpose();
  const Eigen::Vector3d half = 0.5 * box.size;
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  bool any = false;
  for (const Eigen::Vector3d& centre : voxel_centres) {
    const Eigen::Vector3d local = R.transpose() * (centre - box.center);
    if ((local.array().abs() > half.array()).any()) continue;
    low = low.cwiseMin(local - reach);
    high = high.cwiseMax(local + reach);
    any = true;
  }
  if (!any) return std::nullopt;
  // Never past the box drawn: whole cubes of a rotated box reach beyond it,
  // and a box grown to hold them took in more voxels at the next press.
  low = low.cwiseMax(-half);
  high = high.cwiseMin(half);
  OrientedBox tight = box;
  tight.size = high - low;
  tight.center = box.center + R * (0.5 * (low + high));
  return tight;
}

}  // namespace lom
