#include "lom/ui/conversion_progress.hpp"

#include <QApplication>
#include <QEvent>
#include <QProgressBar>
#include <QProgressDialog>
#include <QPushButton>
#include <QWidget>
#include <QWindow>
#include <algorithm>

#include "lom/ui/sequence_controller.hpp"

namespace lom::ui {

namespace {

// The input that a modal dialog keeps from the windows it blocks.
bool isUserInput(QEvent::Type type) {
  switch (type) {
    case QEvent::MouseButtonPress:
    case QEvent::MouseButtonRelease:
    case QEvent::MouseButtonDblClick:
    case QEvent::MouseMove:
    case QEvent::Wheel:
    case QEvent::KeyPress:
    case QEvent::KeyRelease:
    case QEvent::ShortcutOverride:
    case QEvent::Shortcut:
    case QEvent::ContextMenu:
    case QEvent::DragEnter:
    case QEvent::DragMove:
    case QEvent::Drop:
    case QEvent::TouchBegin:
    case QEvent::TouchUpdate:
    case QEvent::TouchEnd:
    case QEvent::TabletPress:
    case QEvent::TabletMove:
    case QEvent::TabletRelease:
    case QEvent::NativeGesture:
    case QEvent::Gesture:
      return true;
    default:
      return false;
  }
}

// The window (top-level widget) that `watched` belongs to, if it is a widget
// or a widget's window.
QWidget* windowOf(QObject* watched) {
  if (auto* widget = qobject_cast<QWidget*>(watched)) return widget->window();
  if (auto* window = qobject_cast<QWindow*>(watched))
    for (QWidget* top : QApplication::topLevelWidgets())
      if (top->windowHandle() == window) return top;
  return nullptr;
}

}  // namespace

ConversionProgress::ConversionProgress(QWidget* window, SequenceController& controller)
    : QObject(window), window_(window), controller_(controller) {
  connect(&controller_, &SequenceController::conversionStarted, this, &ConversionProgress::show);
  connect(&controller_, &SequenceController::conversionProgress, this,
          &ConversionProgress::setProgress);
  connect(&controller_, &SequenceController::conversionReading, this,
          &ConversionProgress::setReading);
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
  if (dialog_ && isUserInput(event->type()) && blocksInput(watched, event)) {
    // As a modal dialog does, a click on the window brings it back to the front.
    if (event->type() == QEvent::MouseButtonPress) {
      dialog_->raise();
      dialog_->activateWindow();
    }
    return true;
  }
  return QObject::eventFilter(watched, event);
}

bool ConversionProgress::blocksInput(QObject* watched, QEvent* event) const {
  // A shortcut goes to its action, of whichever window has the keyboard.
  QWidget* target =
      event->type() == QEvent::Shortcut ? QApplication::activeWindow() : windowOf(watched);
  // The dialog and a question asked meanwhile (closing the window asks) take
  // their input; so do windows that are not the studio's main window's.
  if (!target || target == dialog_ || target->isModal()) return false;
  for (QWidget* widget = target; widget; widget = widget->parentWidget())
    if (widget == window_) return true;
  return false;
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
  dialog->setBar(bar_);
  cancel_button_ = new QPushButton(tr("Cancel"), dialog);
  dialog->setCancelButton(cancel_button_);
  dialog->setAutoReset(false);
  dialog->setAutoClose(false);
  dialog->setMinimumDuration(0);
  dialog->setMinimumWidth(420);
  // Not modal: Qt drops a close of the window a modal dialog blocks without
  // a word, and closing the window during a conversion asks whether to stop
  // it (MainWindow::closeEvent). The window's input is kept from it here
  // instead (eventFilter), so that the open sequence does not change under
  // the conversion that will replace it.
  dialog->setWindowModality(Qt::NonModal);
  // Cancel and Escape end here; the dialog does not hide itself then (it
  // would unblock the window while the conversion still winds down).
  QObject::disconnect(dialog, SIGNAL(canceled()), dialog, SLOT(cancel()));
  connect(dialog, &QProgressDialog::canceled, this, &ConversionProgress::cancel);
  dialog->installEventFilter(this);
  qApp->installEventFilter(this);
  dialog_ = dialog;
  updateBar();
  dialog->show();
}

void ConversionProgress::setProgress(int done, int total) {
  done_ = done;
  total_ = total;
  reading_ = -1;
  updateBar();
}

void ConversionProgress::setReading(int per_mille) {
  reading_ = std::clamp(per_mille, 0, 1000);
  updateBar();
}

void ConversionProgress::updateBar() {
  if (!dialog_ || !cancel_button_->isEnabled()) return;
  if (reading_ >= 0) {
    // A compressed bag is read through before its first frame (for a minute,
    // when large): the bar moves meanwhile.
    bar_->setFormat(tr("Reading the recording: %p%"));
    bar_->setRange(0, 1000);
    bar_->setValue(reading_);
    bar_->setTextVisible(true);
    return;
  }
  bar_->setFormat(tr("%v of %m frames"));
  if (total_ <= 0) {
    bar_->setRange(0, 0);  // a busy indicator until the number of frames is known
    bar_->setTextVisible(false);
    return;
  }
  bar_->setRange(0, total_);
  bar_->setValue(std::clamp(done_, 0, total_));
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
  reading_ = -1;
  qApp->removeEventFilter(this);
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
