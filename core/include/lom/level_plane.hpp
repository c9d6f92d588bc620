#pragma once
// Which way is up in a map: its cameras' mean up, levelled by the largest
// plane of occupied voxels close to that direction (a floor, a table top, the
// bottom of a bin). A handheld camera pitched down towards the scene has an up
// tilted towards where it looks; the mean of such ups is tilted as much, which
// renders a room askew and colours heights mostly by distance.
#include <Eigen/Core>
#include <optional>
#include <vector>

namespace lom {

struct LevelPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, on the side of the cameras' up
  size_t voxels = 0;                                  // of the voxels, those on the plane
  size_t sampled = 0;                                 // voxels (all the centres given)
  // normal . p for the points p of the plane (through the mean of the centres
  // on it): a point's height above the plane is normal . point - offset.
  double offset = 0.0;
};

// Planes tilted from the cameras' up by more than this are not levels.
inline constexpr double kMaxLevelTiltDegrees = 30.0;

// The largest plane through the voxel centres (a centre is on it when within
// one voxel edge) whose normal is within kMaxLevelTiltDegrees of `cameras_up`
// and which holds at least a twelfth of the voxels (at least 200): found by a
// consensus search with a fixed seed over at most 4096 evenly spaced centres,
// in which every candidate plane is refitted by least squares to the centres
// on it, again as long as that gathers more of them (three noisy centres span
// a tilted plane that holds only a strip of a wide floor); the eight largest
// distinct candidates of that sample are then counted on every centre, and
// the largest is judged. nullopt when no such plane exists.
// The same input always gives the same plane.
[[nodiscard]] std::optional<LevelPlane> findLevelPlane(const std::vector<Eigen::Vector3d>& centres,
                                                       const Eigen::Vector3d& cameras_up,
                                                       double resolution);

// `cameras_up` levelled: the normal of findLevelPlane when there is one, else `cameras_up`.
[[nodiscard]] Eigen::Vector3d levelledUp(const std::vector<Eigen::Vector3d>& centres,
                                         const Eigen::Vector3d& cameras_up, double resolution);

// Up in a scene and the plane its objects rest on, for boxes that stand level.
struct SceneLevel {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // unit
  std::optional<LevelPlane> plane;                // its normal is `up` when present
};

// levelledUp and its plane, as the studio levels its views: `cameras_up`
// levelled by findLevelPlane; +z and no plane without a cameras' up.
[[nodiscard]] SceneLevel sceneLevel(const std::vector<Eigen::Vector3d>& centres,
                                    const std::optional<Eigen::Vector3d>& cameras_up,
                                    double resolution);

// The cameras' mean up (each camera's -y, in the world) of camera rotations
// R_world_camera, normalised, as LabelMap::camerasUp takes it from the views
// fused: nullopt for none, or when they disagree (the mean is shorter than
// half a unit).
[[nodiscard]] std::optional<Eigen::Vector3d> meanCameraUp(
    const std::vector<Eigen::Matrix3d>& rotations);

}  // namespace lom
