#pragma once
// The 2D panes of the current frame: colour, depth (with its scale) and labels
// (label image or argmax of the probabilities, over the colour image).
#include <QWidget>
#include <optional>

#include "lom/sequence.hpp"

class QLabel;

namespace lom::ui {

class ColourBar;
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
  // The label whose probability the heat map shows (-1 for none).
  void setHeatLabel(int label);
  // Where the frame's probabilities come from, when a segmenter gives them
  // (set before showFrame): its file name (empty: the frame's own files),
  // whether it is still running, and why it gave none.
  void setSegmenterState(const QString& model, bool running, const QString& problem);

  [[nodiscard]] const ImagePane& colorPane() const { return *color_pane_; }
  [[nodiscard]] const ImagePane& depthPane() const { return *depth_pane_; }
  [[nodiscard]] const ImagePane& labelPane() const { return *label_pane_; }
  [[nodiscard]] const LabelLegend& labelLegend() const { return *label_legend_; }
  [[nodiscard]] const ImagePane& heatPane() const { return *heat_pane_; }
  // The hover readout's text (empty when no pixel is hovered).
  [[nodiscard]] QString readoutText() const;
  void hoverPixel(const QPoint& pixel);

 private:
  void showLabelLegend(const LabelSet& label_set, const LabelImage& labels);
  void showHeatMap();

  ImagePane* color_pane_;
  ImagePane* depth_pane_;
  ColourBar* depth_legend_;
  ImagePane* label_pane_;
  LabelLegend* label_legend_;
  ImagePane* heat_pane_;
  ColourBar* heat_legend_;  // 0..1 under the probability pane
  QLabel* readout_;
  // The frame shown (owned by the sequence controller until the next frame).
  const Sequence* sequence_ = nullptr;
  const FrameData* frame_ = nullptr;
  const std::optional<LabelImage>* labels_ = nullptr;
  int heat_label_ = -1;
  QString segmenter_model_;
  bool segmenter_running_ = false;
  QString segmenter_problem_;
  QPoint hovered_{-1, -1};  // the image pixel under the mouse, (-1, -1) for none
};

}  // namespace lom::ui
