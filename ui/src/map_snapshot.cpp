#include "lom/ui/map_snapshot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "lom/level_plane.hpp"

namespace lom::ui {

MapSnapshotPtr takeSnapshot(const LabelMap& map, size_t frames_fused) {
  auto snapshot = std::make_shared<MapSnapshot>();
  map.forEachOccupied([&](const OccupiedVoxel& voxel) { snapshot->voxels.push_back(voxel); });
  snapshot->counts = map.occupiedCountPerLabel();
  snapshot->resolution = map.parameters().resolution;
  snapshot->occupancy_threshold = map.parameters().occupancy_threshold;
  snapshot->frames_fused = frames_fused;
  // Levelled from the voxels already gathered (LabelMap::upDirection would gather them again).
  if (const auto cameras_up = map.camerasUp()) {
    std::vector<Eigen::Vector3d> centres;
    centres.reserve(snapshot->voxels.size());
    for (const OccupiedVoxel& voxel : snapshot->voxels) centres.push_back(voxel.center);
    snapshot->up = levelledUp(centres, *cameras_up, snapshot->resolution);
  }
  return snapshot;
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

}  // namespace lom::ui
