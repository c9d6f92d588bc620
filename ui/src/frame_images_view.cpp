#include "lom/ui/frame_images_view.hpp"

#include <QVBoxLayout>
#include <map>

#include "lom/ui/depth_legend.hpp"
#include "lom/ui/frame_labels.hpp"
#include "lom/ui/image_conversion.hpp"
#include "lom/ui/image_pane.hpp"
#include "lom/ui/label_legend.hpp"

namespace lom::ui {

namespace {
constexpr size_t kMaxLegendEntries = 12;
}

FrameImagesView::FrameImagesView(QWidget* parent)
    : QWidget(parent),
      color_pane_(new ImagePane(tr("Colour"))),
      depth_pane_(new ImagePane(tr("Depth"))),
      depth_legend_(new DepthLegend),
      label_pane_(new ImagePane(tr("Labels"))),
      label_legend_(new LabelLegend) {
  color_pane_->setObjectName("colorPane");
  depth_pane_->setObjectName("depthPane");
  label_pane_->setObjectName("labelPane");
  label_legend_->setObjectName("labelLegend");

  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(4, 4, 4, 4);
  layout->addWidget(color_pane_, 1);
  layout->addWidget(depth_pane_, 1);
  layout->addWidget(depth_legend_);
  layout->addWidget(label_pane_, 1);
  layout->addWidget(label_legend_);
  clear();
}

void FrameImagesView::clear() {
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

  QImage color;
  if (frame->color) color = toQImage(*frame->color);
  if (color.isNull())
    color_pane_->setPlaceholder(tr("No colour image in this frame"));
  else
    color_pane_->setImage(color);

  const auto range = validDepthRange(frame->depth);
  depth_legend_->setRange(range);
  if (range)
    depth_pane_->setImage(depthToQImage(frame->depth, *range));
  else
    depth_pane_->setPlaceholder(tr("No valid depth in this frame"));

  label_legend_->setEntries({});
  label_legend_->setNote(QString());
  if (!labels) {
    label_pane_->setPlaceholder(tr("No labels or probabilities in this frame"));
    return;
  }
  label_pane_->setImage(labelsToQImage(*labels, sequence.labels, color));
  showLabelLegend(sequence.labels, *labels);
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
