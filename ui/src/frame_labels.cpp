#include "lom/ui/frame_labels.hpp"

#include <limits>

namespace lom::ui {

LabelImage argmaxLabels(const ProbabilityImage& proba) {
  LabelImage labels;
  labels.width = proba.width;
  labels.height = proba.height;
  labels.ids.assign(static_cast<size_t>(proba.width) * proba.height, 0);
  if (proba.channels <= 0) return labels;

  auto labelOfChannel = [&](int channel) {
    return channel < static_cast<int>(proba.channel_labels.size()) ? proba.channel_labels[channel]
                                                                   : channel;
  };
  for (int v = 0; v < proba.height; ++v) {
    for (int u = 0; u < proba.width; ++u) {
      const float* p = proba.pixel(u, v);
      int best_label = labelOfChannel(0);
      float best = p[0];
      for (int c = 1; c < proba.channels; ++c) {
        const int label = labelOfChannel(c);
        if (p[c] > best || (p[c] == best && label < best_label)) {
          best = p[c];
          best_label = label;
        }
      }
      labels.ids[static_cast<size_t>(v) * proba.width + u] =
          static_cast<std::uint16_t>(best_label < 0 ? 0 : best_label);
    }
  }
  return labels;
}

std::optional<LabelImage> labelsOfFrame(const FrameData& frame) {
  if (frame.label) return *frame.label;
  if (frame.proba) return argmaxLabels(*frame.proba);
  return std::nullopt;
}

QColor labelColor(const LabelSet& labels, int id) {
  if (!labels.contains(id)) return {255, 0, 255};
  const Rgb& rgb = labels.at(id).color;
  return {rgb[0], rgb[1], rgb[2]};
}

}  // namespace lom::ui
