#include "lom/ui/map_snapshot.hpp"

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

}  // namespace lom::ui
