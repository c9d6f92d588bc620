// The playback icons are drawn in the palette's button text colour: on a
// dark palette they are light (Qt's own media icons stayed dark there, about
// 1.3:1 against the buttons), and each kind is its own picture.
#include "lom/ui/media_icons.hpp"

#include <gtest/gtest.h>

#include <QImage>
#include <QPixmap>
#include <set>

namespace lom::ui {
namespace {

// The darkest and the lightest opaque pixel's grey level (0..255).
std::pair<int, int> opaqueGreyRange(const QImage& image) {
  int darkest = 255, lightest = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QColor c = image.pixelColor(x, y);
      if (c.alpha() < 200) continue;
      darkest = std::min(darkest, qGray(c.rgb()));
      lightest = std::max(lightest, qGray(c.rgb()));
    }
  return {darkest, lightest};
}

QPalette darkPalette() {
  QPalette dark;
  dark.setColor(QPalette::Button, QColor(49, 54, 59));
  dark.setColor(QPalette::Window, QColor(49, 54, 59));
  dark.setColor(QPalette::Active, QPalette::ButtonText, QColor(239, 240, 241));
  dark.setColor(QPalette::Inactive, QPalette::ButtonText, QColor(239, 240, 241));
  dark.setColor(QPalette::Disabled, QPalette::ButtonText, QColor(110, 113, 117));
  return dark;
}

TEST(MediaIcons, DrawnInTheButtonTextColourOfADarkPalette) {
  const QPalette dark = darkPalette();
  std::set<QByteArray> pictures;
  for (const MediaIcon kind : {MediaIcon::Play, MediaIcon::Pause, MediaIcon::First,
                               MediaIcon::Previous, MediaIcon::Next, MediaIcon::Last}) {
    const QIcon icon = mediaIcon(kind, dark);
    const QImage normal = icon.pixmap(24, 24, QIcon::Normal).toImage();
    const QImage disabled = icon.pixmap(24, 24, QIcon::Disabled).toImage();
    const auto [normal_dark, normal_light] = opaqueGreyRange(normal);
    ASSERT_GT(normal_light, 0) << "something is drawn";
    EXPECT_GE(normal_dark, 200) << "light on the dark buttons";
    const auto [disabled_dark, disabled_light] = opaqueGreyRange(disabled);
    EXPECT_LE(disabled_light, 130) << "disabled: dimmer than enabled";
    pictures.insert(QByteArray(reinterpret_cast<const char*>(normal.constBits()),
                               static_cast<int>(normal.sizeInBytes())));
  }
  EXPECT_EQ(pictures.size(), 6u) << "each kind is its own picture";
}

TEST(MediaIcons, DarkOnALightPalette) {
  QPalette light;
  light.setColor(QPalette::Active, QPalette::ButtonText, Qt::black);
  const QImage play = mediaIcon(MediaIcon::Play, light).pixmap(24, 24).toImage();
  EXPECT_LE(opaqueGreyRange(play).second, 40);
}

}  // namespace
}  // namespace lom::ui
