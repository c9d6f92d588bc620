#pragma once
// The label image a frame is displayed with: its label image when it has one,
// otherwise the per-pixel argmax of its probability image.
#include <QColor>
#include <optional>

#include "lom/images.hpp"
#include "lom/labels.hpp"
#include "lom/sequence.hpp"

namespace lom::ui {

[[nodiscard]] std::optional<LabelImage> labelsOfFrame(const FrameData& frame);

// Argmax over the channels of `proba`; ties go to the lower label id.
[[nodiscard]] LabelImage argmaxLabels(const ProbabilityImage& proba);

// Display colour of a label; ids outside the set are magenta so they stand out.
[[nodiscard]] QColor labelColor(const LabelSet& labels, int id);

}  // namespace lom::ui
