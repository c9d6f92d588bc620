#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <optional>

namespace lom {

// The unit quaternion of [qx, qy, qz, qw] given at any finite, non-zero
// scale: the components are divided by the largest magnitude before
// normalising, so that neither tiny ([1e-200, 0, 0, 1e-200]) nor huge
// ([1e300, 1e300, 0, 0]) components underflow or overflow. nullopt for a zero
// or non-finite quaternion.
[[nodiscard]] inline std::optional<Eigen::Quaterniond> unitQuaternion(const Eigen::Vector4d& xyzw) {
  if (!xyzw.allFinite()) return std::nullopt;
  const double largest = xyzw.cwiseAbs().maxCoeff();
  if (!(largest > 0.0)) return std::nullopt;
  const Eigen::Vector4d scaled = xyzw / largest;  // largest magnitude 1: the norm is in [1, 2]
  return Eigen::Quaterniond(scaled[3], scaled[0], scaled[1], scaled[2]).normalized();
}

// An oriented box: centre, full edge lengths along its own axes, and the
// rotation from box axes to world (unit quaternion).
struct OrientedBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();

  [[nodiscard]] bool contains(const Eigen::Vector3d& p_world, double margin = 0.0) const {
    const Eigen::Vector3d p_box = rotation.conjugate() * (p_world - center);
    return (p_box.array().abs() <= (0.5 * size.array() + margin)).all();
  }
  [[nodiscard]] double volume() const { return size.prod(); }
};

}  // namespace lom
