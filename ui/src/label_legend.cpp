#include "lom/ui/label_legend.hpp"

#include <QPainter>

namespace lom::ui {

namespace {
constexpr int kSpacing = 10;
constexpr int kGap = 4;
}  // namespace

LabelLegend::LabelLegend(QWidget* parent) : QWidget(parent) {
  QSizePolicy policy(QSizePolicy::Preferred, QSizePolicy::Preferred);
  policy.setHeightForWidth(true);
  setSizePolicy(policy);
}

void LabelLegend::setEntries(std::vector<Entry> entries) {
  entries_ = std::move(entries);
  updateGeometry();
  update();
}

void LabelLegend::setNote(const QString& note) {
  note_ = note;
  update();
}

template <typename Place>
int LabelLegend::layOut(int width, Place place) const {
  const QFontMetrics metrics = fontMetrics();
  const int row_height = metrics.height() + kGap;
  const int swatch = metrics.ascent();
  int x = 0, y = 0;
  for (const Entry& entry : entries_) {
    const int entry_width = swatch + kGap + metrics.horizontalAdvance(entry.name);
    if (x > 0 && x + entry_width > width) {
      x = 0;
      y += row_height;
    }
    place(entry, QRect(x, y, entry_width, row_height), swatch);
    x += entry_width + kSpacing;
  }
  return y + row_height;
}

int LabelLegend::heightForWidth(int width) const {
  return layOut(width, [](const Entry&, const QRect&, int) {});
}

void LabelLegend::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.setPen(palette().color(QPalette::WindowText));
  if (entries_.empty()) {
    painter.drawText(rect(), Qt::AlignLeft | Qt::AlignTop, note_);
    return;
  }
  layOut(width(), [&](const Entry& entry, const QRect& area, int swatch) {
    const QRect box(area.left(), area.top() + (area.height() - swatch) / 2, swatch, swatch);
    painter.fillRect(box, entry.color);
    painter.drawText(area.adjusted(swatch + kGap, 0, 0, 0), Qt::AlignLeft | Qt::AlignVCenter,
                     entry.name);
  });
}

}  // namespace lom::ui
