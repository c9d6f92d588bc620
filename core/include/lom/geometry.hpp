#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lom {

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
