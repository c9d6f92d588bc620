#include "lom/ui/timeline_widget.hpp"

#include <QAction>
#include <QComboBox>
#include <QEvent>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QTimer>
#include <QToolButton>

#include "lom/ui/media_icons.hpp"

namespace lom::ui {

namespace {

// A flat (auto-raise) tool button is drawn as a raised button while it has
// the keyboard focus: the style draws a flat one the same with and without
// it, so Tab reached it unseen.
class RaisedWhileFocused : public QObject {
 public:
  explicit RaisedWhileFocused(QToolButton* button) : QObject(button), button_(button) {
    button->installEventFilter(this);
  }
  bool eventFilter(QObject*, QEvent* event) override {
    if (event->type() == QEvent::FocusIn)
      button_->setAutoRaise(false);
    else if (event->type() == QEvent::FocusOut)
      button_->setAutoRaise(true);
    return false;
  }

 private:
  QToolButton* button_;
};

QToolButton* flatButton() {
  auto* button = new QToolButton;
  button->setAutoRaise(true);
  new RaisedWhileFocused(button);
  return button;
}

QToolButton* buttonFor(QAction* action) {
  QToolButton* button = flatButton();
  button->setDefaultAction(action);
  return button;
}

}  // namespace

TimelineWidget::TimelineWidget(const StepActions& actions, QWidget* parent)
    : QWidget(parent),
      slider_(new QSlider(Qt::Horizontal)),
      frame_number_(new QSpinBox),
      frame_count_(new QLabel),
      play_(flatButton()),
      speed_(new QComboBox),
      play_timer_(new QTimer(this)) {
  play_->setObjectName("playButton");
  play_->setCheckable(true);
  play_->setIcon(mediaIcon(MediaIcon::Play, palette()));
  play_->setToolTip(tr("Play / pause (Space)"));
  // Names a screen reader says (a tooltip is only its description).
  play_->setAccessibleName(tr("Play"));
  play_->setShortcut(Qt::Key_Space);
  speed_->setObjectName("playSpeed");
  for (int fps : {1, 2, 5, 10, 15, 30}) speed_->addItem(tr("%1 fps").arg(fps), fps);
  speed_->setCurrentIndex(2);
  speed_->setToolTip(tr("Playback speed"));
  connect(play_, &QToolButton::toggled, this, &TimelineWidget::setPlaying);
  connect(speed_, qOverload<int>(&QComboBox::currentIndexChanged), this, [this] {
    play_timer_->setInterval(1000 / std::max(1, speed_->currentData().toInt()));
  });
  play_timer_->setInterval(1000 / 5);
  connect(play_timer_, &QTimer::timeout, this, [this] {
    if (current_ + 1 >= count_) return setPlaying(false);
    emit frameRequested(current_ + 1);
  });
  slider_->setObjectName("frameSlider");
  frame_number_->setObjectName("frameNumber");
  slider_->setAccessibleName(tr("Frame"));
  frame_number_->setAccessibleName(tr("Frame number"));
  speed_->setAccessibleName(tr("Playback speed"));
  slider_->setTracking(true);
  frame_number_->setKeyboardTracking(false);
  frame_number_->setPrefix(tr("frame "));

  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(6, 2, 6, 2);
  layout->addWidget(buttonFor(actions.first));
  layout->addWidget(buttonFor(actions.previous));
  layout->addWidget(play_);
  layout->addWidget(slider_, 1);
  layout->addWidget(buttonFor(actions.next));
  layout->addWidget(buttonFor(actions.last));
  layout->addWidget(frame_number_);
  layout->addWidget(frame_count_);
  layout->addWidget(speed_);

  connect(slider_, &QSlider::valueChanged, this, &TimelineWidget::frameRequested);
  connect(frame_number_, qOverload<int>(&QSpinBox::valueChanged), this,
          [this](int number) { emit frameRequested(number - 1); });
  setFrameCount(0);
}

void TimelineWidget::setPlaying(bool playing) {
  playing = playing && count_ > 1;
  if (play_->isChecked() != playing) {
    const QSignalBlocker block(play_);
    play_->setChecked(playing);
  }
  play_->setIcon(mediaIcon(playing ? MediaIcon::Pause : MediaIcon::Play, palette()));
  if (playing) {
    if (current_ + 1 >= count_) emit frameRequested(0);  // from the start again
    play_timer_->start();
  } else {
    play_timer_->stop();
  }
}

bool TimelineWidget::isPlaying() const { return play_timer_->isActive(); }

void TimelineWidget::setFrameCount(int count) {
  count_ = count;
  if (count <= 1) setPlaying(false);
  play_->setEnabled(count > 1);
  const QSignalBlocker block_slider(slider_);
  const QSignalBlocker block_number(frame_number_);
  slider_->setRange(0, std::max(0, count - 1));
  frame_number_->setRange(count > 0 ? 1 : 0, count);
  frame_count_->setText(tr("of %1").arg(count));
  slider_->setEnabled(count > 0);
  frame_number_->setEnabled(count > 0);
}

void TimelineWidget::setCurrentFrame(int index) {
  current_ = index;
  const QSignalBlocker block_slider(slider_);
  const QSignalBlocker block_number(frame_number_);
  slider_->setValue(index);
  frame_number_->setValue(index + 1);
}

}  // namespace lom::ui
