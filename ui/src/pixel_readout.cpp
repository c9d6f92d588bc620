#include "lom/ui/pixel_readout.hpp"

#include <QObject>
#include <algorithm>
#include <cmath>

#include "lom/ui/elision.hpp"
#include "lom/ui/image_conversion.hpp"

namespace lom::ui {

namespace {
int channelOf(const ProbabilityImage& proba, int label) {
  if (proba.channel_labels.empty()) return label < proba.channels ? label : -1;
  const auto it = std::find(proba.channel_labels.begin(), proba.channel_labels.end(), label);
  return it == proba.channel_labels.end() ? -1 : static_cast<int>(it - proba.channel_labels.begin());
}
}  // namespace

float probabilityOf(const ProbabilityImage& proba, int u, int v, int label) {
  const int channel = channelOf(proba, label);
  return channel < 0 ? 0.f : proba.pixel(u, v)[channel];
}

QColor probabilityColor(double p) {
  // depthColor runs from blue to yellow; a dark start keeps p = 0 dark.
  const QColor c = depthColor(p);
  const double fade = 0.25 + 0.75 * p;
  return QColor(static_cast<int>(c.red() * fade), static_cast<int>(c.green() * fade),
                static_cast<int>(c.blue() * fade));
}

QImage probabilityHeatMap(const ProbabilityImage& proba, int label) {
  if (proba.width <= 0 || proba.height <= 0) return {};
  QImage image(proba.width, proba.height, QImage::Format_RGB32);
  const int channel = channelOf(proba, label);
  for (int v = 0; v < proba.height; ++v) {
    auto* row = reinterpret_cast<QRgb*>(image.scanLine(v));
    for (int u = 0; u < proba.width; ++u) {
      const double p = channel < 0 ? 0.0 : std::clamp<double>(proba.pixel(u, v)[channel], 0.0, 1.0);
      row[u] = probabilityColor(p).rgb();
    }
  }
  return image;
}

QString describePixel(const Sequence& sequence, const FrameData& frame,
                      const std::optional<LabelImage>& labels, int u, int v, int selected_label) {
  auto name = [&](int id) {
    // Shortened: a long name would be one unbreakable word widening the readout.
    return sequence.labels.contains(id)
               ? shortName(QString::fromStdString(sequence.labels.at(id).name))
               : QString::number(id);
  };
  QString text = QObject::tr("(%1, %2)").arg(u).arg(v);
  if (u < frame.depth.width && v < frame.depth.height) {
    const float z = frame.depth.at(u, v);
    text += std::isfinite(z) && z > 0.f ? QObject::tr("  depth %1 m").arg(z, 0, 'f', 3)
                                        : QObject::tr("  no depth");
  }
  if (labels && u < labels->width && v < labels->height) {
    const int id = labels->at(u, v);
    text += QObject::tr("  label %1 %2").arg(id).arg(name(id));
    if (frame.proba && u < frame.proba->width && v < frame.proba->height)
      text += QObject::tr(" (p %1)").arg(probabilityOf(*frame.proba, u, v, id), 0, 'f', 2);
  }
  if (frame.proba && selected_label >= 0 && u < frame.proba->width && v < frame.proba->height)
    text += QObject::tr("  p(%1) %2")
                .arg(name(selected_label))
                .arg(probabilityOf(*frame.proba, u, v, selected_label), 0, 'f', 2);
  return text;
}

}  // namespace lom::ui
