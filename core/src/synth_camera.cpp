// The camera: intrinsics for the image size and the looking-around path.
#include <cmath>

#include "synth_internal.hpp"

namespace lom::synth {

namespace {

constexpr double kDegree = M_PI / 180.0;

Eigen::Isometry3d lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  // OpenCV camera axes: z forward, x right, y down.
  const Eigen::Vector3d forward = (target - eye).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << right, down, forward;
  pose.translation() = eye;
  return pose;
}

}  // namespace

// A left-to-right arc in front of the opening with one up-down sweep, always
// looking at the middle of the bin's contents from about 0.6 m.
void makeCameraPath(const SynthOptions& options, SynthLayout& layout) {
  Rng rng(streamSeed(options.seed, Stream::Path));
  const Eigen::Vector3d target(0.5 * kBinDepth, 0.0, 0.07);
  const double azimuth_left = -rng.uniform(24, 32) * kDegree;
  const double azimuth_right = rng.uniform(24, 32) * kDegree;
  const double elevation = rng.uniform(22, 26) * kDegree;
  const double elevation_sweep = rng.uniform(5, 7) * kDegree;
  const double distance = rng.uniform(0.56, 0.62);
  const int frames = options.frames;
  for (int i = 0; i < frames; ++i) {
    const double t = frames > 1 ? static_cast<double>(i) / (frames - 1) : 0.5;
    const double azimuth = azimuth_left + t * (azimuth_right - azimuth_left);
    const double tilt = elevation + elevation_sweep * std::sin(2 * M_PI * t);
    const Eigen::Vector3d toward_camera(-std::cos(tilt) * std::cos(azimuth),
                                        std::cos(tilt) * std::sin(azimuth), std::sin(tilt));
    layout.T_world_camera.push_back(lookAt(target + distance * toward_camera, target));
    layout.view.push_back(false);
  }
  const int views = options.views;
  for (int k = 0; k < views; ++k) {
    const long index = std::lround(static_cast<double>(k) * (frames - 1) / (views - 1));
    layout.view[static_cast<size_t>(index)] = true;
  }
}

CameraIntrinsics scaledCamera(int width, int height) {
  // The sequence camera at 640 x 480, scaled about the pixel-centre convention.
  CameraIntrinsics camera;
  const double sx = width / 640.0, sy = height / 480.0;
  camera.width = width;
  camera.height = height;
  camera.fx = 615.2 * sx;
  camera.fy = 615.2 * sy;
  camera.cx = (319.5 + 0.5) * sx - 0.5;
  camera.cy = (239.5 + 0.5) * sy - 0.5;
  camera.depth_scale = 0.001;
  return camera;
}

}  // namespace lom::synth
