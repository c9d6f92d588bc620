#include <cmath>
#include <cstdio>

#include "lom/sequence.hpp"

namespace lom {

std::vector<std::string> cameraJumps(const Sequence& sequence, double limit_metres) {
  std::vector<std::string> jumps;
  for (size_t i = 1; i < sequence.frames.size(); ++i) {
    const double metres = (sequence.frames[i].T_world_camera.translation() -
                           sequence.frames[i - 1].T_world_camera.translation())
                              .norm();
    if (!(metres > limit_metres)) continue;
    char text[200];
    std::snprintf(text, sizeof(text),
                  "frames[%zu].T_world_camera: the camera is %.4g m from where it was in "
                  "frames[%zu] (a wrong pose?)",
                  i, metres, i - 1);
    jumps.emplace_back(text);
  }
  return jumps;
}

}  // namespace lom
