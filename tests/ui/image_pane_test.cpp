// The pixel an image pane reports under the mouse is the one drawn there (the
// left edge of each screen pixel named one up to a few to the left of the one
// drawn, and the last columns and rows drawn could not be reached), at sizes
// that shrink the image by a whole factor and by a fraction, and enlarge it.
#include "lom/ui/image_pane.hpp"

#include <gtest/gtest.h>

#include <QApplication>
#include <QImage>
#include <QMouseEvent>

namespace lom::ui {
namespace {

// Each pixel's colour says where it lies: u in red and the low bits of green,
// v in blue and the high bits of green.
QImage coordinateImage(int width, int height) {
  QImage image(width, height, QImage::Format_RGB32);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      image.setPixel(u, v, qRgb(u & 255, (u >> 8) | ((v >> 8) << 4), v & 255));
  return image;
}

QPoint coordinatesOf(QRgb colour) {
  return {qRed(colour) | ((qGreen(colour) & 15) << 8),
          qBlue(colour) | ((qGreen(colour) >> 4) << 8)};
}

TEST(ImagePaneTest, TheReadoutNamesThePixelDrawnUnderTheMouse) {
  for (const QSize size : {QSize(160, 200), QSize(214, 200), QSize(900, 760)}) {
    SCOPED_TRACE(size.width());
    ImagePane pane("Colour");
    pane.setImage(coordinateImage(640, 480));
    pane.resize(size);
    pane.show();
    QApplication::processEvents();
    const QImage drawn = pane.grab().toImage();
    ASSERT_EQ(drawn.size(), size);  // one device pixel per pixel here
    QPoint hovered(-1, -1);
    QObject::connect(&pane, &ImagePane::hovered, [&](const QPoint& pixel) { hovered = pixel; });
    int compared = 0, differ = 0;
    int max_u = -1, max_v = -1;
    for (int y = 0; y < size.height(); y += 3)
      for (int x = 0; x < size.width(); x += 3) {
        hovered = {-1, -1};
        QMouseEvent move(QEvent::MouseMove, QPointF(x, y), Qt::NoButton, Qt::NoButton,
                         Qt::NoModifier);
        QApplication::sendEvent(&pane, &move);
        if (hovered.x() < 0) continue;
        ++compared;
        max_u = std::max(max_u, hovered.x());
        max_v = std::max(max_v, hovered.y());
        if (hovered != coordinatesOf(drawn.pixel(x, y))) ++differ;
      }
    EXPECT_GT(compared, 1000);
    EXPECT_EQ(differ, 0) << "of " << compared;
  }
}

}  // namespace
}  // namespace lom::ui
