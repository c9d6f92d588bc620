#pragma once
#include <functional>
// Pieces shared by the reference and the fast integration paths.
#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>

#include "lom/fusion.hpp"
#include "voxel_grid.hpp"

namespace lom {

struct PixelRay {
  grid::Key end_key{};        // voxel containing the measured point
  bool beyond_range = false;  // farther than max range: misses only, no hit
};

void checkFrameInputs(const LabelMap& map, const CameraIntrinsics& camera, const DepthImage& depth,
                      const FrameEvidence& evidence);

// What the processor runs, read once: with AVX2 the row kernels of the fast
// path (pixel_projector.cpp, fast_logit.cpp) use their AVX2 builds; with
// AVX-512 (F) 8-bit probability codes are summed a whole pixel per
// instruction, and with its byte permutes (BW, VBMI) four pixels at a time.
struct CpuFeatures {
  bool avx2 = false;
  bool avx512 = false;
  bool avx512_bytes = false;
};
inline const CpuFeatures& cpuFeatures() {
  static const CpuFeatures features = [] {
    CpuFeatures f;
#if defined(__x86_64__) && defined(__GNUC__)
    f.avx2 = __builtin_cpu_supports("avx2");
    f.avx512 = __builtin_cpu_supports("avx512f");
    f.avx512_bytes = f.avx512 && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vbmi");
#endif
    return f;
  }();
  return features;
}
inline bool cpuHasAvx2() { return cpuFeatures().avx2; }
inline bool cpuHasAvx512() { return cpuFeatures().avx512; }
inline bool cpuHasAvx512Bytes() { return cpuFeatures().avx512_bytes; }

// A pixel's end voxel packed in 64 bits: x << 33 | y << 17 | z << 1 | beyond
// max range. kNoVoxel marks a pixel without a valid depth or outside the map's
// key range.
inline constexpr std::uint64_t kNoVoxel = ~std::uint64_t{0};
inline std::uint64_t packVoxel(std::uint32_t x, std::uint32_t y, std::uint32_t z, bool beyond_range) {
  return (std::uint64_t{x} << 33) | (std::uint64_t{y} << 17) | (std::uint64_t{z} << 1) |
         (beyond_range ? 1u : 0u);
}
inline std::uint64_t packVoxel(const grid::Key& key, bool beyond_range) {
  return packVoxel(key[0], key[1], key[2], beyond_range);
}
inline PixelRay unpackVoxel(std::uint64_t packed) {
  return {{static_cast<std::uint16_t>(packed >> 33), static_cast<std::uint16_t>(packed >> 17),
           static_cast<std::uint16_t>(packed >> 1)},
          (packed & 1u) != 0};
}

// Back-projects the pixels of one frame into end voxels, a row at a time
// (row-constant terms once per row, no branch per pixel). Both integration
// paths use it, so they agree on every pixel's voxel to the last bit.
class PixelProjector {
 public:
  PixelProjector(const grid::Grid& g, const CameraIntrinsics& camera,
                 const Eigen::Isometry3d& T_world_camera, double max_range)
      : grid_(g),
        rotation_(T_world_camera.rotation()),
        origin_(T_world_camera.translation()),
        inverse_fx_(1.0 / camera.fx),
        inverse_fy_(1.0 / camera.fy),
        cx_(camera.cx),
        cy_(camera.cy),
        max_range_squared_(max_range > 0.0 ? max_range * max_range : -1.0) {}

  // out[u] = packVoxel(end voxel of pixel (u, v)), or kNoVoxel. Vectorised
  // with AVX-512 or AVX2 where the processor has them and `kernels` allows
  // them (every choice gives the same keys).
  void projectRow(int v, const float* depth_row, int width, std::uint64_t* out,
                  VectorKernels kernels = VectorKernels::Best) const;
  [[nodiscard]] const Eigen::Vector3d& origin() const { return origin_; }

 private:
  grid::Grid grid_;
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d origin_;
  double inverse_fx_, inverse_fy_, cx_, cy_;
  double max_range_squared_;
};

// Where the pixel's ray ends: the centre of its end voxel (as in OctoMap's
// discretized insertion), or the point at max range towards it.
Eigen::Vector3d rayEnd(const grid::Grid& g, const Eigen::Vector3d& origin, const grid::Key& end_key,
                       bool beyond_range, double max_range);
// rayEnd and grid::setUpRay for `count` packed end voxels, eight at a time
// (AVX-512 F; core/src/ray_setup.cpp): the same walks to the last bit. Rays
// setUpRay would refuse (an end outside the key range) are left out; returns
// how many walks were written to `walks` (room for `count`).
size_t setUpRaysAvx512(const grid::Grid& g, const Eigen::Vector3d& origin, double max_range,
                       const std::uint64_t* voxels, size_t count, grid::RayWalk* walks);

FrameStats integrateFrameReference(LabelMap& map, const CameraIntrinsics& camera,
                                   const Eigen::Isometry3d& T_world_camera,
                                   const DepthImage& depth, const FrameEvidence& evidence);
FrameStats integrateFrameFast(LabelMap& map, const CameraIntrinsics& camera,
                              const Eigen::Isometry3d& T_world_camera, const DepthImage& depth,
                              const FrameEvidence& evidence, int threads, VectorKernels kernels,
                              double frame_memory_limit_bytes,
                              const std::function<bool()>& cancelled = {});

// IntegrationOptions::frame_memory_limit_bytes, in the fast path once the
// frame's rays are marked: whether a frame whose rays crossed at most
// `most_crossed` voxels is to be checked, and the check, which throws
// lom::Error (field "depth") when `crossed` voxels would take more than the
// limit (0: more than availableMemoryBytes).
[[nodiscard]] bool frameMemoryNeedsCheck(size_t most_crossed, double limit_bytes);
// Throws lom::Error (field "depth") when a frame whose rays cross `crossed`
// voxels could take more memory than `limit_bytes` (0: what the system has
// available). The first estimate charges every crossed voxel as new to the
// map (kFusionBytesPerCrossedVoxel); when that does not fit and
// `count_new_voxels` is given, only the voxels it counts as new are charged
// their nodes, and the update streams only what they need beyond
// `reusable_stream_bytes` (the buffers earlier frames left, kept for reuse).
void checkFrameMemory(size_t crossed, double limit_bytes, double resolution,
                      const std::function<size_t()>& count_new_voxels = {},
                      double reusable_stream_bytes = 0.0);

// logit of a probability clamped to [kProbabilityEpsilon, 1 - kProbabilityEpsilon].
float clampedLogit(float p);

// out[i] = clampedLogit(probabilities[i]) within 1e-6, vectorised
// (core/src/fast_logit.cpp). `allow_avx2 = false` forces the baseline
// instruction set (for tests: both give the same bits).
void logitRow(const float* probabilities, size_t count, float* out, bool allow_avx2 = true);


}  // namespace lom
