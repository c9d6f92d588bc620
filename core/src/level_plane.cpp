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
// A refit turns a candidate only as far as the centres within one voxel edge
// of it pull it, and a noisy floor spreads its centres over a few edges: on
// the Kinect room, straightening a candidate tilted a few degrees took 10 to
// 30 refits, each gathering a few percent more centres.
constexpr int kMaxRefits = 32;
constexpr size_t kFinalists = 8;  // distinct planes of the sample compared on every centre

struct Plane {
  Eigen::Vector3d normal;
  Eigen::Vector3d point;
};

// The centres within `tolerance` of a plane: how many, and their first and
// second moments about the plane's point (small numbers, whatever the map's
// extent), from which their least-squares plane follows.
struct Gathered {
  size_t on = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d products = Eigen::Matrix3d::Zero();
};

Gathered gather(const std::vector<Eigen::Vector3d>& points, const Plane& plane, double tolerance) {
  Gathered gathered;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d offset = p - plane.point;
    if (std::abs(plane.normal.dot(offset)) > tolerance) continue;
    ++gathered.on;
    gathered.sum += offset;
    gathered.products += offset * offset.transpose();
  }
  return gathered;
}

// The least-squares plane through the gathered centres, its normal on the
// side of `up`; nullopt when they are too few or their plane is no level.
std::optional<Plane> fitted(const Gathered& gathered, const Plane& plane, const Eigen::Vector3d& up,
                            double min_alignment) {
  if (gathered.on < 3) return std::nullopt;
  const double on = static_cast<double>(gathered.on);
  const Eigen::Vector3d mean = gathered.sum / on;
  const Eigen::Matrix3d scatter = gathered.products - on * mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  Eigen::Vector3d normal = solver.eigenvectors().col(0);  // the smallest spread
  if (normal.dot(up) < 0.0) normal = -normal;
  if (!normal.allFinite() || normal.dot(up) < min_alignment) return std::nullopt;
  return Plane{normal.normalized(), plane.point + mean};
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
  // far enough apart that the voxel grid alone tilts their plane by a few
  // degrees at most. Depth noise tilts it further (three floor centres of the
  // Kinect room fused to 10 m span planes 2 to 20 degrees off the floor,
  // 5 in the median), and across a floor several metres long such a plane
  // stays within a voxel edge of the floor only on a strip: each candidate is
  // therefore refitted by least squares to the centres on it, again as long
  // as that gathers more of them, before it is compared or judged.
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
  // Every trial's plane, with the sampled centres on it.
  std::vector<std::pair<size_t, Plane>> candidates;
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
    Plane plane{normal, a};
    Gathered gathered = gather(sample, plane, tolerance);
    for (int refit = 0; refit < kMaxRefits; ++refit) {
      const auto straighter = fitted(gathered, plane, up, min_alignment);
      if (!straighter) break;
      const Gathered more = gather(sample, *straighter, tolerance);
      if (more.on < gathered.on) break;
      const bool grew = more.on > gathered.on;
      plane = *straighter;
      gathered = more;
      if (!grew) break;
    }
    candidates.emplace_back(gathered.on, plane);
  }
  // The evenly spaced sample follows the order of the centres (sorted keys),
  // and can hold fewer centres of the floor than of a plane across the
  // objects' tops: scene 3 of synth picked a plane 9 cm up, tilted by 11
  // degrees, holding 560 sampled centres, while the floor held more of all
  // the centres (1435 against 1250). The largest distinct candidates of the
  // sample are therefore compared on every centre.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  const double same_normal = std::cos(2.0 * M_PI / 180.0);
  std::vector<Plane> finalists;
  for (const auto& [on, plane] : candidates) {
    if (finalists.size() == kFinalists) break;
    const bool seen = std::any_of(finalists.begin(), finalists.end(), [&](const Plane& other) {
      return other.normal.dot(plane.normal) >= same_normal &&
             std::abs(other.normal.dot(plane.point - other.point)) <= tolerance;
    });
    if (!seen) finalists.push_back(plane);
  }
  size_t best_count = 0;
  Plane best{up, Eigen::Vector3d::Zero()};
  for (const Plane& plane : finalists) {
    const size_t on = gather(centres, plane, tolerance).on;
    if (on > best_count) {
      best_count = on;
      best = plane;
    }
  }
  if (best_count < std::max(kMinimumOnPlane, centres.size() / 12)) return std::nullopt;
  return LevelPlane{best.normal, best_count, centres.size(), best.normal.dot(best.point)};
}

Eigen::Vector3d levelledUp(const std::vector<Eigen::Vector3d>& centres,
                           const Eigen::Vector3d& cameras_up, double resolution) {
  const auto plane = findLevelPlane(centres, cameras_up, resolution);
  return plane ? plane->normal : cameras_up;
}

SceneLevel sceneLevel(const std::vector<Eigen::Vector3d>& centres,
                      const std::optional<Eigen::Vector3d>& cameras_up, double resolution) {
  SceneLevel level;
  if (!cameras_up || !cameras_up->allFinite() || !(cameras_up->norm() > 1e-12)) return level;
  level.plane = findLevelPlane(centres, *cameras_up, resolution);
  level.up = level.plane ? level.plane->normal : cameras_up->normalized();
  return level;
}

std::optional<Eigen::Vector3d> meanCameraUp(const std::vector<Eigen::Matrix3d>& rotations) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  size_t views = 0;
  for (const Eigen::Matrix3d& rotation : rotations) {
    const Eigen::Vector3d up = -rotation.col(1);
    if (!up.allFinite()) continue;
    sum += up;
    ++views;
  }
  const double length = sum.norm();
  if (views == 0 || !std::isfinite(length) || length < 0.5 * static_cast<double>(views))
    return std::nullopt;
  return Eigen::Vector3d(sum / length);
}

}  // namespace lom
