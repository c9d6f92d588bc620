#include "lom/ui/wheel_guard.hpp"

#include <QAbstractSpinBox>
#include <QComboBox>
#include <QEvent>
#include <QWidget>

namespace lom::ui {

namespace {

class WheelGuard : public QObject {
 public:
  using QObject::QObject;

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (event->type() != QEvent::Wheel) return false;
    const auto* widget = qobject_cast<QWidget*>(watched);
    if (!widget || widget->hasFocus()) return false;
    // Ignored and filtered: Qt then offers the wheel to the parents, so the
    // scroll area around the field scrolls.
    event->ignore();
    return true;
  }
};

}  // namespace

void guardWheel(QWidget& panel) {
  auto* guard = new WheelGuard(&panel);
  auto guardOne = [guard](QWidget* field) {
    field->setFocusPolicy(Qt::StrongFocus);
    field->installEventFilter(guard);
  };
  for (QAbstractSpinBox* box : panel.findChildren<QAbstractSpinBox*>()) guardOne(box);
  for (QComboBox* combo : panel.findChildren<QComboBox*>()) guardOne(combo);
}

}  // namespace lom::ui
