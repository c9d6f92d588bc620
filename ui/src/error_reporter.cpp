#include "lom/ui/error_reporter.hpp"

#include <QMessageBox>
#include <QPointer>

namespace lom::ui {

ErrorReporter messageBoxErrorReporter(QWidget* parent) {
  // The parent may be gone by the time a late error arrives; QPointer turns
  // that into a parentless box instead of a dangling pointer.
  QPointer<QWidget> guarded_parent(parent);
  return [guarded_parent](const QString& title, const QString& message) {
    QMessageBox box(QMessageBox::Warning, title, message, QMessageBox::Ok, guarded_parent.data());
    // Messages name files and fields: let people copy them into a bug report.
    box.setTextInteractionFlags(Qt::TextSelectableByMouse);
    box.exec();
  };
}

}  // namespace lom::ui
