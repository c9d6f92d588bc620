#pragma once
// The progress of a ROS bag's or dataset folder's conversion when it is
// opened: a dialog over the window ("Converting NAME…", how far the recording
// has been read, then frames done of total) whose Cancel stops the conversion
// and keeps the open sequence. The window takes no input meanwhile, as under a
// modal dialog, except that it can still be closed (which asks first).
#include <QObject>
#include <QPointer>
#include <QString>

class QProgressBar;
class QProgressDialog;
class QPushButton;
class QWidget;

namespace lom::ui {

class SequenceController;

class ConversionProgress : public QObject {
  Q_OBJECT

 public:
  // The dialog is shown over `window`, and only while `window` is on screen
  // (a window that is never shown converts without one).
  ConversionProgress(QWidget* window, SequenceController& controller);

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  void show(const QString& name);
  void setProgress(int done, int total);
  void setReading(int per_mille);
  void updateBar();
  void cancel();
  void close();
  // Whether `event` for `watched` is input to the window (or a panel floated
  // from it) that the dialog keeps from it.
  [[nodiscard]] bool blocksInput(QObject* watched, QEvent* event) const;

  QWidget* window_;
  SequenceController& controller_;
  QPointer<QProgressDialog> dialog_;
  QProgressBar* bar_ = nullptr;
  QPushButton* cancel_button_ = nullptr;
  int done_ = 0;
  int total_ = 0;
  int reading_ = -1;  // thousandths of the recording read before its frames; -1 after
};

}  // namespace lom::ui
