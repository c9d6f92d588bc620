#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "lom/fusion.hpp"
#include "lom/sequence.hpp"

namespace lom {

std::vector<std::string> cameraJumps(const Sequence& sequence, double limit_metres, size_t first,
                                     size_t last) {
  std::vector<std::string> jumps;
  // A camera outside every map's extent is a wrong pose of its own
  // (checkCameraExtents names it): measured from it, its neighbours would
  // seem to jump, and the warning would name the wrong frame.
  std::optional<size_t> previous;
  for (size_t i = first; i < std::min(last, sequence.frames.size()); ++i) {
    const Eigen::Vector3d camera = sequence.frames[i].T_world_camera.translation();
    if (!insideMapExtent(camera, kMaxFusionResolution)) continue;
    const std::optional<size_t> before = previous;
    previous = i;
    if (!before) continue;
    const double metres = (camera - sequence.frames[*before].T_world_camera.translation()).norm();
    if (!(metres > limit_metres)) continue;
    char text[200];
    std::snprintf(text, sizeof(text),
                  "frames[%zu].pose: the camera is %.4g m from where it was in "
                  "frames[%zu] (a wrong pose?)",
                  i, metres, *before);
    jumps.emplace_back(text);
  }
  return jumps;
}

namespace {

constexpr double kRadiansToDegrees = 57.29577951308232;

// The angle the pixels from 0 to `size` span seen from a pinhole with focal
// length `f` and principal point `c` (all in pixels), in degrees.
double fieldOfView(double size, double f, double c) {
  return (std::atan(c / f) + std::atan((size - c) / f)) * kRadiansToDegrees;
}

// The message for one camera, or nothing when its field of view is plausible.
std::optional<std::string> implausibleCamera(const std::string& field, const CameraIntrinsics& camera) {
  const double across = fieldOfView(camera.width, camera.fx, camera.cx);
  const double down = fieldOfView(camera.height, camera.fy, camera.cy);
  const auto plausible = [](double degrees) { return degrees <= kMaxPlausibleFieldOfView; };
  if (plausible(across) && plausible(down)) {
    // A camera matrix of smaller (or larger) images: its principal point lies
    // far from the centre of these, though the field of view may look fine.
    const double at_x = camera.cx / camera.width;
    const double at_y = camera.cy / camera.height;
    const auto centred = [](double at) {
      return at >= kMinPrincipalPointFraction && at <= 1.0 - kMinPrincipalPointFraction;
    };
    if (centred(at_x) && centred(at_y)) return std::nullopt;
    char text[500];
    std::snprintf(text, sizeof(text),
                  "%s: the principal point cx = %.6g, cy = %.6g lies at %.0f %% and %.0f %% of "
                  "the %d x %d pixels' width and height; a camera's lies near the centre (are "
                  "these the intrinsics of %.0f x %.0f pixel images? scale fx, fy, cx and cy by "
                  "the ratio of the sizes)",
                  field.c_str(), camera.cx, camera.cy, 100.0 * at_x, 100.0 * at_y, camera.width,
                  camera.height, 2.0 * camera.cx, 2.0 * camera.cy);
    return std::string(text);
  }
  char text[400];
  std::snprintf(text, sizeof(text),
                "%s: fx = %.6g, fy = %.6g, cx = %.6g, cy = %.6g give a field of view of %.1f x "
                "%.1f degrees at %d x %d pixels; depth cameras see about 40 to 120 degrees "
                "(are fx and fy in pixels, for images of this size?)",
                field.c_str(), camera.fx, camera.fy, camera.cx, camera.cy, across, down,
                camera.width, camera.height);
  return std::string(text);
}

}  // namespace

std::vector<std::string> implausibleIntrinsics(const Sequence& sequence, size_t first_frame,
                                               size_t last_frame) {
  std::vector<std::string> warnings;
  const size_t begin = std::min(first_frame, sequence.frames.size());
  const size_t end = std::min(last_frame, sequence.frames.size());
  const bool shared_camera_used =
      begin >= end || std::any_of(sequence.frames.begin() + static_cast<std::ptrdiff_t>(begin),
                                  sequence.frames.begin() + static_cast<std::ptrdiff_t>(end),
                                  [](const FrameRecord& frame) { return !frame.camera; });
  if (shared_camera_used)
    if (auto warning = implausibleCamera("camera", sequence.camera)) warnings.push_back(*warning);
  // Cameras of their own: the first implausible one, and how many more.
  std::optional<std::string> first;
  size_t others = 0;
  for (size_t i = begin; i < end; ++i) {
    if (!sequence.frames[i].camera) continue;
    auto warning = implausibleCamera("frames[" + std::to_string(i) + "].camera", *sequence.frames[i].camera);
    if (!warning) continue;
    if (first)
      ++others;
    else
      first = std::move(warning);
  }
  if (first)
    warnings.push_back(*first + (others ? " (and " + std::to_string(others) + " more frames)" : ""));
  return warnings;
}

}  // namespace lom
