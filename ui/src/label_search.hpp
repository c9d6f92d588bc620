#pragma once
// Keys in the studio's fields and label drop-downs: which of them the window's
// one-key shortcuts get, and finding a label by typing its name.
#include <QEvent>
#include <QKeyEvent>
#include <QObject>
#include <functional>
#include <optional>

class QComboBox;

namespace lom::ui {

// Decides, for a widget with the focus, who gets a key the window has a
// shortcut for: `take` returns true when the widget takes it (it gets the key
// press), false when it leaves it to the window's shortcut, nothing for Qt's
// default.
class ShortcutKeys : public QObject {
 public:
  ShortcutKeys(QObject* parent, std::function<std::optional<bool>(const QKeyEvent&)> take)
      : QObject(parent), take_(std::move(take)) {}

 protected:
  bool eventFilter(QObject*, QEvent* event) override {
    if (event->type() != QEvent::ShortcutOverride) return false;
    const std::optional<bool> take = take_(*static_cast<QKeyEvent*>(event));
    if (!take) return false;
    event->setAccepted(*take);
    return true;
  }

 private:
  std::function<std::optional<bool>(const QKeyEvent&)> take_;
};

// Letters typed into a label drop-down ("10 dove_beauty_bar") with the focus
// find a label by its name, and are not the window's one-key box edits (W
// moves a box, B adds one), which would otherwise change a box while the user
// picks a label. Letters typed within a second add up ("do" finds
// dove_beauty_bar past dasani_water_bottle); the choice counts as the user's
// (activated). The filters are children of `combo`.
void searchLabelsByName(QComboBox& combo);

}  // namespace lom::ui
