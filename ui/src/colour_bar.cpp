#include "lom/ui/colour_bar.hpp"

#include <QColor>
#include <QFontMetrics>
#include <QLinearGradient>
#include <QPainter>
#include <algorithm>

namespace lom::ui {

ColourBar::ColourBar(std::function<QColor(double)> colour, QString caption, QWidget* parent,
                     QString unit)
    : QWidget(parent),
      colour_(std::move(colour)),
      caption_(std::move(caption)),
      unit_(std::move(unit)) {
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
  const QStringList texts = shownTexts();
  if (texts.size() < 2) return;
  painter.drawText(text_row, Qt::AlignLeft, texts.front());
  if (texts.size() == 3) painter.drawText(text_row, Qt::AlignHCenter, texts[1]);
  painter.drawText(text_row, Qt::AlignRight, texts.back());
}

QStringList ColourBar::shownTexts() const {
  if (!range_) return {};
  const QString low = QString::number(range_->first, 'f', 2) + unit_;
  const QString high = QString::number(range_->second, 'f', 2) + unit_;
  const QFontMetrics metrics = fontMetrics();
  const int room = width() - 8;  // the bar's width
  const int gap = metrics.horizontalAdvance(QStringLiteral("  "));
  const int ends = std::max(metrics.horizontalAdvance(low), metrics.horizontalAdvance(high));
  // The caption sits in the middle: it needs the ends' room on both sides.
  if (2 * (ends + gap) + metrics.horizontalAdvance(caption_) <= room) return {low, caption_, high};
  if (metrics.horizontalAdvance(low) + gap + metrics.horizontalAdvance(high) <= room)
    return {low, high};
  return {};  // too narrow for the numbers: the colours alone
}

}  // namespace lom::ui
