// logit of a row of probabilities for the fast integration path, written so
// that g++ vectorises it (no libm call, no branch). Compiled with
// -fno-trapping-math (core/CMakeLists.txt) so that the selects stay branch-free.
//
// logit(p) = log(r), r = p / (1 - p) clamped to the ratios of the probability
// clamp [kProbabilityEpsilon, 1 - kProbabilityEpsilon] (p = 1 gives r = inf,
// clamped like p = 1 - epsilon). log(r): r = m 2^e with m in [sqrt(1/2),
// sqrt(2)); log(m) = t - t^2/2 + t^3 P(t), t = m - 1, with P of degree 6
// fitted (weighted least squares on Chebyshev nodes) to the relative error of
// log(1 + t); e log(2) in two parts so that e * the first part is exact.
// Over every float p in [0, 1] the result is within 1e-6 of clampedLogit(p)
// (tests/unit/test_fast_logit.cpp). No fused multiply-add is enabled, so the
// vector and scalar builds give the same bits.
#include <cstdint>
#include <cstring>

#include "fusion_internal.hpp"

namespace lom {

namespace {

inline float asFloat(std::uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof(f));
  return f;
}
inline std::uint32_t asBits(float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof(bits));
  return bits;
}

[[gnu::always_inline]] inline void logitKernel(const float* __restrict p, size_t count,
                                               float* __restrict out) {
  const auto lowest = static_cast<float>(kProbabilityEpsilon / (1.0 - kProbabilityEpsilon));
  const auto highest = static_cast<float>((1.0 - kProbabilityEpsilon) / kProbabilityEpsilon);
  constexpr std::uint32_t kSqrtHalfBits = 0x3f3504f3u;  // bits of sqrt(1/2)
  constexpr float kLog2High = 0.693359375f;             // 9 significant bits: e * it is exact
  constexpr float kLog2Low = -2.12194440e-4f;           // log(2) - kLog2High
  for (size_t i = 0; i < count; ++i) {
    float q = p[i];
    q = q < 1.f ? q : 1.f;  // as the clamp of clampedLogit: above 1 counts as 1
    q = q > 0.f ? q : 0.f;
    float r = q / (1.f - q);
    r = r > lowest ? r : lowest;  // p = 0
    r = r < highest ? r : highest;  // p = 1: r = inf
    const std::uint32_t bits = asBits(r);
    const auto e = static_cast<std::int32_t>(bits - kSqrtHalfBits) >> 23;
    const float t = asFloat(bits - (static_cast<std::uint32_t>(e) << 23)) - 1.f;
    float poly = 0.0850695338f;
    poly = poly * t - 0.141974718f;
    poly = poly * t + 0.149509795f;
    poly = poly * t - 0.165879491f;
    poly = poly * t + 0.199605965f;
    poly = poly * t - 0.250009694f;
    poly = poly * t + 0.333339726f;
    const float t2 = t * t;
    const auto exponent = static_cast<float>(e);
    out[i] = (exponent * kLog2Low + (t - 0.5f * t2 + t2 * t * poly)) + exponent * kLog2High;
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target("avx2")]] void logitRowAvx2(const float* p, size_t count, float* out) {
  logitKernel(p, count, out);
}
#endif

}  // namespace

void logitRow(const float* probabilities, size_t count, float* out, bool allow_avx2) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (allow_avx2 && cpuHasAvx2()) return logitRowAvx2(probabilities, count, out);
#endif
  logitKernel(probabilities, count, out);
}

}  // namespace lom
