#include "lom/ui/conversion_progress.hpp"

#include <QEvent>
#include <QProgressBar>
#include <QProgressDialog>
#include <QPushButton>
#include <QWidget>
#include <algorithm>

#include "lom/ui/sequence_controller.hpp"

namespace lom::ui {

ConversionProgress::ConversionProgress(QWidget* window, SequenceController& controller)
    : QObject(window), window_(window), controller_(controller) {
  connect(&controller_, &SequenceController::conversionStarted, this, &ConversionProgress::show);
  connect(&controller_, &SequenceController::conversionProgress, this,
          &ConversionProgress::setProgress);
  connect(&controller_, &SequenceController::conversionFinished, this, &ConversionProgress::close);
}

bool ConversionProgress::eventFilter(QObject* watched, QEvent* event) {
  // Closing the dialog cancels; it stays to say so until the conversion ends.
  // The event's type is looked at first: a dialog being destroyed (no longer a
  // QProgressDialog) still sends events through this filter as it hides.
  if (event->type() == QEvent::Close && watched == dialog_) {
    event->ignore();
    cancel();
    return true;
  }
  return QObject::eventFilter(watched, event);
}

void ConversionProgress::show(const QString& name) {
  if (dialog_ || !window_->isVisible()) return;
  auto* dialog = new QProgressDialog(window_);
  dialog->setObjectName("conversionProgress");
  dialog->setWindowTitle(tr("Opening %1").arg(name));
  dialog->setLabelText(tr("Converting %1…").arg(name));
  // The bar and the button are ours, so that the bar can be updated without
  // QProgressDialog::setValue (which processes events) and the button
  // disabled once pressed.
  bar_ = new QProgressBar(dialog);
  bar_->setFormat(tr("%v of %m frames"));
  dialog->setBar(bar_);
  cancel_button_ = new QPushButton(tr("Cancel"), dialog);
  dialog->setCancelButton(cancel_button_);
  dialog->setAutoReset(false);
  dialog->setAutoClose(false);
  dialog->setMinimumDuration(0);
  dialog->setMinimumWidth(420);
  dialog->setWindowModality(Qt::WindowModal);
  // Cancel and Escape end here; the dialog does not hide itself then (it
  // would unblock the window while the conversion still winds down).
  QObject::disconnect(dialog, SIGNAL(canceled()), dialog, SLOT(cancel()));
  connect(dialog, &QProgressDialog::canceled, this, &ConversionProgress::cancel);
  dialog->installEventFilter(this);
  dialog_ = dialog;
  setProgress(done_, total_);
  dialog->show();
}

void ConversionProgress::setProgress(int done, int total) {
  done_ = done;
  total_ = total;
  if (!dialog_ || !cancel_button_->isEnabled()) return;
  if (total <= 0) {
    bar_->setRange(0, 0);  // a busy indicator until the number of frames is known
    bar_->setTextVisible(false);
    return;
  }
  bar_->setRange(0, total);
  bar_->setValue(std::clamp(done, 0, total));
  bar_->setTextVisible(true);
}

void ConversionProgress::cancel() {
  controller_.cancelConversion();
  if (!dialog_ || !cancel_button_->isEnabled()) return;
  // The importer stops after the frame it is converting.
  dialog_->setLabelText(tr("Cancelling…"));
  cancel_button_->setEnabled(false);
  bar_->setRange(0, 0);
  bar_->setTextVisible(false);
}

void ConversionProgress::close() {
  done_ = 0;
  total_ = 0;
  // Deleted at once: QProgressDialog's own timer would show it again. The
  // filter goes first, so that the events of its destruction do not reach it.
  QProgressDialog* dialog = dialog_;
  dialog_ = nullptr;
  bar_ = nullptr;
  cancel_button_ = nullptr;
  if (!dialog) return;
  dialog->removeEventFilter(this);
  delete dialog;
}

}  // namespace lom::ui
