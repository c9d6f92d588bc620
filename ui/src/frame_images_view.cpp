#include "lom/ui/frame_images_view.hpp"

#include <QFontMetrics>
#include <QGridLayout>
#include <QLabel>
#include <QResizeEvent>
#include <QVBoxLayout>
#include <algorithm>
#include <map>

#include "lom/ui/colour_bar.hpp"
#include "lom/ui/elision.hpp"
#include "lom/ui/frame_labels.hpp"
#include "lom/ui/image_conversion.hpp"
#include "lom/ui/image_pane.hpp"
#include "lom/ui/label_legend.hpp"
#include "lom/ui/pixel_readout.hpp"

namespace lom::ui {

namespace {
constexpr size_t kMaxLegendEntries = 12;

// The pixel readout: word-wrapped, as high as the longest readout needs at
// its width. Its height follows its width, never its text: a readout of one
// line, two or none resized the panes above it, which moved the picture under
// a cursor that had not moved; and a fixed two lines cut off the third a
// narrow panel or a large font wraps the longest readouts into.
class ReadoutLabel : public QLabel {
 public:
  ReadoutLabel() {
    setWordWrap(true);
    setFixedHeight(heightAt(400));
  }

 protected:
  void resizeEvent(QResizeEvent* event) override {
    QLabel::resizeEvent(event);
    fitHeight();
  }
  void changeEvent(QEvent* event) override {
    QLabel::changeEvent(event);
    if (event->type() == QEvent::FontChange) fitHeight();
  }

 private:
  void fitHeight() {
    const int needed = heightAt(contentsRect().width());
    if (needed != height()) setFixedHeight(needed);  // the same width comes back: no loop
  }
  [[nodiscard]] int heightAt(int width) const {
    // A long name in capitals, the widest a label name is shown (shortName).
    const QString name = shortName(QStringLiteral("KYJEN_SQUEAKIN_EGGS_PLUSH_PUPPIES_XL"));
    const QString longest = QStringLiteral(
                                "(6399, 4799)  depth 10.000 m  label 39 %1 (p 1.00)  "
                                "p(%1) 1.00")
                                .arg(name);
    const QRect text = fontMetrics().boundingRect(QRect(0, 0, std::max(width, 40), 1 << 20),
                                                  Qt::TextWordWrap | Qt::AlignLeft, longest);
    return std::max(2 * fontMetrics().lineSpacing(), text.height()) + 4;
  }
};

}  // namespace

FrameImagesView::FrameImagesView(QWidget* parent)
    : QWidget(parent),
      color_pane_(new ImagePane(tr("Colour"))),
      depth_pane_(new ImagePane(tr("Depth"))),
      depth_legend_(new ColourBar(depthColor, tr("depth"))),
      label_pane_(new ImagePane(tr("Labels"))),
      label_legend_(new LabelLegend),
      heat_pane_(new ImagePane(tr("Probability"))),
      heat_legend_(new ColourBar(probabilityColor, tr("probability"), nullptr, QString())),
      readout_(new ReadoutLabel) {
  heat_pane_->setObjectName("heatPane");
  readout_->setObjectName("pixelReadout");
  readout_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
  color_pane_->setObjectName("colorPane");
  depth_pane_->setObjectName("depthPane");
  label_pane_->setObjectName("labelPane");
  label_legend_->setObjectName("labelLegend");

  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(4, 4, 4, 4);
  auto* grid = new QGridLayout;
  auto* depth_column = new QVBoxLayout;
  depth_column->addWidget(depth_pane_, 1);
  depth_column->addWidget(depth_legend_);
  auto* label_column = new QVBoxLayout;
  label_column->addWidget(label_pane_, 1);
  label_column->addWidget(label_legend_);
  grid->addWidget(color_pane_, 0, 0);
  grid->addLayout(depth_column, 0, 1);
  grid->addLayout(label_column, 1, 0);
  auto* heat_column = new QVBoxLayout;
  heat_column->addWidget(heat_pane_, 1);
  heat_column->addWidget(heat_legend_);
  heat_legend_->setObjectName("heatLegend");
  grid->addLayout(heat_column, 1, 1);
  layout->addLayout(grid, 1);
  layout->addWidget(readout_);
  for (ImagePane* pane : {color_pane_, depth_pane_, label_pane_, heat_pane_})
    connect(pane, &ImagePane::hovered, this, &FrameImagesView::hoverPixel);
  clear();
}

void FrameImagesView::setHeatLabel(int label) {
  heat_label_ = label;
  showHeatMap();
  hoverPixel(hovered_);  // the pixel still under the mouse, for this label
}

void FrameImagesView::setSegmenterState(const QString& model, bool running,
                                        const QString& problem) {
  segmenter_model_ = model;
  segmenter_running_ = running;
  segmenter_problem_ = problem;
}

void FrameImagesView::showHeatMap() {
  const bool known_label = sequence_ && sequence_->labels.contains(heat_label_);
  heat_legend_->setRange(std::nullopt);  // shown with a heat map only
  if (!frame_) {
    heat_pane_->setCaption(tr("Probability"));
    heat_pane_->setPlaceholder(QString());
  } else if (!frame_->proba && !segmenter_model_.isEmpty()) {
    heat_pane_->setCaption(segmenter_running_ ? tr("Probability: segmenting…")
                                              : tr("Probability: none"));
    heat_pane_->setPlaceholder(
        segmenter_running_ ? tr("The segmenter %1 is running on this frame…").arg(segmenter_model_)
                           : tr("The segmenter %1 gave no probabilities: %2")
                                 .arg(segmenter_model_, segmenter_problem_));
  } else if (!frame_->proba) {
    heat_pane_->setCaption(tr("Probability: none"));
    heat_pane_->setPlaceholder(tr("No probabilities in this frame"));
  } else if (!known_label) {
    heat_pane_->setCaption(tr("Probability (choose a label)"));
    heat_pane_->setPlaceholder(tr("Choose a label in the map legend"));
  } else {
    const QString name = QString::fromStdString(sequence_->labels.at(heat_label_).name);
    heat_pane_->setCaption(
        segmenter_model_.isEmpty()
            ? tr("Probability of %1").arg(name)
            : tr("Probability of %1 (segmenter %2)").arg(name, segmenter_model_));
    heat_pane_->setImage(probabilityHeatMap(*frame_->proba, heat_label_));
    heat_legend_->setRange(std::make_pair(0.0, 1.0));
  }
}

QString FrameImagesView::readoutText() const { return readout_->text(); }

void FrameImagesView::hoverPixel(const QPoint& pixel) {
  hovered_ = pixel;
  if (!frame_ || !sequence_ || pixel.x() < 0 || pixel.y() < 0 || pixel.x() >= frame_->depth.width ||
      pixel.y() >= frame_->depth.height) {
    readout_->clear();
    return;
  }
  readout_->setText(describePixel(*sequence_, *frame_, *labels_, pixel.x(), pixel.y(), heat_label_));
  readout_->setToolTip(readout_->text());  // whole, when two lines cannot hold it
}

void FrameImagesView::clear() {
  sequence_ = nullptr;
  frame_ = nullptr;
  labels_ = nullptr;
  showHeatMap();
  readout_->clear();
  color_pane_->setPlaceholder(tr("No sequence open"));
  depth_pane_->setPlaceholder(QString());
  label_pane_->setPlaceholder(QString());
  depth_legend_->setRange(std::nullopt);
  label_legend_->setEntries({});
  label_legend_->setNote(QString());
}

void FrameImagesView::showFrame(const Sequence& sequence, const FrameData* frame,
                                const std::optional<LabelImage>& labels) {
  if (!frame) {
    clear();
    color_pane_->setPlaceholder(tr("This frame's files could not be read"));
    return;
  }
  sequence_ = &sequence;
  frame_ = frame;
  labels_ = &labels;
  showHeatMap();

  QImage color;
  if (frame->color) color = toQImage(*frame->color);
  if (color.isNull())
    color_pane_->setPlaceholder(tr("No colour image in this frame"));
  else
    color_pane_->setImage(color);

  const auto range = validDepthRange(frame->depth);
  depth_legend_->setRange(
      range ? std::optional(std::make_pair(range->near_metres, range->far_metres)) : std::nullopt);
  if (range)
    depth_pane_->setImage(depthToQImage(frame->depth, *range));
  else
    depth_pane_->setPlaceholder(tr("No valid depth in this frame"));

  label_legend_->setEntries({});
  label_legend_->setNote(QString());
  if (!labels) {
    label_pane_->setPlaceholder(tr("No labels or probabilities in this frame"));
  } else {
    label_pane_->setImage(labelsToQImage(*labels, sequence.labels, color));
    showLabelLegend(sequence.labels, *labels);
  }
  // The mouse resting on a pane while frames step (playback, Page Down):
  // the readout describes the new frame's pixel, not the last one's.
  hoverPixel(hovered_);
}

void FrameImagesView::showLabelLegend(const LabelSet& label_set, const LabelImage& labels) {
  std::map<int, size_t> pixels_per_label;
  for (auto id : labels.ids)
    if (id != 0) ++pixels_per_label[id];

  std::vector<LabelLegend::Entry> entries;
  for (const auto& [id, count] : pixels_per_label) {
    if (entries.size() == kMaxLegendEntries) {
      entries.push_back(
          {Qt::transparent, tr("… %1 more").arg(pixels_per_label.size() - kMaxLegendEntries)});
      break;
    }
    const QString name = label_set.contains(id) ? QString::fromStdString(label_set.at(id).name)
                                                : tr("unknown id %1").arg(id);
    entries.push_back({labelColor(label_set, id), name});
  }
  label_legend_->setNote(tr("only background"));
  label_legend_->setEntries(std::move(entries));
}

}  // namespace lom::ui
