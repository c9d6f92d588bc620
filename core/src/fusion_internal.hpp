#pragma once
// Pieces shared by the reference and the fast integration paths.
#include <cmath>

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

// Back-projects pixels of one frame into end voxels. Both integration paths use
// it, so they agree on every pixel's voxel to the last bit.
class PixelProjector {
 public:
  PixelProjector(const grid::Grid& g, const CameraIntrinsics& camera,
                 const Eigen::Isometry3d& T_world_camera, double max_range)
      : grid_(g),
        rotation_(T_world_camera.rotation()),
        origin_(T_world_camera.translation()),
        inverse_fx_(1.0 / camera.fx),
        inverse_fy_(1.0 / camera.fy),
        cx_(camera.cx),
        cy_(camera.cy),
        max_range_squared_(max_range > 0.0 ? max_range * max_range : -1.0) {}

  // False for pixels without a valid depth or outside the map's key range.
  bool ray(int u, int v, float depth, PixelRay& out) const {
    if (!(depth > 0.f) || !std::isfinite(depth)) return false;
    const double x = (u - cx_) * inverse_fx_;  // the pixel's direction at z = 1
    const double y = (v - cy_) * inverse_fy_;
    const double z = depth;
    const Eigen::Vector3d point =
        origin_ + z * (rotation_.col(0) * x + rotation_.col(1) * y + rotation_.col(2));
    if (!grid_.keyOf(point, out.end_key)) return false;
    out.beyond_range = max_range_squared_ > 0.0 && z * z * (x * x + y * y + 1.0) > max_range_squared_;
    return true;
  }
  [[nodiscard]] const Eigen::Vector3d& origin() const { return origin_; }

 private:
  grid::Grid grid_;
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d origin_;
  double inverse_fx_, inverse_fy_, cx_, cy_;
  double max_range_squared_;
};

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
