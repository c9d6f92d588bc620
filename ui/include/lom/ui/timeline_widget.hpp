#pragma once
// Frame navigation under the views: step buttons, a slider and the frame number.
#include <QWidget>

class QAction;
class QComboBox;
class QLabel;
class QSlider;
class QSpinBox;
class QTimer;
class QToolButton;

namespace lom::ui {

class TimelineWidget : public QWidget {
  Q_OBJECT

 public:
  struct StepActions {
    QAction* first;
    QAction* previous;
    QAction* next;
    QAction* last;
  };

  explicit TimelineWidget(const StepActions& actions, QWidget* parent = nullptr);

  void setFrameCount(int count);  // 0 disables the timeline
  void setCurrentFrame(int index);
  [[nodiscard]] QSlider& slider() { return *slider_; }
  // Playback: steps one frame per tick at the chosen speed, stops at the end.
  void setPlaying(bool playing);
  [[nodiscard]] bool isPlaying() const;
  [[nodiscard]] QComboBox& speed() { return *speed_; }

 signals:
  void frameRequested(int index);

 private:
  QSlider* slider_;
  QSpinBox* frame_number_;  // 1-based, as people count frames
  QLabel* frame_count_;
  QToolButton* play_;
  QComboBox* speed_;
  QTimer* play_timer_;
  int count_ = 0;
  int current_ = -1;
};

}  // namespace lom::ui
