#pragma once
// Pieces shared by the reference and the fast integration paths.
#include <Eigen/Geometry>

#include "lom/fusion.hpp"
#include "voxel_grid.hpp"

namespace lom {

struct PixelRay {
  grid::Key end_key{};        // voxel containing the measured point
  bool beyond_range = false;  // farther than max range: misses only, no hit
};

void checkFrameInputs(const LabelMap& map, const CameraIntrinsics& camera, const DepthImage& depth,
                      const FrameEvidence& evidence);

// False for pixels without a valid depth or outside the map's key range.
bool pixelRay(const grid::Grid& g, const CameraIntrinsics& camera,
              const Eigen::Isometry3d& T_world_camera, double max_range, int u, int v, float z,
              PixelRay& ray);

// Where the pixel's ray ends: the centre of its end voxel (as in OctoMap's
// discretized insertion), or the point at max range towards it.
Eigen::Vector3d rayEnd(const grid::Grid& g, const Eigen::Vector3d& origin, const grid::Key& end_key,
                       bool beyond_range, double max_range);

FrameStats integrateFrameReference(LabelMap& map, const CameraIntrinsics& camera,
                                   const Eigen::Isometry3d& T_world_camera,
                                   const DepthImage& depth, const FrameEvidence& evidence);
FrameStats integrateFrameFast(LabelMap& map, const CameraIntrinsics& camera,
                              const Eigen::Isometry3d& T_world_camera, const DepthImage& depth,
                              const FrameEvidence& evidence, int threads);

// logit of a probability clamped to [kProbabilityEpsilon, 1 - kProbabilityEpsilon].
float clampedLogit(float p);

}  // namespace lom
