#include "lom/ui/box_math.hpp"

#include <algorithm>
#include <cmath>

namespace lom::ui {

Eigen::Vector3d rollPitchYaw(const Eigen::Quaterniond& rotation) {
  const Eigen::Matrix3d r = rotation.normalized().toRotationMatrix();
  // Pitch of +-90 degrees (gimbal lock): roll and yaw turn about the same
  // axis and atan2 of the vanishing entries was noise; the turn is given to
  // yaw, roll 0.
  if (std::hypot(r(2, 1), r(2, 2)) < 1e-9)
    return {0.0, std::copysign(M_PI / 2, -r(2, 0)), std::atan2(-r(0, 1), r(1, 1))};
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  return {roll, pitch, yaw};
}

Eigen::Quaterniond fromRollPitchYaw(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .normalized();
}

OrientedBox movedInBoxFrame(const OrientedBox& box, const Eigen::Vector3d& delta) {
  OrientedBox moved = box;
  moved.center += box.rotation * delta;
  return moved;
}

OrientedBox turnedAboutZ(const OrientedBox& box, double radians) {
  OrientedBox turned = box;
  turned.rotation =
      (box.rotation * Eigen::AngleAxisd(radians, Eigen::Vector3d::UnitZ())).normalized();
  return turned;
}

OrientedBox resized(const OrientedBox& box, int axis, double step, double minimum) {
  OrientedBox result = box;
  // Never the other way than the step (a shrink of a box already under the
  // minimum leaves it as it is).
  const double wanted = std::max(minimum, box.size[axis] + step);
  result.size[axis] =
      step < 0 ? std::min(box.size[axis], wanted) : std::max(box.size[axis], wanted);
  return result;
}

bool sameBoxUpToRounding(const OrientedBox& a, const OrientedBox& b) {
  constexpr double kTolerance = 1e-9;
  return (a.center - b.center).cwiseAbs().maxCoeff() <= kTolerance &&
         (a.size - b.size).cwiseAbs().maxCoeff() <= kTolerance &&
         a.rotation.angularDistance(b.rotation) <= kTolerance;
}

}  // namespace lom::ui
