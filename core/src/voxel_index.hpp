#pragma once
// A set of voxel keys for queries by coordinates, including neighbours just
// outside the key range: the voxel surface builder (mesh_voxels.cpp) and the
// Euclidean clustering (box_fit.cpp) ask for every neighbour of every voxel.
//
// The set is filed in 4x4x4 bricks. A coordinate plus kMargin (so -kMargin
// .. 65535 + kMargin, neighbours within kMargin of any key) has 17 bits: a
// brick's coordinates (the top 15) pack into 45 bits, a voxel's place in its
// brick into 6. A brick's voxels are one 64-bit mask, found through a flat
// hash of the brick's coordinates; the voxels are ranked by brick, then by
// place in the brick, so a voxel's rank is its brick's first rank plus the
// voxels before it in the mask. Neighbours mostly share a brick, which the
// last look-up keeps: most queries cost a bit test, not a hash probe (a
// std::unordered_set of the voxels cost a cache miss per query). Ranking
// the bricks in Morton order instead was 4-8 % slower for the surface.
// Not for concurrent queries (the last brick is cached).
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "flat_index.hpp"
#include "lom/label_map.hpp"

namespace lom {

// Set bits of v (the builtin calls into libgcc when the target may lack
// the popcnt instruction).
inline unsigned bitCount(std::uint64_t v) {
  v = v - ((v >> 1) & 0x5555555555555555ULL);
  v = (v & 0x3333333333333333ULL) + ((v >> 2) & 0x3333333333333333ULL);
  v = (v + (v >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
  return static_cast<unsigned>((v * 0x0101010101010101ULL) >> 56);
}

class VoxelIndex {
 public:
  using Cell = std::array<int, 3>;
  static constexpr std::uint32_t kAbsent = 0xffffffffu;
  // Queries may reach this far outside the key range 0..65535.
  static constexpr int kMargin = 32;

  explicit VoxelIndex(const std::vector<VoxelKey>& keys) {
    struct Placed {
      std::uint64_t place;
      Cell cell;
    };
    std::vector<Placed> sorted;
    sorted.reserve(keys.size());
    for (const VoxelKey& k : keys) {
      const Cell cell{k.x, k.y, k.z};
      sorted.push_back({placeKey(cell), cell});
    }
    std::sort(sorted.begin(), sorted.end(),
              [](const Placed& a, const Placed& b) { return a.place < b.place; });
    sorted.erase(std::unique(sorted.begin(), sorted.end(),
                             [](const Placed& a, const Placed& b) { return a.place == b.place; }),
                 sorted.end());
    cells_.reserve(sorted.size());
    bricks_.reset(sorted.size() / 4 + 1);
    for (const auto& [place, cell] : sorted) {
      const std::uint64_t brick = place >> 6;
      if (masks_.empty() || brick != last_brick_key_) {
        bool inserted = false;
        bricks_.findOrInsert(brick, static_cast<std::uint32_t>(masks_.size()), inserted);
        masks_.push_back(0);
        first_rank_.push_back(static_cast<std::uint32_t>(cells_.size()));
        last_brick_key_ = brick;
      }
      masks_.back() |= std::uint64_t{1} << (place & 63u);
      cells_.push_back(cell);
    }
    last_brick_key_ = FlatIndex::kEmpty;
  }

  // The voxels, in rank order, without repeats.
  [[nodiscard]] const std::vector<Cell>& cells() const { return cells_; }
  [[nodiscard]] size_t size() const { return cells_.size(); }

  // The rank of `cell`, or kAbsent when it is not in the set. Coordinates
  // more than kMargin outside the key range are never in it.
  [[nodiscard]] std::uint32_t rankOf(const Cell& cell) const {
    for (const int c : cell)
      if (static_cast<unsigned>(c + kMargin) > static_cast<unsigned>(65535 + 2 * kMargin))
        return kAbsent;
    const std::uint64_t place = placeKey(cell);
    const std::uint64_t brick = place >> 6;
    if (brick != last_brick_key_) {
      const std::uint32_t* found = bricks_.find(brick);
      last_brick_key_ = brick;
      last_brick_ = found ? *found : kAbsent;
    }
    if (last_brick_ == kAbsent) return kAbsent;
    const std::uint64_t mask = masks_[last_brick_];
    const unsigned bit = static_cast<unsigned>(place & 63u);
    if (!((mask >> bit) & 1u)) return kAbsent;
    return first_rank_[last_brick_] +
           static_cast<std::uint32_t>(bitCount(mask & ((std::uint64_t{1} << bit) - 1)));
  }
  [[nodiscard]] bool contains(const Cell& cell) const { return rankOf(cell) != kAbsent; }

 private:
  static std::uint64_t placeKey(const Cell& c) {
    const auto x = static_cast<std::uint64_t>(c[0] + kMargin),
               y = static_cast<std::uint64_t>(c[1] + kMargin),
               z = static_cast<std::uint64_t>(c[2] + kMargin);
    const std::uint64_t brick = (x >> 2) | ((y >> 2) << 15) | ((z >> 2) << 30);
    return (brick << 6) | (x & 3u) | ((y & 3u) << 2) | ((z & 3u) << 4);
  }

  std::vector<Cell> cells_;
  FlatIndex bricks_;
  std::vector<std::uint64_t> masks_;
  std::vector<std::uint32_t> first_rank_;
  // The brick of the last look-up (kAbsent: not in the set).
  mutable std::uint64_t last_brick_key_ = FlatIndex::kEmpty;
  mutable std::uint32_t last_brick_ = kAbsent;
};

}  // namespace lom
