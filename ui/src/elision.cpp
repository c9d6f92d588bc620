#include "lom/ui/elision.hpp"

#include <QAbstractItemView>
#include <QHelpEvent>
#include <QStyleOptionComboBox>
#include <QStylePainter>
#include <QToolTip>
#include <algorithm>

namespace lom::ui {

namespace {
// Enough for a label id and a short name (longer ones are elided, told
// whole in the tooltip), and narrow enough for the docks of a 1024-pixel-wide
// window.
constexpr int kMinimumContentsLength = 12;
}  // namespace

QString shortName(const QString& name, int max_characters) {
  if (name.size() <= max_characters) return name;
  return name.left(std::max(0, max_characters - 1)) + QStringLiteral("…");
}

ElidingComboBox::ElidingComboBox(QWidget* parent) : QComboBox(parent) {
  setSizeAdjustPolicy(QComboBox::AdjustToMinimumContentsLengthWithIcon);
  setMinimumContentsLength(kMinimumContentsLength);
  view()->setTextElideMode(Qt::ElideRight);
}

int ElidingComboBox::textWidth() const {
  QStyleOptionComboBox option;
  initStyleOption(&option);
  const QRect field =
      style()->subControlRect(QStyle::CC_ComboBox, &option, QStyle::SC_ComboBoxEditField, this);
  const int icon = option.currentIcon.isNull() ? 0 : option.iconSize.width() + 4;
  return field.width() - icon - 2;
}

QString ElidingComboBox::shownText() const {
  return fontMetrics().elidedText(currentText(), Qt::ElideRight, textWidth());
}

QString ElidingComboBox::elidedToolTip() const {
  return shownText() == currentText() ? QString() : currentText();
}

bool ElidingComboBox::event(QEvent* event) {
  if (event->type() != QEvent::ToolTip || !toolTip().isEmpty()) return QComboBox::event(event);
  // Asked when shown: the current item may have changed with signals blocked.
  const QString tip = elidedToolTip();
  if (tip.isEmpty())
    QToolTip::hideText();
  else
    QToolTip::showText(static_cast<QHelpEvent*>(event)->globalPos(), tip, this);
  return true;
}

void ElidingComboBox::paintEvent(QPaintEvent*) {
  QStylePainter painter(this);
  painter.setPen(palette().color(QPalette::Text));
  QStyleOptionComboBox option;
  initStyleOption(&option);
  painter.drawComplexControl(QStyle::CC_ComboBox, option);
  option.currentText = shownText();
  painter.drawControl(QStyle::CE_ComboBoxLabel, option);
}

}  // namespace lom::ui
