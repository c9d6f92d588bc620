// The pixel an image pane reports under the mouse is the one drawn there, the
// image pixel under the screen pixel's centre (the left edge of each screen
// pixel named one up to a few to the left of the one drawn, and the last
// columns and rows drawn could not be reached).
#include "lom/ui/image_pane.hpp"

#include <gtest/gtest.h>

#include <QApplication>
#include <QImage>
#include <QMouseEvent>

namespace lom::ui {
namespace {

TEST(ImagePaneTest, TheLastColumnAndRowOfAShrunkImageCanBeHovered) {
  ImagePane pane("Colour");
  QImage image(640, 480, QImage::Format_RGB32);
  image.fill(Qt::gray);
  pane.setImage(image);
  pane.resize(160, 200);  // the image drawn 160 x 120: four image pixels per screen pixel
  pane.show();
  QApplication::processEvents();
  QPoint last(-1, -1);
  int max_u = -1, max_v = -1, min_u = 1 << 30, min_v = 1 << 30;
  QObject::connect(&pane, &ImagePane::hovered, [&](const QPoint& pixel) { last = pixel; });
  const auto hover = [&](int x, int y) {
    QMouseEvent move(QEvent::MouseMove, QPointF(x, y), Qt::NoButton, Qt::NoButton, Qt::NoModifier);
    QApplication::sendEvent(&pane, &move);
    if (last.x() < 0) return;
    max_u = std::max(max_u, last.x());
    max_v = std::max(max_v, last.y());
    min_u = std::min(min_u, last.x());
    min_v = std::min(min_v, last.y());
  };
  for (int x = 0; x < pane.width(); ++x) hover(x, pane.height() / 2);
  for (int y = 0; y < pane.height(); ++y) hover(pane.width() / 2, y);
  // Screen pixel x shows image pixel floor((x + 0.5) * 4): 2 to 638, 2 to 478.
  EXPECT_EQ(min_u, 2);
  EXPECT_EQ(min_v, 2);
  EXPECT_EQ(max_u, 638);
  EXPECT_EQ(max_v, 478);
}

}  // namespace
}  // namespace lom::ui
