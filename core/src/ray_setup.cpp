// setUpRaysAvx512 (fusion_internal.hpp): the walks of the fast path's rays,
// eight at a time. Each lane makes the operations rayEnd and grid::setUpRay
// make for one ray, in the same order, and vector division, square root and
// rounding are correctly rounded as their scalar forms are, so the walks are
// the same to the last bit (FastRaySetUpTest). Built with -ffp-contract=off
// (core/CMakeLists.txt): a fused multiply-add would round differently.
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "fusion_internal.hpp"

namespace lom {

// The lambdas return vectors but are inlined, so the ABI note does not
// apply; g++ 12 reads the "undefined" pass-through register of some AVX-512
// intrinsics as maybe uninitialised.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC push_options
#pragma GCC target("avx512f")
size_t setUpRaysAvx512(const grid::Grid& g, const Eigen::Vector3d& origin, double max_range,
                       const std::uint64_t* voxels, size_t count, grid::RayWalk* walks) {
  grid::Key origin_key;
  if (!g.keyOf(origin, origin_key)) return 0;  // setUpRay fails for every ray
  const __m512d resolution = _mm512_set1_pd(g.resolution), inverse = _mm512_set1_pd(g.inverse);
  const __m512d half = _mm512_set1_pd(0.5), zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
  const __m512d range = _mm512_set1_pd(max_range), limit = _mm512_set1_pd(grid::kKeyOffset);
  const __m512d o[3] = {_mm512_set1_pd(origin[0]), _mm512_set1_pd(origin[1]),
                        _mm512_set1_pd(origin[2])};
  const __m512i sign = _mm512_set1_epi64(std::numeric_limits<std::int64_t>::min());
  auto squaredNorm = [](const __m512d* d) {  // Eigen's order for a 3-vector: (x x + y y) + z z
    return _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(d[0], d[0]), _mm512_mul_pd(d[1], d[1])),
                         _mm512_mul_pd(d[2], d[2]));
  };
  size_t set_up = 0;
  for (size_t first = 0; first < count; first += 8) {
    const int lanes = static_cast<int>(std::min<size_t>(8, count - first));
    alignas(32) std::int32_t key[3][8] = {};
    std::uint32_t beyond_bits = 0;
    for (int l = 0; l < lanes; ++l) {
      const PixelRay ray = unpackVoxel(voxels[first + static_cast<size_t>(l)]);
      for (int a = 0; a < 3; ++a) key[a][l] = ray.end_key[static_cast<size_t>(a)];
      beyond_bits |= (ray.beyond_range ? 1u : 0u) << l;
    }
    const auto beyond = static_cast<__mmask8>(beyond_bits);
    // rayEnd: the end voxel's centre, or the point at max range towards it.
    __m512d target[3], towards[3], end[3];
    for (int a = 0; a < 3; ++a) {
      const __m256i offset_key =
          _mm256_sub_epi32(_mm256_load_si256(reinterpret_cast<const __m256i*>(key[a])),
                           _mm256_set1_epi32(grid::kKeyOffset));
      const __m512d k = _mm512_cvtepi32_pd(offset_key);
      target[a] = _mm512_mul_pd(_mm512_add_pd(k, half), resolution);
      towards[a] = _mm512_sub_pd(target[a], o[a]);
    }
    const __m512d towards_squared = squaredNorm(towards);
    const __m512d towards_norm = _mm512_sqrt_pd(towards_squared);
    const __mmask8 nonzero = _mm512_cmp_pd_mask(towards_squared, zero, _CMP_GT_OQ);
    for (int a = 0; a < 3; ++a) {
      const __m512d unit = _mm512_mask_div_pd(towards[a], nonzero, towards[a], towards_norm);
      end[a] =
          _mm512_mask_blend_pd(beyond, target[a], _mm512_add_pd(o[a], _mm512_mul_pd(unit, range)));
    }
    // setUpRay: the end's key, then the walk.
    __mmask8 inside = static_cast<__mmask8>((1u << lanes) - 1);
    __m256i end_key[3];
    for (int a = 0; a < 3; ++a) {
      const __m512d scaled = _mm512_mul_pd(inverse, end[a]);
      inside &= _mm512_cmp_pd_mask(scaled, _mm512_sub_pd(zero, limit), _CMP_GE_OQ) &
                _mm512_cmp_pd_mask(scaled, limit, _CMP_LT_OQ);
      const __m512d floored =
          _mm512_roundscale_pd(scaled, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
      end_key[a] =
          _mm256_add_epi32(_mm512_cvttpd_epi32(floored), _mm256_set1_epi32(grid::kKeyOffset));
    }
    __m512d delta[3];
    for (int a = 0; a < 3; ++a) delta[a] = _mm512_sub_pd(end[a], o[a]);
    const __m512d length = _mm512_sqrt_pd(squaredNorm(delta));
    alignas(64) double t_max[3][8], t_delta[3][8], lengths[8], steps_bound[8];
    alignas(32) std::int32_t end_keys[3][8];
    __mmask8 up[3], down[3];
    for (int a = 0; a < 3; ++a) {
      const __m512d direction = _mm512_div_pd(delta[a], length);
      up[a] = _mm512_cmp_pd_mask(direction, zero, _CMP_GT_OQ);
      down[a] = _mm512_cmp_pd_mask(direction, zero, _CMP_LT_OQ);
      const __m512d border =
          _mm512_mul_pd(_mm512_add_pd(_mm512_set1_pd(static_cast<double>(
                                          origin_key[static_cast<size_t>(a)] - grid::kKeyOffset)),
                                      _mm512_maskz_mov_pd(up[a], one)),
                        resolution);
      const __m512d magnitude =
          _mm512_castsi512_pd(_mm512_andnot_si512(sign, _mm512_castpd_si512(direction)));
      const __m512d none = _mm512_set1_pd(std::numeric_limits<double>::max());
      const auto moving = static_cast<__mmask8>(up[a] | down[a]);
      _mm512_store_pd(t_max[a],
                      _mm512_mask_div_pd(none, moving, _mm512_sub_pd(border, o[a]), direction));
      _mm512_store_pd(t_delta[a], _mm512_mask_div_pd(none, moving, resolution, magnitude));
      _mm256_store_si256(reinterpret_cast<__m256i*>(end_keys[a]), end_key[a]);
    }
    _mm512_store_pd(lengths, length);
    _mm512_store_pd(steps_bound, _mm512_roundscale_pd(_mm512_mul_pd(length, inverse),
                                                      _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC));
    for (int l = 0; l < lanes; ++l) {
      if (!((inside >> l) & 1u)) continue;  // the end lies outside the key range
      grid::RayWalk& w = walks[set_up++];
      bool same_voxel = true;
      for (int a = 0; a < 3; ++a) {
        w.key[a] = origin_key[static_cast<size_t>(a)];
        w.end_key[a] = end_keys[a][l];
        same_voxel &= w.key[a] == w.end_key[a];
      }
      if (same_voxel) continue;  // setUpRay stops here: nothing to visit
      for (int a = 0; a < 3; ++a) {
        w.step[a] = (up[a] >> l) & 1u ? 1 : (down[a] >> l) & 1u ? -1 : 0;
        w.t_max[a] = t_max[a][l];
        w.t_delta[a] = t_delta[a][l];
      }
      w.length = lengths[l];
      w.max_steps = 3L * static_cast<long>(steps_bound[l]) + 3;
    }
  }
  return set_up;
}
#pragma GCC pop_options
#pragma GCC diagnostic pop

}  // namespace lom
