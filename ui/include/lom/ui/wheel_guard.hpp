#pragma once
// Spin boxes and combo boxes take the mouse wheel only when they have the
// keyboard focus (a click or Tab gives it). Otherwise the wheel scrolls the
// panel they sit in: scrolling a dock past the Boxes fields must not relabel,
// move or turn the selected box.
class QWidget;

namespace lom::ui {

// Guards every spin box and combo box inside `panel` (present when called).
void guardWheel(QWidget& panel);

}  // namespace lom::ui
