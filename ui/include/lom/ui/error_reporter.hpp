#pragma once
// Where the studio sends errors a user can cause (unreadable sequences,
// broken frame files). Injectable so tests and the screenshot mode capture
// them instead of opening a modal dialog.
#include <QString>
#include <functional>

class QWidget;

namespace lom::ui {

using ErrorReporter = std::function<void(const QString& title, const QString& message)>;

// Shows each error in a warning QMessageBox over `parent`; a long message
// (shortMessage) shows its beginning, and the whole of it under Show Details.
[[nodiscard]] ErrorReporter messageBoxErrorReporter(QWidget* parent);

// What a dialog shows of `message` so that it fits on a screen: the message
// itself when it has at most `max_lines` lines and `max_chars` characters;
// else its first lines (cut at a word within `max_chars`), its last
// paragraph when short (the advice messages end with), and a line saying how
// much more Show Details holds. `shortened` tells whether it was cut.
struct ShortMessage {
  QString text;
  bool shortened = false;
};
[[nodiscard]] ShortMessage shortMessage(const QString& message, int max_lines = 14,
                                        int max_chars = 1400);

}  // namespace lom::ui
