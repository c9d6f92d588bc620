#pragma once
// Exact volumes of intersections between voxels and oriented boxes, and the
// exact 3D IoU of two oriented boxes (definitions: docs/evaluation.md).
#include <vector>

#include <Eigen/Core>

#include "lom/geometry.hpp"

namespace lom {

// A convex polyhedron as its faces; each face is a convex polygon whose
// vertices follow its boundary (either direction).
struct ConvexPolyhedron {
  std::vector<std::vector<Eigen::Vector3d>> faces;
};

[[nodiscard]] ConvexPolyhedron boxPolyhedron(const OrientedBox& box);

// The part of `polyhedron` where normal . x <= offset.
[[nodiscard]] ConvexPolyhedron clipByHalfSpace(const ConvexPolyhedron& polyhedron,
                                               const Eigen::Vector3d& normal, double offset);

[[nodiscard]] double polyhedronVolume(const ConvexPolyhedron& polyhedron);

// Exact volume of the intersection of two oriented boxes.
[[nodiscard]] double intersectionVolume(const OrientedBox& a, const OrientedBox& b);

// Exact intersection over union of two oriented boxes (0 when both are empty).
[[nodiscard]] double boxIoU(const OrientedBox& a, const OrientedBox& b);

// Exact volume of an axis-aligned cube (a voxel) inside an oriented box.
// Cubes entirely inside or clearly outside take a fast path; the others are clipped.
class VoxelBoxIntersector {
 public:
  VoxelBoxIntersector(const OrientedBox& box, double voxel_edge);
  [[nodiscard]] double volume(const Eigen::Vector3d& voxel_center) const;
  // Centre mode's test: the voxel's centre is inside the box, taken at least
  // one voxel edge thick along each of its axes (a thinner box still holds
  // one layer of voxels).
  [[nodiscard]] bool centerInside(const Eigen::Vector3d& voxel_center) const;
  // How many voxels of the grid (centres at (i + 0.5) * edge on each axis)
  // have their centres inside the box, by the test of centerInside: the box
  // rasterised on the map's grid. Column by column along z, so the cost grows
  // with the box's footprint in voxels, not its volume; a box whose
  // footprint spans more than kMaxCentreColumns columns is counted as its
  // volume in voxels instead.
  [[nodiscard]] double centresInside() const;
  static constexpr double kMaxCentreColumns = 16777216.0;  // 2^24

 private:
  OrientedBox box_;
  Eigen::Matrix3d world_to_box_;
  Eigen::Vector3d half_size_;
  double edge_;
  // Half extent of the voxel along each box axis: 0.5 * edge * sum_i |R_ji|.
  Eigen::Vector3d voxel_reach_on_box_axes_;
  // Half extent of the box along each world axis.
  Eigen::Vector3d box_reach_on_world_axes_;
  // The box as centre mode counts it: at least one voxel edge thick along
  // each of its axes, so that a box thinner than a voxel holds one layer of
  // voxel centres wherever it lies between the grid's centre planes.
  OrientedBox counted_box_;
  Eigen::Vector3d counted_half_size_;
  Eigen::Vector3d counted_reach_on_world_axes_;
};

}  // namespace lom
