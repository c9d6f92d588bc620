// Depth clean-up for imported frames: holes, range limits, flying pixels at
// depth edges and optional edge-preserving (bilateral) smoothing.
#include <algorithm>
#include <cmath>

#include "import_internal.hpp"
#include "lom/error.hpp"
#include "lom/import.hpp"

namespace lom {

namespace {

// 1000000 and 0.05 as typed, not 1000000.000000 and 0.050000.
std::string numberText(double value) { return import_detail::formatNumber(value, 15); }

void checkOptions(const DepthFilterOptions& o) {
  auto fail = [](const std::string& field, const std::string& expected, double found) {
    throw Error("", field, expected, numberText(found));
  };
  if (!std::isfinite(o.min_depth) || o.min_depth < 0.0)
    fail("min_depth", "a non-negative depth in metres", o.min_depth);
  if (!std::isfinite(o.max_depth)) fail("max_depth", "a depth in metres (<= 0: no limit)", o.max_depth);
  if (o.max_depth > 0.0 && o.max_depth <= o.min_depth)
    fail("max_depth", "a depth above min_depth (" + numberText(o.min_depth) + " m) or <= 0",
         o.max_depth);
  if (o.flying_pixels) {
    if (!(o.flying_pixel_ratio > 0.0) || !std::isfinite(o.flying_pixel_ratio))
      fail("flying_pixel_ratio", "a positive fraction of the depth, e.g. 0.05",
           o.flying_pixel_ratio);
    if (o.flying_pixel_radius < 1 || o.flying_pixel_radius > 10)
      fail("flying_pixel_radius", "a neighbourhood radius from 1 to 10 pixels",
           o.flying_pixel_radius);
  }
  if (o.bilateral_radius < 0 || o.bilateral_radius > 15)
    fail("bilateral_radius", "a radius from 0 (off) to 15 pixels", o.bilateral_radius);
  if (o.bilateral_radius > 0) {
    if (!(o.bilateral_sigma_space > 0.0))
      fail("bilateral_sigma_space", "a positive number of pixels", o.bilateral_sigma_space);
    if (!(o.bilateral_sigma_depth > 0.0))
      fail("bilateral_sigma_depth", "a positive fraction of the depth", o.bilateral_sigma_depth);
  }
}

}  // namespace

DepthFilterStats filterDepth(DepthImage& depth, const DepthFilterOptions& options) {
  checkOptions(options);
  const int w = depth.width, h = depth.height;
  if (w < 0 || h < 0 || depth.metres.size() != static_cast<size_t>(w) * static_cast<size_t>(h))
    throw Error("", "depth image", "width x height values",
                std::to_string(depth.metres.size()) + " values for " + std::to_string(w) + " x " +
                    std::to_string(h));
  DepthFilterStats stats;
  const float min_z = static_cast<float>(options.min_depth);
  const float max_z =
      options.max_depth > 0.0 ? static_cast<float>(options.max_depth) : INFINITY;
  for (float& z : depth.metres) {
    if (z == 0.0f) continue;
    if (!std::isfinite(z) || z < 0.0f) {
      z = 0.0f;
      ++stats.invalid;
    } else if (z < min_z || z > max_z) {
      z = 0.0f;
      ++stats.out_of_range;
    }
  }

  auto index = [w](int u, int v) { return static_cast<size_t>(v) * static_cast<size_t>(w) + u; };

  if (options.flying_pixels) {
    const std::vector<float> source = depth.metres;
    const int r = options.flying_pixel_radius;
    const float ratio = static_cast<float>(options.flying_pixel_ratio);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const float z = source[index(u, v)];
        if (z <= 0.0f) continue;
        const float limit = ratio * z;
        bool flying = false;
        for (int dv = -r; dv <= r && !flying; ++dv) {
          const int vv = v + dv;
          if (vv < 0 || vv >= h) continue;
          for (int du = -r; du <= r; ++du) {
            const int uu = u + du;
            if (uu < 0 || uu >= w || (du == 0 && dv == 0)) continue;
            const float n = source[index(uu, vv)];
            if (n > 0.0f && std::abs(n - z) > limit) {
              flying = true;
              break;
            }
          }
        }
        if (flying) {
          depth.metres[index(u, v)] = 0.0f;
          ++stats.flying;
        }
      }
  }

  if (options.bilateral_radius > 0) {
    const std::vector<float> source = depth.metres;
    const int r = options.bilateral_radius;
    const double inv_space = 1.0 / (2.0 * options.bilateral_sigma_space * options.bilateral_sigma_space);
    std::vector<double> spatial(static_cast<size_t>((2 * r + 1) * (2 * r + 1)));
    for (int dv = -r; dv <= r; ++dv)
      for (int du = -r; du <= r; ++du)
        spatial[static_cast<size_t>((dv + r) * (2 * r + 1) + du + r)] =
            std::exp(-(du * du + dv * dv) * inv_space);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const float z = source[index(u, v)];
        if (z <= 0.0f) continue;
        const double sigma = options.bilateral_sigma_depth * z;
        const double inv_range = 1.0 / (2.0 * sigma * sigma);
        double sum = 0.0, weights = 0.0;
        for (int dv = -r; dv <= r; ++dv) {
          const int vv = v + dv;
          if (vv < 0 || vv >= h) continue;
          for (int du = -r; du <= r; ++du) {
            const int uu = u + du;
            if (uu < 0 || uu >= w) continue;
            const float n = source[index(uu, vv)];
            if (n <= 0.0f) continue;
            const double d = n - z;
            const double weight =
                spatial[static_cast<size_t>((dv + r) * (2 * r + 1) + du + r)] *
                std::exp(-d * d * inv_range);
            sum += weight * n;
            weights += weight;
          }
        }
        depth.metres[index(u, v)] = static_cast<float>(sum / weights);
      }
  }

  for (float z : depth.metres) stats.kept += z > 0.0f;
  return stats;
}

}  // namespace lom
