// Every control Tab reaches has a name a screen reader can say: its own, a
// label's that is its buddy, or its text; a tooltip alone is only a
// description.
#include <gtest/gtest.h>

#include <QAccessible>
#include <QApplication>
#include <QLabel>
#include <QTest>
#include <cmath>

#include "demo_window_fixture.hpp"
#include "lom/ui/main_window.hpp"

namespace lom::ui {
namespace {

class AccessibleNamesTest : public fixture::DemoWindowTest {};

TEST_F(AccessibleNamesTest, EveryControlTabReachesHasAName) {
  openAndFuse();
  QStringList unnamed;
  for (QWidget* widget : window_.findChildren<QWidget*>()) {
    if (!(widget->focusPolicy() & Qt::TabFocus) || !widget->isEnabled()) continue;
    if (widget->focusProxy() != nullptr) continue;  // the proxy is the one reached
    // Parts of a control that are not controls of their own (a combo box's
    // popup, a spin box's line edit, a scroll bar, a tab bar's tabs).
    if (!widget->isVisibleTo(&window_)) continue;
    const QString class_name = widget->metaObject()->className();
    if (class_name == "QLineEdit" && widget->parentWidget() &&
        (widget->parentWidget()->inherits("QAbstractSpinBox") ||
         widget->parentWidget()->inherits("QComboBox")))
      continue;
    if (widget->inherits("QTabBar") || widget->inherits("QScrollBar")) continue;
    QAccessibleInterface* accessible = QAccessible::queryAccessibleInterface(widget);
    ASSERT_NE(accessible, nullptr);
    if (accessible->text(QAccessible::Name).trimmed().isEmpty())
      unnamed << QString("%1 \"%2\"").arg(class_name, widget->objectName());
  }
  EXPECT_TRUE(unnamed.isEmpty()) << unnamed.join(", ").toStdString();
}

// WCAG's contrast ratio of two colours (1 to 21; text needs 4.5).
double contrast(const QColor& a, const QColor& b) {
  const auto luminance = [](const QColor& c) {
    const auto channel = [](double v) {
      return v <= 0.03928 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    };
    return 0.2126 * channel(c.redF()) + 0.7152 * channel(c.greenF()) + 0.0722 * channel(c.blueF());
  };
  const double la = luminance(a), lb = luminance(b);
  return (std::max(la, lb) + 0.05) / (std::min(la, lb) + 0.05);
}

TEST_F(AccessibleNamesTest, TheScoreWarningsReadOnTheirBackground) {
  auto* warnings = window_.findChild<QLabel*>("evaluationWarnings");
  ASSERT_NE(warnings, nullptr);
  const QPalette colours = warnings->palette();
  EXPECT_GE(contrast(colours.color(QPalette::WindowText), colours.color(QPalette::Window)), 4.5);
}

}  // namespace
}  // namespace lom::ui
