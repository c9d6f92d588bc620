#pragma once
// The 2D panes of the current frame: colour, depth (with its scale) and labels
// (label image or argmax of the probabilities, over the colour image).
#include <QWidget>
#include <optional>

#include "lom/sequence.hpp"

namespace lom::ui {

class DepthLegend;
class ImagePane;
class LabelLegend;

class FrameImagesView : public QWidget {
  Q_OBJECT

 public:
  explicit FrameImagesView(QWidget* parent = nullptr);

  // `frame` may be null when the frame's files could not be read.
  void showFrame(const Sequence& sequence, const FrameData* frame,
                 const std::optional<LabelImage>& labels);
  void clear();

  [[nodiscard]] const ImagePane& colorPane() const { return *color_pane_; }
  [[nodiscard]] const ImagePane& depthPane() const { return *depth_pane_; }
  [[nodiscard]] const ImagePane& labelPane() const { return *label_pane_; }
  [[nodiscard]] const LabelLegend& labelLegend() const { return *label_legend_; }

 private:
  void showLabelLegend(const LabelSet& label_set, const LabelImage& labels);

  ImagePane* color_pane_;
  ImagePane* depth_pane_;
  DepthLegend* depth_legend_;
  ImagePane* label_pane_;
  LabelLegend* label_legend_;
};

}  // namespace lom::ui
