#include "lom/box_fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "lom/error.hpp"
#include "voxel_index.hpp"

namespace lom {

namespace {

// OctoMap's key of the voxel whose lower corner is at the origin (tree_max_val at depth 16).
constexpr int kKeyOrigin = 32768;

struct Extent {
  Eigen::Matrix3d axes;  // columns: box axes in world
  Eigen::Vector3d low, high;
  [[nodiscard]] double volume() const { return (high - low).prod(); }
};

// The rules of a fit, as box_fit.hpp states them.
constexpr double kTiltedVolumeShare = 0.8;      // a tilted box must be this much smaller
constexpr size_t kSparseLayerVoxels = 2;        // an end layer with fewer voxels is sparse...
constexpr double kSparseLayerShare = 0.01;      // ... or with fewer than this share of them ...
constexpr double kSparseLayerOfTypical = 0.25;  // ... and this share of the median layer
constexpr double kMaxTrimShare = 0.05;          // trimmed at most from each end of an axis
constexpr double kBelowSupportEdges = 1.0;      // voxel centres this far below the support
constexpr size_t kYawSampleVoxels = 4096;       // the yaw search looks at this many at most
constexpr double kCoarseYawStepDegrees = 1.0;
constexpr double kFineYawStepDegrees = 0.05;
// Layers of a span of more voxel edges than this are not counted (a label
// spread over a room); its voxels are all enclosed.
constexpr double kMaxLayers = 1e6;

// How far a voxel reaches from its centre along a box axis: half an edge,
// its cube's extent along a box aligned with the voxel grid. A box turned
// against the grid would reach further to hold whole cubes (up to 0.87 edges
// along a diagonal), so that the size of a box would depend on how the world's
// axes lie and not only on the object.
double cubeReach(const Eigen::Vector3d& /*axis*/, double resolution) { return 0.5 * resolution; }

struct Span {
  double low = 0.0, high = 0.0;
  [[nodiscard]] double length() const { return high - low; }
};

// The extent of the voxel cubes along one axis, given their centres'
// coordinates along it (`along`) and a cube's reach: one-voxel-edge layers at
// either end that hold few voxels (sparse: fewer than kSparseLayerVoxels or
// kSparseLayerShare of them, and under kSparseLayerOfTypical of the median
// layer, so that a thin object keeps its ends) are left out, layer after
// layer, as long as that leaves out at most kMaxTrimShare of the voxels at
// that end. A stray voxel or a chain of them joined to an object by the
// cluster tolerance then does not stretch its box.
Span robustSpan(std::vector<double>& along, double reach, double resolution) {
  const auto [min_it, max_it] = std::minmax_element(along.begin(), along.end());
  const double min = *min_it, max = *max_it;
  const double layers = std::floor((max - min) / resolution) + 1.0;
  Span span{min - reach, max + reach};
  const size_t n = along.size();
  const auto cap = static_cast<size_t>(std::floor(kMaxTrimShare * static_cast<double>(n)));
  if (cap == 0 || !(layers <= kMaxLayers)) return span;  // tiny objects keep every voxel
  const auto count = static_cast<size_t>(layers);
  const auto layerOf = [&](double value) {
    return std::min(count - 1, static_cast<size_t>(std::floor((value - min) / resolution)));
  };
  std::vector<size_t> voxels(count, 0);
  for (const double value : along) ++voxels[layerOf(value)];
  std::vector<size_t> filled;
  for (const size_t v : voxels)
    if (v > 0) filled.push_back(v);
  std::nth_element(filled.begin(), filled.begin() + filled.size() / 2, filled.end());
  const double typical = static_cast<double>(filled[filled.size() / 2]);
  const double few =
      std::max(static_cast<double>(kSparseLayerVoxels), kSparseLayerShare * static_cast<double>(n));
  const auto sparse = [&](size_t v) {
    return static_cast<double>(v) < few && static_cast<double>(v) < kSparseLayerOfTypical * typical;
  };
  size_t first = 0, last = count - 1, trimmed_low = 0, trimmed_high = 0;
  while (first < last &&
         (voxels[first] == 0 || (sparse(voxels[first]) && trimmed_low + voxels[first] <= cap))) {
    trimmed_low += voxels[first];
    ++first;
  }
  while (last > first &&
         (voxels[last] == 0 || (sparse(voxels[last]) && trimmed_high + voxels[last] <= cap))) {
    trimmed_high += voxels[last];
    --last;
  }
  if (trimmed_low == 0 && trimmed_high == 0) return span;
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const double value : along) {
    const size_t layer = layerOf(value);
    if (layer < first || layer > last) continue;
    low = std::min(low, value);
    high = std::max(high, value);
  }
  return {low - reach, high + reach};
}

// The robust extent (robustSpan along each axis) of the voxel cubes along `axes`.
Extent enclose(const std::vector<Eigen::Vector3d>& centers, const Eigen::Matrix3d& axes,
               double resolution) {
  Extent extent{axes, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::vector<double> along(centers.size());
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d axis = axes.col(a);
    for (size_t i = 0; i < centers.size(); ++i) along[i] = axis.dot(centers[i]);
    const Span span = robustSpan(along, cubeReach(axis, resolution), resolution);
    extent.low[a] = span.low;
    extent.high[a] = span.high;
  }
  return extent;
}

// The area of the robust footprint of the voxel cubes on the level plane
// along u and v (unit, level, perpendicular).
double footprintArea(const std::vector<Eigen::Vector3d>& centers, const Eigen::Vector3d& u,
                     const Eigen::Vector3d& v, double resolution, std::vector<double>& along) {
  along.resize(centers.size());
  double area = 1.0;
  for (const Eigen::Vector3d& axis : {u, v}) {
    for (size_t i = 0; i < centers.size(); ++i) along[i] = axis.dot(centers[i]);
    area *= robustSpan(along, cubeReach(axis, resolution), resolution).length();
  }
  return area;
}

}  // namespace

Eigen::Vector3d voxelCenter(const VoxelKey& key, double resolution) {
  return {(static_cast<int>(key.x) - kKeyOrigin + 0.5) * resolution,
          (static_cast<int>(key.y) - kKeyOrigin + 0.5) * resolution,
          (static_cast<int>(key.z) - kKeyOrigin + 0.5) * resolution};
}

std::vector<std::vector<VoxelKey>> voxelClusters(const std::vector<VoxelKey>& keys,
                                                 double tolerance_voxels) {
  if (!(tolerance_voxels >= 0.0 && tolerance_voxels <= kMaxClusterTolerance))
    throw std::invalid_argument(
        "voxel clusters: the tolerance must be a number of voxel edges from 0 to " +
        std::to_string(static_cast<int>(kMaxClusterTolerance)) + ", got " +
        std::to_string(tolerance_voxels));
  if (keys.empty()) return {};
  static_assert(kMaxClusterTolerance <= VoxelIndex::kMargin,
                "neighbour queries stay within the index's margin");
  const int reach = std::max(1, static_cast<int>(std::floor(tolerance_voxels)));
  std::vector<VoxelIndex::Cell> offsets;
  for (int dx = -reach; dx <= reach; ++dx)
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dz = -reach; dz <= reach; ++dz) {
        const int squared = dx * dx + dy * dy + dz * dz;
        // 26-neighbours (touching by a face, an edge or a corner) are always
        // connected, whatever the tolerance.
        const bool touching = std::abs(dx) <= 1 && std::abs(dy) <= 1 && std::abs(dz) <= 1;
        if (squared > 0 && (touching || squared <= tolerance_voxels * tolerance_voxels))
          offsets.push_back({dx, dy, dz});
      }

  // Flood fill by rank (the index's order: neighbours are mostly in the brick
  // of the last query); each cluster's keys are then sorted.
  const VoxelIndex index(keys);
  const std::vector<VoxelIndex::Cell>& cells = index.cells();
  constexpr std::uint32_t kUnset = ~std::uint32_t{0};
  std::vector<std::uint32_t> cluster_of(cells.size(), kUnset);
  std::vector<std::vector<VoxelKey>> clusters;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < cells.size(); ++seed) {
    if (cluster_of[seed] != kUnset) continue;
    const auto cluster = static_cast<std::uint32_t>(clusters.size());
    std::vector<VoxelKey> members;
    cluster_of[seed] = cluster;
    stack.push_back(seed);
    while (!stack.empty()) {
      const VoxelIndex::Cell c = cells[stack.back()];
      stack.pop_back();
      members.push_back({static_cast<std::uint16_t>(c[0]), static_cast<std::uint16_t>(c[1]),
                         static_cast<std::uint16_t>(c[2])});
      for (const auto& d : offsets) {
        const std::uint32_t rank = index.rankOf({c[0] + d[0], c[1] + d[1], c[2] + d[2]});
        if (rank == VoxelIndex::kAbsent || cluster_of[rank] != kUnset) continue;
        cluster_of[rank] = cluster;
        stack.push_back(rank);
      }
    }
    std::sort(members.begin(), members.end());
    clusters.push_back(std::move(members));
  }
  // Largest first; among equal sizes, the one holding the smallest key first.
  std::sort(clusters.begin(), clusters.end(),
            [](const std::vector<VoxelKey>& a, const std::vector<VoxelKey>& b) {
              return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
            });
  return clusters;
}

std::vector<VoxelKey> bulkVoxels(const std::vector<VoxelKey>& keys, size_t min_part_voxels) {
  std::vector<VoxelKey> bulk;
  for (const auto& part : voxelClusters(keys, 1.0))
    if (part.size() >= min_part_voxels) bulk.insert(bulk.end(), part.begin(), part.end());
  if (bulk.empty()) bulk = keys;
  std::sort(bulk.begin(), bulk.end());
  bulk.erase(std::unique(bulk.begin(), bulk.end()), bulk.end());
  return bulk;
}

std::vector<VoxelKey> largestCluster(const std::vector<VoxelKey>& keys, double tolerance_voxels) {
  std::vector<std::vector<VoxelKey>> clusters = voxelClusters(keys, tolerance_voxels);
  return clusters.empty() ? std::vector<VoxelKey>{} : std::move(clusters.front());
}

namespace {

// The unit up and the level references of the canonical frame: x (the
// world's x made perpendicular to up, or its y when up is along x) and y (up x
// that x), which breaks ties of the x sign.
struct LevelFrame {
  Eigen::Vector3d up, x, y;
};

LevelFrame levelFrame(const Eigen::Vector3d& up) {
  const double length = up.norm();
  if (!up.allFinite() || !(length > 1e-12))
    throw std::invalid_argument("box frame: up must be a finite, non-zero direction");
  LevelFrame frame;
  frame.up = up / length;
  for (const Eigen::Vector3d& world :
       {Eigen::Vector3d(Eigen::Vector3d::UnitX()), Eigen::Vector3d(Eigen::Vector3d::UnitY())}) {
    frame.x = world - world.dot(frame.up) * frame.up;
    if (frame.x.norm() > 1e-6) break;
  }
  frame.x.normalize();
  frame.y = frame.up.cross(frame.x);
  return frame;
}

}  // namespace

Eigen::Quaterniond levelRotation(const Eigen::Vector3d& up) {
  const LevelFrame frame = levelFrame(up);
  Eigen::Matrix3d axes;
  axes.col(0) = frame.x;
  axes.col(1) = frame.y;
  axes.col(2) = frame.up;
  return Eigen::Quaterniond(axes).normalized();
}

OrientedBox fitOrientedBox(const std::vector<VoxelKey>& keys, double resolution,
                           const Eigen::Vector3d& up_direction,
                           const std::optional<LevelPlane>& support) {
  if (keys.empty()) throw std::invalid_argument("fitOrientedBox: no voxels");
  const LevelFrame level = levelFrame(up_direction);
  std::vector<Eigen::Vector3d> centers;
  centers.reserve(keys.size());
  for (const auto& key : keys) centers.push_back(voxelCenter(key, resolution));

  // Voxels of the label under the plane the objects rest on are the label
  // bleeding into the floor (a mask's edge projected past the object), not
  // the object; they are left out unless they are most of it (an object
  // under a table top taken for the support).
  if (support && support->normal.allFinite() && support->normal.norm() > 1e-12) {
    const Eigen::Vector3d normal = support->normal.normalized();
    const double lowest = support->offset - kBelowSupportEdges * resolution;
    std::vector<Eigen::Vector3d> above;
    above.reserve(centers.size());
    for (const Eigen::Vector3d& c : centers)
      if (normal.dot(c) >= lowest) above.push_back(c);
    if (2 * above.size() >= centers.size()) centers = std::move(above);
  }

  // The level box: z along up, its yaw the one of the smallest footprint,
  // searched over a quarter turn (the footprint repeats after it) in coarse
  // steps and then finely around the best. Each yaw is judged by its robust
  // extents, so stray voxels do not turn the box. Ties keep the first yaw, so
  // a block aligned with the level x gets an unturned box.
  std::vector<Eigen::Vector3d> sample;
  const std::vector<Eigen::Vector3d>* searched = &centers;
  if (centers.size() > kYawSampleVoxels) {
    sample.reserve(kYawSampleVoxels);
    for (size_t i = 0; i < kYawSampleVoxels; ++i)
      sample.push_back(centers[i * centers.size() / kYawSampleVoxels]);
    searched = &sample;
  }
  std::vector<double> along;
  const auto levelAxis = [&](double degrees) -> Eigen::Vector3d {
    const double radians = degrees * M_PI / 180.0;
    return std::cos(radians) * level.x + std::sin(radians) * level.y;
  };
  const auto areaAt = [&](double degrees) {
    const Eigen::Vector3d u = levelAxis(degrees);
    return footprintArea(*searched, u, level.up.cross(u), resolution, along);
  };
  double best_yaw = 0.0, best_area = areaAt(0.0);
  for (double yaw = kCoarseYawStepDegrees; yaw < 90.0; yaw += kCoarseYawStepDegrees) {
    const double area = areaAt(yaw);
    if (area < best_area * (1.0 - 1e-9)) {
      best_area = area;
      best_yaw = yaw;
    }
  }
  const double coarse_yaw = best_yaw;
  for (double offset = -kCoarseYawStepDegrees; offset <= kCoarseYawStepDegrees + 1e-9;
       offset += kFineYawStepDegrees) {
    if (std::abs(offset) < 1e-9) continue;
    const double area = areaAt(coarse_yaw + offset);
    if (area < best_area * (1.0 - 1e-9)) {
      best_area = area;
      best_yaw = coarse_yaw + offset;
    }
  }
  Eigen::Matrix3d level_axes;
  level_axes.col(0) = levelAxis(best_yaw);
  level_axes.col(1) = level.up.cross(level_axes.col(0));
  level_axes.col(2) = level.up;
  const Extent along_level = enclose(centers, level_axes, resolution);

  // A box along the principal axes of the voxel centres is tilted whenever
  // they are (surfaces seen from one side, a sloping top) and turned by
  // chance for near-symmetric objects: it is kept only for an object that
  // lies tilted, whose box it makes clearly smaller.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& c : centers) mean += c;
  mean /= static_cast<double>(centers.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& c : centers) covariance += (c - mean) * (c - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d principal = solver.eigenvectors();
  // A right-handed frame, so that it is a rotation.
  if (principal.determinant() < 0) principal.col(2) = -principal.col(2);
  const Extent along_principal = enclose(centers, principal, resolution);
  const Extent& best =
      principal.allFinite() && along_principal.volume() < kTiltedVolumeShare * along_level.volume()
          ? along_principal
          : along_level;

  OrientedBox box;
  box.center = best.axes * (0.5 * (best.low + best.high));
  // The same box in a predictable frame (PCA orders its axes by spread and
  // picks their signs at random; the level box's yaw is within a quarter
  // turn): z is the axis nearest up, pointing up; x
  // the one of the other two nearest the level x, pointing along it (so yaw
  // lies in (-90, 90] degrees); y = z x x. Box edits (move up, grow the
  // height, yaw) then act as their names say.
  const Eigen::Vector3d size = best.high - best.low;
  const Eigen::Vector3d along_up = best.axes.transpose() * level.up;
  const Eigen::Vector3d along_x = best.axes.transpose() * level.x;
  int zi = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(along_up[i]) > std::abs(along_up[zi])) zi = i;
  const int a = (zi + 1) % 3, b = (zi + 2) % 3;
  const bool a_is_x = std::abs(along_x[a]) > std::abs(along_x[b]) ||
                      (std::abs(along_x[a]) == std::abs(along_x[b]) && a < b);
  const int xi = a_is_x ? a : b, yi = a_is_x ? b : a;
  Eigen::Vector3d z = best.axes.col(zi);
  if (z.dot(level.up) < 0.0) z = -z;
  Eigen::Vector3d x = best.axes.col(xi);
  const double x_along = x.dot(level.x);
  if (x_along < 0.0 || (x_along == 0.0 && x.dot(level.y) < 0.0)) x = -x;
  Eigen::Matrix3d axes;
  axes.col(0) = x;
  axes.col(1) = z.cross(x);
  axes.col(2) = z;
  box.size = Eigen::Vector3d(size[xi], size[yi], size[zi]);
  box.rotation = Eigen::Quaterniond(axes).normalized();
  return box;
}

SceneLevel sceneLevelOf(const LabelMap& map, const std::optional<Eigen::Vector3d>& cameras_up) {
  const std::optional<Eigen::Vector3d> recorded = map.camerasUp();
  return sceneLevel(map.occupiedCentres(), recorded ? recorded : cameras_up,
                    map.parameters().resolution);
}

std::vector<Eigen::Vector3d> finestVoxelCentres(const std::vector<OccupiedVoxel>& leaves,
                                                double resolution, std::optional<int> label) {
  std::vector<Eigen::Vector3d> centres;
  if (!(resolution > 0.0)) return centres;
  auto perEdge = [resolution](const OccupiedVoxel& leaf) {
    return std::max(1L, std::lround(leaf.size / resolution));
  };
  double total = 0.0;
  for (const OccupiedVoxel& leaf : leaves)
    if (!label || leaf.label == *label) total += std::pow(static_cast<double>(perEdge(leaf)), 3.0);
  if (total > static_cast<double>(kMaxExpandedVoxels))
    throw Error("(map)", "voxels",
                "at most " + std::to_string(kMaxExpandedVoxels) +
                    " voxels at the map's resolution (occupied leaves larger than a voxel stand "
                    "for all their voxels)",
                std::to_string(static_cast<unsigned long long>(total)) + " voxels");
  centres.reserve(static_cast<size_t>(total));
  for (const OccupiedVoxel& leaf : leaves) {
    if (label && leaf.label != *label) continue;
    const int per_edge = static_cast<int>(perEdge(leaf));
    const Eigen::Vector3d first =
        leaf.center - Eigen::Vector3d::Constant(0.5 * leaf.size - 0.5 * resolution);
    for (int i = 0; i < per_edge; ++i)
      for (int j = 0; j < per_edge; ++j)
        for (int k = 0; k < per_edge; ++k)
          centres.push_back(first + resolution * Eigen::Vector3d(i, j, k));
  }
  return centres;
}

std::optional<OrientedBox> tightenBox(const OrientedBox& box,
                                      const std::vector<Eigen::Vector3d>& voxel_centres,
                                      double resolution) {
  const Eigen::Matrix3d R =
      box.rotation.normalized().toRotationMatrix();  // box axes (columns) in the world
  // Half the extent of an axis-aligned cube along each box axis.
  const Eigen::Vector3d reach = 0.5 * resolution * R.cwiseAbs().colwise().sum().transpose();
  const Eigen::Vector3d half = 0.5 * box.size;
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  bool any = false;
  for (const Eigen::Vector3d& centre : voxel_centres) {
    const Eigen::Vector3d local = R.transpose() * (centre - box.center);
    if ((local.array().abs() > half.array()).any()) continue;
    low = low.cwiseMin(local - reach);
    high = high.cwiseMax(local + reach);
    any = true;
  }
  if (!any) return std::nullopt;
  // Never past the box drawn: whole cubes of a rotated box reach beyond it,
  // and a box grown to hold them took in more voxels at the next press.
  low = low.cwiseMax(-half);
  high = high.cwiseMin(half);
  OrientedBox tight = box;
  tight.size = high - low;
  tight.center = box.center + R * (0.5 * (low + high));
  return tight;
}

}  // namespace lom
