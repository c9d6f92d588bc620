// Back-projection of a depth row into packed end voxels (fusion_internal.hpp).
// Compiled with -fno-trapping-math (core/CMakeLists.txt): without it g++ keeps
// the per-pixel selects as branches and does not vectorise the row.
#include <cstdint>
#include <limits>

#include "fusion_internal.hpp"

namespace lom {

namespace {

struct RowTerms {
  double origin[3], first_column[3], row_term[3], third_column[3];
  double inverse, cx, inverse_fx, yy_plus_one, max_range_squared;
};

// Branch-free so that it compiles to vector code. With kFloorInstruction
// (SSE4.1 and later) floor is one instruction; otherwise it is truncation
// stepped down for negatives. Both are the exact floor, and no fused
// multiply-add is enabled (it would round differently), so every build and
// every machine gives the same keys.
template <bool kFloorInstruction>
[[gnu::always_inline]] inline void projectRowKernel(const RowTerms& r, const float* __restrict depth_row,
                                                    int width, std::uint64_t* __restrict out) {
  const double limit = grid::kKeyOffset;
  const double o0 = r.origin[0], o1 = r.origin[1], o2 = r.origin[2];
  const double a0 = r.first_column[0], a1 = r.first_column[1], a2 = r.first_column[2];
  const double b0 = r.row_term[0], b1 = r.row_term[1], b2 = r.row_term[2];
  const double c0 = r.third_column[0], c1 = r.third_column[1], c2 = r.third_column[2];
  const double inverse = r.inverse, cx = r.cx, inverse_fx = r.inverse_fx;
  const double yy_plus_one = r.yy_plus_one, max_range_squared = r.max_range_squared;
  const bool use_range = max_range_squared > 0.0;
  const auto floorToInt = [](double value) -> std::int32_t {
    if constexpr (kFloorInstruction) {
      return static_cast<std::int32_t>(__builtin_floor(value));
    } else {
      const auto truncated = static_cast<std::int32_t>(value);
      return truncated - (value < truncated ? 1 : 0);
    }
  };
  for (int u = 0; u < width; ++u) {
    const float d = depth_row[u];
    const bool measured = (d > 0.f) & (d <= std::numeric_limits<float>::max());  // not NaN or inf
    const double z = measured ? static_cast<double>(d) : 0.0;
    const double x = (u - cx) * inverse_fx;
    // p_world = origin + z * (R.col(0) x + R.col(1) y + R.col(2)), scaled to voxels.
    const double s0 = inverse * (o0 + z * ((a0 * x + b0) + c0));
    const double s1 = inverse * (o1 + z * ((a1 * x + b1) + c1));
    const double s2 = inverse * (o2 + z * ((a2 * x + b2) + c2));
    const bool inside = measured & (s0 >= -limit) & (s0 < limit) & (s1 >= -limit) & (s1 < limit) &
                        (s2 >= -limit) & (s2 < limit);
    const std::uint32_t k0 = static_cast<std::uint32_t>(floorToInt(inside ? s0 : 0.0) + grid::kKeyOffset);
    const std::uint32_t k1 = static_cast<std::uint32_t>(floorToInt(inside ? s1 : 0.0) + grid::kKeyOffset);
    const std::uint32_t k2 = static_cast<std::uint32_t>(floorToInt(inside ? s2 : 0.0) + grid::kKeyOffset);
    const bool beyond = use_range & (z * z * (x * x + yy_plus_one) > max_range_squared);
    out[u] = inside ? packVoxel(k0, k1, k2, beyond) : kNoVoxel;
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target("avx2")]] void projectRowAvx2(const RowTerms& r, const float* depth_row, int width,
                                            std::uint64_t* out) {
  projectRowKernel<true>(r, depth_row, width, out);
}
// Eight doubles per register. AVX-512 has fused multiply-adds: this file is
// built with -ffp-contract=off (core/CMakeLists.txt), so none is used.
[[gnu::target("avx512f,prefer-vector-width=512")]] void projectRowAvx512(const RowTerms& r, const float* depth_row,
                                                                          int width, std::uint64_t* out) {
  projectRowKernel<true>(r, depth_row, width, out);
}
#endif

}  // namespace

void PixelProjector::projectRow(int v, const float* depth_row, int width, std::uint64_t* out,
                                VectorKernels kernels) const {
  RowTerms r;
  const double y = (v - cy_) * inverse_fy_;
  for (int i = 0; i < 3; ++i) {
    r.origin[i] = origin_[i];
    r.first_column[i] = rotation_(i, 0);
    r.row_term[i] = rotation_(i, 1) * y;
    r.third_column[i] = rotation_(i, 2);
  }
  r.inverse = grid_.inverse;
  r.cx = cx_;
  r.inverse_fx = inverse_fx_;
  r.yy_plus_one = y * y + 1.0;
  r.max_range_squared = max_range_squared_;
#if defined(__x86_64__) && defined(__GNUC__)
  if (kernels != VectorKernels::UpToAvx2 && kernels != VectorKernels::Baseline && cpuHasAvx512())
    return projectRowAvx512(r, depth_row, width, out);
  if (kernels != VectorKernels::Baseline && cpuHasAvx2()) return projectRowAvx2(r, depth_row, width, out);
#endif
  projectRowKernel<false>(r, depth_row, width, out);
}

}  // namespace lom
