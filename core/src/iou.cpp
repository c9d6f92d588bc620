// Convex polyhedron clipping (Sutherland-Hodgman, face by face) for exact
// voxel/box and box/box intersection volumes.
#include "lom/iou.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace lom {

namespace {

// Corner i of a box has sign bit 0 for x, 1 for y, 2 for z (set = +half).
constexpr std::array<std::array<int, 4>, 6> kBoxFaces{{
    {0, 2, 6, 4}, {1, 3, 7, 5},  // -x, +x
    {0, 1, 5, 4}, {2, 3, 7, 6},  // -y, +y
    {0, 1, 3, 2}, {4, 5, 7, 6},  // -z, +z
}};

ConvexPolyhedron polyhedronFromCorners(const std::array<Eigen::Vector3d, 8>& corners) {
  ConvexPolyhedron polyhedron;
  polyhedron.faces.reserve(6);
  for (const auto& face : kBoxFaces)
    polyhedron.faces.push_back(
        {corners[face[0]], corners[face[1]], corners[face[2]], corners[face[3]]});
  return polyhedron;
}

std::array<Eigen::Vector3d, 8> boxCorners(const Eigen::Vector3d& center, const Eigen::Matrix3d& axes,
                                          const Eigen::Vector3d& half) {
  std::array<Eigen::Vector3d, 8> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d signs((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
    corners[static_cast<size_t>(i)] = center + axes * signs.cwiseProduct(half);
  }
  return corners;
}

// Orders the points of the new face made by a cut along their boundary.
std::vector<Eigen::Vector3d> orderAroundNormal(std::vector<Eigen::Vector3d> points,
                                               const Eigen::Vector3d& normal, double tolerance) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  const Eigen::Vector3d helper =
      std::abs(normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = normal.cross(helper).normalized();
  const Eigen::Vector3d v = normal.cross(u).normalized();
  std::vector<std::pair<double, Eigen::Vector3d>> by_angle;
  by_angle.reserve(points.size());
  for (const auto& p : points) by_angle.emplace_back(std::atan2((p - mean).dot(v), (p - mean).dot(u)), p);
  std::sort(by_angle.begin(), by_angle.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3d> ordered;
  ordered.reserve(by_angle.size());
  for (const auto& [angle, p] : by_angle)
    if (ordered.empty() || (p - ordered.back()).norm() > tolerance) ordered.push_back(p);
  while (ordered.size() > 1 && (ordered.front() - ordered.back()).norm() <= tolerance) ordered.pop_back();
  return ordered;
}

// Volume of the part of the box-frame polyhedron inside [-half, half].
double volumeInsideCentredBox(ConvexPolyhedron polyhedron, const Eigen::Vector3d& half) {
  for (int axis = 0; axis < 3 && !polyhedron.faces.empty(); ++axis) {
    const Eigen::Vector3d normal = Eigen::Vector3d::Unit(axis);
    polyhedron = clipByHalfSpace(polyhedron, normal, half[axis]);
    if (polyhedron.faces.empty()) break;
    polyhedron = clipByHalfSpace(polyhedron, -normal, half[axis]);
  }
  return polyhedronVolume(polyhedron);
}

}  // namespace

ConvexPolyhedron boxPolyhedron(const OrientedBox& box) {
  return polyhedronFromCorners(
      boxCorners(box.center, box.rotation.toRotationMatrix(), 0.5 * box.size));
}

ConvexPolyhedron clipByHalfSpace(const ConvexPolyhedron& polyhedron, const Eigen::Vector3d& normal,
                                 double offset) {
  // Points within `tolerance` of the plane count as on it, so that faces lying
  // in the plane and vertices touching it are neither lost nor doubled.
  double scale = std::abs(offset);
  for (const auto& face : polyhedron.faces)
    for (const auto& p : face) scale = std::max(scale, std::abs(normal.dot(p)));
  const double tolerance = 1e-12 * std::max(scale, 1e-300);

  ConvexPolyhedron clipped;
  std::vector<Eigen::Vector3d> cut;
  bool face_in_plane = false;
  for (const auto& face : polyhedron.faces) {
    std::vector<Eigen::Vector3d> kept;
    bool all_on_plane = true;
    const size_t n = face.size();
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& a = face[i];
      const Eigen::Vector3d& b = face[(i + 1) % n];
      const double da = normal.dot(a) - offset;
      const double db = normal.dot(b) - offset;
      all_on_plane = all_on_plane && std::abs(da) <= tolerance;
      if (da <= tolerance) {
        kept.push_back(a);
        if (da >= -tolerance) cut.push_back(a);
      }
      if ((da < -tolerance && db > tolerance) || (da > tolerance && db < -tolerance)) {
        const Eigen::Vector3d crossing = a + (b - a) * (da / (da - db));
        kept.push_back(crossing);
        cut.push_back(crossing);
      }
    }
    face_in_plane = face_in_plane || all_on_plane;
    if (kept.size() >= 3) clipped.faces.push_back(std::move(kept));
  }
  // A face already lying in the plane closes the polyhedron; a second one would count twice.
  if (!face_in_plane && cut.size() >= 3 && !clipped.faces.empty()) {
    auto cap = orderAroundNormal(std::move(cut), normal, tolerance);
    if (cap.size() >= 3) clipped.faces.push_back(std::move(cap));
  }
  return clipped;
}

double polyhedronVolume(const ConvexPolyhedron& polyhedron) {
  // Tetrahedra from an interior point (the vertex mean of a convex polyhedron)
  // to a fan of each face; all have the same sign, so absolute values add up.
  Eigen::Vector3d apex = Eigen::Vector3d::Zero();
  size_t count = 0;
  for (const auto& face : polyhedron.faces) {
    for (const auto& p : face) apex += p;
    count += face.size();
  }
  if (count == 0) return 0.0;
  apex /= static_cast<double>(count);
  double six_volume = 0.0;
  for (const auto& face : polyhedron.faces) {
    const Eigen::Vector3d a = face[0] - apex;
    for (size_t i = 1; i + 1 < face.size(); ++i)
      six_volume += std::abs(a.dot((face[i] - apex).cross(face[i + 1] - apex)));
  }
  return six_volume / 6.0;
}

double intersectionVolume(const OrientedBox& a, const OrientedBox& b) {
  const Eigen::Vector3d half_a = 0.5 * a.size;
  const Eigen::Vector3d half_b = 0.5 * b.size;
  if ((a.center - b.center).norm() > half_a.norm() + half_b.norm()) return 0.0;
  const Eigen::Matrix3d world_to_b = b.rotation.toRotationMatrix().transpose();
  const Eigen::Matrix3d a_axes_in_b = world_to_b * a.rotation.toRotationMatrix();
  const Eigen::Vector3d a_center_in_b = world_to_b * (a.center - b.center);
  return volumeInsideCentredBox(polyhedronFromCorners(boxCorners(a_center_in_b, a_axes_in_b, half_a)),
                                half_b);
}

double boxIoU(const OrientedBox& a, const OrientedBox& b) {
  const double inter = intersectionVolume(a, b);
  const double uni = a.volume() + b.volume() - inter;
  if (!(uni > 0.0)) return 0.0;
  return std::clamp(inter / uni, 0.0, 1.0);
}

VoxelBoxIntersector::VoxelBoxIntersector(const OrientedBox& box, double voxel_edge)
    : box_(box),
      world_to_box_(box.rotation.toRotationMatrix().transpose()),
      half_size_(0.5 * box.size),
      edge_(voxel_edge) {
  const Eigen::Matrix3d abs_rotation = world_to_box_.cwiseAbs();
  voxel_reach_on_box_axes_ = 0.5 * edge_ * abs_rotation.rowwise().sum();
  box_reach_on_world_axes_ = abs_rotation.transpose() * half_size_;
  counted_box_ = box_;
  counted_box_.size = box_.size.cwiseMax(edge_);
  counted_half_size_ = 0.5 * counted_box_.size;
  counted_reach_on_world_axes_ = abs_rotation.transpose() * counted_half_size_;
}

bool VoxelBoxIntersector::centerInside(const Eigen::Vector3d& voxel_center) const {
  return counted_box_.contains(voxel_center);
}

double VoxelBoxIntersector::centresInside() const {
  auto centre = [this](std::int64_t i) { return (static_cast<double>(i) + 0.5) * edge_; };
  // Grid indices whose centres may be inside: the box's world-axis extent,
  // one index wider on each side (the test below decides).
  auto range = [&](int axis) {
    const double low = box_.center[axis] - counted_reach_on_world_axes_[axis];
    const double high = box_.center[axis] + counted_reach_on_world_axes_[axis];
    return std::pair<std::int64_t, std::int64_t>{
        static_cast<std::int64_t>(std::floor(low / edge_ - 0.5)) - 1,
        static_cast<std::int64_t>(std::ceil(high / edge_ - 0.5)) + 1};
  };
  const auto [x0, x1] = range(0);
  const auto [y0, y1] = range(1);
  const auto [z0, z1] = range(2);
  // A box wider than any object (40 m at 1 cm) is counted by its volume: the
  // columns would take seconds, and a layer of voxels more or less is a small
  // part of it.
  if (static_cast<double>(x1 - x0 + 1) * static_cast<double>(y1 - y0 + 1) > kMaxCentreColumns)
    return counted_box_.volume() / (edge_ * edge_ * edge_);
  // Along a column (x, y fixed) the box coordinates are a + z r: each of the
  // box's slabs |a_j + z r_j| <= h_j bounds z to an interval.
  const Eigen::Vector3d r = world_to_box_.col(2);
  double count = 0.0;
  for (std::int64_t ix = x0; ix <= x1; ++ix)
    for (std::int64_t iy = y0; iy <= y1; ++iy) {
      const Eigen::Vector3d a =
          world_to_box_ * (Eigen::Vector3d(centre(ix), centre(iy), 0.0) - box_.center);
      double low = -std::numeric_limits<double>::infinity(), high = -low;
      for (int j = 0; j < 3; ++j) {
        if (std::abs(r[j]) < 1e-12) {
          if (std::abs(a[j]) > counted_half_size_[j] + 1e-9 * edge_)
            high = low;  // the column misses the slab
          continue;
        }
        const double t0 = (-counted_half_size_[j] - a[j]) / r[j],
                     t1 = (counted_half_size_[j] - a[j]) / r[j];
        low = std::max(low, std::min(t0, t1));
        high = std::min(high, std::max(t0, t1));
      }
      if (!(low <= high + edge_)) continue;
      // The estimate's ends, settled by the test itself (rounding may move a
      // centre on a face to either side).
      auto inside = [&](std::int64_t iz) {
        return iz >= z0 && iz <= z1 &&
               centerInside(Eigen::Vector3d(centre(ix), centre(iy), centre(iz)));
      };
      std::int64_t first =
          std::clamp(static_cast<std::int64_t>(std::ceil(low / edge_ - 0.5)), z0, z1);
      std::int64_t last =
          std::clamp(static_cast<std::int64_t>(std::floor(high / edge_ - 0.5)), z0, z1);
      if (first > last) last = first;  // a column that grazes the box: its one candidate
      while (inside(first - 1)) --first;
      while (first <= last && !inside(first)) ++first;
      while (inside(last + 1)) ++last;
      while (last >= first && !inside(last)) --last;
      if (first <= last) count += static_cast<double>(last - first + 1);
    }
  return count;
}

double VoxelBoxIntersector::volume(const Eigen::Vector3d& voxel_center) const {
  const double full = edge_ * edge_ * edge_;
  const Eigen::Vector3d offset_world = voxel_center - box_.center;
  const Eigen::Vector3d offset_box = world_to_box_ * offset_world;
  const Eigen::Array3d distance = offset_box.array().abs();
  if (((distance + voxel_reach_on_box_axes_.array()) <= half_size_.array()).all()) return full;
  // Separating axes among the box's and the voxel's face normals.
  if ((distance > half_size_.array() + voxel_reach_on_box_axes_.array()).any()) return 0.0;
  if ((offset_world.array().abs() > 0.5 * edge_ + box_reach_on_world_axes_.array()).any()) return 0.0;
  const double volume = volumeInsideCentredBox(
      polyhedronFromCorners(boxCorners(offset_box, world_to_box_, Eigen::Vector3d::Constant(0.5 * edge_))),
      half_size_);
  return std::clamp(volume, 0.0, full);
}

}  // namespace lom
