#include "lom/ui/map_snapshot.hpp"

namespace lom::ui {

MapSnapshotPtr takeSnapshot(const LabelMap& map, size_t frames_fused) {
  auto snapshot = std::make_shared<MapSnapshot>();
  map.forEachOccupied([&](const OccupiedVoxel& voxel) { snapshot->voxels.push_back(voxel); });
  snapshot->counts = map.occupiedCountPerLabel();
  snapshot->resolution = map.parameters().resolution;
  snapshot->occupancy_threshold = map.parameters().occupancy_threshold;
  snapshot->frames_fused = frames_fused;
  snapshot->up = map.upDirection();
  return snapshot;
}

}  // namespace lom::ui
