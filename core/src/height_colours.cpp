#include "lom/height_colours.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace lom {

Rgb shadedLabelColour(const LabelSet& labels, int id) {
  if (id == 0) return kShadedBackgroundColour;
  if (!labels.contains(id)) return {255, 0, 255};
  const Rgb& colour = labels.at(id).color;
  return colour == Rgb{0, 0, 0} ? Rgb{96, 96, 96} : colour;
}

Rgb heightRampColour(double t) {
  // Evenly spaced stops, linear in between: neighbouring heights get
  // neighbouring colours, and the ends are told apart at a glance.
  static constexpr std::array<std::array<double, 3>, 5> kStops{{
      {49, 54, 149},   // low: blue
      {69, 167, 201},  // cyan
      {102, 189, 99},  // green
      {250, 204, 52},  // yellow
      {215, 48, 39},   // high: red
  }};
  if (!(t >= 0.0)) t = 0.0;  // also NaN
  t = std::min(t, 1.0);
  const double position = t * static_cast<double>(kStops.size() - 1);
  const size_t below = std::min(static_cast<size_t>(position), kStops.size() - 2);
  const double w = position - static_cast<double>(below);
  Rgb out{};
  for (size_t c = 0; c < 3; ++c)
    out[c] = static_cast<std::uint8_t>(
        std::lround((1.0 - w) * kStops[below][c] + w * kStops[below + 1][c]));
  return out;
}

HeightColours::HeightColours(const Eigen::Vector3d& up, double lowest, double highest)
    : up_(Eigen::Vector3d::UnitZ()), lowest_(lowest), highest_(highest) {
  const double length = up.norm();
  if (std::isfinite(length) && length > 1e-12) up_ = up / length;
}

HeightColours HeightColours::spanning(const std::vector<Eigen::Vector3d>& points,
                                      const Eigen::Vector3d& up) {
  HeightColours colours(up, 0.0, 0.0);
  if (points.empty()) return colours;
  std::vector<double> heights;
  heights.reserve(points.size());
  for (const Eigen::Vector3d& p : points) heights.push_back(colours.height(p));
  // From the 1st to the 99th percentile once there are enough points: a few
  // stray voxels (depth noise far from the scene) must not squeeze the rest
  // into a sliver of the ramp.
  const size_t n = heights.size();
  const size_t cut = n >= kPercentileMinimum ? n / 100 : 0;
  std::nth_element(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(cut),
                   heights.end());
  colours.lowest_ = heights[cut];
  std::nth_element(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(n - 1 - cut),
                   heights.end());
  colours.highest_ = heights[n - 1 - cut];
  return colours;
}

double HeightColours::fraction(const Eigen::Vector3d& point) const {
  const double span = highest_ - lowest_;
  if (!(span > 0.0)) return 0.5;
  return std::clamp((height(point) - lowest_) / span, 0.0, 1.0);
}

}  // namespace lom
