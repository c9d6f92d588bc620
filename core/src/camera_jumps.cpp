#include <cmath>
#include <cstdio>
#include <optional>

#include "lom/fusion.hpp"
#include "lom/sequence.hpp"

namespace lom {

std::vector<std::string> cameraJumps(const Sequence& sequence, double limit_metres) {
  std::vector<std::string> jumps;
  // A camera outside every map's extent is a wrong pose of its own
  // (checkCameraExtents names it): measured from it, its neighbours would
  // seem to jump, and the warning would name the wrong frame.
  std::optional<size_t> previous;
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
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

}  // namespace lom
