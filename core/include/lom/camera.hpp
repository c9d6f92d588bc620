#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lom {

// Pinhole intrinsics of the depth-registered colour camera.
struct CameraIntrinsics {
  int width = 640;
  int height = 480;
  double fx = 615.2;
  double fy = 615.2;
  double cx = 298.4;
  double cy = 247.5;
  double depth_scale = 0.001;  // 16-bit depth PNG value * depth_scale = metres

  // Camera-frame point of pixel (u, v) (u = column, v = row) at depth z metres.
  [[nodiscard]] Eigen::Vector3d backProject(double u, double v, double z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
  // Pixel coordinates (u, v) of a camera-frame point with z > 0.
  [[nodiscard]] Eigen::Vector2d project(const Eigen::Vector3d& p_camera) const {
    return {fx * p_camera.x() / p_camera.z() + cx, fy * p_camera.y() / p_camera.z() + cy};
  }
  bool operator==(const CameraIntrinsics& o) const {
    return width == o.width && height == o.height && fx == o.fx && fy == o.fy && cx == o.cx &&
           cy == o.cy && depth_scale == o.depth_scale;
  }
};

}  // namespace lom
