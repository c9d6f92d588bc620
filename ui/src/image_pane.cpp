#include "lom/ui/image_pane.hpp"

#include <QPainter>

namespace lom::ui {

ImagePane::ImagePane(const QString& caption, QWidget* parent) : QWidget(parent), caption_(caption) {
  setMinimumSize(160, 130);
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Expanding);
}

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
  const int caption_height = fontMetrics().height() + 4;
  painter.setPen(palette().color(QPalette::WindowText));
  painter.drawText(QRect(0, 0, width(), caption_height), Qt::AlignLeft | Qt::AlignVCenter,
                   caption_);

  const QRect area(0, caption_height, width(), height() - caption_height);
  painter.fillRect(area, palette().color(QPalette::Dark));
  if (image_.isNull()) {
    painter.setPen(palette().color(QPalette::BrightText));
    painter.drawText(area.adjusted(6, 6, -6, -6), Qt::AlignCenter | Qt::TextWordWrap, placeholder_);
    return;
  }
  QSize fitted = image_.size().scaled(area.size(), Qt::KeepAspectRatio);
  QRect target(QPoint(0, 0), fitted);
  target.moveCenter(area.center());
  // Smooth scaling would blur label borders into colours no label has.
  painter.setRenderHint(QPainter::SmoothPixmapTransform, false);
  painter.drawImage(target, image_);
}

}  // namespace lom::ui
