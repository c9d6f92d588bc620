#include "lom/ui/score_chart.hpp"

#include <QPainter>

namespace lom::ui {

ScoreChart::ScoreChart(QWidget* parent) : QWidget(parent) {
  setObjectName("scoreChart");
  setMinimumHeight(130);
}

void ScoreChart::setObjects(std::vector<ObjectScore> objects) {
  objects_ = std::move(objects);
  update();
}

QColor ScoreChart::methodColor(int method) {
  static const QColor colors[3] = {QColor(150, 160, 175), QColor(90, 120, 200),
                                   QColor(230, 120, 30)};
  return colors[method % 3];
}

void ScoreChart::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.fillRect(rect(), palette().base());
  const QFontMetrics metrics = fontMetrics();
  const int legend_height = metrics.height() + 4;
  const QRect plot = rect().adjusted(28, legend_height + 4, -6, -metrics.height() - 6);
  painter.setPen(palette().color(QPalette::Mid));
  for (int percent = 0; percent <= 100; percent += 25) {
    const int y = plot.bottom() - plot.height() * percent / 100;
    painter.drawLine(plot.left(), y, plot.right(), y);
    painter.drawText(QRect(0, y - metrics.height() / 2, 24, metrics.height()),
                     Qt::AlignRight | Qt::AlignVCenter, QString::number(percent));
  }
  const QString names[3] = {tr("Proj. mean"), tr("Proj. max"), tr("LabelOctoMap")};
  int x = plot.left();
  for (int m = 0; m < 3; ++m) {
    painter.fillRect(x, 4, 10, 10, methodColor(m));
    painter.setPen(palette().color(QPalette::Text));
    painter.drawText(x + 14, 4 + metrics.ascent() - 1, names[m]);
    x += 20 + metrics.horizontalAdvance(names[m]);
  }
  if (objects_.empty() || plot.width() <= 0) return;
  const double group = static_cast<double>(plot.width()) / objects_.size();
  const double bar = std::max(1.0, group * 0.8 / 3.0);
  for (size_t i = 0; i < objects_.size(); ++i) {
    const MethodScores& s = objects_[i].iou_3d;
    const double values[3] = {s.projection_mean, s.projection_max, s.labeloctomap};
    const double left = plot.left() + group * i + group * 0.1;
    for (int m = 0; m < 3; ++m) {
      const int height = static_cast<int>(plot.height() * std::clamp(values[m], 0.0, 1.0));
      painter.fillRect(QRectF(left + bar * m, plot.bottom() - height, bar - 1, height),
                       methodColor(m));
    }
    painter.setPen(palette().color(QPalette::Text));
    painter.drawText(QRectF(plot.left() + group * i, plot.bottom() + 2, group, metrics.height()),
                     Qt::AlignHCenter | Qt::AlignTop, QString::number(objects_[i].label));
  }
}

}  // namespace lom::ui
