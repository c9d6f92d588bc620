// Exact ray casting of the shelf boxes, object boxes and cylinders, one ray
// through each pixel centre.
#include <algorithm>
#include <cmath>
#include <limits>

#include "synth_internal.hpp"

namespace lom::synth {

namespace {

constexpr double kNearest = 0.05;  // metres; nothing is closer to the camera

// A primitive in its own frame, with the camera ray mapped into that frame:
// for the pixel ray (x, y, 1) in camera coordinates, the local ray is
// origin + t * (x * dir_x + y * dir_y + dir_z) where t is the camera depth.
struct Primitive {
  bool cylinder = false;
  int label = 0;
  Eigen::Vector3d half;
  Eigen::Matrix3d local_to_world;
  Eigen::Vector3d origin, dir_x, dir_y, dir_z;
  int u_min = 0, u_max = -1, v_min = 0, v_max = -1;  // pixels the primitive may cover
};

struct LocalHit {
  double t = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

bool hitBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& half,
            LocalHit& hit) {
  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  int entry_axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (std::abs(o[k]) > half[k]) return false;
      continue;
    }
    double t1 = (-half[k] - o[k]) / d[k];
    double t2 = (half[k] - o[k]) / d[k];
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > t_near) {
      t_near = t1;
      entry_axis = k;
    }
    t_far = std::min(t_far, t2);
  }
  if (entry_axis < 0 || t_near > t_far || t_near < kNearest || t_near >= hit.t) return false;
  hit.t = t_near;
  hit.normal = Eigen::Vector3d::Zero();
  hit.normal[entry_axis] = d[entry_axis] > 0 ? -1.0 : 1.0;
  return true;
}

// Cylinder of radius half.x around the local z axis, |z| <= half.z.
bool hitCylinder(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& half,
                 LocalHit& hit) {
  const double radius = half.x(), half_height = half.z();
  bool found = false;
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a > 1e-15) {
    const double b = 2.0 * (o.x() * d.x() + o.y() * d.y());
    const double c = o.x() * o.x() + o.y() * o.y() - radius * radius;
    const double discriminant = b * b - 4.0 * a * c;
    if (discriminant >= 0.0) {
      const double t = (-b - std::sqrt(discriminant)) / (2.0 * a);
      const Eigen::Vector3d p = o + t * d;
      if (t >= kNearest && t < hit.t && std::abs(p.z()) <= half_height) {
        hit.t = t;
        hit.normal = Eigen::Vector3d(p.x(), p.y(), 0.0).normalized();
        found = true;
      }
    }
  }
  if (std::abs(d.z()) > 1e-12) {
    const double cap_z = d.z() > 0 ? -half_height : half_height;  // the cap facing the ray
    const double t = (cap_z - o.z()) / d.z();
    const Eigen::Vector3d p = o + t * d;
    if (t >= kNearest && t < hit.t && p.x() * p.x() + p.y() * p.y() <= radius * radius) {
      hit.t = t;
      hit.normal = Eigen::Vector3d(0, 0, cap_z > 0 ? 1.0 : -1.0);
      found = true;
    }
  }
  return found;
}

// Pixel rectangle covered by the projection of the box corners; the whole
// image when a corner is behind the camera.
void boundPixels(const OrientedBox& box, const Eigen::Isometry3d& T_camera_world,
                 const CameraIntrinsics& camera, Primitive& primitive) {
  double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo;
  double v_lo = u_lo, v_hi = -u_lo;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d sign(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1);
    const Eigen::Vector3d p_world = box.center + box.rotation * (0.5 * box.size.cwiseProduct(sign));
    const Eigen::Vector3d p_camera = T_camera_world * p_world;
    if (p_camera.z() < kNearest) {
      primitive.u_min = 0, primitive.u_max = camera.width - 1;
      primitive.v_min = 0, primitive.v_max = camera.height - 1;
      return;
    }
    const Eigen::Vector2d uv = camera.project(p_camera);
    u_lo = std::min(u_lo, uv.x()), u_hi = std::max(u_hi, uv.x());
    v_lo = std::min(v_lo, uv.y()), v_hi = std::max(v_hi, uv.y());
  }
  primitive.u_min = std::max(0, static_cast<int>(std::floor(u_lo)) - 1);
  primitive.u_max = std::min(camera.width - 1, static_cast<int>(std::ceil(u_hi)) + 1);
  primitive.v_min = std::max(0, static_cast<int>(std::floor(v_lo)) - 1);
  primitive.v_max = std::min(camera.height - 1, static_cast<int>(std::ceil(v_hi)) + 1);
}

Primitive makePrimitive(const OrientedBox& box, bool cylinder, int label,
                        const Eigen::Isometry3d& T_world_camera, const CameraIntrinsics& camera) {
  Primitive p;
  p.cylinder = cylinder;
  p.label = label;
  p.half = 0.5 * box.size;
  p.local_to_world = box.rotation.toRotationMatrix();
  const Eigen::Matrix3d world_to_local = p.local_to_world.transpose();
  const Eigen::Matrix3d camera_to_local = world_to_local * T_world_camera.linear();
  p.origin = world_to_local * (T_world_camera.translation() - box.center);
  p.dir_x = camera_to_local.col(0);
  p.dir_y = camera_to_local.col(1);
  p.dir_z = camera_to_local.col(2);
  boundPixels(box, T_world_camera.inverse(), camera, p);
  return p;
}

}  // namespace

SurfaceImage castRays(const SynthLayout& layout, size_t frame) {
  const CameraIntrinsics& camera = layout.camera;
  const Eigen::Isometry3d& pose = layout.T_world_camera.at(frame);
  std::vector<Primitive> primitives;
  for (const auto& box : layout.shelf)
    primitives.push_back(makePrimitive(box, false, 0, pose, camera));
  for (const auto& object : layout.objects)
    primitives.push_back(makePrimitive(object.box, object.shape == SynthShape::Cylinder,
                                       object.label, pose, camera));

  SurfaceImage image;
  image.width = camera.width;
  image.height = camera.height;
  const size_t pixels = static_cast<size_t>(camera.width) * camera.height;
  image.depth.assign(pixels, 0.0f);
  image.normal.assign(pixels, Eigen::Vector3f::Zero());
  image.cos_incidence.assign(pixels, 0.0f);
  image.label.assign(pixels, 0);

  std::vector<const Primitive*> row_primitives;
  for (int v = 0; v < camera.height; ++v) {
    row_primitives.clear();
    for (const auto& p : primitives)
      if (v >= p.v_min && v <= p.v_max) row_primitives.push_back(&p);
    const double y = (v - camera.cy) / camera.fy;
    for (int u = 0; u < camera.width; ++u) {
      const double x = (u - camera.cx) / camera.fx;
      LocalHit hit;
      const Primitive* nearest = nullptr;
      for (const Primitive* p : row_primitives) {
        if (u < p->u_min || u > p->u_max) continue;
        const Eigen::Vector3d d = x * p->dir_x + y * p->dir_y + p->dir_z;
        const bool closer = p->cylinder ? hitCylinder(p->origin, d, p->half, hit)
                                        : hitBox(p->origin, d, p->half, hit);
        if (closer) nearest = p;
      }
      if (!nearest) continue;
      const size_t i = static_cast<size_t>(v) * camera.width + u;
      const Eigen::Vector3d normal = nearest->local_to_world * hit.normal;
      const Eigen::Vector3d ray = (pose.linear() * Eigen::Vector3d(x, y, 1.0)).normalized();
      image.depth[i] = static_cast<float>(hit.t);
      image.normal[i] = normal.cast<float>();
      image.cos_incidence[i] = static_cast<float>(std::abs(normal.dot(ray)));
      image.label[i] = static_cast<std::uint16_t>(nearest->label);
    }
  }
  return image;
}

}  // namespace lom::synth
