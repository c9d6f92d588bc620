#include "lom/ui/image_pane.hpp"

#include <QHelpEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QToolTip>
#include <algorithm>
#include <cmath>
#include <vector>

namespace lom::ui {

namespace {

// The image pixel shown at device pixel `device` of `device_extent` drawn
// from `extent` image pixels: the one under the device pixel's centre. The
// drawing and the readout both use it, so the readout names what is drawn
// (Qt's own scaling samples a little differently, and not alike at every
// size).
int sampledIndex(int device, int device_extent, int extent) {
  const auto index = static_cast<int>((device + 0.5) * extent / device_extent);
  return std::clamp(index, 0, extent - 1);
}

QImage sampled(const QImage& image, const QSize& device_size) {
  const QImage source = image.convertToFormat(QImage::Format_ARGB32);
  QImage out(device_size, QImage::Format_ARGB32);
  std::vector<int> columns(static_cast<size_t>(device_size.width()));
  for (int x = 0; x < device_size.width(); ++x)
    columns[static_cast<size_t>(x)] = sampledIndex(x, device_size.width(), source.width());
  for (int y = 0; y < device_size.height(); ++y) {
    const auto* in = reinterpret_cast<const QRgb*>(
        source.constScanLine(sampledIndex(y, device_size.height(), source.height())));
    auto* row = reinterpret_cast<QRgb*>(out.scanLine(y));
    for (int x = 0; x < device_size.width(); ++x) row[x] = in[columns[static_cast<size_t>(x)]];
  }
  return out;
}

}  // namespace

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
  // The image pixel drawn under the centre of the screen pixel (the left
  // edge named one up to a few to the left, and never the last columns and
  // rows).
  const qreal ratio = devicePixelRatioF();
  const QSize device = deviceSizeOf(target);
  // The device pixel under the pointer: Qt gives its position in fractions of
  // a logical pixel where one holds several device pixels (HiDPI).
  const QPointF at = event->localPos() - QPointF(target.topLeft());
  const int x = std::clamp(static_cast<int>(std::floor(at.x() * ratio)), 0, device.width() - 1);
  const int y = std::clamp(static_cast<int>(std::floor(at.y() * ratio)), 0, device.height() - 1);
  emit hovered({sampledIndex(x, device.width(), image_.width()),
                sampledIndex(y, device.height(), image_.height())});
}

void ImagePane::leaveEvent(QEvent*) { emit hovered({-1, -1}); }

QSize ImagePane::deviceSizeOf(const QRect& target) const {
  const qreal ratio = devicePixelRatioF();
  return {std::max(1, qRound(target.width() * ratio)),
          std::max(1, qRound(target.height() * ratio))};
}

void ImagePane::setImage(const QImage& image) {
  image_ = image;
  drawn_ = QImage();
  placeholder_.clear();
  update();
}

void ImagePane::setPlaceholder(const QString& text) {
  image_ = QImage();
  drawn_ = QImage();
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
  // Pixel for pixel as the readout maps the mouse (and unblurred: smooth
  // scaling would blur label borders into colours no label has).
  const QSize device = deviceSizeOf(target);
  if (drawn_.size() != device) {
    drawn_ = sampled(image_, device);
    drawn_.setDevicePixelRatio(devicePixelRatioF());
  }
  painter.drawImage(target.topLeft(), drawn_);
}

}  // namespace lom::ui
