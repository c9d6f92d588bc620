#include "lom/ui/score_chart.hpp"

#include <QPainter>
#include <algorithm>
#include <cmath>

namespace lom::ui {

namespace {

// Least free space between two label ids under the axis, in pixels.
constexpr int kAxisLabelGap = 6;

}  // namespace

ScoreChart::ScoreChart(QWidget* parent) : QWidget(parent) {
  setObjectName("scoreChart");
  setMinimumHeight(kMinimumHeight);
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

QRect ScoreChart::plotRect() const {
  const QFontMetrics metrics = fontMetrics();
  const int legend_height = metrics.height() + 4;
  return rect().adjusted(28, legend_height + 4, -6, -metrics.height() - 6);
}

std::vector<ScoreChart::AxisLabel> ScoreChart::axisLabels() const {
  const QRect plot = plotRect();
  if (objects_.empty() || plot.width() <= 0) return {};
  const QFontMetrics metrics = fontMetrics();
  const double group = static_cast<double>(plot.width()) / static_cast<double>(objects_.size());
  int widest = 0;
  for (const ObjectScore& object : objects_)
    widest = std::max(widest, metrics.horizontalAdvance(QString::number(object.label)));
  // Every step-th label: centred under its group they are at least a gap apart.
  const auto step = static_cast<size_t>(
      std::max(1.0, std::ceil(static_cast<double>(widest + kAxisLabelGap) / group)));
  std::vector<AxisLabel> labels;
  for (size_t i = 0; i < objects_.size(); i += step) {
    const int text_width = metrics.horizontalAdvance(QString::number(objects_[i].label));
    const double centre = plot.left() + group * (static_cast<double>(i) + 0.5);
    // Kept inside the widget; one pushed in at an edge may then crowd its
    // neighbour, and is left out.
    const int left = std::clamp(static_cast<int>(std::lround(centre - text_width / 2.0)), 0,
                                std::max(0, width() - text_width));
    const QRect rect(left, plot.bottom() + 2, text_width, metrics.height());
    if (!labels.empty() && rect.left() < labels.back().rect.right() + 1 + kAxisLabelGap) continue;
    labels.push_back({i, rect});
  }
  return labels;
}

std::vector<ScoreChart::GridLabel> ScoreChart::gridLabels() const {
  const QRect plot = plotRect();
  const int text_height = fontMetrics().height();
  int step = 100;  // the fewest: 0 and 100
  for (int candidate : {25, 50})
    if (plot.height() * candidate / 100 > text_height) {
      step = candidate;
      break;
    }
  std::vector<GridLabel> labels;
  for (int percent = 0; percent <= 100; percent += step) {
    const int y = plot.bottom() - plot.height() * percent / 100;
    labels.push_back({percent, QRect(0, y - text_height / 2, 24, text_height)});
  }
  return labels;
}

void ScoreChart::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.fillRect(rect(), palette().base());
  const QFontMetrics metrics = fontMetrics();
  const QRect plot = plotRect();
  for (const GridLabel& label : gridLabels()) {
    const int y = label.rect.center().y();
    painter.setPen(palette().color(QPalette::Mid));  // faint lines
    painter.drawLine(plot.left(), y, plot.right(), y);
    // Numbers in the text colour: the grid's grey on white was 2:1, too faint to read.
    painter.setPen(palette().color(QPalette::Text));
    painter.drawText(label.rect, Qt::AlignRight | Qt::AlignVCenter, QString::number(label.percent));
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
  const double group = static_cast<double>(plot.width()) / static_cast<double>(objects_.size());
  const double bar = std::max(1.0, group * 0.8 / 3.0);
  for (size_t i = 0; i < objects_.size(); ++i) {
    const MethodScores& s = objects_[i].iou_3d;
    const double values[3] = {s.projection_mean, s.projection_max, s.labeloctomap};
    const double left = plot.left() + group * static_cast<double>(i) + group * 0.1;
    for (int m = 0; m < 3; ++m) {
      const int height = static_cast<int>(plot.height() * std::clamp(values[m], 0.0, 1.0));
      painter.fillRect(QRectF(left + bar * m, plot.bottom() - height, bar - 1, height),
                       methodColor(m));
    }
  }
  painter.setPen(palette().color(QPalette::Text));
  for (const AxisLabel& label : axisLabels())
    painter.drawText(label.rect, Qt::AlignCenter, QString::number(objects_[label.object].label));
}

}  // namespace lom::ui
