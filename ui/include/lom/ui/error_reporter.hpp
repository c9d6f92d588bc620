#pragma once
// Where the studio sends errors a user can cause (unreadable sequences,
// broken frame files). Injectable so tests and the screenshot mode capture
// them instead of opening a modal dialog.
#include <QString>
#include <functional>

class QWidget;

namespace lom::ui {

using ErrorReporter = std::function<void(const QString& title, const QString& message)>;

// Shows each error in a warning QMessageBox over `parent`.
[[nodiscard]] ErrorReporter messageBoxErrorReporter(QWidget* parent);

}  // namespace lom::ui
