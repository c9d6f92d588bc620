#pragma once
// Checks on triangle meshes shared by the mesh and export tests: closedness,
// orientation, enclosed volume, Euler characteristic; and small labelled maps
// built voxel by voxel.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "lom/export.hpp"
#include "lom/label_map.hpp"
#include "lom/octree/label_octree.hpp"

namespace lom::test {

using Triangle = std::array<std::int64_t, 3>;

struct EdgeReport {
  size_t edges = 0;
  size_t edges_not_shared_by_two = 0;  // watertight: 0
  size_t directed_edges_repeated = 0;  // consistently oriented: 0
};

inline EdgeReport edgeReport(const std::vector<Triangle>& triangles) {
  std::map<std::pair<std::int64_t, std::int64_t>, int> undirected, directed;
  for (const auto& t : triangles)
    for (int i = 0; i < 3; ++i) {
      const std::int64_t a = t[static_cast<size_t>(i)], b = t[static_cast<size_t>((i + 1) % 3)];
      ++undirected[{std::min(a, b), std::max(a, b)}];
      ++directed[{a, b}];
    }
  EdgeReport report;
  report.edges = undirected.size();
  for (const auto& [edge, count] : undirected) report.edges_not_shared_by_two += count != 2;
  for (const auto& [edge, count] : directed) report.directed_edges_repeated += count != 1;
  return report;
}

// Divergence theorem: sum over triangles of det(a, b, c) / 6.
inline double enclosedVolume(const std::vector<Eigen::Vector3d>& vertices,
                             const std::vector<Triangle>& triangles) {
  double six = 0.0;
  for (const auto& t : triangles)
    six += vertices[static_cast<size_t>(t[0])].dot(
        vertices[static_cast<size_t>(t[1])].cross(vertices[static_cast<size_t>(t[2])]));
  return six / 6.0;
}

inline double surfaceArea(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<Triangle>& triangles) {
  double area = 0.0;
  for (const auto& t : triangles) {
    const Eigen::Vector3d& a = vertices[static_cast<size_t>(t[0])];
    area += 0.5 * (vertices[static_cast<size_t>(t[1])] - a)
                      .cross(vertices[static_cast<size_t>(t[2])] - a)
                      .norm();
  }
  return area;
}

inline double smallestTriangleArea(const std::vector<Eigen::Vector3d>& vertices,
                                   const std::vector<Triangle>& triangles) {
  double smallest = 1e300;
  for (const auto& t : triangles) {
    const Eigen::Vector3d& a = vertices[static_cast<size_t>(t[0])];
    smallest = std::min(smallest, 0.5 * (vertices[static_cast<size_t>(t[1])] - a)
                                            .cross(vertices[static_cast<size_t>(t[2])] - a)
                                            .norm());
  }
  return smallest;
}

inline std::vector<Triangle> trianglesOf(const SurfaceMesh& mesh) {
  std::vector<Triangle> out;
  for (const auto& t : mesh.triangles) out.push_back({t[0], t[1], t[2]});
  return out;
}

// ---- Small maps ----

inline LabelSet numberedLabels(int n) {
  std::vector<LabelInfo> list;
  for (int i = 0; i < n; ++i) list.push_back({i, "Label " + std::to_string(i), vocColor(i)});
  return LabelSet(list);
}

inline VoxelKey gridKey(int i, int j, int k) {
  return {static_cast<std::uint16_t>(32768 + i), static_cast<std::uint16_t>(32768 + j),
          static_cast<std::uint16_t>(32768 + k)};
}

inline std::vector<VoxelKey> blockKeys(int i0, int i1, int j0, int j1, int k0, int k1) {
  std::vector<VoxelKey> keys;
  for (int i = i0; i < i1; ++i)
    for (int j = j0; j < j1; ++j)
      for (int k = k0; k < k1; ++k) keys.push_back(gridKey(i, j, k));
  return keys;
}

// Builds a map voxel by voxel: occupied voxels of given labels, free voxels.
class MapBuilder {
 public:
  MapBuilder(int num_labels, double resolution)
      : map_(numberedLabels(num_labels), params(resolution)) {}

  MapBuilder& occupy(const std::vector<VoxelKey>& keys, int label) {
    std::vector<float> hit(static_cast<size_t>(map_.numLabels()), -2.f);
    hit[static_cast<size_t>(label)] = 2.f;
    for (const auto& k : keys) {
      const octomap::OcTreeKey key(k.x, k.y, k.z);
      map_.tree().applyHit(key, hit.data());
      touched_.push_back(key);
    }
    return *this;
  }
  MapBuilder& clear(const std::vector<VoxelKey>& keys) {
    for (const auto& k : keys) {
      const octomap::OcTreeKey key(k.x, k.y, k.z);
      map_.tree().applyMiss(key);
      touched_.push_back(key);
    }
    return *this;
  }
  LabelMap build() {
    map_.tree().refreshAncestors(touched_);
    touched_.clear();
    return std::move(map_);
  }

 private:
  static MapParameters params(double resolution) {
    MapParameters p;
    p.resolution = resolution;
    return p;
  }
  LabelMap map_;
  std::vector<octomap::OcTreeKey> touched_;
};

}  // namespace lom::test
