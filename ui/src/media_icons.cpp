#include "lom/ui/media_icons.hpp"

#include <QPainter>
#include <QPainterPath>
#include <QPixmap>
#include <QPolygonF>

namespace lom::ui {

namespace {

// A triangle pointing right (or left) in the box from x0 to x1, of height h.
QPolygonF triangle(double x0, double x1, double h, bool right) {
  const double top = 0.2 * h, bottom = 0.8 * h, middle = 0.5 * h;
  return right ? QPolygonF({QPointF(x0, top), QPointF(x1, middle), QPointF(x0, bottom)})
               : QPolygonF({QPointF(x1, top), QPointF(x0, middle), QPointF(x1, bottom)});
}

QPixmap draw(MediaIcon kind, int size, const QColor& colour) {
  QPixmap pixmap(size, size);
  pixmap.fill(Qt::transparent);
  QPainter painter(&pixmap);
  painter.setRenderHint(QPainter::Antialiasing);
  painter.setPen(Qt::NoPen);
  painter.setBrush(colour);
  const double s = size;
  const auto bar = [&](double x0, double x1) {
    painter.drawRect(QRectF(x0, 0.2 * s, x1 - x0, 0.6 * s));
  };
  switch (kind) {
    case MediaIcon::Play:
      painter.drawPolygon(triangle(0.25 * s, 0.8 * s, s, true));
      break;
    case MediaIcon::Pause:
      bar(0.25 * s, 0.42 * s);
      bar(0.58 * s, 0.75 * s);
      break;
    case MediaIcon::First:
      bar(0.2 * s, 0.3 * s);
      painter.drawPolygon(triangle(0.3 * s, 0.8 * s, s, false));
      break;
    case MediaIcon::Previous:
      painter.drawPolygon(triangle(0.1 * s, 0.5 * s, s, false));
      painter.drawPolygon(triangle(0.5 * s, 0.9 * s, s, false));
      break;
    case MediaIcon::Next:
      painter.drawPolygon(triangle(0.1 * s, 0.5 * s, s, true));
      painter.drawPolygon(triangle(0.5 * s, 0.9 * s, s, true));
      break;
    case MediaIcon::Last:
      painter.drawPolygon(triangle(0.2 * s, 0.7 * s, s, true));
      bar(0.7 * s, 0.8 * s);
      break;
  }
  return pixmap;
}

}  // namespace

QIcon mediaIcon(MediaIcon kind, const QPalette& palette) {
  QIcon icon;
  for (const int size : {16, 24, 32, 48}) {
    icon.addPixmap(draw(kind, size, palette.color(QPalette::Active, QPalette::ButtonText)),
                   QIcon::Normal);
    icon.addPixmap(draw(kind, size, palette.color(QPalette::Disabled, QPalette::ButtonText)),
                   QIcon::Disabled);
  }
  return icon;
}

}  // namespace lom::ui
