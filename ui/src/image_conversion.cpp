#include "lom/ui/image_conversion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "lom/ui/frame_labels.hpp"

namespace lom::ui {

namespace {

bool isValidDepth(float metres) { return std::isfinite(metres) && metres > 0.f; }

// Perceptually ordered stops (dark violet near .. yellow far), readable on
// both the dark 3D background and the light window.
constexpr std::array<std::array<int, 3>, 5> kDepthStops = {
    {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}}};

}  // namespace

QImage toQImage(const ColorImage& color) {
  if (color.rgb.size() != static_cast<size_t>(color.width) * color.height * 3) return {};
  QImage image(color.width, color.height, QImage::Format_RGB888);
  const size_t row_bytes = static_cast<size_t>(color.width) * 3;
  for (int v = 0; v < color.height; ++v)
    std::memcpy(image.scanLine(v), color.rgb.data() + v * row_bytes, row_bytes);
  return image;
}

std::optional<DepthRange> validDepthRange(const DepthImage& depth) {
  std::optional<DepthRange> range;
  for (float metres : depth.metres) {
    if (!isValidDepth(metres)) continue;
    if (!range) {
      range = DepthRange{metres, metres};
    } else {
      range->near_metres = std::min(range->near_metres, metres);
      range->far_metres = std::max(range->far_metres, metres);
    }
  }
  return range;
}

QColor depthColor(double t) {
  t = std::clamp(t, 0.0, 1.0) * (kDepthStops.size() - 1);
  const auto low = std::min(static_cast<size_t>(t), kDepthStops.size() - 2);
  const double f = t - static_cast<double>(low);
  auto mix = [&](int channel) {
    return static_cast<int>(
        std::lround((1 - f) * kDepthStops[low][channel] + f * kDepthStops[low + 1][channel]));
  };
  return {mix(0), mix(1), mix(2)};
}

QImage depthToQImage(const DepthImage& depth, const DepthRange& range) {
  if (depth.metres.size() != static_cast<size_t>(depth.width) * depth.height) return {};
  QImage image(depth.width, depth.height, QImage::Format_RGB32);
  const double span = std::max(1e-6, double(range.far_metres) - range.near_metres);
  for (int v = 0; v < depth.height; ++v) {
    auto* row = reinterpret_cast<QRgb*>(image.scanLine(v));
    for (int u = 0; u < depth.width; ++u) {
      const float metres = depth.at(u, v);
      row[u] = isValidDepth(metres) ? depthColor((metres - range.near_metres) / span).rgb()
                                    : qRgb(0, 0, 0);
    }
  }
  return image;
}

namespace {
constexpr double kBaseBrightness = 0.6;  // of the grey photo under the labels
}  // namespace

QImage labelsToQImage(const LabelImage& labels, const LabelSet& label_set, const QImage& base,
                      double opacity) {
  if (labels.ids.size() != static_cast<size_t>(labels.width) * labels.height) return {};
  const bool has_base =
      !base.isNull() && base.width() == labels.width && base.height() == labels.height;
  QImage image = has_base ? base.convertToFormat(QImage::Format_RGB32)
                          : QImage(labels.width, labels.height, QImage::Format_RGB32);
  for (int v = 0; v < labels.height; ++v) {
    auto* row = reinterpret_cast<QRgb*>(image.scanLine(v));
    for (int u = 0; u < labels.width; ++u) {
      const int id = labels.at(u, v);
      if (has_base) {
        // The photo dimmed to grey, so that the labels stand out from it and
        // the pane never looks like the colour image (whose objects may be
        // painted in their label colours).
        const int grey = static_cast<int>(
            std::lround(kBaseBrightness *
                        (0.299 * qRed(row[u]) + 0.587 * qGreen(row[u]) + 0.114 * qBlue(row[u]))));
        row[u] = qRgb(grey, grey, grey);
      }
      if (has_base && id == 0) continue;
      const QColor label = labelColor(label_set, id);
      if (!has_base) {
        row[u] = label.rgb();
        continue;
      }
      auto blend = [&](int over, int under) {
        return static_cast<int>(std::lround(opacity * over + (1 - opacity) * under));
      };
      row[u] = qRgb(blend(label.red(), qRed(row[u])), blend(label.green(), qGreen(row[u])),
                    blend(label.blue(), qBlue(row[u])));
    }
  }
  return image;
}

}  // namespace lom::ui
