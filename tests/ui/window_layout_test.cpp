// The window's layout: it fits a laptop's 1366x768 screen.
#include <gtest/gtest.h>

#include <QApplication>
#include <QPushButton>
#include <QStatusBar>
#include <QTest>

#include "demo_window_fixture.hpp"
#include "lom/fusion.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/scene_view.hpp"

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

}  // namespace
}  // namespace lom::ui
