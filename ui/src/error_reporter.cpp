#include "lom/ui/error_reporter.hpp"

#include <QCoreApplication>
#include <QMessageBox>
#include <QPointer>
#include <QStringList>
#include <algorithm>

namespace lom::ui {

ShortMessage shortMessage(const QString& message, int max_lines, int max_chars) {
  const QStringList lines = message.split('\n');
  if (lines.size() <= max_lines && message.size() <= max_chars) return {message, false};
  // The advice after the last blank line stays when it is short.
  QString advice;
  const int paragraph = message.lastIndexOf(QStringLiteral("\n\n"));
  if (paragraph > 0 && message.size() - paragraph - 2 <= 300 &&
      !message.mid(paragraph + 2).contains('\n'))
    advice = message.mid(paragraph + 2);
  const QString head_source = advice.isEmpty() ? message : message.left(paragraph);
  QStringList head = head_source.split('\n').mid(0, std::max(1, max_lines - 4));
  QString text = head.join('\n');
  const int budget = std::max(200, max_chars - static_cast<int>(advice.size()));
  if (text.size() > budget) {
    int cut = text.lastIndexOf(' ', budget);
    if (cut < budget / 2) cut = budget;
    text = text.left(cut);
  }
  const int shown_lines = static_cast<int>(text.count('\n')) + 1;
  const int more_lines = static_cast<int>(head_source.count('\n')) + 1 - shown_lines;
  text += QStringLiteral(" …\n\n");
  if (more_lines == 1)
    text += QCoreApplication::translate("ErrorReporter",
                                        "(1 more line: Show Details… holds the whole message)");
  else if (more_lines > 1)
    text += QCoreApplication::translate("ErrorReporter",
                                        "(%1 more lines: Show Details… holds the whole message)")
                .arg(more_lines);
  else
    text += QCoreApplication::translate("ErrorReporter",
                                        "(cut short: Show Details… holds the whole message)");
  if (!advice.isEmpty()) text += QStringLiteral("\n\n") + advice;
  return {text, true};
}

ErrorReporter messageBoxErrorReporter(QWidget* parent) {
  // The parent may be gone by the time a late error arrives; QPointer turns
  // that into a parentless box instead of a dangling pointer.
  QPointer<QWidget> guarded_parent(parent);
  return [guarded_parent](const QString& title, const QString& message) {
    const ShortMessage shown = shortMessage(message);
    QMessageBox box(QMessageBox::Warning, title, shown.text, QMessageBox::Ok,
                    guarded_parent.data());
    // Messages name files and fields: let people copy them into a bug report.
    box.setTextInteractionFlags(Qt::TextSelectableByMouse);
    if (shown.shortened) box.setDetailedText(message);
    box.exec();
  };
}

}  // namespace lom::ui
