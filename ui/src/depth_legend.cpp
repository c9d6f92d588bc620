#include "lom/ui/depth_legend.hpp"

#include <QLinearGradient>
#include <QPainter>

namespace lom::ui {

DepthLegend::DepthLegend(QWidget* parent) : QWidget(parent) {
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Fixed);
}

void DepthLegend::setRange(std::optional<DepthRange> range) {
  range_ = range;
  update();
}

void DepthLegend::paintEvent(QPaintEvent*) {
  if (!range_) return;
  QPainter painter(this);
  const int text_height = fontMetrics().height();
  const QRect bar(4, 2, width() - 8, height() - text_height - 6);

  QLinearGradient gradient(bar.topLeft(), bar.topRight());
  constexpr int kStops = 16;
  for (int i = 0; i <= kStops; ++i) {
    const double t = double(i) / kStops;
    gradient.setColorAt(t, depthColor(t));
  }
  painter.fillRect(bar, gradient);
  painter.setPen(palette().color(QPalette::Mid));
  painter.drawRect(bar.adjusted(0, 0, -1, -1));

  painter.setPen(palette().color(QPalette::WindowText));
  const QRect text_row(bar.left(), bar.bottom() + 2, bar.width(), text_height);
  painter.drawText(text_row, Qt::AlignLeft, QString::number(range_->near_metres, 'f', 2) + " m");
  painter.drawText(text_row, Qt::AlignHCenter, tr("depth"));
  painter.drawText(text_row, Qt::AlignRight, QString::number(range_->far_metres, 'f', 2) + " m");
}

}  // namespace lom::ui
