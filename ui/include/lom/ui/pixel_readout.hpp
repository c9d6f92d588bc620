#pragma once
// The 2D panes' per-pixel helpers: the probability heat map of one label and
// the text shown while hovering a pixel.
#include <QColor>
#include <QImage>
#include <QString>
#include <optional>

#include "lom/sequence.hpp"

namespace lom::ui {

// Probability of `label` in each pixel, coloured from dark (0) to bright (1);
// null when the frame has no probability image.
[[nodiscard]] QImage probabilityHeatMap(const ProbabilityImage& proba, int label);
// The heat map's colour of probability p in 0..1 (dark at 0, yellow at 1).
[[nodiscard]] QColor probabilityColor(double p);

// Probability of `label` at (u, v); 0 for labels without a channel.
[[nodiscard]] float probabilityOf(const ProbabilityImage& proba, int u, int v, int label);

// "u, v: depth 0.734 m, label 3 name (p 0.82), p(selected) 0.10".
[[nodiscard]] QString describePixel(const Sequence& sequence, const FrameData& frame,
                                    const std::optional<LabelImage>& labels, int u, int v,
                                    int selected_label);

}  // namespace lom::ui
