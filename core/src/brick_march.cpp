// BrickSet::markWalksAvx512: eight walks at once, one per lane of AVX-512
// registers. Each lane takes its walk's steps as stepWalk takes them (the
// same comparisons of the same doubles, the same tie rule, the same stops),
// so the marks are the same as markWalk's; a lane whose walk ends takes the
// next walk. A step at a time per lane, but without the branch on the axis
// that a single walk mispredicts (two steps in five are off the main axis,
// at no regular interval) and eight steps per instruction.
#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "brick_set.hpp"

namespace lom {

namespace {

// A walk's key in one 64-bit lane: three 21-bit fields, one per axis. Each
// holds the key component, negated on axes walked downwards (so that every
// step adds one), plus a bias that keeps it positive however far a walk goes;
// a step is then one addition of a constant and the end test one comparison.
constexpr int kFieldBits = 21;
constexpr std::int64_t kFieldBias = std::int64_t{1} << 19;
constexpr std::int64_t kFieldMask = (std::int64_t{1} << kFieldBits) - 1;

std::int64_t packLaneKey(const int* key, const int* step) {
  std::int64_t packed = 0;
  for (int a = 0; a < 3; ++a)
    packed |= ((step[a] < 0 ? -key[a] : key[a]) + kFieldBias) << (kFieldBits * a);
  return packed;
}

// The bricks a call's walks can reach: a box of them, numbered x fastest.
// Lanes carry their brick's number, which a step into the next brick moves
// by a constant; the marks' pass looks the number up in `index` (the brick's
// index in the set, or kNone until it is first needed).
struct BrickBox {
  static constexpr std::int32_t kNone = -1;
  int low[3] = {}, size[3] = {};
  std::vector<std::int32_t> index;

  // The bricks of every key within one voxel of the walks' start and end
  // voxels (a walk's key passes its end key by at most one voxel on an axis,
  // when a border at the end point's distance rounds below it). False when
  // the box holds more than `limit` bricks.
  bool cover(const grid::RayWalk* walks, size_t count, size_t limit) {
    int lo[3] = {1 << 30, 1 << 30, 1 << 30}, hi[3] = {-(1 << 30), -(1 << 30), -(1 << 30)};
    for (size_t i = 0; i < count; ++i)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], std::min(walks[i].key[a], walks[i].end_key[a]) - 1);
        hi[a] = std::max(hi[a], std::max(walks[i].key[a], walks[i].end_key[a]) + 1);
      }
    size_t bricks = 1;
    for (int a = 0; a < 3; ++a) {
      low[a] = lo[a] >> 4;  // floor, also below zero
      size[a] = (hi[a] >> 4) - low[a] + 1;
      bricks *= static_cast<size_t>(size[a]);
    }
    if (bricks > limit) return false;
    index.assign(bricks, kNone);
    return true;
  }
  [[nodiscard]] std::int64_t numberOf(int x, int y, int z) const {
    return ((x >> 4) - low[0]) +
           static_cast<std::int64_t>(size[0]) *
               (((y >> 4) - low[1]) + static_cast<std::int64_t>(size[1]) * ((z >> 4) - low[2]));
  }
  [[nodiscard]] std::int64_t stride(int axis) const {
    return axis == 0 ? 1 : axis == 1 ? size[0] : static_cast<std::int64_t>(size[0]) * size[1];
  }
  // The brick's packed coordinates (BrickSet::packBrick's layout) from its number.
  [[nodiscard]] std::uint64_t packedOf(std::int64_t number) const {
    const auto bx = static_cast<std::uint64_t>(low[0] + number % size[0]);
    number /= size[0];
    const auto by = static_cast<std::uint64_t>(low[1] + number % size[1]);
    const auto bz = static_cast<std::uint64_t>(low[2] + number / size[1]);
    return (bx << 24) | (by << 12) | bz;
  }
};

// The walks of one call, a field per array (what a lane loads when it takes
// a walk), padded so that eight values can be loaded from any walk on.
struct LaneWalks {
  std::vector<double> t_max[3], t_delta[3], length;
  // `local` is the start voxel's Morton index in its brick with the bits of
  // downward axes flipped (every step adds one there too); `flip` holds those
  // bits; `brick` the brick's number in the BrickBox.
  std::vector<std::int64_t> key, end_key, local, flip, brick;
  size_t count = 0;

  void reserve(size_t walks) {
    count = 0;
    const size_t padded = walks + 8;
    if (length.size() >= padded) return;
    for (int a = 0; a < 3; ++a) {
      t_max[a].resize(padded);
      t_delta[a].resize(padded);
    }
    for (auto* field : {&key, &end_key, &local, &flip, &brick}) field->resize(padded);
    length.resize(padded);
  }
};

// Marks waiting to be ORed into the bricks: word index, bits.
struct PendingMarks {
  std::vector<std::uint64_t> word = std::vector<std::uint64_t>(4096);
  std::vector<std::uint64_t> bits = std::vector<std::uint64_t>(4096);
};

}  // namespace

// g++ 12 reads the "undefined" pass-through register of some AVX-512
// intrinsics (shifts) as maybe uninitialised.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC push_options
#pragma GCC target("avx512f,popcnt")
void BrickSet::markWalksAvx512(const grid::RayWalk* walks, size_t count) {
  // Per-thread scratch, reached once per call (from a static library built
  // as position-independent code, every use of a thread_local would look up
  // its address anew).
  static thread_local LaneWalks thread_lanes;
  static thread_local BrickBox thread_box;
  static thread_local PendingMarks thread_marks;
  LaneWalks& lanes = thread_lanes;
  BrickBox& box = thread_box;
  // Far-reaching walks (a box of more than 32,768 bricks: a look-up table of
  // more than 128 KiB to fill per call) go one at a time.
  if (!box.cover(walks, count, std::size_t{1} << 15)) {
    for (size_t i = 0; i < count; ++i) markWalk(walks[i]);
    return;
  }
  auto indexOf = [&](std::int64_t number) -> std::uint32_t {
    std::int32_t& index = box.index[static_cast<size_t>(number)];
    if (index == BrickBox::kNone)
      index = static_cast<std::int32_t>(brickIndex(box.packedOf(number)));
    return static_cast<std::uint32_t>(index);
  };
  lanes.reserve(count);
  // Per walk: its first voxel marked here, its state written out for a lane.
  for (size_t i = 0; i < count; ++i) {
    const grid::RayWalk& w = walks[i];
    const int k0 = w.key[0], k1 = w.key[1], k2 = w.key[2];
    if (k0 == w.end_key[0] && k1 == w.end_key[1] && k2 == w.end_key[2]) continue;  // visits nothing
    // A walk takes at most one step per border before the end point, and
    // one more per axis where rounding puts a border at that distance below
    // it: when that could exceed its step budget, it goes one step at a time
    // (the lanes do not count steps).
    const int borders =
        std::abs(w.end_key[0] - k0) + std::abs(w.end_key[1] - k1) + std::abs(w.end_key[2] - k2);
    if (borders + 3 > w.max_steps) {
      markWalk(w);
      continue;
    }
    const auto x = static_cast<unsigned>(k0), y = static_cast<unsigned>(k1),
               z = static_cast<unsigned>(k2);
    const unsigned local = localIndex(x, y, z);
    const std::int64_t brick = box.numberOf(k0, k1, k2);
    bits(indexOf(brick))[local >> 6] |= std::uint64_t{1} << (local & 63);
    const size_t j = lanes.count++;
    unsigned flip = 0;
    for (int a = 0; a < 3; ++a) {
      lanes.t_max[a][j] = w.t_max[a];
      lanes.t_delta[a][j] = w.t_delta[a];
      if (w.step[a] < 0) flip |= axisBits(a);
    }
    lanes.length[j] = w.length;
    lanes.key[j] = packLaneKey(w.key, w.step);
    lanes.end_key[j] = packLaneKey(w.end_key, w.step);
    lanes.local[j] = local ^ flip;
    lanes.flip[j] = flip;
    lanes.brick[j] = brick;
  }
  const size_t total = lanes.count;
  if (total == 0) return;

  __m512d m0 = _mm512_setzero_pd(), m1 = m0, m2 = m0, td0 = m0, td1 = m0, td2 = m0, length = m0;
  __m512i key = _mm512_setzero_si512(), end_key = key, local = key, flip = key, brick = key;
  size_t next = 0;
  // Gives the walks from `next` on to the lanes of `free_lanes`, in lane
  // order; returns the lanes that took one.
  auto take = [&](__mmask8 free_lanes) __attribute__((always_inline))->__mmask8 {
    const size_t left = total - next;
    unsigned lanes_taking = free_lanes;
    if (static_cast<size_t>(__builtin_popcount(lanes_taking)) > left) {
      unsigned kept = 0;
      for (size_t c = 0; c < left; ++c) {
        kept |= lanes_taking & (0u - lanes_taking);
        lanes_taking &= lanes_taking - 1;
      }
      lanes_taking = kept;
    }
    const auto m = static_cast<__mmask8>(lanes_taking);
    if (!m) return 0;
    // Loaded into a register first: expanding straight from memory is slow
    // on some processors (AMD Zen 4), and g++ would fold the load into it.
    auto pd = [&](__m512d v, const std::vector<double>& f) __attribute__((always_inline)) {
      __m512d loaded = _mm512_loadu_pd(f.data() + next);
      asm("" : "+v"(loaded));
      return _mm512_mask_expand_pd(v, m, loaded);
    };
    auto epi = [&](__m512i v, const std::vector<std::int64_t>& f) __attribute__((always_inline)) {
      __m512i loaded = _mm512_loadu_si512(f.data() + next);
      asm("" : "+v"(loaded));
      return _mm512_mask_expand_epi64(v, m, loaded);
    };
    m0 = pd(m0, lanes.t_max[0]);
    m1 = pd(m1, lanes.t_max[1]);
    m2 = pd(m2, lanes.t_max[2]);
    td0 = pd(td0, lanes.t_delta[0]);
    td1 = pd(td1, lanes.t_delta[1]);
    td2 = pd(td2, lanes.t_delta[2]);
    length = pd(length, lanes.length);
    key = epi(key, lanes.key);
    end_key = epi(end_key, lanes.end_key);
    local = epi(local, lanes.local);
    flip = epi(flip, lanes.flip);
    brick = epi(brick, lanes.brick);
    next += static_cast<size_t>(__builtin_popcount(lanes_taking));
    return m;
  };

  const __m512i mask0 = _mm512_set1_epi64(axisBits(0)), mask1 = _mm512_set1_epi64(axisBits(1)),
                mask2 = _mm512_set1_epi64(axisBits(2));
  const __m512i key_step0 = _mm512_set1_epi64(1),
                key_step1 = _mm512_set1_epi64(std::int64_t{1} << kFieldBits),
                key_step2 = _mm512_set1_epi64(std::int64_t{1} << (2 * kFieldBits));
  const __m512i stride0 = _mm512_set1_epi64(box.stride(0)),
                stride1 = _mm512_set1_epi64(box.stride(1)),
                stride2 = _mm512_set1_epi64(box.stride(2));
  const __m512i one = key_step0, low6 = _mm512_set1_epi64(63), zero = _mm512_setzero_si512();
  std::uint64_t* const pending_words = thread_marks.word.data();
  std::uint64_t* const pending_masks = thread_marks.bits.data();
  const size_t pending_limit = thread_marks.word.size() - 16;
  size_t pending = 0;
  // A pending mark's word: its brick's number, then the word in the brick.
  auto applyMarks = [&] {
    for (size_t i = 0; i < pending; ++i) {
      const std::uint64_t brick_word = pending_words[i];
      bits(indexOf(static_cast<std::int64_t>(brick_word >> 6)))[brick_word & 63] |=
          pending_masks[i];
    }
    pending = 0;
  };
  // Pending bits start empty: their first flush ORs nothing into a word it names.
  __m512i pending_word = _mm512_set1_epi64(static_cast<std::int64_t>(lanes.brick[0] << 6)),
          pending_bits = zero;
  __mmask8 active = take(0xff);
  while (active) {
    // nextAxis: x unless y is strictly closer, then z if strictly closer.
    const __mmask8 y_first = _mm512_cmp_pd_mask(m1, m0, _CMP_LT_OQ);
    const __m512d closer = _mm512_mask_blend_pd(y_first, m0, m1);
    const __mmask8 z_first = _mm512_cmp_pd_mask(m2, closer, _CMP_LT_OQ);
    const __m512d border = _mm512_mask_blend_pd(z_first, closer, m2);
    // stepWalk's stop at a border past the end point. Every lane steps,
    // stopping or not, idle or not (a stopped lane's state is not used
    // again), so that the stop is off the chain from one step to the next.
    const __mmask8 past_end = _mm512_mask_cmp_pd_mask(active, border, length, _CMP_GT_OQ);
    const auto go2 = z_first;
    const auto go1 = static_cast<__mmask8>(y_first & ~z_first);
    const auto go0 = static_cast<__mmask8>(~y_first & ~z_first);
    m0 = _mm512_mask_add_pd(m0, go0, m0, td0);
    m1 = _mm512_mask_add_pd(m1, go1, m1, td1);
    m2 = _mm512_mask_add_pd(m2, go2, m2, td2);
    const __m512i key_step =
        _mm512_mask_blend_epi64(go2, _mm512_mask_blend_epi64(go1, key_step0, key_step1), key_step2);
    key = _mm512_add_epi64(key, key_step);
    // The stepped axis's bits of the local index, plus one (a dilated +1:
    // subtract the axis's bits, keep the axis's bits); zero when the step
    // leaves the brick, which then moves the lane's brick on that axis.
    const __m512i axis_mask =
        _mm512_mask_blend_epi64(go2, _mm512_mask_blend_epi64(go1, mask0, mask1), mask2);
    const __m512i axis_bits = _mm512_and_si512(
        _mm512_sub_epi64(_mm512_and_si512(local, axis_mask), axis_mask), axis_mask);
    local = _mm512_ternarylogic_epi64(local, axis_mask, axis_bits, 0xBA);  // (local & ~mask) | bits
    const __mmask8 crossed = _mm512_cmpeq_epi64_mask(axis_bits, zero);
    const __mmask8 down = _mm512_test_epi64_mask(flip, axis_mask);
    const __m512i stride =
        _mm512_mask_blend_epi64(go2, _mm512_mask_blend_epi64(go1, stride0, stride1), stride2);
    brick = _mm512_mask_add_epi64(brick, crossed, brick,
                                  _mm512_mask_sub_epi64(stride, down, zero, stride));
    // The end voxel is not marked. (`done` may also name idle lanes: they
    // can take walks too.)
    const __mmask8 reached = _mm512_cmpeq_epi64_mask(key, end_key);
    const auto done = static_cast<__mmask8>(past_end | reached);
    const auto mark = static_cast<__mmask8>(active & ~done);
    // A lane's marks in one word gather in `pending_bits`; a mark in another
    // word appends the pending ones to `marks`, without branches.
    const __m512i unflipped = _mm512_xor_si512(local, flip);
    const __m512i lane_word =
        _mm512_or_si512(_mm512_slli_epi64(brick, 6), _mm512_srli_epi64(unflipped, 6));
    const __m512i lane_bit = _mm512_sllv_epi64(one, _mm512_and_si512(unflipped, low6));
    const __mmask8 flush = _mm512_mask_cmpneq_epi64_mask(mark, lane_word, pending_word);
    _mm512_storeu_si512(pending_words + pending, _mm512_maskz_compress_epi64(flush, pending_word));
    _mm512_storeu_si512(pending_masks + pending, _mm512_maskz_compress_epi64(flush, pending_bits));
    pending += static_cast<size_t>(__builtin_popcount(flush));
    pending_word = _mm512_mask_mov_epi64(pending_word, flush, lane_word);
    pending_bits = _mm512_mask_mov_epi64(pending_bits, flush, zero);
    pending_bits = _mm512_mask_or_epi64(pending_bits, mark, pending_bits, lane_bit);
    if (pending > pending_limit) applyMarks();
    active = static_cast<__mmask8>(active & ~done);
    if (done && next < total) active = static_cast<__mmask8>(active | take(done));
  }
  _mm512_storeu_si512(pending_words + pending, pending_word);
  _mm512_storeu_si512(pending_masks + pending, pending_bits);
  pending += 8;
  applyMarks();
}
#pragma GCC pop_options
#pragma GCC diagnostic pop

}  // namespace lom
