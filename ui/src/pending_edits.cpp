#include "lom/ui/pending_edits.hpp"

#include <QAbstractSpinBox>
#include <QApplication>
#include <QWidget>

namespace lom::ui {

bool commitPendingEdits() {
  // The focus is on the spin box's line edit, a child of the spin box.
  for (QWidget* widget = QApplication::focusWidget(); widget; widget = widget->parentWidget())
    if (auto* spin = qobject_cast<QAbstractSpinBox*>(widget)) {
      spin->interpretText();
      return true;
    }
  return false;
}

}  // namespace lom::ui
