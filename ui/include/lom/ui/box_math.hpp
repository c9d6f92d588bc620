#pragma once
// Small helpers for editing oriented boxes: Euler angles and key-step edits.
#include <Eigen/Geometry>

#include "lom/geometry.hpp"

namespace lom::ui {

// Roll, pitch, yaw in radians with R = Rz(yaw) * Ry(pitch) * Rx(roll).
[[nodiscard]] Eigen::Vector3d rollPitchYaw(const Eigen::Quaterniond& rotation);
[[nodiscard]] Eigen::Quaterniond fromRollPitchYaw(const Eigen::Vector3d& roll_pitch_yaw);

// Moves the box along its own axes by `delta` (box frame, metres).
[[nodiscard]] OrientedBox movedInBoxFrame(const OrientedBox& box, const Eigen::Vector3d& delta);
// Turns the box about its own z axis.
[[nodiscard]] OrientedBox turnedAboutZ(const OrientedBox& box, double radians);
// Grows (or shrinks, for negative steps) one edge, never below `minimum`.
[[nodiscard]] OrientedBox resized(const OrientedBox& box, int axis, double step,
                                  double minimum = 0.002);
// Whether two boxes differ only by rounding (a nanometre, a nanoradian): what
// the 3D handles give back for a click that moved nothing.
[[nodiscard]] bool sameBoxUpToRounding(const OrientedBox& a, const OrientedBox& b);

}  // namespace lom::ui
