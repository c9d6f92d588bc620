#pragma once
// What the GUI thread sees of the map: a copy of its occupied voxels and
// per-label counts, made by the map worker (the only thread touching the map).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "lom/label_map.hpp"

namespace lom::ui {

struct MapSnapshot {
  std::vector<OccupiedVoxel> voxels;
  std::map<int, size_t> counts;  // finest-resolution voxels per label
  double resolution = 0.0;
  double occupancy_threshold = 0.5;
  size_t frames_fused = 0;
  // The map's up direction (LabelMap::upDirection: its cameras' mean up,
  // levelled by the largest plane of voxels near it; for a map that records
  // no camera, the fallback up given to takeSnapshot, levelled alike).
  std::optional<Eigen::Vector3d> up;

  [[nodiscard]] bool empty() const { return voxels.empty(); }
};

using MapSnapshotPtr = std::shared_ptr<const MapSnapshot>;

// `fallback_up` stands in for the cameras' up of a map that records none (an
// older map opened with the sequence it was fused from: its cameras' mean up).
[[nodiscard]] MapSnapshotPtr takeSnapshot(
    const LabelMap& map, size_t frames_fused,
    const std::optional<Eigen::Vector3d>& fallback_up = std::nullopt);

// The box holding the cubes of the snapshot's bulk: the voxels shown (labels
// in `hidden` left out) in connected parts of at least kBulkPartVoxels
// finest voxels (bulkVoxels), as `render` frames a map. Leaves larger than
// the resolution count as their finest voxels; those of more than 16^3 are
// bulk by themselves. None when no voxel is shown. What the 3D view frames
// (Zoom to Map, the standard views, Reset Camera).
[[nodiscard]] std::optional<Eigen::AlignedBox3d> bulkBounds(const MapSnapshot& snapshot,
                                                            const std::set<int>& hidden);

// The same bulk as cubes of edge `edge` (the resolution) centred on
// `centres`: the finest voxels of the bulk, and for each leaf of more than
// 16^3 voxels eight cubes in its corners. `box` is bulkBounds. The 3D view
// frames these cubes, as `render` frames the voxels.
struct MapBulk {
  std::vector<Eigen::Vector3d> centres;
  double edge = 0.0;
  Eigen::AlignedBox3d box;
};
[[nodiscard]] std::optional<MapBulk> mapBulk(const MapSnapshot& snapshot,
                                             const std::set<int>& hidden);

// Where the ray from `origin` along `direction` first enters a voxel of the
// snapshot (a cube of the voxel's size; voxels of `hidden` labels left out):
// the point on that voxel's face and the voxel's index, or none when it meets
// no voxel. What a click in the 3D view picks and the mouse hovers over.
struct VoxelHit {
  Eigen::Vector3d point;
  size_t voxel = 0;  // in snapshot.voxels
};
// Decimals that print the centres of voxels of edge `voxel_size` exactly
// (odd multiples of half the edge: 3 for 1 cm, 4 for 5 mm, 5 for 2.5 mm);
// at least 3 (millimetres), at most 6.
[[nodiscard]] int coordinateDecimals(double voxel_size);

[[nodiscard]] std::optional<VoxelHit> firstVoxelHit(const MapSnapshot& snapshot,
                                                    const std::set<int>& hidden,
                                                    const Eigen::Vector3d& origin,
                                                    const Eigen::Vector3d& direction);

}  // namespace lom::ui
