#pragma once
// Oriented boxes fitted to an object's voxels, for the box IU of the evaluation
// (docs/evaluation.md, "Box IU").
#include <optional>
#include <vector>

#include "lom/geometry.hpp"
#include "lom/label_map.hpp"

namespace lom {

// The largest tolerance of the clustering below, in voxel edges: each voxel
// looks at every key within the tolerance, a count that grows with its cube
// (35,000 keys at 20).
inline constexpr double kMaxClusterTolerance = 20.0;

// The largest Euclidean cluster of voxels: two voxels are neighbours when their
// centres are at most `tolerance_voxels` voxel edges apart, or when they touch
// (face, edge or corner: 26-neighbours, whatever the tolerance). Ties go to the
// cluster holding the smallest key, so the result is deterministic. Sorted.
// Throws std::invalid_argument unless 0 <= tolerance_voxels <=
// kMaxClusterTolerance.
[[nodiscard]] std::vector<VoxelKey> largestCluster(const std::vector<VoxelKey>& keys,
                                                   double tolerance_voxels);

// Every such cluster, largest first (equal sizes: the one holding the
// smallest key first), each sorted. The same tolerance rule and limits.
[[nodiscard]] std::vector<std::vector<VoxelKey>> voxelClusters(const std::vector<VoxelKey>& keys,
                                                               double tolerance_voxels);

// The bulk of a map's voxels: those in connected parts (26-neighbours) of at
// least `min_part_voxels` voxels, sorted. Specks such as flying pixels far
// from the scene are left out; every voxel is kept when no part is that large.
// What views frame (`render`, the studio's Zoom to Map).
inline constexpr size_t kBulkPartVoxels = 8;
[[nodiscard]] std::vector<VoxelKey> bulkVoxels(const std::vector<VoxelKey>& keys,
                                               size_t min_part_voxels = kBulkPartVoxels);

// A box enclosing every voxel cube: the smaller of the box along the principal
// axes of the voxel centres and the axis-aligned box (which wins ties). Its
// frame is canonical: box z is the axis nearest `up` (world +z by default),
// pointing up, and box x the other axis nearest the world's x made level
// (perpendicular to `up`; the world's y when `up` is along x), pointing that
// way (yaw in (-90, 90] degrees for up = +z). Box edits in the box's frame
// (move up, grow the height, turn) then act as their names say. The box's
// shape does not depend on `up`, only which of its axes is called which.
// Keys are OctoMap keys of voxels of edge `resolution`. Throws
// std::invalid_argument for no keys or an `up` that is zero or not finite.
[[nodiscard]] OrientedBox fitOrientedBox(const std::vector<VoxelKey>& keys, double resolution,
                                         const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

// The rotation of a box level with `up`: its z is `up` (normalised), its x the
// world's x made perpendicular to `up` (the world's y when `up` is along x).
// Throws std::invalid_argument for an `up` that is zero or not finite.
[[nodiscard]] Eigen::Quaterniond levelRotation(const Eigen::Vector3d& up);

// Centre of the voxel with OctoMap key `key` (same as LabelMap::centerOf).
[[nodiscard]] Eigen::Vector3d voxelCenter(const VoxelKey& key, double resolution);

// The centres of the finest-resolution voxels of occupied leaves (those of
// `label` only, when given): a pruned leaf of edge 2^d voxels stands for
// (2^d)^3 of them, centred on its sub-grid. Throws lom::Error (field
// "voxels") beyond kMaxExpandedVoxels of them, as LabelMap does.
[[nodiscard]] std::vector<Eigen::Vector3d> finestVoxelCentres(
    const std::vector<OccupiedVoxel>& leaves, double resolution,
    std::optional<int> label = std::nullopt);

// The box with `box`'s rotation that tightly encloses the cubes (edge
// `resolution`) of the voxels whose centres lie inside `box`: a box drawn
// roughly around an object, pulled onto the voxels it holds, so that it holds
// their cubes whole, but never past the box given (so a second call changes
// nothing). None when no centre lies inside.
[[nodiscard]] std::optional<OrientedBox> tightenBox(
    const OrientedBox& box, const std::vector<Eigen::Vector3d>& voxel_centres, double resolution);

}  // namespace lom
