#include "lom/ui/timeline_widget.hpp"

#include <QAction>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QToolButton>

namespace lom::ui {

namespace {
QToolButton* buttonFor(QAction* action) {
  auto* button = new QToolButton;
  button->setDefaultAction(action);
  button->setAutoRaise(true);
  return button;
}
}  // namespace

TimelineWidget::TimelineWidget(const StepActions& actions, QWidget* parent)
    : QWidget(parent),
      slider_(new QSlider(Qt::Horizontal)),
      frame_number_(new QSpinBox),
      frame_count_(new QLabel) {
  slider_->setObjectName("frameSlider");
  frame_number_->setObjectName("frameNumber");
  slider_->setTracking(true);
  frame_number_->setKeyboardTracking(false);
  frame_number_->setPrefix(tr("frame "));

  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(6, 2, 6, 2);
  layout->addWidget(buttonFor(actions.first));
  layout->addWidget(buttonFor(actions.previous));
  layout->addWidget(slider_, 1);
  layout->addWidget(buttonFor(actions.next));
  layout->addWidget(buttonFor(actions.last));
  layout->addWidget(frame_number_);
  layout->addWidget(frame_count_);

  connect(slider_, &QSlider::valueChanged, this, &TimelineWidget::frameRequested);
  connect(frame_number_, qOverload<int>(&QSpinBox::valueChanged), this,
          [this](int number) { emit frameRequested(number - 1); });
  setFrameCount(0);
}

void TimelineWidget::setFrameCount(int count) {
  const QSignalBlocker block_slider(slider_);
  const QSignalBlocker block_number(frame_number_);
  slider_->setRange(0, std::max(0, count - 1));
  frame_number_->setRange(count > 0 ? 1 : 0, count);
  frame_count_->setText(tr("of %1").arg(count));
  slider_->setEnabled(count > 0);
  frame_number_->setEnabled(count > 0);
}

void TimelineWidget::setCurrentFrame(int index) {
  const QSignalBlocker block_slider(slider_);
  const QSignalBlocker block_number(frame_number_);
  slider_->setValue(index);
  frame_number_->setValue(index + 1);
}

}  // namespace lom::ui
