// The fast integration path. Same rule as the reference path (docs/fusion.md),
// organised around where the cost is: the free voxels in the view frustum.
//  1. Rows are split between threads. Each row is back-projected at once
//     into packed end voxels (vectorised, core/src/pixel_projector.cpp), and
//     pixels are grouped by end voxel (a small direct-mapped cache of recent
//     voxels in front of an open-addressing table); each group sums its
//     pixels' log-odds. 8-bit probability images with up to 16 channels (what
//     generated scenes and `segment --dtype uint8` write) go through a vector
//     kernel that turns a whole pixel's codes (four pixels' with AVX-512 byte
//     permutes) into log-odds from a 256-entry table and adds them in
//     registers (coded_row_kernel.inc); other 8-bit
//     images go through the same table a value at a time, and float images
//     through the vectorised row logit (core/src/fast_logit.cpp).
//  2. One ray per end voxel marks the crossed voxels in 16^3 bit bricks, so a
//     voxel crossed by many rays costs one bit (threads mark their own
//     bricks; brick_set.hpp); with AVX-512, eight rays at once, one per
//     vector lane (brick_march.cpp). Each thread starts on its own groups'
//     rays as soon as its rows are done, in chunks, and then helps with the
//     other threads' groups; the first thread merges the groups meanwhile.
//  3. Hit voxels are removed from the marks; misses (read from the bricks in
//     Morton order, leaving out the 4^3 blocks the tree holds as saturated
//     free space, which a miss cannot change) and hits (sorted; with a
//     probability image used as is, a hit lists its channels' labels and the
//     one value every other label gets) are built at once and merge, in two
//     halves, into one depth-first update stream that the tree applies in one
//     pass, cut in two halves that run at once (LabelOcTree::applySortedUpdates).
// The parallel phases run on worker threads kept between frames
// (worker_pool.hpp). Per-thread state sits on its own cache lines.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include <immintrin.h>

#include "brick_set.hpp"
#include "flat_index.hpp"
#include "fusion_internal.hpp"
#include "lom/octree/label_octree.hpp"
#include "worker_pool.hpp"

namespace lom {

namespace {

// Storage whose blocks start on a cache line, for whole-register loads.
template <typename T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <typename U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}  // NOLINT: allocator conversion
  T* allocate(size_t count) { return static_cast<T*>(::operator new(count * sizeof(T), std::align_val_t{64})); }
  void deallocate(T* p, size_t) { ::operator delete(p, std::align_val_t{64}); }
  bool operator==(const CacheLineAllocator&) const { return true; }
  bool operator!=(const CacheLineAllocator&) const { return false; }
};

// The pixels of one thread's rows, grouped by end voxel.
struct alignas(64) PixelGroups {  // own cache lines: threads write theirs per pixel
  struct Group {
    std::uint64_t voxel = 0;  // packVoxel(end key, beyond max range)
    std::uint32_t pixels = 0;
  };
  FlatIndex index{4096};
  std::vector<Group> groups;
  // Per group: one value per summed channel, then padding up to `stride`.
  std::vector<float, CacheLineAllocator<float>> sums;
  size_t stride = 0;
  size_t valid_pixels = 0;
  // The groups of recently seen voxels, direct-mapped: runs of pixels in a
  // row alternate between a few voxels (depth noise), and mostly hit here.
  // 2048 slots (24 KiB, within the first-level cache): at 640x480 and 1 cm,
  // 8,000 look-ups in the table per frame for 5,900 groups (21,000 with 256
  // slots, whose misses cost a mispredicted branch and a table probe each).
  static constexpr int kRecentBits = 11;
  std::array<std::uint64_t, 1u << kRecentBits> recent_key;
  std::array<std::uint32_t, 1u << kRecentBits> recent_group;

  PixelGroups() { recent_key.fill(FlatIndex::kEmpty); }
  // Empties the groups, keeping the memory (for reuse from frame to frame).
  void clear(size_t sums_stride) {
    index.clear();
    groups.clear();
    sums.clear();
    stride = sums_stride;
    valid_pixels = 0;
    recent_key.fill(FlatIndex::kEmpty);
  }

  float* sumsOf(size_t group) { return sums.data() + group * stride; }
  // Out of line: the rare way (a recent-voxel cache miss) must not take
  // registers from groupRow's loop.
  [[gnu::noinline]] std::uint32_t groupFor(std::uint64_t voxel) {
    bool inserted = false;
    const std::uint32_t group =
        index.findOrInsert(voxel, static_cast<std::uint32_t>(groups.size()), inserted);
    if (inserted) {
      groups.push_back({voxel, 0});
      sums.resize(sums.size() + stride, 0.f);
    }
    return group;
  }
  std::uint32_t cachedGroupFor(std::uint64_t voxel) {
    const size_t slot = static_cast<size_t>(FlatIndex::mix(voxel) >> (64 - kRecentBits));
    if (recent_key[slot] == voxel) return recent_group[slot];
    recent_key[slot] = voxel;
    recent_group[slot] = groupFor(voxel);
    return recent_group[slot];
  }
};

// 8-bit probability images with at most 16 channels go in two passes per row:
// groupRow finds each pixel's group (hash look-ups, calls), then a vector
// kernel without calls (coded_row_kernel.inc) sums the log-odds, the table
// held in registers. Each group's sums are then 16 floats on one cache line.
constexpr size_t kCodedStride = 16;
constexpr std::uint32_t kNoGroup = ~std::uint32_t{0};

// group_of[u] = the group of pixel u, or kNoGroup when it adds no log-odds
// (no voxel, or beyond max range). Counts the pixels of every group when
// `count` (else the kernel counts them); returns the pixels with a voxel.
// Not inlined into the pixel phase's lambda: there, short of registers, g++
// kept the loop's pointer and counter on the stack, a chain of memory
// increments through every pixel.
template <bool count>
[[gnu::noinline]] size_t groupRow(PixelGroups& part, const std::uint64_t* voxels, int pixels,
                                  std::uint32_t* group_of) {
  // Every pixel looks its voxel up in the cache of recent voxels: no test for
  // the end of a run, which depth noise makes unpredictable.
  size_t valid = 0;
  for (int u = 0; u < pixels; ++u) {
    const std::uint64_t voxel = voxels[u];
    if (voxel == kNoVoxel) {
      group_of[u] = kNoGroup;
      continue;
    }
    const std::uint32_t group = part.cachedGroupFor(voxel);
    if constexpr (count) ++part.groups[group].pixels;
    ++valid;
    group_of[u] = (voxel & 1u) ? kNoGroup : group;  // beyond max range: misses only
  }
  return valid;
}

struct CodedRow {
  const std::uint32_t* group_of;  // groupRow's output
  int pixels;                     // image width
  const std::uint8_t* codes;      // the row's first code
  const std::uint8_t* codes_end;  // end of the image's codes: no load reaches past it
  int width;                      // channels per pixel, 1..16
  const float* table;             // log-odds of each code
  const std::uint8_t* table_bytes; // byte b of table[c] at table_bytes[256 b + c]
  // Four pixels' codes spread over the register so that the kernel's byte
  // interleaving leaves one pixel per register: byte 16 L + 4 k + j comes
  // from pixel k's channel 4 L + j (byte spread[i] of the four pixels'
  // codes; channels past the width repeat the last code, and land in the
  // sums' padding).
  const std::uint8_t* spread;
  float* sums;                    // the groups' sums, kCodedStride apart, on cache lines
};

// With fewer channels than lanes, the kernel counts each group's pixels in
// the sums' last lane (else groupRow counts them).
constexpr bool kernelCountsPixels(int width) { return width < static_cast<int>(kCodedStride); }

// The 16 codes starting at a pixel's first; past the image's end, zeros.
inline __m128i loadCodes(const CodedRow& r, int u) {
  const std::uint8_t* first = r.codes + static_cast<size_t>(u) * static_cast<size_t>(r.width);
  if (r.codes_end - first >= 16) return _mm_loadu_si128(reinterpret_cast<const __m128i*>(first));
  alignas(16) std::uint8_t copy[16] = {};
  for (int c = 0; c < r.width; ++c) copy[c] = first[c];
  return _mm_load_si128(reinterpret_cast<const __m128i*>(copy));
}

// The kernel, built once per instruction set (coded_row_kernel.inc). Its
// lambdas return vectors; they are inlined, so the ABI note does not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
// g++ 12 reads the "undefined" pass-through register of some AVX-512
// intrinsics (shuffles, byte permutes) as maybe uninitialised.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC push_options
#pragma GCC target("avx2")
#define LOM_CODED_ROW_KERNEL sumCodedRowAvx2
#define LOM_CODED_ROW_KIND 0
#include "coded_row_kernel.inc"
#undef LOM_CODED_ROW_KERNEL
#undef LOM_CODED_ROW_KIND
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f")
#define LOM_CODED_ROW_KERNEL sumCodedRowAvx512
#define LOM_CODED_ROW_KIND 1
#include "coded_row_kernel.inc"
#undef LOM_CODED_ROW_KERNEL
#undef LOM_CODED_ROW_KIND
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f,avx512bw,avx512vbmi")
#define LOM_CODED_ROW_KERNEL sumCodedRowAvx512Bytes
#define LOM_CODED_ROW_KIND 2
#include "coded_row_kernel.inc"
#undef LOM_CODED_ROW_KERNEL
#undef LOM_CODED_ROW_KIND
#pragma GCC pop_options
#pragma GCC diagnostic pop

// sums[c] += add[c]; restrict lets g++ use vector adds.
inline void addInto(float* __restrict sums, const float* __restrict add, int width) {
  for (int c = 0; c < width; ++c) sums[c] += add[c];
}

// One row's pixels added to their groups' sums, for the images the coded
// kernel does not take (float probabilities, or more than 16 channels).
// Consecutive pixels often end in the same voxel (depth noise keeps the runs
// short, about two pixels at 640x480 and 1 cm): a run shares one group
// look-up and one pixel count. `Run` adds a pixel's log-odds to the run's
// group: start(sums), add(u), end(). Returns the pixels with a voxel. Not
// inlined, as groupRow.
template <class Run>
[[gnu::noinline]] size_t sumRow(PixelGroups& part, const std::uint64_t* voxels, int pixels,
                                Run run) {
  size_t valid = 0;
  std::uint64_t run_voxel = kNoVoxel;
  std::uint32_t run_pixels = 0, group = 0;
  for (int u = 0; u < pixels; ++u) {
    const std::uint64_t voxel = voxels[u];
    if (voxel == kNoVoxel) continue;
    if (voxel != run_voxel) {
      if (run_pixels) {
        part.groups[group].pixels += run_pixels;
        run.end();
      }
      valid += run_pixels;
      run_pixels = 0;
      run_voxel = voxel;
      group = part.cachedGroupFor(voxel);
      run.start(part.sumsOf(group));
    }
    ++run_pixels;
    if (!(voxel & 1u)) run.add(u);  // beyond max range: misses only
  }
  if (run_pixels) {
    part.groups[group].pixels += run_pixels;
    run.end();
  }
  return valid + run_pixels;
}

// Log-odds of `width` channels per pixel, added in memory.
struct FloatRun {
  const float* logits;
  int width;
  float* sums = nullptr;
  void start(float* group_sums) { sums = group_sums; }
  void add(int u) {
    addInto(sums, logits + static_cast<size_t>(u) * static_cast<size_t>(width), width);
  }
  void end() {}
};

// One channel (a single-label map): the run's sum stays in a register instead
// of being read back from memory at every pixel (a chain of store and load).
// The same additions in the same order.
struct OneChannelRun {
  const float* logits;
  float* sum = nullptr;
  float value = 0.f;
  void start(float* group_sum) {
    sum = group_sum;
    value = *sum;
  }
  void add(int u) { value += logits[u]; }
  void end() { *sum = value; }
};

// 8-bit codes of `width` channels per pixel, through the log-odds table.
struct CodedRun {
  const std::uint8_t* codes;
  const float* code_logit;
  int width;
  float* sums = nullptr;
  void start(float* group_sums) { sums = group_sums; }
  void add(int u) {
    const std::uint8_t* pixel = codes + static_cast<size_t>(u) * static_cast<size_t>(width);
    for (int c = 0; c < width; ++c) sums[c] += code_logit[pixel[c]];
  }
  void end() {}
};

// How far the rays of one part's groups are cast: `rays` is the number of its
// groups once its pixels are grouped (until then kNotReady), `next` the first
// group whose ray no thread has taken yet.
struct alignas(64) RayProgress {  // own cache lines: every thread takes chunks
  static constexpr size_t kNotReady = ~size_t{0};
  std::atomic<size_t> rays{kNotReady};
  std::atomic<size_t> next{0};
};

// Waits for another thread's part: a pause, and the processor to others
// when the wait drags on (the other thread may not be running).
inline void waitBriefly() {
  static thread_local unsigned spins = 0;
  if (++spins % 64 == 0)
    std::this_thread::yield();
  else
    _mm_pause();
}

// Per-frame working memory, kept between the frames fused by one thread:
// fresh tables and streams every frame would cost page faults and copies.
struct FastScratch {
  std::vector<PixelGroups> parts;
  std::vector<BrickSet> marks;
  std::vector<float> hit_values;
  std::vector<VoxelUpdate> hits, misses, updates, spare;

  // What the frame-to-frame memory would keep: the streams and the marks,
  // which grow with the voxels a frame crosses (the pixel groups are bounded
  // by the image).
  [[nodiscard]] size_t memoryBytes() const {
    size_t bytes = hit_values.capacity() * sizeof(float);
    for (const auto* stream : {&hits, &misses, &updates, &spare})
      bytes += stream->capacity() * sizeof(VoxelUpdate);
    for (const BrickSet& set : marks) bytes += set.memoryBytes();
    return bytes;
  }
};

// Beyond this, a frame's working memory is given back when the frame ends
// rather than kept for the next: a frame of a fine room-scale map crosses
// tens of millions of voxels, and the thread that fused it (the studio's
// worker lives for the whole session) would hold gigabytes long after the
// map is gone. Frames of a bin at 1 cm keep a few MiB.
constexpr size_t kScratchKeptBytes = size_t{256} << 20;

// Log-odds of each 8-bit code, the same for every frame.
struct CodeTables {
  std::array<float, 256> logit{};
  std::array<std::uint8_t, 1024> logit_bytes{};  // byte b of logit[c] at 256 b + c
};
const CodeTables& codeTables() {
  static const CodeTables tables = [] {
    CodeTables t;
    for (int c = 0; c < 256; ++c) {
      const float value = clampedLogit(probabilityOfCode(static_cast<std::uint8_t>(c)));
      t.logit[static_cast<size_t>(c)] = value;
      std::uint32_t bits = 0;
      std::memcpy(&bits, &value, sizeof bits);
      for (int b = 0; b < 4; ++b)
        t.logit_bytes[static_cast<size_t>(256 * b + c)] =
            static_cast<std::uint8_t>(bits >> (8 * b));
    }
    return t;
  }();
  return tables;
}

// Merges the hits and the misses (both sorted by Morton code, no code in
// both) into `updates`, in two halves at once when `threads` > 1: the halves
// split at the middle miss, so each merges about half of the stream.
void mergeUpdates(const std::vector<VoxelUpdate>& hits, const std::vector<VoxelUpdate>& misses,
                  std::vector<VoxelUpdate>& updates, int threads) {
  updates.resize(hits.size() + misses.size());
  auto byMorton = [](const VoxelUpdate& a, const VoxelUpdate& b) { return a.morton < b.morton; };
  // Below this, waking the other thread costs more than it saves.
  constexpr size_t kMinimumForTwo = 4096;
  if (threads < 2 || misses.size() < kMinimumForTwo) {
    std::merge(hits.begin(), hits.end(), misses.begin(), misses.end(), updates.begin(), byMorton);
    return;
  }
  const auto miss_cut = misses.begin() + static_cast<std::ptrdiff_t>(misses.size() / 2);
  const auto hit_cut = std::lower_bound(hits.begin(), hits.end(), *miss_cut, byMorton);
  const auto out_cut = updates.begin() + ((hit_cut - hits.begin()) + (miss_cut - misses.begin()));
  runParts(2, [&](int part) {
    if (part == 0)
      std::merge(hits.begin(), hit_cut, misses.begin(), miss_cut, updates.begin(), byMorton);
    else
      std::merge(hit_cut, hits.end(), miss_cut, misses.end(), out_cut, byMorton);
  });
}

bool hasDuplicateChannels(const ProbabilityImage& proba) {
  std::vector<int> labels = proba.channel_labels;
  std::sort(labels.begin(), labels.end());
  return std::adjacent_find(labels.begin(), labels.end()) != labels.end();
}

}  // namespace

FrameStats integrateFrameFast(LabelMap& map, const CameraIntrinsics& camera,
                              const Eigen::Isometry3d& T_world_camera, const DepthImage& depth,
                              const FrameEvidence& evidence, int threads, VectorKernels kernels,
                              double frame_memory_limit_bytes,
                              const std::function<bool()>& cancelled) {
  // Between phases only: nothing of the map has changed before the tree pass.
  const auto stopIfCancelled = [&cancelled] {
    if (cancelled && cancelled()) throw FrameCancelled();
  };
  stopIfCancelled();
  const bool vector_kernels = kernels != VectorKernels::Baseline;
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
  const bool coded = direct && !direct->codes.empty() &&
                     (direct->values.empty() || direct->codes.size() == direct->values.size());
  const CodeTables& code_tables = codeTables();
  const std::array<float, 256>& code_logit = code_tables.logit;
  const std::array<std::uint8_t, 1024>& code_logit_bytes = code_tables.logit_bytes;
  // Up to 16 channels of 8-bit codes: a pixel at a time in vector registers.
  void (*coded_kernel)(const CodedRow&) = nullptr;
  const std::uint8_t* codes_end = coded ? direct->codes.data() + direct->codes.size() : nullptr;
  if (coded && width <= 16 && vector_kernels)
    coded_kernel = cpuHasAvx512Bytes() && kernels == VectorKernels::Best ? sumCodedRowAvx512Bytes
                   : cpuHasAvx512() && (kernels == VectorKernels::Best || kernels == VectorKernels::UpToAvx512F)
                       ? sumCodedRowAvx512
                   : cpuHasAvx2() ? sumCodedRowAvx2
                                  : nullptr;
  std::array<std::uint8_t, 64> code_spread{};
  if (coded_kernel)
    for (int i = 0; i < 64; ++i) {
      const int pixel = (i % 16) / 4, channel = 4 * (i / 16) + i % 4;
      code_spread[static_cast<size_t>(i)] = static_cast<std::uint8_t>(pixel * width + std::min(channel, width - 1));
    }
  const PixelProjector projector(g, camera, T_world_camera, max_range);
  const size_t stride = coded_kernel ? kCodedStride : static_cast<size_t>(width);
  const bool count_in_kernel = coded_kernel && kernelCountsPixels(width);
  thread_local FastScratch scratch;
  struct ReleaseLarge {
    FastScratch& scratch;
    ~ReleaseLarge() {
      if (scratch.memoryBytes() > kScratchKeptBytes) scratch = FastScratch();
    }
  } release_large{scratch};
  std::vector<PixelGroups>& parts = scratch.parts;
  parts.resize(static_cast<size_t>(threads));
  std::vector<BrickSet>& marks = scratch.marks;
  marks.resize(static_cast<size_t>(threads));
  auto groupPixels = [&](int t) {
    PixelGroups& part = parts[static_cast<size_t>(t)];
    const size_t row_values = static_cast<size_t>(depth.width) * static_cast<size_t>(width);
    std::vector<float> row_probabilities(direct ? 0 : row_values, 0.f);
    std::vector<float> row_logits(coded ? 0 : row_values, 0.f);
    std::vector<std::uint64_t> row(static_cast<size_t>(depth.width));
    std::vector<std::uint32_t> group_of(coded_kernel ? static_cast<size_t>(depth.width) : 0);
    const int rows_begin = depth.height * t / threads;
    const int rows_end = depth.height * (t + 1) / threads;
    size_t valid_pixels = 0;  // counted here: part's fields are written per pixel
    for (int v = rows_begin; v < rows_end; ++v) {
      projector.projectRow(v, depth.metres.data() + static_cast<size_t>(v) * depth.width,
                           depth.width, row.data(), kernels);
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
        logitRow(probabilities, row_values, row_logits.data(), vector_kernels);
      }
      if (coded_kernel) {
        valid_pixels += count_in_kernel ? groupRow<false>(part, row.data(), depth.width, group_of.data())
                                         : groupRow<true>(part, row.data(), depth.width, group_of.data());
        coded_kernel({group_of.data(), depth.width, codes, codes_end, width, code_logit.data(), code_logit_bytes.data(),
                      code_spread.data(), part.sums.data()});
        continue;
      }
      if (coded)
        valid_pixels +=
            sumRow(part, row.data(), depth.width, CodedRun{codes, code_logit.data(), width});
      else if (width == 1)
        valid_pixels += sumRow(part, row.data(), depth.width, OneChannelRun{row_logits.data()});
      else
        valid_pixels += sumRow(part, row.data(), depth.width, FloatRun{row_logits.data(), width});
    }
    part.valid_pixels = valid_pixels;
    if (count_in_kernel)  // the pixels of groups beyond max range are not needed
      for (size_t i = 0; i < part.groups.size(); ++i)
        part.groups[i].pixels = static_cast<std::uint32_t>(part.sumsOf(i)[kCodedStride - 1]);
  };
  // The other parts' groups merged into the first's.
  PixelGroups& all = parts[0];
  auto mergeGroups = [&] {
    for (size_t p = 1; p < parts.size(); ++p) {
      PixelGroups& part = parts[p];
      all.valid_pixels += part.valid_pixels;
      for (size_t i = 0; i < part.groups.size(); ++i) {
        const auto& group = part.groups[i];
        const std::uint32_t target = all.groupFor(group.voxel);
        all.groups[target].pixels += group.pixels;
        addInto(all.sumsOf(target), part.sumsOf(i), width);
      }
    }
  };
  // 1 and 2 in one parallel phase: each thread groups its rows' pixels, then
  // casts one ray per end voxel, its own part's first, handed out in chunks,
  // then those of the other parts as each is ready; so a thread that finishes
  // its rows early does not wait. The first thread merges the other parts'
  // groups into its own as soon as all are ready, while rays are still cast:
  // a voxel that two parts saw (pixels on both sides of their rows' border)
  // casts its ray twice, which marks the same voxels again.
  std::vector<RayProgress> progress(static_cast<size_t>(threads));
  // Rays are handed out in chunks; where the processor has AVX-512 a chunk's
  // rays are set up and marked eight at a time (the lanes run dry at a
  // chunk's end, so chunks are not small).
  constexpr size_t kRayChunk = 128;
  const bool eight_walks_at_once =
      vector_kernels && kernels != VectorKernels::UpToAvx2 && cpuHasAvx512();
  auto allReady = [&] {
    for (const RayProgress& p : progress)
      if (p.rays.load(std::memory_order_acquire) == RayProgress::kNotReady) return false;
    return true;
  };
  runParts(threads, [&](int t) {
    PixelGroups& part = parts[static_cast<size_t>(t)];
    part.clear(stride);
    // The merge appends to the first part's groups while other threads cast
    // their rays: room for every pixel's group, so they are never moved.
    if (t == 0 && threads > 1)
      part.groups.reserve(static_cast<size_t>(depth.width) * static_cast<size_t>(depth.height));
    BrickSet& mark = marks[static_cast<size_t>(t)];
    mark.clear();
    RayProgress& own = progress[static_cast<size_t>(t)];
    std::array<grid::RayWalk, kRayChunk> walks;
    std::array<std::uint64_t, kRayChunk> voxels;
    try {
      groupPixels(t);
    } catch (...) {  // the frame is abandoned; the other threads must not wait for this part
      own.rays.store(0, std::memory_order_release);
      throw;
    }
    own.rays.store(part.groups.size(), std::memory_order_release);
    bool merged = t != 0 || threads == 1;
    for (int k = 0; k < threads; ++k) {
      const size_t p = static_cast<size_t>((t + k) % threads);
      RayProgress& from = progress[p];
      const std::vector<PixelGroups::Group>& groups = parts[p].groups;
      size_t count;
      while ((count = from.rays.load(std::memory_order_acquire)) == RayProgress::kNotReady)
        waitBriefly();
      for (size_t first = from.next.fetch_add(kRayChunk); first < count;
           first = from.next.fetch_add(kRayChunk)) {
        const size_t last = std::min(first + kRayChunk, count);
        size_t set_up = 0;
        if (eight_walks_at_once) {
          for (size_t i = first; i < last; ++i) voxels[i - first] = groups[i].voxel;
          set_up = setUpRaysAvx512(g, origin, max_range, voxels.data(), last - first, walks.data());
        } else {
          for (size_t i = first; i < last; ++i) {
            const PixelRay ray = unpackVoxel(groups[i].voxel);
            const Eigen::Vector3d end = rayEnd(g, origin, ray.end_key, ray.beyond_range, max_range);
            set_up += grid::setUpRay(g, origin, end, walks[set_up]);
          }
        }
        mark.markWalks(walks.data(), set_up, eight_walks_at_once);
        if (!merged && allReady()) {
          mergeGroups();
          merged = true;
        }
      }
    }
    if (!merged) mergeGroups();  // every part was ready before its rays were taken
  });

  // A frame whose rays crossed more voxels than the memory can take is
  // refused here, before it changes the map (the streams and the new nodes
  // below grow with the crossed voxels; the marks are bits).
  stopIfCancelled();
  size_t bricks = 0;
  for (const BrickSet& mark : marks) bricks += mark.brickCount();
  if (frameMemoryNeedsCheck(bricks * BrickSet::kWords * 64, frame_memory_limit_bytes)) {
    // Each voxel once, however many threads marked it (a sum of the threads'
    // counts depended on how the rays were shared out).
    size_t crossed = 0;
    for (size_t t = 0; t < marks.size(); ++t) crossed += marks[t].markedCountNotIn(marks.data(), t);
    // Only when that does not fit: the voxels a miss adds nodes for, one walk
    // from the root each (later frames of a scene cross mostly known voxels
    // and saturated free space; a merged leaf that is not saturated splits).
    const auto count_new = [&] {
      size_t fresh = 0;
      for (size_t t = 0; t < marks.size(); ++t)
        marks[t].forEachMarkedNotIn(marks.data(), t, [&](const octomap::OcTreeKey& key) {
          if (!tree.missAddsNoNode(key)) ++fresh;  // missing, or in a leaf to split
        });
      return fresh;
    };
    // The streams' buffers of earlier frames are reused: only growth beyond them costs.
    const double reusable =
        static_cast<double>(scratch.misses.capacity() + scratch.spare.capacity()) *
        static_cast<double>(sizeof(VoxelUpdate));
    checkFrameMemory(crossed, frame_memory_limit_bytes, map.parameters().resolution, count_new,
                     reusable);
    stopIfCancelled();
  }

  // 3. Hits: full per-label log-odds; they are never also misses in this
  // frame. The hit stream and the miss stream are built at once.
  const float unlisted = clampedLogit(0.f);
  std::vector<float>& hit_values = scratch.hit_values;
  std::vector<VoxelUpdate>& hits = scratch.hits;
  std::vector<VoxelUpdate>& misses = scratch.misses;
  std::vector<VoxelUpdate>& spare = scratch.spare;
  hits.clear();
  misses.clear();
  size_t miss_count = 0;
  // With a probability image used as is, a hit lists its channels' labels
  // (ascending) and then the log-odds every other label gets; else all labels.
  HitLabels listed;
  std::array<int, 256> channel_of_listed{};
  if (direct) {
    listed.count = width;
    for (int c = 0; c < width; ++c) channel_of_listed[static_cast<size_t>(c)] = c;
    std::sort(channel_of_listed.begin(), channel_of_listed.begin() + width, [&](int a, int b) {
      return direct->channel_labels[static_cast<size_t>(a)] < direct->channel_labels[static_cast<size_t>(b)];
    });
    for (int i = 0; i < width; ++i) {
      const int channel = channel_of_listed[static_cast<size_t>(i)];
      listed.ids[i] = static_cast<std::uint8_t>(direct->channel_labels[static_cast<size_t>(channel)]);
    }
  }
  const size_t hit_stride = direct ? static_cast<size_t>(width) + 1 : static_cast<size_t>(n);
  // Hits can point at the groups' sums when the channels are already in label
  // order and each group's row has a spare lane for the rest's value.
  const bool in_place = direct && all.stride > static_cast<size_t>(width) &&
                        std::is_sorted(channel_of_listed.begin(), channel_of_listed.begin() + width);
  auto buildHits = [&] {
    // At most one hit per group (groups beyond max range have none).
    hit_values.resize(in_place ? 0 : all.groups.size() * hit_stride);
    hits.reserve(all.groups.size());
    for (size_t i = 0; i < all.groups.size(); ++i) {
      const auto& group = all.groups[i];
      if (group.voxel & 1u) continue;
      const grid::Key key = unpackVoxel(group.voxel).end_key;
      float* sums = all.sumsOf(i);
      float* values = in_place ? sums : hit_values.data() + hits.size() * hit_stride;
      if (direct) {  // in place, the sums already list the labels in order; a spare lane takes the rest
        if (!in_place)
          for (int c = 0; c < width; ++c) values[c] = sums[channel_of_listed[static_cast<size_t>(c)]];
        values[width] = unlisted * static_cast<float>(group.pixels);
      } else {
        std::copy(sums, sums + n, values);
      }
      VoxelUpdate update;
      update.key = octomap::OcTreeKey(key[0], key[1], key[2]);
      update.morton = grid::mortonCode(key[0], key[1], key[2]);
      update.hit = values;
      hits.push_back(update);
    }
    sortByMorton(hits, spare);
  };
  auto buildMisses = [&] {
    for (size_t t = 1; t < marks.size(); ++t) marks[0].mergeFrom(marks[t]);
    for (const auto& group : all.groups)
      if (!(group.voxel & 1u)) marks[0].clear(unpackVoxel(group.voxel).end_key);  // a hit
    miss_count = marks[0].appendMisses(misses, &tree);
  };
  if (threads > 1) {
    runParts(2, [&](int part) {
      if (part == 0)
        buildHits();
      else
        buildMisses();
    });
  } else {
    buildHits();
    buildMisses();
  }
  stopIfCancelled();
  std::vector<VoxelUpdate>& updates = scratch.updates;
  mergeUpdates(hits, misses, updates, threads);
  stopIfCancelled();
  tree.applySortedUpdates(updates, threads, direct ? &listed : nullptr);

  FrameStats stats;
  stats.valid_pixels = all.valid_pixels;
  stats.hit_voxels = hits.size();
  stats.miss_voxels = miss_count;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace lom
