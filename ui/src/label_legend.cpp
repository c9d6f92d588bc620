#include "lom/ui/label_legend.hpp"

#include <QHelpEvent>
#include <QPainter>
#include <QToolTip>
#include <algorithm>

namespace lom::ui {

namespace {
constexpr int kSpacing = 10;
constexpr int kGap = 4;
// Names longer than about this many characters are elided, so that one long
// name neither takes a row of its own nor widens the legend.
constexpr int kMaxNameCharacters = 28;
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
  const int max_name_width =
      std::max(0, std::min(width - swatch - kGap, kMaxNameCharacters * metrics.averageCharWidth()));
  int x = 0, y = 0;
  for (const Entry& entry : entries_) {
    const QString name = metrics.elidedText(entry.name, Qt::ElideRight, max_name_width);
    const int entry_width = swatch + kGap + metrics.horizontalAdvance(name);
    if (x > 0 && x + entry_width > width) {
      x = 0;
      y += row_height;
    }
    place(entry, name, QRect(x, y, entry_width, row_height), swatch);
    x += entry_width + kSpacing;
  }
  return y + row_height;
}

int LabelLegend::heightForWidth(int width) const {
  return layOut(width, [](const Entry&, const QString&, const QRect&, int) {});
}

std::vector<QString> LabelLegend::shownNames() const {
  std::vector<QString> names;
  layOut(width(),
         [&](const Entry&, const QString& name, const QRect&, int) { names.push_back(name); });
  return names;
}

QString LabelLegend::toolTipAt(const QPoint& point) const {
  QString tip;
  layOut(width(), [&](const Entry& entry, const QString& name, const QRect& area, int) {
    if (area.contains(point) && name != entry.name) tip = entry.name;
  });
  return tip;
}

bool LabelLegend::event(QEvent* event) {
  if (event->type() != QEvent::ToolTip) return QWidget::event(event);
  const auto* help = static_cast<QHelpEvent*>(event);
  const QString tip = toolTipAt(help->pos());
  if (tip.isEmpty())
    QToolTip::hideText();
  else
    QToolTip::showText(help->globalPos(), tip, this);
  return true;
}

void LabelLegend::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.setPen(palette().color(QPalette::WindowText));
  if (entries_.empty()) {
    painter.drawText(rect(), Qt::AlignLeft | Qt::AlignTop, note_);
    return;
  }
  layOut(width(), [&](const Entry& entry, const QString& name, const QRect& area, int swatch) {
    const QRect box(area.left(), area.top() + (area.height() - swatch) / 2, swatch, swatch);
    painter.fillRect(box, entry.color);
    painter.drawText(area.adjusted(swatch + kGap, 0, 0, 0), Qt::AlignLeft | Qt::AlignVCenter, name);
  });
}

}  // namespace lom::ui
