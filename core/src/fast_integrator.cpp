// The fast integration path. Same rule as the reference path (docs/fusion.md),
// organised around where the cost is: the free voxels in the view frustum.
//  1. Rows are split between threads. Each row is back-projected at once
//     into packed end voxels (vectorised, core/src/pixel_projector.cpp), and
//     its log-odds come from a 256-entry table for 8-bit probability images
//     or from the vectorised row logit (core/src/fast_logit.cpp) otherwise.
//     Pixels are grouped by end voxel (a small direct-mapped cache of recent
//     voxels in front of an open-addressing table); each group sums its
//     pixels' log-odds.
//  2. One ray per end voxel marks the crossed voxels in 16^3 bit bricks, so a
//     voxel crossed by many rays costs one bit (threads mark their own bricks).
//  3. Hit voxels are removed from the marks; misses (read from the bricks in
//     Morton order) and hits (sorted) merge into one depth-first update stream
//     that the tree applies in one pass, cut in two halves that run at once
//     (LabelOcTree::applySortedUpdates).
// Per-thread state sits on its own cache lines: threads write it per pixel.
#include <algorithm>
#include <array>
#include <chrono>
#include <thread>

#include "flat_index.hpp"
#include "fusion_internal.hpp"
#include "lom/octree/label_octree.hpp"

namespace lom {

namespace {

// Voxels as bits in 16 x 16 x 16 bricks, each brick's bits in Morton order.
class alignas(64) BrickSet {  // own cache lines: each thread marks its own
 public:
  static constexpr int kWords = 64;  // 4096 bits
  using Bits = std::array<std::uint64_t, kWords>;

  void set(unsigned x, unsigned y, unsigned z) {
    Bits& bits = brick(packBrick(x, y, z));
    const unsigned local = localIndex(x, y, z);
    bits[local >> 6] |= std::uint64_t{1} << (local & 63);
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
  // Appends every marked voxel as a miss, in Morton (depth-first) order.
  void appendMisses(std::vector<VoxelUpdate>& out) const {
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

// The pixels of one thread's rows, grouped by end voxel.
struct alignas(64) PixelGroups {  // own cache lines: threads write theirs per pixel
  struct Group {
    std::uint64_t voxel = 0;  // packVoxel(end key, beyond max range)
    std::uint32_t pixels = 0;
  };
  FlatIndex index{4096};
  std::vector<Group> groups;
  std::vector<float> sums;  // per group: one value per summed channel
  size_t valid_pixels = 0;
  // The groups of recently seen voxels, direct-mapped: runs of pixels in a
  // row alternate between a few voxels (depth noise), and mostly hit here.
  static constexpr int kRecentBits = 8;
  std::array<std::uint64_t, 1u << kRecentBits> recent_key;
  std::array<std::uint32_t, 1u << kRecentBits> recent_group;

  PixelGroups() { recent_key.fill(FlatIndex::kEmpty); }

  std::uint32_t groupFor(std::uint64_t voxel, int width) {
    bool inserted = false;
    const std::uint32_t group =
        index.findOrInsert(voxel, static_cast<std::uint32_t>(groups.size()), inserted);
    if (inserted) {
      groups.push_back({voxel, 0});
      sums.resize(sums.size() + static_cast<size_t>(width), 0.f);
    }
    return group;
  }
  std::uint32_t cachedGroupFor(std::uint64_t voxel, int width) {
    const size_t slot = static_cast<size_t>(FlatIndex::mix(voxel) >> (64 - kRecentBits));
    if (recent_key[slot] == voxel) return recent_group[slot];
    recent_key[slot] = voxel;
    recent_group[slot] = groupFor(voxel, width);
    return recent_group[slot];
  }
};

// sums[c] += add[c]; restrict lets g++ use vector adds.
inline void addInto(float* __restrict sums, const float* __restrict add, int width) {
  for (int c = 0; c < width; ++c) sums[c] += add[c];
}

template <typename Work>
void runOnThreads(int threads, Work&& work) {
  if (threads <= 1) {
    work(0);
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back([&, t] { work(t); });
  work(0);
  for (auto& thread : pool) thread.join();
}

bool hasDuplicateChannels(const ProbabilityImage& proba) {
  std::vector<int> labels = proba.channel_labels;
  std::sort(labels.begin(), labels.end());
  return std::adjacent_find(labels.begin(), labels.end()) != labels.end();
}

}  // namespace

FrameStats integrateFrameFast(LabelMap& map, const CameraIntrinsics& camera,
                              const Eigen::Isometry3d& T_world_camera, const DepthImage& depth,
                              const FrameEvidence& evidence, int threads) {
  const auto start = std::chrono::steady_clock::now();
  checkFrameInputs(map, camera, depth, evidence);
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, std::max(1, depth.height));
  LabelOcTree& tree = map.tree();
  const int n = map.numLabels();
  const double max_range = map.parameters().max_range;
  const grid::Grid g(map.parameters().resolution);
  const Eigen::Vector3d origin = T_world_camera.translation();

  // With a probability image used as is, only its channels need a logit per
  // pixel; labels without a channel get logit(epsilon) per pixel.
  const ProbabilityImage* direct = evidence.directProbabilities();
  if (direct && hasDuplicateChannels(*direct)) direct = nullptr;
  const int width = direct ? direct->channels : n;

  // 1. Group pixels by end voxel.
  // Log-odds per pixel: 8-bit images through a 256-entry table (the same
  // clampedLogit the reference path calls, so the same bits); other images a
  // row at a time with the vectorised logit (within 1e-6 of clampedLogit).
  const bool coded = direct && !direct->codes.empty() && direct->codes.size() == direct->values.size();
  std::array<float, 256> code_logit{};
  if (coded)
    for (int c = 0; c < 256; ++c)
      code_logit[static_cast<size_t>(c)] = clampedLogit(probabilityOfCode(static_cast<std::uint8_t>(c)));
  const PixelProjector projector(g, camera, T_world_camera, max_range);
  std::vector<PixelGroups> parts(static_cast<size_t>(threads));
  runOnThreads(threads, [&](int t) {
    PixelGroups& part = parts[static_cast<size_t>(t)];
    const size_t row_values = static_cast<size_t>(depth.width) * static_cast<size_t>(width);
    std::vector<float> row_probabilities(direct ? 0 : row_values, 0.f);
    std::vector<float> row_logits(coded ? 0 : row_values, 0.f);
    std::vector<std::uint64_t> row(static_cast<size_t>(depth.width));
    const int rows_begin = depth.height * t / threads;
    const int rows_end = depth.height * (t + 1) / threads;
    size_t valid_pixels = 0;  // counted here: part's fields are written per pixel
    for (int v = rows_begin; v < rows_end; ++v) {
      projector.projectRow(v, depth.metres.data() + static_cast<size_t>(v) * depth.width,
                           depth.width, row.data());
      const std::uint8_t* codes =
          coded ? direct->codes.data() + static_cast<size_t>(v) * row_values : nullptr;
      if (!coded) {
        const float* probabilities = row_probabilities.data();
        if (direct) {
          probabilities = direct->pixel(0, v);
        } else {
          for (int u = 0; u < depth.width; ++u)
            if (row[static_cast<size_t>(u)] != kNoVoxel && !(row[static_cast<size_t>(u)] & 1u))
              evidence.probabilities(u, v, row_probabilities.data() + static_cast<size_t>(u) * n);
        }
        logitRow(probabilities, row_values, row_logits.data());
      }
      // Consecutive pixels often end in the same voxel (depth noise keeps
      // the runs short, about two pixels at 640x480 and 1 cm): a run shares
      // one group look-up and one pixel count.
      std::uint64_t run_voxel = kNoVoxel;
      std::uint32_t run_pixels = 0, group = 0;
      float* sums = nullptr;
      for (int u = 0; u < depth.width; ++u) {
        const std::uint64_t voxel = row[static_cast<size_t>(u)];
        if (voxel == kNoVoxel) continue;
        if (voxel != run_voxel) {
          if (run_pixels) part.groups[group].pixels += run_pixels;
          valid_pixels += run_pixels;
          run_pixels = 0;
          run_voxel = voxel;
          group = part.cachedGroupFor(voxel, width);
          sums = part.sums.data() + static_cast<size_t>(group) * static_cast<size_t>(width);
        }
        ++run_pixels;
        if (voxel & 1u) continue;  // beyond max range: misses only
        const size_t first = static_cast<size_t>(u) * static_cast<size_t>(width);
        if (coded) {
          for (int c = 0; c < width; ++c) sums[c] += code_logit[codes[first + static_cast<size_t>(c)]];
        } else {
          addInto(sums, row_logits.data() + first, width);
        }
      }
      if (run_pixels) part.groups[group].pixels += run_pixels;
      valid_pixels += run_pixels;
    }
    part.valid_pixels = valid_pixels;
  });
  PixelGroups& all = parts[0];
  for (size_t t = 1; t < parts.size(); ++t) {
    const PixelGroups& part = parts[t];
    all.valid_pixels += part.valid_pixels;
    for (size_t i = 0; i < part.groups.size(); ++i) {
      const auto& group = part.groups[i];
      const std::uint32_t target = all.groupFor(group.voxel, width);
      all.groups[target].pixels += group.pixels;
      float* sums = all.sums.data() + static_cast<size_t>(target) * static_cast<size_t>(width);
      const float* add = part.sums.data() + i * static_cast<size_t>(width);
      for (int c = 0; c < width; ++c) sums[c] += add[c];
    }
  }

  // 2. One ray per end voxel.
  std::vector<BrickSet> marks(static_cast<size_t>(threads));
  runOnThreads(threads, [&](int t) {
    BrickSet& mark = marks[static_cast<size_t>(t)];
    for (size_t i = static_cast<size_t>(t); i < all.groups.size(); i += static_cast<size_t>(threads)) {
      const PixelRay ray = unpackVoxel(all.groups[i].voxel);
      const Eigen::Vector3d end = rayEnd(g, origin, ray.end_key, ray.beyond_range, max_range);
      grid::traverseRay(g, origin, end, [&](unsigned x, unsigned y, unsigned z) { mark.set(x, y, z); });
    }
  });
  for (size_t t = 1; t < marks.size(); ++t) marks[0].mergeFrom(marks[t]);

  // 3. Hits: full per-label log-odds; they are never also misses in this frame.
  const float unlisted = clampedLogit(0.f);
  std::vector<float> hit_values;
  std::vector<VoxelUpdate> hits;
  size_t hit_count = 0;
  for (const auto& group : all.groups) hit_count += (group.voxel & 1u) ? 0 : 1;
  hit_values.resize(hit_count * static_cast<size_t>(n));
  hits.reserve(hit_count);
  for (size_t i = 0; i < all.groups.size(); ++i) {
    const auto& group = all.groups[i];
    if (group.voxel & 1u) continue;  // beyond max range
    const grid::Key key = unpackVoxel(group.voxel).end_key;
    marks[0].clear(key);
    float* values = hit_values.data() + hits.size() * static_cast<size_t>(n);
    const float* sums = all.sums.data() + i * static_cast<size_t>(width);
    if (direct) {
      std::fill(values, values + n, unlisted * static_cast<float>(group.pixels));
      for (int c = 0; c < width; ++c) values[direct->channel_labels[static_cast<size_t>(c)]] = sums[c];
    } else {
      std::copy(sums, sums + n, values);
    }
    VoxelUpdate update;
    update.key = octomap::OcTreeKey(key[0], key[1], key[2]);
    update.morton = grid::mortonCode(key[0], key[1], key[2]);
    update.hit = values;
    hits.push_back(update);
  }
  std::sort(hits.begin(), hits.end(),
            [](const VoxelUpdate& a, const VoxelUpdate& b) { return a.morton < b.morton; });

  std::vector<VoxelUpdate> misses;
  marks[0].appendMisses(misses);
  std::vector<VoxelUpdate> updates(hits.size() + misses.size());
  std::merge(hits.begin(), hits.end(), misses.begin(), misses.end(), updates.begin(),
             [](const VoxelUpdate& a, const VoxelUpdate& b) { return a.morton < b.morton; });
  tree.applySortedUpdates(updates, threads);

  FrameStats stats;
  stats.valid_pixels = all.valid_pixels;
  stats.hit_voxels = hits.size();
  stats.miss_voxels = misses.size();
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace lom
