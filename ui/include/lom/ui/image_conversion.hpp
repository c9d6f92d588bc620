#pragma once
// Adapters from the core's plain image structs to QImage for the 2D panes.
#include <QColor>
#include <QImage>
#include <optional>

#include "lom/images.hpp"
#include "lom/labels.hpp"

namespace lom::ui {

struct DepthRange {
  float near_metres = 0.f;
  float far_metres = 0.f;
};

[[nodiscard]] QImage toQImage(const ColorImage& color);

// Range of the valid (finite, > 0) depths; nullopt when the image has none.
[[nodiscard]] std::optional<DepthRange> validDepthRange(const DepthImage& depth);

// Colour map used for depth: t = 0 (near) .. 1 (far).
[[nodiscard]] QColor depthColor(double t);

// Depth coloured with depthColor over `range`; pixels without depth are black.
[[nodiscard]] QImage depthToQImage(const DepthImage& depth, const DepthRange& range);

// Label colours blended over `base` (same size, or null for plain label
// colours), which is shown as a dimmed grey image: background pixels (label
// 0) show it, labelled pixels are their label's colour over it.
[[nodiscard]] QImage labelsToQImage(const LabelImage& labels, const LabelSet& label_set,
                                    const QImage& base = {}, double opacity = 0.65);

}  // namespace lom::ui
