#pragma once
// Oriented boxes fitted to an object's voxels, for the box IU of the evaluation
// (docs/evaluation.md, "Box IU").
#include <optional>
#include <vector>

#include "lom/geometry.hpp"
#include "lom/label_map.hpp"
#include "lom/level_plane.hpp"

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

// The box of an object's voxels, level with the scene: box z is `up`
// (normalised; world +z by default), the box's height the voxels' extent along
// up, and its yaw the one whose footprint (the voxel cubes projected onto the
// plane perpendicular to up) has the smallest area, searched over a quarter
// turn to within 0.05 degrees. The box therefore turns with the world: a
// rigid rotation of the voxels and of `up` alike gives the same box, rotated
// (within a voxel, as the voxels themselves differ). Only an object that lies
// tilted gets a tilted box: the box along the principal axes of the voxel
// centres is taken instead when its volume is under 0.8 times the level
// box's (surfaces seen from one side tilt principal axes by several degrees
// for a box only a few percent smaller, which the level box beats by far).
//
// Each voxel reaches half an edge from its centre along each box axis (its
// cube's extent in a box aligned with the voxel grid; a box turned against
// the grid would otherwise grow with the turn). Extents are robust. With
// `support` (the plane the objects rest on: the scene's level plane, whose
// normal is up), voxels whose centres lie more than a voxel edge below it are
// left out, unless they are more than half of the voxels. Along each box axis, end layers one voxel
// edge thick holding fewer than max(2, 1% of the voxels) voxels, and fewer than a quarter of the
// median layer's, are left out layer after layer, for at most 5% of the
// voxels at each end: a stray voxel or a chain of them joined to an object
// does not stretch its box, an object of under 20 voxels keeps every voxel,
// and a thin object (its every layer as sparse) keeps its ends.
//
// Its frame is canonical: box z is the axis nearest `up`, pointing up (`up`
// itself for a level box), and box x the other axis nearest the world's x
// made level (perpendicular to `up`; the world's y when `up` is along x),
// pointing that way (yaw in (-90, 90] degrees from that level x). Box edits
// in the box's frame (move up, grow the height, turn) then act as their names
// say. Keys are OctoMap keys of voxels of edge `resolution`. Throws
// std::invalid_argument for no keys or an `up` that is zero or not finite.
[[nodiscard]] OrientedBox fitOrientedBox(const std::vector<VoxelKey>& keys, double resolution,
                                         const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ(),
                                         const std::optional<LevelPlane>& support = std::nullopt);

// The level of a map's scene for its boxes, as the studio levels its views
// (LabelMap::upDirection): the cameras' mean up the map records, levelled by
// the largest plane of its occupied voxels (sceneLevel of lom/level_plane.hpp),
// which is the support of fitOrientedBox. `cameras_up` stands in for a map
// that records no camera (fused by an older version, or generated): the mean
// up of the poses it was fused from (meanCameraUp). +z and no plane without
// either. Gathers the map's occupied leaves once: call it once per map, not
// per object.
[[nodiscard]] SceneLevel sceneLevelOf(
    const LabelMap& map, const std::optional<Eigen::Vector3d>& cameras_up = std::nullopt);

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
