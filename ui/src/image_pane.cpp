#include "lom/ui/image_pane.hpp"

#include <QHelpEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QToolTip>
#include <algorithm>

namespace lom::ui {

ImagePane::ImagePane(const QString& caption, QWidget* parent) : QWidget(parent), caption_(caption) {
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Expanding);
  setMouseTracking(true);
}

void ImagePane::setCaption(const QString& caption) {
  caption_ = caption;
  update();
}

int ImagePane::captionHeight() const { return fontMetrics().height() + 4; }

QString ImagePane::shownCaption() const {
  return fontMetrics().elidedText(caption_, Qt::ElideRight, width());
}

QString ImagePane::captionToolTip() const {
  return shownCaption() == caption_ ? QString() : caption_;
}

bool ImagePane::event(QEvent* event) {
  if (event->type() != QEvent::ToolTip) return QWidget::event(event);
  const auto* help = static_cast<QHelpEvent*>(event);
  const QRect caption_row(0, 0, width(), captionHeight());
  const QString tip = captionToolTip();
  if (caption_row.contains(help->pos()) && !tip.isEmpty())
    QToolTip::showText(help->globalPos(), tip, this, caption_row);
  else
    QToolTip::hideText();
  return true;
}

QRect ImagePane::imageRect() const {
  const int caption_height = captionHeight();
  const QRect area(0, caption_height, width(), height() - caption_height);
  QRect target(QPoint(0, 0), image_.size().scaled(area.size(), Qt::KeepAspectRatio));
  target.moveCenter(area.center());
  return target;
}

void ImagePane::mouseMoveEvent(QMouseEvent* event) {
  const QRect target = imageRect();
  if (image_.isNull() || !target.contains(event->pos()) || target.width() <= 0) {
    emit hovered({-1, -1});
    return;
  }
  // The image pixel drawn under the screen pixel: the one under its centre,
  // as drawing a scaled image samples it (the left edge named a pixel up to
  // a few to the left, and never the last columns and rows).
  const int u =
      static_cast<int>((event->pos().x() - target.left() + 0.5) * image_.width() / target.width());
  const int v =
      static_cast<int>((event->pos().y() - target.top() + 0.5) * image_.height() / target.height());
  emit hovered({std::clamp(u, 0, image_.width() - 1), std::clamp(v, 0, image_.height() - 1)});
}

void ImagePane::leaveEvent(QEvent*) { emit hovered({-1, -1}); }

void ImagePane::setImage(const QImage& image) {
  image_ = image;
  placeholder_.clear();
  update();
}

void ImagePane::setPlaceholder(const QString& text) {
  image_ = QImage();
  placeholder_ = text;
  update();
}

void ImagePane::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  const int caption_height = captionHeight();
  painter.setPen(palette().color(QPalette::WindowText));
  painter.drawText(QRect(0, 0, width(), caption_height), Qt::AlignLeft | Qt::AlignVCenter,
                   shownCaption());

  const QRect area(0, caption_height, width(), height() - caption_height);
  painter.fillRect(area, palette().color(QPalette::Dark));
  if (image_.isNull()) {
    painter.setPen(palette().color(QPalette::BrightText));
    painter.drawText(area.adjusted(6, 6, -6, -6), Qt::AlignCenter | Qt::TextWordWrap, placeholder_);
    return;
  }
  const QRect target = imageRect();
  // Smooth scaling would blur label borders into colours no label has.
  painter.setRenderHint(QPainter::SmoothPixmapTransform, false);
  painter.drawImage(target, image_);
}

}  // namespace lom::ui
