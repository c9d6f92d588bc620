#pragma once
// Answers the modal dialogs the studio opens while a test runs: every message
// box gets the button whose text (without '&') starts with `button`, and every
// file dialog gets `file` chosen (or is cancelled when `file` is empty). What
// was asked is recorded for the test to check.
#include <QAbstractButton>
#include <QApplication>
#include <QFileDialog>
#include <QMessageBox>
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

  void setButton(const QString& button) { button_ = button; }
  void setFile(const QString& file) { file_ = file; }

 private:
  void answer() {
    for (QWidget* widget : QApplication::topLevelWidgets()) {
      if (!widget->isVisible()) continue;
      if (auto* box = qobject_cast<QMessageBox*>(widget)) {
        questions << box->text();
        for (QAbstractButton* candidate : box->buttons())
          if (candidate->text().remove('&').startsWith(button_)) {
            candidate->click();
            return;
          }
        box->reject();  // no such button: as Escape would
        return;
      }
      if (auto* dialog = qobject_cast<QFileDialog*>(widget)) {
        const QStringList selected = dialog->selectedFiles();
        proposed_files << (selected.isEmpty() ? QString() : selected.front());
        if (file_.isEmpty()) {
          dialog->reject();
        } else {
          dialog->selectFile(file_);
          static_cast<QDialog*>(dialog)->accept();  // as the Save/Open button does
        }
        return;
      }
    }
  }

  QString button_;
  QString file_;
  QTimer timer_;
};

}  // namespace lom::ui::test
