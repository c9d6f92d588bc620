// What an RGB-D sensor makes of the ray-cast surfaces: a structured-light
// style depth image and a flat-shaded colour image.
#include <algorithm>
#include <cmath>

#include "synth_internal.hpp"

namespace lom::synth {

namespace {

constexpr float kMaxRange = 3.5f;  // metres; farther surfaces give no return
// Returns fail more and more often from 72 deg between ray and normal on,
// half of them at 75 deg, all beyond 78 deg.
constexpr float kGrazingCosine = 0.2079f;  // cos 78 deg
constexpr float kFadingCosine = 0.3090f;   // cos 72 deg
constexpr float kEdgeJump = 0.02f;         // metres between neighbours
constexpr double kShadowedEdgeLoss = 0.8;  // far side of a depth edge
constexpr double kNearEdgeLoss = 0.15;     // near side of a depth edge
constexpr double kDropout = 0.002;

// Axial noise of a structured-light sensor grows with the square of the depth.
double depthSigma(double z) { return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4); }

// Largest depth step to a 4-neighbour, measured toward nearer (positive) and
// farther (negative) neighbours. Pixels that see nothing count as far away.
void edgeSteps(const SurfaceImage& s, int u, int v, float& toward_nearer, float& toward_farther) {
  const float z = s.depth[static_cast<size_t>(v) * s.width + u];
  toward_nearer = 0.0f;
  toward_farther = 0.0f;
  const int du[] = {1, -1, 0, 0}, dv[] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int nu = u + du[k], nv = v + dv[k];
    if (nu < 0 || nv < 0 || nu >= s.width || nv >= s.height) continue;
    const float n = s.depth[static_cast<size_t>(nv) * s.width + nu];
    if (n <= 0.0f) {
      toward_farther = std::max(toward_farther, kMaxRange);
      continue;
    }
    toward_nearer = std::max(toward_nearer, z - n);
    toward_farther = std::max(toward_farther, n - z);
  }
}

bool sensorLosesPixel(const SurfaceImage& s, int u, int v, Rng& rng) {
  const size_t i = static_cast<size_t>(v) * s.width + u;
  const float cosine = s.cos_incidence[i];
  if (cosine < kGrazingCosine) return true;
  if (cosine < kFadingCosine &&
      rng.chance((kFadingCosine - cosine) / (kFadingCosine - kGrazingCosine)))
    return true;
  float toward_nearer = 0.0f, toward_farther = 0.0f;
  edgeSteps(s, u, v, toward_nearer, toward_farther);
  if (toward_nearer > kEdgeJump && rng.chance(kShadowedEdgeLoss)) return true;
  if (toward_farther > kEdgeJump && rng.chance(kNearEdgeLoss)) return true;
  return rng.chance(kDropout);
}

using Rgbf = Eigen::Vector3f;

Rgbf baseColor(const SurfaceImage& s, size_t i) {
  const int label = s.label[i];
  if (label == kSynthTransparentLabel) return {0.80f, 0.88f, 0.93f};
  if (label > 0) {
    const Rgb c = vocColor(label);
    return Rgbf(c[0], c[1], c[2]) / 255.0f;
  }
  const Eigen::Vector3f& n = s.normal[i];
  if (n.x() < -0.9f) return {0.62f, 0.42f, 0.24f};  // the shelf's front faces
  if (n.z() > 0.9f) return {0.70f, 0.63f, 0.52f};   // bin floor
  return {0.78f, 0.72f, 0.62f};                     // bin walls and ceiling
}

}  // namespace

DepthImage senseDepth(const SurfaceImage& surface, double depth_scale, bool noise, Rng& rng) {
  DepthImage depth;
  depth.width = surface.width;
  depth.height = surface.height;
  depth.metres.assign(surface.depth.size(), 0.0f);
  for (int v = 0; v < surface.height; ++v)
    for (int u = 0; u < surface.width; ++u) {
      const size_t i = static_cast<size_t>(v) * surface.width + u;
      double z = surface.depth[i];
      if (z <= 0.0 || z > kMaxRange || surface.label[i] == kSynthTransparentLabel) continue;
      if (noise) {
        if (sensorLosesPixel(surface, u, v, rng)) continue;
        z += depthSigma(z) * rng.normal();
      }
      // The value stored in the 16-bit PNG, so memory and file agree.
      depth.metres[i] = static_cast<float>(std::round(z / depth_scale) * depth_scale);
    }
  return depth;
}

ColorImage shadeColor(const SurfaceImage& surface, Rng& rng) {
  ColorImage color;
  color.width = surface.width;
  color.height = surface.height;
  color.rgb.resize(surface.depth.size() * 3);
  for (int v = 0; v < surface.height; ++v)
    for (int u = 0; u < surface.width; ++u) {
      const size_t i = static_cast<size_t>(v) * surface.width + u;
      Rgbf rgb;
      if (surface.depth[i] <= 0.0f) {
        rgb = Rgbf(0.16f, 0.17f, 0.19f) * (1.0f - 0.3f * v / surface.height);
      } else {
        // Head light plus some light from above, dimmer with distance.
        const float light = (0.45f + 0.55f * surface.cos_incidence[i] +
                             0.12f * std::max(0.0f, surface.normal[i].z())) *
                            std::clamp(1.15f - 0.25f * surface.depth[i], 0.6f, 1.0f);
        rgb = baseColor(surface, i) * light;
      }
      const float grain = static_cast<float>(rng.below(5) - 2) / 255.0f;
      for (int c = 0; c < 3; ++c)
        color.rgb[3 * i + c] =
            static_cast<std::uint8_t>(std::lround(std::clamp(rgb[c] + grain, 0.0f, 1.0f) * 255.0f));
    }
  return color;
}

}  // namespace lom::synth
