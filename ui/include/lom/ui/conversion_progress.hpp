#pragma once
// The progress of a ROS bag's or dataset folder's conversion when it is
// opened: a modal dialog over the window ("Converting NAME…", frames done of
// total) whose Cancel stops the conversion and keeps the open sequence.
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
  void cancel();
  void close();

  QWidget* window_;
  SequenceController& controller_;
  QPointer<QProgressDialog> dialog_;
  QProgressBar* bar_ = nullptr;
  QPushButton* cancel_button_ = nullptr;
  int done_ = 0;
  int total_ = 0;
};

}  // namespace lom::ui
