#pragma once
// Answers the modal dialogs the studio opens while a test runs: every message
// box gets the button whose text (without '&') starts with `button` (or with
// one of its alternatives separated by '|', the first that fits), and every
// file dialog gets `file` chosen (or is cancelled when `file` is empty). What
// was asked is recorded for the test to check.
#include <QAbstractButton>
#include <QApplication>
#include <QFileDialog>
#include <QFileInfo>
#include <QLineEdit>
#include <QList>
#include <QMessageBox>
#include <QMetaObject>
#include <QPointer>
#include <QString>
#include <QStringList>
#include <QTimer>

namespace lom::ui::test {

class DialogAnswerer {
 public:
  explicit DialogAnswerer(QString button, QString file = {})
      : button_(std::move(button)), file_(std::move(file)) {
    timer_.setInterval(20);
    QObject::connect(&timer_, &QTimer::timeout, [this] { answer(); });
    timer_.start();
  }

  // Texts of the message boxes answered, in order.
  QStringList questions;
  // The file each file dialog proposed when it opened.
  QStringList proposed_files;

 private:
  // The answers are queued, not given from the timer: a dialog may ask
  // another question while it closes, and a timer is not re-entered.
  void answer() {
    // A message box first: it may be asked on top of a file dialog.
    for (QWidget* widget : QApplication::topLevelWidgets()) {
      auto* box = qobject_cast<QMessageBox*>(widget);
      if (!box || !box->isVisible()) continue;
      if (answered_.contains(box)) continue;
      answered_ << box;
      questions << box->text();
      for (const QString& wanted : button_.split('|'))
        for (QAbstractButton* candidate : box->buttons())
          if (candidate->text().remove('&').startsWith(wanted)) {
            QMetaObject::invokeMethod(candidate, "click", Qt::QueuedConnection);
            return;
          }
      QMetaObject::invokeMethod(box, "reject", Qt::QueuedConnection);  // as Escape would
      return;
    }
    for (QWidget* widget : QApplication::topLevelWidgets()) {
      auto* dialog = qobject_cast<QFileDialog*>(widget);
      if (!dialog || !dialog->isVisible() || answered_.contains(dialog)) continue;
      answered_ << dialog;
      const QStringList selected = dialog->selectedFiles();
      proposed_files << (selected.isEmpty() ? QString() : selected.front());
      if (file_.isEmpty()) {
        QMetaObject::invokeMethod(dialog, "reject", Qt::QueuedConnection);
      } else {
        dialog->selectFile(file_);
        // selectFile leaves the name field alone while it has the keyboard
        // focus (a dialog that became active before this answer): the name
        // is typed into it, as a user would.
        if (auto* name = dialog->findChild<QLineEdit*>(QStringLiteral("fileNameEdit")))
          name->setText(QFileInfo(file_).fileName());
        // As the Save/Open button does.
        QMetaObject::invokeMethod(dialog, "accept", Qt::QueuedConnection);
      }
      return;
    }
  }

  QString button_;
  QString file_;
  QList<QPointer<QDialog>> answered_;  // each dialog is answered once
  QTimer timer_;
};

}  // namespace lom::ui::test
