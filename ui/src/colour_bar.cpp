#include "lom/ui/colour_bar.hpp"

#include <QColor>
#include <QLinearGradient>
#include <QPainter>

namespace lom::ui {

ColourBar::ColourBar(std::function<QColor(double)> colour, QString caption, QWidget* parent)
    : QWidget(parent), colour_(std::move(colour)), caption_(std::move(caption)) {
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Fixed);
}

void ColourBar::setRange(std::optional<std::pair<double, double>> range) {
  range_ = range;
  update();
}

void ColourBar::paintEvent(QPaintEvent*) {
  if (!range_) return;
  QPainter painter(this);
  const int text_height = fontMetrics().height();
  const QRect bar(4, 2, width() - 8, height() - text_height - 6);

  QLinearGradient gradient(bar.topLeft(), bar.topRight());
  constexpr int kStops = 16;
  for (int i = 0; i <= kStops; ++i) {
    const double t = double(i) / kStops;
    gradient.setColorAt(t, colour_(t));
  }
  painter.fillRect(bar, gradient);
  painter.setPen(palette().color(QPalette::Mid));
  painter.drawRect(bar.adjusted(0, 0, -1, -1));

  painter.setPen(palette().color(QPalette::WindowText));
  const QRect text_row(bar.left(), bar.bottom() + 2, bar.width(), text_height);
  painter.drawText(text_row, Qt::AlignLeft, QString::number(range_->first, 'f', 2) + " m");
  painter.drawText(text_row, Qt::AlignHCenter, caption_);
  painter.drawText(text_row, Qt::AlignRight, QString::number(range_->second, 'f', 2) + " m");
}

}  // namespace lom::ui
