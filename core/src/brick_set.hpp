#pragma once
// The fast path's per-frame set of crossed voxels: bits in 16 x 16 x 16
// bricks (one bit per voxel however many rays cross it), each brick's bits in
// Morton order, so that the misses come out in the tree's depth-first order.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <utility>
#include <vector>

#include <emmintrin.h>

#include "flat_index.hpp"
#include "lom/octree/label_octree.hpp"
#include "voxel_grid.hpp"

namespace lom {

class alignas(64) BrickSet {  // own cache lines: each thread marks its own
 public:
  static constexpr int kWords = 64;  // 4096 bits

  // Unmarks everything, keeping the memory (for reuse from frame to frame).
  void clear() {
    index_.clear();
    words_.clear();
    keys_.clear();
    cached_key_ = ~std::uint64_t{0};
  }
  // Marks the voxels the walk crosses: exactly those grid::traverseRay
  // visits (the same steps, chosen by the same comparisons of the same
  // doubles). See markSlices.
  [[gnu::noinline]] void markWalk(const grid::RayWalk& w) {
    // The slices run along the axis with the shortest distance between
    // borders (ties: the lowest axis).
    const double* td = w.t_delta;
    const int d = td[1] < td[0] ? (td[2] < td[1] ? 2 : 1) : (td[2] < td[0] ? 2 : 0);
    if (d == 0)
      markSlices<0>(w);
    else if (d == 1)
      markSlices<1>(w);
    else
      markSlices<2>(w);
  }
  // Marks the voxels of `count` walks, the same as markWalk on each. With
  // `eight_at_once` (only on processors with AVX-512 F), eight walks advance
  // together, one per vector lane (brick_march.cpp).
  void markWalks(const grid::RayWalk* walks, size_t count, bool eight_at_once) {
    if (eight_at_once) {
      markWalksAvx512(walks, count);
      return;
    }
    for (size_t i = 0; i < count; ++i) markWalk(walks[i]);
  }
  [[nodiscard]] size_t brickCount() const { return keys_.size(); }
  // The memory kept for reuse, in bytes.
  [[nodiscard]] size_t memoryBytes() const {
    return index_.memoryBytes() + (words_.capacity() + keys_.capacity()) * sizeof(std::uint64_t);
  }
  // The voxels marked (one per voxel however many rays crossed it).
  [[nodiscard]] size_t markedCount() const {
    size_t marked = 0;
    for (const std::uint64_t word : words_)
      marked += static_cast<size_t>(__builtin_popcountll(word));
    return marked;
  }
  // The voxels marked here and in none of the sets `others[0..count)`:
  // summed over the threads' sets, each voxel once.
  [[nodiscard]] size_t markedCountNotIn(const BrickSet* others, size_t count) const {
    size_t marked = 0;
    for (size_t i = 0; i < keys_.size(); ++i) {
      std::uint64_t words[kWords];
      marksNotIn(i, others, count, words);
      for (const std::uint64_t word : words)
        marked += static_cast<size_t>(__builtin_popcountll(word));
    }
    return marked;
  }
  // Calls `visit(key)` (an octomap::OcTreeKey) for each voxel marked here and
  // in none of the sets `others[0..count)`.
  template <class Visit>
  void forEachMarkedNotIn(const BrickSet* others, size_t count, Visit visit) const {
    const LocalTables& tables = tables_;
    for (size_t i = 0; i < keys_.size(); ++i) {
      std::uint64_t words[kWords];
      marksNotIn(i, others, count, words);
      const auto [bx, by, bz] = unpackBrick(keys_[i]);
      for (int w = 0; w < kWords; ++w)
        for (std::uint64_t word = words[w]; word; word &= word - 1) {
          const auto& offset = tables.offset[static_cast<unsigned>(w * 64 + __builtin_ctzll(word))];
          visit(octomap::OcTreeKey(static_cast<std::uint16_t>((bx << 4) | offset[0]),
                                   static_cast<std::uint16_t>((by << 4) | offset[1]),
                                   static_cast<std::uint16_t>((bz << 4) | offset[2])));
        }
    }
  }
  void clear(const grid::Key& key) {
    const std::uint32_t* index = index_.find(packBrick(key[0], key[1], key[2]));
    if (!index) return;
    const unsigned local = localIndex(key[0], key[1], key[2]);
    bits(*index)[local >> 6] &= ~(std::uint64_t{1} << (local & 63));
  }
  void mergeFrom(const BrickSet& other) {
    for (size_t i = 0; i < other.keys_.size(); ++i) {
      std::uint64_t* into = bitsOf(other.keys_[i]);
      const std::uint64_t* from = other.bits(i);
      for (int w = 0; w < kWords; ++w) into[w] |= from[w];
    }
  }
  // Appends every marked voxel as a miss, in Morton (depth-first) order,
  // except, given a tree, those of its saturated free 4^3 blocks (one word of
  // a brick each), where a miss changes nothing; their marks are cleared.
  // Returns how many voxels were marked, appended or not.
  size_t appendMisses(std::vector<VoxelUpdate>& out, const LabelOcTree* tree = nullptr) {
    size_t marked = 0, kept = 0;
    for (size_t i = 0; i < keys_.size(); ++i) {
      const auto [bx, by, bz] = unpackBrick(keys_[i]);
      const std::uint64_t saturated =
          tree ? tree->saturatedFreeBlocks(octomap::OcTreeKey(static_cast<std::uint16_t>(bx << 4),
                                                              static_cast<std::uint16_t>(by << 4),
                                                              static_cast<std::uint16_t>(bz << 4)))
               : 0;
      std::uint64_t* words = bits(i);
      for (int w = 0; w < kWords; ++w) {
        const size_t count = static_cast<size_t>(__builtin_popcountll(words[w]));
        marked += count;
        if ((saturated >> w) & 1u)
          words[w] = 0;
        else
          kept += count;
      }
    }
    out.reserve(out.size() + kept);
    std::vector<std::pair<std::uint64_t, size_t>> order;
    order.reserve(keys_.size());
    for (size_t i = 0; i < keys_.size(); ++i) {
      const auto [bx, by, bz] = unpackBrick(keys_[i]);
      order.emplace_back(grid::mortonCode(bx, by, bz), i);
    }
    std::sort(order.begin(), order.end());
    const LocalTables& tables = tables_;
    for (const auto& [brick_morton, i] : order) {
      const auto [bx, by, bz] = unpackBrick(keys_[i]);
      const std::uint64_t* words = bits(i);
      for (int w = 0; w < kWords; ++w) {
        std::uint64_t word = words[w];
        while (word) {
          const int bit = __builtin_ctzll(word);
          word &= word - 1;
          const unsigned local = static_cast<unsigned>(w * 64 + bit);
          const auto& offset = tables.offset[local];
          VoxelUpdate update;
          update.morton = (brick_morton << 12) | local;
          update.key = octomap::OcTreeKey(static_cast<std::uint16_t>((bx << 4) | offset[0]),
                                          static_cast<std::uint16_t>((by << 4) | offset[1]),
                                          static_cast<std::uint16_t>((bz << 4) | offset[2]));
          out.push_back(update);
        }
      }
    }
    return marked;
  }

 private:
  // Brick i's marks less those of the same brick in `others[0..count)`.
  void marksNotIn(size_t i, const BrickSet* others, size_t count, std::uint64_t* words) const {
    std::copy(bits(i), bits(i) + kWords, words);
    for (size_t o = 0; o < count; ++o)
      if (const std::uint32_t* theirs = others[o].index_.find(keys_[i]))
        for (int w = 0; w < kWords; ++w) words[w] &= ~others[o].bits(*theirs)[w];
  }

  // The walk in slices along axis D: one step on D and the steps on the other
  // two axes (A < B) before it. A step at a time, the walk's choice of axis
  // is a branch the processor cannot predict (in a frame of the benchmark
  // scene, two steps in five are not on D, at no regular interval). When
  // D's borders are strictly closer together than A's and B's (always, but
  // for rays within about 1e-12 of a diagonal), a slice holds at most one
  // step on A and one on B, and it is done without branches: compare the
  // border distances, add where a step is taken, mark the slice's voxels.
  // The steps from the end voxel's slab on, and slices where A or B leaves
  // the brick, go a step at a time, from the same state.
  template <int D>
  void markSlices(const grid::RayWalk& w) {
    constexpr int A = D == 0 ? 1 : 0, B = D == 2 ? 1 : 2;
    int k0 = w.key[0], k1 = w.key[1], k2 = w.key[2];
    const int e0 = w.end_key[0], e1 = w.end_key[1], e2 = w.end_key[2];
    if (k0 == e0 && k1 == e1 && k2 == e2) return;
    std::uint64_t* bits = bitsOf(
        packBrick(static_cast<unsigned>(k0), static_cast<unsigned>(k1), static_cast<unsigned>(k2)));
    unsigned local =
        localIndex(static_cast<unsigned>(k0), static_cast<unsigned>(k1), static_cast<unsigned>(k2));
    bits[local >> 6] |= std::uint64_t{1} << (local & 63);
    // Per axis: its bits in the local (Morton) index, what to add to them for
    // one step (a dilated +1 or -1), and their value right after leaving the brick.
    unsigned mask[3], add[3], wrapped[3];
    for (int a = 0; a < 3; ++a) {
      mask[a] = axisBits(a);
      add[a] = w.step[a] > 0 ? 0u - mask[a] : ~0u;
      wrapped[a] = w.step[a] > 0 ? 0u : mask[a];
    }
    double m0 = w.t_max[0], m1 = w.t_max[1], m2 = w.t_max[2];
    long i = 0;  // steps taken
    // One step, as traverseRay takes it; the axis stepped, or -1 at the end.
    auto step = [&]() -> int {
      if (i >= w.max_steps) return -1;
      ++i;
      const int axis = grid::stepWalk(w, k0, k1, k2, m0, m1, m2);
      if (axis < 0) return -1;
      const unsigned bits_a = ((local & mask[axis]) + add[axis]) & mask[axis];
      local = (local & ~mask[axis]) | bits_a;
      if (k0 == e0 && k1 == e1 && k2 == e2) return -1;
      if (bits_a == wrapped[axis])
        bits = bitsOf(packBrick(static_cast<unsigned>(k0), static_cast<unsigned>(k1),
                                static_cast<unsigned>(k2)));
      bits[local >> 6] |= std::uint64_t{1} << (local & 63);
      return axis;
    };
    int& kA = pick<A>(k0, k1, k2);
    int& kB = pick<B>(k0, k1, k2);
    int& kD = pick<D>(k0, k1, k2);
    double& mA = pick<A>(m0, m1, m2);
    double& mB = pick<B>(m0, m1, m2);
    double& mD = pick<D>(m0, m1, m2);
    const int sA = w.step[A], sB = w.step[B], sD = w.step[D];
    // The D steps that stay out of the end voxel's slab: no slice among them
    // reaches the end voxel or the end point.
    long left = std::abs(pick<D>(e0, e1, e2) - kD) - 1;
    // At most one A step per slice needs t_delta[A] > t_delta[D] by more than
    // the rounding of the sums (a few ulps of `length`).
    const double margin = 1e-12 * (w.length + w.t_delta[D]);
    if (!(w.t_delta[A] - w.t_delta[D] > margin && w.t_delta[B] - w.t_delta[D] > margin)) left = 0;
    if (i + 3 * left + 3 > w.max_steps) left = 0;  // slices take at most three steps
    // Coordinates inside the brick, mirrored on axes walked downwards so that
    // every step adds one; flipping them back gives the key's low bits.
    const unsigned flipA = sA < 0 ? 15u : 0u, flipB = sB < 0 ? 15u : 0u, flipD = sD < 0 ? 15u : 0u;
    const __m128d tdA = _mm_set_sd(w.t_delta[A]), tdB = _mm_set_sd(w.t_delta[B]);
    const __m128d tdD = _mm_set_sd(w.t_delta[D]);
    const auto& spread = tables_.spread;
    constexpr int kBrickShift = D == 0 ? 24 : D == 1 ? 12 : 0;  // D's field in packBrick
    while (left > 0) {
      unsigned xa = (static_cast<unsigned>(kA) & 15u) ^ flipA;
      unsigned xb = (static_cast<unsigned>(kB) & 15u) ^ flipB;
      unsigned xd = (static_cast<unsigned>(kD) & 15u) ^ flipD;
      const unsigned xa0 = xa, xb0 = xb;
      // Each axis's bits of the current voxel's local index.
      unsigned qA = static_cast<unsigned>(spread[xa ^ flipA]) << A;
      unsigned qB = static_cast<unsigned>(spread[xb ^ flipB]) << B;
      unsigned qD = static_cast<unsigned>(spread[xd ^ flipD]) << D;
      std::uint64_t brick_key = packBrick(static_cast<unsigned>(k0), static_cast<unsigned>(k1),
                                          static_cast<unsigned>(k2));
      __m128d vA = _mm_set_sd(mA), vB = _mm_set_sd(mB), vD = _mm_set_sd(mD);
      long done = 0;
      for (; done < left; ++done) {
        // Steps on A and B before D's, with nextAxis's ties (the lower axis).
        const __m128d takeA = A < D ? _mm_cmple_sd(vA, vD) : _mm_cmplt_sd(vA, vD);
        const __m128d takeB = B < D ? _mm_cmple_sd(vB, vD) : _mm_cmplt_sd(vB, vD);
        const unsigned cA = static_cast<unsigned>(_mm_movemask_pd(takeA));  // upper lanes hold +0.0
        const unsigned cB = static_cast<unsigned>(_mm_movemask_pd(takeB));
        const unsigned xa2 = xa + cA, xb2 = xb + cB;
        if ((xa2 | xb2) & 16u) break;  // A or B leaves the brick: this slice a step at a time
        const unsigned a_first = static_cast<unsigned>(_mm_comile_sd(vA, vB));
        const unsigned xd2 = (xd + 1) & 15u;
        const unsigned qA2 = static_cast<unsigned>(spread[xa2 ^ flipA]) << A;
        const unsigned qB2 = static_cast<unsigned>(spread[xb2 ^ flipB]) << B;
        const unsigned qD2 = static_cast<unsigned>(spread[xd2 ^ flipD]) << D;
        // The voxels after A's and B's steps (the same voxel when neither
        // steps), after the first of two steps, and after D's step.
        const unsigned ab = qA2 | qB2;
        const unsigned before_d = ab | qD, after_d = ab | qD2;
        // (Picked in two steps: g++ turns a nested choice into a branch.)
        const unsigned first_ab = a_first ? (qA2 | qB) : (qA | qB2);
        const unsigned between = (cA & cB) ? (first_ab | qD) : before_d;
        bits[between >> 6] |= std::uint64_t{1} << (between & 63);
        bits[before_d >> 6] |= std::uint64_t{1} << (before_d & 63);
        if (xd2 == 0) {  // D's step leaves the brick
          brick_key += static_cast<std::uint64_t>(static_cast<std::int64_t>(sD)) << kBrickShift;
          bits = bitsOf(brick_key);
        }
        bits[after_d >> 6] |= std::uint64_t{1} << (after_d & 63);
        vA = _mm_add_sd(vA, _mm_and_pd(takeA, tdA));  // + 0.0 where no step: the same value
        vB = _mm_add_sd(vB, _mm_and_pd(takeB, tdB));
        vD = _mm_add_sd(vD, tdD);
        xa = xa2;
        xb = xb2;
        xd = xd2;
        qA = qA2;
        qB = qB2;
        qD = qD2;
      }
      // Back to the step-at-a-time state.
      mA = _mm_cvtsd_f64(vA);
      mB = _mm_cvtsd_f64(vB);
      mD = _mm_cvtsd_f64(vD);
      kA += sA * static_cast<int>(xa - xa0);
      kB += sB * static_cast<int>(xb - xb0);
      kD += sD * static_cast<int>(done);
      i += done + static_cast<long>(xa - xa0) + static_cast<long>(xb - xb0);
      local = qA | qB | qD;
      left -= done;
      if (left == 0) break;
      int axis;
      do {
        axis = step();
        if (axis < 0) return;
      } while (axis != D);
      --left;
    }
    while (step() >= 0) {
    }
  }
  // x, y or z by a constant axis index: keeps the walk's state in registers.
  template <int a, typename T>
  static T& pick(T& x, T& y, T& z) {
    if constexpr (a == 0)
      return x;
    else if constexpr (a == 1)
      return y;
    else
      return z;
  }

  struct LocalTables {
    std::array<std::uint16_t, 16> spread{};                  // 4-bit value -> every third bit
    std::array<std::array<std::uint8_t, 3>, 4096> offset{};  // local Morton index -> x, y, z
  };
  static const LocalTables& localTables() {
    static const LocalTables tables = [] {
      LocalTables t;
      for (unsigned v = 0; v < 16; ++v) t.spread[v] = static_cast<std::uint16_t>(grid::spreadBits3(v));
      for (unsigned x = 0; x < 16; ++x)
        for (unsigned y = 0; y < 16; ++y)
          for (unsigned z = 0; z < 16; ++z)
            t.offset[t.spread[x] | (t.spread[y] << 1) | (t.spread[z] << 2)] = {
                static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y),
                static_cast<std::uint8_t>(z)};
      return t;
    }();
    return tables;
  }
  // Axis a's bits in a voxel's local (Morton) index: every third bit from a.
  static constexpr unsigned axisBits(int a) { return 0x249u << a; }
  [[nodiscard]] unsigned localIndex(unsigned x, unsigned y, unsigned z) const {
    const auto& spread = tables_.spread;
    return spread[x & 15u] | (spread[y & 15u] << 1) | (spread[z & 15u] << 2);
  }
  static std::uint64_t packBrick(unsigned x, unsigned y, unsigned z) {
    return (std::uint64_t{x >> 4} << 24) | (std::uint64_t{y >> 4} << 12) | (z >> 4);
  }
  static std::array<std::uint16_t, 3> unpackBrick(std::uint64_t packed) {
    return {static_cast<std::uint16_t>(packed >> 24), static_cast<std::uint16_t>((packed >> 12) & 0xfff),
            static_cast<std::uint16_t>(packed & 0xfff)};
  }
  [[gnu::noinline]] std::uint64_t* bitsOf(std::uint64_t packed) { return bits(brickIndex(packed)); }
  std::uint64_t* bits(size_t index) { return words_.data() + index * kWords; }
  const std::uint64_t* bits(size_t index) const { return words_.data() + index * kWords; }
  // The brick's index (a new, empty brick when it has none yet).
  std::uint32_t brickIndex(std::uint64_t packed) {
    if (packed == cached_key_) return cached_index_;
    bool inserted = false;
    cached_index_ = index_.findOrInsert(packed, static_cast<std::uint32_t>(keys_.size()), inserted);
    if (inserted) {
      words_.resize(words_.size() + kWords, 0);
      keys_.push_back(packed);
    }
    cached_key_ = packed;
    return cached_index_;
  }
  void markWalksAvx512(const grid::RayWalk* walks, size_t count);  // brick_march.cpp

  FlatIndex index_{256};
  std::vector<std::uint64_t> words_;  // kWords per brick, in the order of keys_
  std::vector<std::uint64_t> keys_;
  std::uint64_t cached_key_ = ~std::uint64_t{0};
  std::uint32_t cached_index_ = 0;
  const LocalTables& tables_ = localTables();
};

}  // namespace lom
