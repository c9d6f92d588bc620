#pragma once
// Key arithmetic and ray traversal on OctoMap's voxel grid (16-bit keys
// centred on 32768), in double precision. Every fusion path uses these, so the
// reference and fast paths visit exactly the same voxels.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Core>

namespace lom::grid {

constexpr int kKeyOffset = 32768;  // OctoMap's tree_max_val for depth 16

using Key = std::array<std::uint16_t, 3>;

struct Grid {
  double resolution = 0.01;
  double inverse = 100.0;

  explicit Grid(double res) : resolution(res), inverse(1.0 / res) {}

  // False when the point lies outside the 16-bit key range.
  [[nodiscard]] bool keyOf(const Eigen::Vector3d& p, Key& key) const {
    for (int i = 0; i < 3; ++i) {
      const double scaled = inverse * p[i];
      if (!(scaled >= -kKeyOffset && scaled < kKeyOffset)) return false;
      // floor() without a libm call: truncate, then step down for negatives.
      int index = static_cast<int>(scaled);
      if (scaled < index) --index;
      key[static_cast<size_t>(i)] = static_cast<std::uint16_t>(index + kKeyOffset);
    }
    return true;
  }
  [[nodiscard]] double centerOf(std::uint16_t k) const {
    return (static_cast<double>(static_cast<int>(k) - kKeyOffset) + 0.5) * resolution;
  }
  [[nodiscard]] Eigen::Vector3d centerOf(const Key& key) const {
    return {centerOf(key[0]), centerOf(key[1]), centerOf(key[2])};
  }
};

// A 3D DDA walk from `origin` towards `end`, set up once per segment. Both the
// generic traversal below and the fast path's bit-marking walk step it with the
// same comparisons on the same doubles, so they visit the same voxels.
struct RayWalk {
  int key[3] = {};       // the origin's voxel
  int end_key[3] = {};   // the voxel containing `end` (not visited)
  int step[3] = {};      // -1, 0 or +1 per axis
  double t_max[3] = {};  // distance along the ray to the next border per axis
  double t_delta[3] = {};
  double length = 0.0;
  long max_steps = 0;    // a ray crosses at most this many voxels; guards against rounding loops
};

// False when either end is outside the key range (nothing to visit). When
// both ends are in the same voxel, `walk.key` equals `walk.end_key`.
inline bool setUpRay(const Grid& grid, const Eigen::Vector3d& origin, const Eigen::Vector3d& end,
                     RayWalk& walk) {
  Key key, end_key;
  if (!grid.keyOf(origin, key) || !grid.keyOf(end, end_key)) return false;
  for (int i = 0; i < 3; ++i) {
    walk.key[i] = key[static_cast<size_t>(i)];
    walk.end_key[i] = end_key[static_cast<size_t>(i)];
  }
  if (key == end_key) return true;
  const Eigen::Vector3d delta = end - origin;
  const double length = delta.norm();
  const Eigen::Vector3d direction = delta / length;
  for (int i = 0; i < 3; ++i) {
    if (direction[i] > 0.0) {
      walk.step[i] = 1;
    } else if (direction[i] < 0.0) {
      walk.step[i] = -1;
    } else {
      walk.step[i] = 0;
    }
    if (walk.step[i] != 0) {
      // Distance along the ray to the first voxel border in this dimension.
      const double border = (static_cast<double>(walk.key[i] - kKeyOffset) + (walk.step[i] > 0 ? 1.0 : 0.0)) *
                            grid.resolution;
      walk.t_max[i] = (border - origin[i]) / direction[i];
      walk.t_delta[i] = grid.resolution / std::fabs(direction[i]);
    } else {
      walk.t_max[i] = std::numeric_limits<double>::max();
      walk.t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  walk.length = length;
  walk.max_steps = 3L * static_cast<long>(std::ceil(length * grid.inverse)) + 3;
  return true;
}

// The axis of the next step: x unless y is strictly closer, then z if strictly
// closer than the chosen one.
inline int nextAxis(double m0, double m1, double m2) {
  if (m1 < m0 ? m2 < m1 : m2 < m0) return 2;
  return m1 < m0 ? 1 : 0;
}

// One step of a walk from the key k and the border distances m: the axis
// stepped (its key component and border distance advanced), or -1, changing
// nothing, when that border lies past the end point (the end voxel reached by
// rounding). Every walk steps through here, so all take the same steps.
inline int stepWalk(const RayWalk& walk, int& k0, int& k1, int& k2, double& m0, double& m1,
                    double& m2) {
  const int axis = nextAxis(m0, m1, m2);
  if (axis == 2) {
    if (m2 > walk.length) return -1;
    k2 += walk.step[2];
    m2 += walk.t_delta[2];
  } else if (axis == 1) {
    if (m1 > walk.length) return -1;
    k1 += walk.step[1];
    m1 += walk.t_delta[1];
  } else {
    if (m0 > walk.length) return -1;
    k0 += walk.step[0];
    m0 += walk.t_delta[0];
  }
  return axis;
}

// Visits, in order, the voxels a walk crosses: its start voxel, then one per
// step, stopping before its end voxel. `visit(x, y, z)` gets the key's three
// components as plain integers (a Key built per step and read back costs a
// stall per step).
template <typename Visit>
void walkRay(const RayWalk& walk, Visit&& visit) {
  int k0 = walk.key[0], k1 = walk.key[1], k2 = walk.key[2];
  const int e0 = walk.end_key[0], e1 = walk.end_key[1], e2 = walk.end_key[2];
  if (k0 == e0 && k1 == e1 && k2 == e2) return;
  visit(static_cast<std::uint16_t>(k0), static_cast<std::uint16_t>(k1), static_cast<std::uint16_t>(k2));
  // The key and the border distances stay in registers: writing a key
  // component to memory and reading the key back at once would stall each
  // step.
  double m0 = walk.t_max[0], m1 = walk.t_max[1], m2 = walk.t_max[2];
  for (long i = 0; i < walk.max_steps; ++i) {
    if (stepWalk(walk, k0, k1, k2, m0, m1, m2) < 0) break;
    if (k0 == e0 && k1 == e1 && k2 == e2) break;
    visit(static_cast<std::uint16_t>(k0), static_cast<std::uint16_t>(k1),
          static_cast<std::uint16_t>(k2));
  }
}

// Visits, in order, the voxels crossed by the segment from `origin` to `end`,
// starting with the origin's voxel and stopping before the voxel that contains
// `end` (a 3D DDA). Returns false (visiting nothing) when either end is
// outside the key range.
template <typename Visit>
bool traverseRay(const Grid& grid, const Eigen::Vector3d& origin, const Eigen::Vector3d& end,
                 Visit&& visit) {
  RayWalk walk;
  if (!setUpRay(grid, origin, end, walk)) return false;
  walkRay(walk, visit);
  return true;
}

}  // namespace lom::grid

namespace lom::grid {

// Spreads the low 16 bits of v so that bit i lands on bit 3i.
inline std::uint64_t spreadBits3(std::uint64_t v) {
  v &= 0xffff;
  v = (v | (v << 32)) & 0x1f00000000ffffULL;
  v = (v | (v << 16)) & 0x1f0000ff0000ffULL;
  v = (v | (v << 8)) & 0x100f00f00f00f00fULL;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3ULL;
  v = (v | (v << 2)) & 0x1249249249249249ULL;
  return v;
}

// Interleaves the key bits so that each 3-bit group, from the top, is OctoMap's
// child index at that depth (x = 1, y = 2, z = 4): sorting by this code visits
// voxels in the tree's depth-first order.
inline std::uint64_t mortonCode(std::uint16_t x, std::uint16_t y, std::uint16_t z) {
  return spreadBits3(x) | (spreadBits3(y) << 1) | (spreadBits3(z) << 2);
}

}  // namespace lom::grid
