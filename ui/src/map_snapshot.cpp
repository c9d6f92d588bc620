#include "lom/ui/map_snapshot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "lom/box_fit.hpp"
#include "lom/level_plane.hpp"

namespace lom::ui {

MapSnapshotPtr takeSnapshot(const LabelMap& map, size_t frames_fused,
                            const std::optional<Eigen::Vector3d>& fallback_up) {
  auto snapshot = std::make_shared<MapSnapshot>();
  map.forEachOccupied([&](const OccupiedVoxel& voxel) { snapshot->voxels.push_back(voxel); });
  snapshot->counts = map.occupiedCountPerLabel();
  snapshot->resolution = map.parameters().resolution;
  snapshot->occupancy_threshold = map.parameters().occupancy_threshold;
  snapshot->frames_fused = frames_fused;
  // Levelled from the voxels already gathered (LabelMap::upDirection would gather them again).
  std::optional<Eigen::Vector3d> cameras_up = map.camerasUp();
  if (!cameras_up && fallback_up && fallback_up->allFinite() && fallback_up->norm() > 1e-12)
    cameras_up = fallback_up->normalized();
  if (cameras_up) {
    std::vector<Eigen::Vector3d> centres;
    centres.reserve(snapshot->voxels.size());
    for (const OccupiedVoxel& voxel : snapshot->voxels) centres.push_back(voxel.center);
    snapshot->up = levelledUp(centres, *cameras_up, snapshot->resolution);
  }
  return snapshot;
}

std::optional<MapBulk> mapBulk(const MapSnapshot& snapshot, const std::set<int>& hidden) {
  constexpr long kKeyOrigin = 32768;
  constexpr long kLargestExpanded = 16;  // leaves of up to 16^3 finest voxels are listed
  const double resolution = snapshot.resolution;
  if (!(resolution > 0.0)) return std::nullopt;
  MapBulk bulk;
  bulk.edge = resolution;
  std::vector<VoxelKey> keys;
  bool any = false;
  for (const OccupiedVoxel& voxel : snapshot.voxels) {
    if (hidden.count(voxel.label)) continue;
    any = true;
    const long edge = std::max(1L, std::lround(voxel.size / resolution));
    if (edge > kLargestExpanded) {
      // Bulk by itself: its corners (less half a voxel, so that the cubes
      // around them end on the leaf's faces) stand for it.
      const double reach = 0.5 * (voxel.size - resolution);
      for (int corner = 0; corner < 8; ++corner)
        bulk.centres.push_back(voxel.center + reach * Eigen::Vector3d(corner & 1 ? 1 : -1,
                                                                      corner & 2 ? 1 : -1,
                                                                      corner & 4 ? 1 : -1));
      continue;
    }
    long first[3];
    for (int axis = 0; axis < 3; ++axis)
      first[axis] = std::lround((voxel.center[axis] - 0.5 * voxel.size) / resolution) + kKeyOrigin;
    for (long x = 0; x < edge; ++x)
      for (long y = 0; y < edge; ++y)
        for (long z = 0; z < edge; ++z) {
          const long k[3] = {first[0] + x, first[1] + y, first[2] + z};
          if (std::min({k[0], k[1], k[2]}) < 0 || std::max({k[0], k[1], k[2]}) > 65535) continue;
          keys.push_back({static_cast<std::uint16_t>(k[0]), static_cast<std::uint16_t>(k[1]),
                          static_cast<std::uint16_t>(k[2])});
        }
  }
  if (!any) return std::nullopt;
  // Big leaves are bulk by themselves; without any, and without any part of
  // kBulkPartVoxels, every voxel is framed (as bulkVoxels does).
  const bool big_leaves = !bulk.centres.empty();
  const auto add = [&](const std::vector<VoxelKey>& part) {
    for (const VoxelKey& key : part) bulk.centres.push_back(voxelCenter(key, resolution));
  };
  if (big_leaves) {
    for (const auto& part : voxelClusters(keys, 1.0))
      if (part.size() >= kBulkPartVoxels) add(part);
  } else {
    add(bulkVoxels(keys));
  }
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * resolution);
  for (const Eigen::Vector3d& centre : bulk.centres) {
    bulk.box.extend(centre - half);
    bulk.box.extend(centre + half);
  }
  return bulk;
}

std::optional<Eigen::AlignedBox3d> bulkBounds(const MapSnapshot& snapshot,
                                              const std::set<int>& hidden) {
  const std::optional<MapBulk> bulk = mapBulk(snapshot, hidden);
  if (!bulk) return std::nullopt;
  return bulk->box;
}

std::optional<VoxelHit> firstVoxelHit(const MapSnapshot& snapshot, const std::set<int>& hidden,
                                      const Eigen::Vector3d& origin,
                                      const Eigen::Vector3d& direction) {
  if (!(direction.squaredNorm() > 0.0) || !direction.allFinite() || !origin.allFinite())
    return std::nullopt;
  const Eigen::Vector3d d = direction.normalized();
  const Eigen::Vector3d inverse = d.cwiseInverse();  // +-inf along axes the ray is parallel to
  double nearest = std::numeric_limits<double>::infinity();
  size_t nearest_voxel = 0;
  for (size_t index = 0; index < snapshot.voxels.size(); ++index) {
    const OccupiedVoxel& voxel = snapshot.voxels[index];
    if (hidden.count(voxel.label)) continue;
    // Slabs: the ray's entry into the cube is the largest of its entries into
    // the three slabs, its exit the smallest exit.
    double entry = 0.0, exit = nearest;
    bool meets = true;
    for (int axis = 0; axis < 3 && meets; ++axis) {
      const double low = voxel.center[axis] - 0.5 * voxel.size - origin[axis];
      const double high = low + voxel.size;
      if (d[axis] == 0.0) {
        meets = low <= 0.0 && high >= 0.0;  // parallel to the slab: inside it or never
        continue;
      }
      const double t0 = low * inverse[axis], t1 = high * inverse[axis];
      entry = std::max(entry, std::min(t0, t1));
      exit = std::min(exit, std::max(t0, t1));
      meets = entry <= exit;
    }
    if (meets && entry < nearest) nearest = entry, nearest_voxel = index;
  }
  if (!std::isfinite(nearest)) return std::nullopt;
  return VoxelHit{origin + nearest * d, nearest_voxel};
}

int coordinateDecimals(double voxel_size) {
  const double half = 0.5 * voxel_size;
  if (!(half > 0.0) || !std::isfinite(half)) return 3;
  for (int decimals = 3; decimals < 6; ++decimals) {
    const double scaled = half * std::pow(10.0, decimals);
    if (std::abs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) return decimals;
  }
  return 6;
}

}  // namespace lom::ui
