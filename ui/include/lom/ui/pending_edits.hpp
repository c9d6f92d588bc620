#pragma once
// Numeric fields commit a typed value only when editing finishes (Enter or
// leaving the field). Whatever decides about unsaved work (closing, opening
// another sequence or boxes, saving) first commits the value being typed, so
// it is neither lost nor left out.
namespace lom::ui {

// Commits the text of the spin box that has the keyboard focus, if any; true
// when a spin box has the focus (a value may be being typed).
bool commitPendingEdits();

}  // namespace lom::ui
