// The window's layout: it fits a laptop's 1366x768 screen, and the heat
// map's caption says what it shows.
#include <gtest/gtest.h>

#include <QApplication>
#include <QPushButton>
#include <QStatusBar>
#include <QTest>

#include "demo_window_fixture.hpp"
#include "lom/fusion.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/image_pane.hpp"
#include "lom/ui/scene_view.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

// A 1366x768 laptop screen less a desktop panel and the window's title bar.
constexpr int kLaptopWindowHeight = 700;
constexpr int kLaptopWidth = 1366;

class WindowLayoutTest : public fixture::DemoWindowTest {
 protected:
  static void settle() {
    QApplication::processEvents();
    QTest::qWait(100);  // posted layout requests and resizes
  }
  void expectFitsALaptop(const char* when) {
    settle();
    EXPECT_LE(window_.minimumSizeHint().height(), kLaptopWindowHeight) << when;
    EXPECT_LE(window_.minimumSize().height(), kLaptopWindowHeight) << when;
    EXPECT_LE(window_.minimumSizeHint().width(), kLaptopWidth) << when;
    // At that height the timeline and the status bar are inside the window.
    window_.resize(kLaptopWidth - 100, kLaptopWindowHeight);
    settle();
    EXPECT_EQ(window_.height(), kLaptopWindowHeight) << when;
    const QRect timeline(window_.timeline().mapTo(&window_, QPoint(0, 0)),
                         window_.timeline().size());
    EXPECT_LE(timeline.bottom(), window_.statusBar()->geometry().top()) << when;
    EXPECT_LE(window_.statusBar()->geometry().bottom(), window_.height()) << when;
    EXPECT_GE(window_.sceneView().height(), 240) << when;
  }
};

TEST_F(WindowLayoutTest, FitsALaptopScreen) {
  // A window opened on such a screen starts inside it.
  const QSize initial = initialWindowSize({kLaptopWidth, 768 - 28});
  EXPECT_LE(initial.width(), kLaptopWidth);
  EXPECT_LE(initial.height(), 768 - 28);
  EXPECT_EQ(initialWindowSize({1920, 1080}), QSize(1280, 960));

  openAndFuse();
  expectFitsALaptop("with the demo fused");

  // The Fusion panel's depth-range note (two lines) and its Re-fuse button,
  // scrolled into view in the short window.
  window_.resize(kLaptopWidth - 100, kLaptopWindowHeight);
  FusionOptions options = window_.session().fusionOptions();
  options.map.max_range = 0.1;  // the demo's depths lie beyond
  window_.session().setFusionOptions(options);
  window_.session().fuse();
  waitForFusion();
  FusionPanel& panel = window_.fusionPanel();
  ASSERT_FALSE(panel.extendRangeButton().isHidden()) << panel.noteText().toStdString();
  ASSERT_FALSE(panel.noteText().isEmpty());
  settle();
  EXPECT_FALSE(panel.extendRangeButton().visibleRegion().isEmpty());
  expectFitsALaptop("with the Fusion panel's range note");
  EXPECT_TRUE(errors_.empty());
}

TEST_F(WindowLayoutTest, HeatMapCaptionSaysWhatItShows) {
  const ImagePane& heat = window_.frameImages().heatPane();
  EXPECT_EQ(heat.caption().toStdString(), "Probability");  // nothing open

  openAndFuse();
  window_.frameImages().setHeatLabel(-1);
  EXPECT_EQ(heat.caption().toStdString(), "Probability (choose a label)");
  const int label = *visibleObjectLabels().begin();
  window_.session().setSelectedLabel(label);
  const QString name =
      QString::fromStdString(window_.controller().sequence().labels.at(label).name);
  EXPECT_EQ(heat.caption().toStdString(), "Probability of " + name.toStdString());
  // Elided or not, depending on the pane's width: the tooltip tells what is cut.
  EXPECT_EQ(heat.captionToolTip().isEmpty(), heat.shownCaption() == heat.caption());
  EXPECT_FALSE(heat.image().isNull());

  // A recording without probability images (the tiny sequence has label images only).
  const test::TinySequence tiny = test::writeTinySequence(temp_.path() / "tiny");
  window_.controller().setDiscardGuard([] { return true; });
  ASSERT_TRUE(window_.controller().openSequence(fixture::qPath(tiny.folder)));
  EXPECT_EQ(heat.caption().toStdString(), "Probability (no probability images)");
  EXPECT_TRUE(heat.image().isNull());
  EXPECT_TRUE(errors_.empty());
}

}  // namespace
}  // namespace lom::ui
