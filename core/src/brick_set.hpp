#pragma once
// The fast path's per-frame set of crossed voxels: bits in 16 x 16 x 16
// bricks (one bit per voxel however many rays cross it), each brick's bits in
// Morton order, so that the misses come out in the tree's depth-first order.
#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "flat_index.hpp"
#include "lom/octree/label_octree.hpp"
#include "voxel_grid.hpp"

namespace lom {

class alignas(64) BrickSet {  // own cache lines: each thread marks its own
 public:
  static constexpr int kWords = 64;  // 4096 bits
  using Bits = std::array<std::uint64_t, kWords>;

  // Marks the voxels the walk crosses, as grid::traverseRay visits them (same
  // comparisons on the same doubles), tracking the voxel's index inside its
  // brick step by step: a step adds one to a coordinate's bits within the
  // Morton index, and only a step out of the brick looks a brick up.
  // Unmarks everything, keeping the memory (for reuse from frame to frame).
  void clear() {
    index_.clear();
    bricks_.clear();
    keys_.clear();
    cached_key_ = ~std::uint64_t{0};
  }
  [[gnu::noinline]] void markWalk(const grid::RayWalk& w) {
    int k0 = w.key[0], k1 = w.key[1], k2 = w.key[2];
    const int e0 = w.end_key[0], e1 = w.end_key[1], e2 = w.end_key[2];
    if (k0 == e0 && k1 == e1 && k2 == e2) return;
    std::uint64_t* bits = brick(packBrick(static_cast<unsigned>(k0), static_cast<unsigned>(k1),
                                          static_cast<unsigned>(k2))).data();
    unsigned local = localIndex(static_cast<unsigned>(k0), static_cast<unsigned>(k1), static_cast<unsigned>(k2));
    bits[local >> 6] |= std::uint64_t{1} << (local & 63);
    // Per axis: its bits in the local index, what to add to them for one
    // step (a dilated +1 or -1), and their value right after leaving the brick.
    unsigned mask[3], add[3], wrapped[3];
    for (int a = 0; a < 3; ++a) {
      mask[a] = 0x249u << a;
      add[a] = w.step[a] > 0 ? 0u - mask[a] : ~0u;
      wrapped[a] = w.step[a] > 0 ? 0u : mask[a];
    }
    double m0 = w.t_max[0], m1 = w.t_max[1], m2 = w.t_max[2];
    const double length = w.length;
    long i = 0;
    while (true) {
      // Steps inside one brick: no calls, so the walk stays in registers.
      bool left_brick = false;
      for (; i < w.max_steps; ++i) {
        const int axis = grid::nextAxis(m0, m1, m2);
        if (axis == 2) {
          if (m2 > length) break;  // passed the end point (end voxel reached by rounding)
          k2 += w.step[2];
          m2 += w.t_delta[2];
        } else if (axis == 1) {
          if (m1 > length) break;
          k1 += w.step[1];
          m1 += w.t_delta[1];
        } else {
          if (m0 > length) break;
          k0 += w.step[0];
          m0 += w.t_delta[0];
        }
        const unsigned bits_a = ((local & mask[axis]) + add[axis]) & mask[axis];
        local = (local & ~mask[axis]) | bits_a;
        if (k0 == e0 && k1 == e1 && k2 == e2) return;
        if (bits_a == wrapped[axis]) {
          left_brick = true;
          ++i;
          break;
        }
        bits[local >> 6] |= std::uint64_t{1} << (local & 63);
      }
      if (!left_brick) return;
      bits = brickOf(static_cast<unsigned>(k0), static_cast<unsigned>(k1), static_cast<unsigned>(k2));
      bits[local >> 6] |= std::uint64_t{1} << (local & 63);
    }
  }
  void clear(const grid::Key& key) {
    const std::uint32_t* index = index_.find(packBrick(key[0], key[1], key[2]));
    if (!index) return;
    const unsigned local = localIndex(key[0], key[1], key[2]);
    bricks_[*index][local >> 6] &= ~(std::uint64_t{1} << (local & 63));
  }
  void mergeFrom(const BrickSet& other) {
    for (size_t i = 0; i < other.bricks_.size(); ++i) {
      Bits& bits = brick(other.keys_[i]);
      for (int w = 0; w < kWords; ++w) bits[static_cast<size_t>(w)] |= other.bricks_[i][static_cast<size_t>(w)];
    }
  }
  // Appends every marked voxel as a miss, in Morton (depth-first) order,
  // except, given a tree, those of its saturated free 4^3 blocks (one word of
  // a brick each), where a miss changes nothing; their marks are cleared.
  // Returns how many voxels were marked, appended or not.
  size_t appendMisses(std::vector<VoxelUpdate>& out, const LabelOcTree* tree = nullptr) {
    size_t marked = 0, kept = 0;
    for (size_t i = 0; i < bricks_.size(); ++i) {
      const auto [bx, by, bz] = unpackBrick(keys_[i]);
      const std::uint64_t saturated =
          tree ? tree->saturatedFreeBlocks(octomap::OcTreeKey(static_cast<std::uint16_t>(bx << 4),
                                                              static_cast<std::uint16_t>(by << 4),
                                                              static_cast<std::uint16_t>(bz << 4)))
               : 0;
      Bits& bits = bricks_[i];
      for (int w = 0; w < kWords; ++w) {
        const size_t count = static_cast<size_t>(__builtin_popcountll(bits[static_cast<size_t>(w)]));
        marked += count;
        if ((saturated >> w) & 1u)
          bits[static_cast<size_t>(w)] = 0;
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
      const Bits& bits = bricks_[i];
      for (int w = 0; w < kWords; ++w) {
        std::uint64_t word = bits[static_cast<size_t>(w)];
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
  [[gnu::noinline]] std::uint64_t* brickOf(unsigned x, unsigned y, unsigned z) {
    return brick(packBrick(x, y, z)).data();
  }
  Bits& brick(std::uint64_t packed) {
    if (packed == cached_key_) return bricks_[cached_index_];
    bool inserted = false;
    cached_index_ = index_.findOrInsert(packed, static_cast<std::uint32_t>(bricks_.size()), inserted);
    if (inserted) {
      bricks_.emplace_back();
      bricks_.back().fill(0);
      keys_.push_back(packed);
    }
    cached_key_ = packed;
    return bricks_[cached_index_];
  }

  FlatIndex index_{256};
  std::vector<Bits> bricks_;
  std::vector<std::uint64_t> keys_;
  std::uint64_t cached_key_ = ~std::uint64_t{0};
  std::uint32_t cached_index_ = 0;
  const LocalTables& tables_ = localTables();
};

}  // namespace lom
