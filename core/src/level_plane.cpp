#include "lom/level_plane.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

namespace lom {

namespace {

constexpr size_t kMinimumVoxels = 50;  // to sample
constexpr size_t kMinimumOnPlane = 200;
constexpr size_t kMaxSampled = 4096;
constexpr int kTrials = 512;
constexpr std::uint32_t kSeed = 20171005u;
constexpr double kNearVoxels = 40.0;
constexpr double kApartVoxels = 8.0;
constexpr int kNearAttempts = 64;

size_t countOn(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal,
               const Eigen::Vector3d& point, double tolerance) {
  size_t on = 0;
  for (const Eigen::Vector3d& p : points) on += std::abs(normal.dot(p - point)) <= tolerance;
  return on;
}

}  // namespace

std::optional<LevelPlane> findLevelPlane(const std::vector<Eigen::Vector3d>& centres,
                                         const Eigen::Vector3d& cameras_up, double resolution) {
  const double up_length = cameras_up.norm();
  if (centres.size() < kMinimumVoxels || !(up_length > 0.0) || !std::isfinite(up_length) ||
      !(resolution > 0.0))
    return std::nullopt;
  const Eigen::Vector3d up = cameras_up / up_length;
  const size_t sampled = std::min(centres.size(), kMaxSampled);
  std::vector<Eigen::Vector3d> sample(sampled);
  for (size_t i = 0; i < sampled; ++i) sample[i] = centres[i * centres.size() / sampled];

  const double min_alignment = std::cos(kMaxLevelTiltDegrees * M_PI / 180.0);
  const double tolerance = resolution;  // voxel centres of a tilted plane lie within ~0.87 edges
  std::mt19937 random(kSeed);
  const auto any = [&] { return sample[static_cast<size_t>(random()) % sampled]; };
  // The other two centres of a trial are drawn near the first: three centres
  // of a plane that holds a tenth of a room's voxels are then drawn together
  // in about one trial in 20 instead of one in 1000. Near enough for that,
  // far enough apart that the voxel grid tilts their plane by a few degrees
  // at most (the fit below straightens it).
  const double near_squared = std::pow(kNearVoxels * resolution, 2);
  const double apart_squared = std::pow(kApartVoxels * resolution, 2);
  const auto near = [&](const Eigen::Vector3d& a, Eigen::Vector3d& out) {
    for (int attempt = 0; attempt < kNearAttempts; ++attempt) {
      out = any();
      const double squared = (out - a).squaredNorm();
      if (squared <= near_squared && squared >= apart_squared) return true;
    }
    return false;
  };
  size_t best_count = 0;
  Eigen::Vector3d best_normal = up, best_point = Eigen::Vector3d::Zero();
  for (int trial = 0; trial < kTrials; ++trial) {
    const Eigen::Vector3d a = any();
    Eigen::Vector3d b, c;
    if (!near(a, b) || !near(a, c)) continue;
    Eigen::Vector3d normal = (b - a).cross(c - a);
    const double length = normal.norm();
    if (!(length > 0.0)) continue;  // repeated or collinear centres
    normal /= length;
    const double alignment = normal.dot(up);
    if (std::abs(alignment) < min_alignment) continue;
    if (alignment < 0.0) normal = -normal;
    const size_t on = countOn(sample, normal, a, tolerance);
    if (on > best_count) {
      best_count = on;
      best_normal = normal;
      best_point = a;
    }
  }
  if (best_count < std::max(kMinimumOnPlane, sampled / 12)) return std::nullopt;

  // Least squares over the centres on the plane, twice (the fitted plane
  // gathers its centres again), as long as the fit stays a level.
  Eigen::Vector3d normal = best_normal, point = best_point;
  for (int round = 0; round < 2; ++round) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    size_t on = 0;
    for (const Eigen::Vector3d& p : sample)
      if (std::abs(normal.dot(p - point)) <= tolerance) {
        mean += p;
        ++on;
      }
    if (on < 3) break;
    mean /= static_cast<double>(on);
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const Eigen::Vector3d& p : sample)
      if (std::abs(normal.dot(p - point)) <= tolerance)
        scatter += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
    Eigen::Vector3d fitted = solver.eigenvectors().col(0);  // the smallest spread
    if (fitted.dot(up) < 0.0) fitted = -fitted;
    if (!fitted.allFinite() || fitted.dot(up) < min_alignment) break;
    normal = fitted.normalized();
    point = mean;
  }
  return LevelPlane{normal, countOn(sample, normal, point, tolerance), sampled};
}

Eigen::Vector3d levelledUp(const std::vector<Eigen::Vector3d>& centres,
                           const Eigen::Vector3d& cameras_up, double resolution) {
  const auto plane = findLevelPlane(centres, cameras_up, resolution);
  return plane ? plane->normal : cameras_up;
}

}  // namespace lom
