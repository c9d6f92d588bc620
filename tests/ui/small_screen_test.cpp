// The window on a 1024x768 screen (a common laptop and projector size): it
// fits, every panel is wide enough for its content, the score chart keeps a
// readable height, and the 3D view's orientation axes show X, Y and Z apart.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QDockWidget>
#include <QPushButton>
#include <QScrollArea>
#include <QTableWidget>
#include <QTest>
#include <functional>
#include <vector>

#include "demo_window_fixture.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/score_chart.hpp"

namespace lom::ui {
namespace {

// A 1024x768 screen: the window the studio opens with on it (with a 28-pixel
// desktop panel), and the whole screen (a projector, a full-screen window).
const QSize kScreenWithPanel(1024, 768 - 28);
const QSize kWholeScreen(1024, 768);
// A panel narrower than this cuts its fields' values or its table's names
// short; a score chart lower than this squeezes its bars into a few pixels.
constexpr int kMinimumPanelWidth = 300;
constexpr int kMinimumChartHeight = 110;
// The 3D view keeps a useful width beside the frame images and the panels.
constexpr int kMinimumSceneWidth = 340;
// Pixels of the X, Y and Z letters that tell them apart at a glance.
constexpr int kMinimumAxisLetterHeight = 10;
// On such a screen the window's minimum leaves at least this much to widen
// the 3D view or a panel beyond their minimum widths.
constexpr int kRoomBeyondMinimum = 100;

class SmallScreenTest : public fixture::DemoWindowTest {
 protected:
  // The window at `size` with the panels where it starts at that size
  // (View > Reset Layout arranges them as the window does when it opens).
  void showAt(const QSize& size) {
    window_.resize(size);
    settle();
    QAction* reset = window_.findAction("Reset Layout");
    ASSERT_NE(reset, nullptr);
    reset->trigger();
    settle();
  }
  void openFuseAndScore() {
    openAndFuse();
    EvaluationPanel& evaluation = window_.evaluationPanel();
    ASSERT_TRUE(QTest::qWaitFor([&] { return !evaluation.isBusy() && evaluation.canExport(); },
                                fixture::kTimeoutMs))
        << evaluation.summaryText().toStdString();
  }
  // `widget` is drawn whole: not cut off by its dock, the window or a scroll area.
  static void expectWhollyVisible(const QWidget& widget, const char* what) {
    EXPECT_TRUE(widget.isVisible()) << what;
    EXPECT_EQ(widget.visibleRegion().boundingRect(), widget.rect()) << what;
  }
};

TEST_F(SmallScreenTest, TheWindowFitsA1024x768Screen) {
  const QSize opened = initialWindowSize(kScreenWithPanel);
  EXPECT_LE(opened.width(), 1024);
  auto expectFits = [&](const char* when) {
    settle();
    EXPECT_LE(window_.minimumSizeHint().width(), opened.width() - kRoomBeyondMinimum) << when;
    EXPECT_LE(window_.minimumSize().width(), opened.width() - kRoomBeyondMinimum) << when;
    EXPECT_LE(window_.minimumSizeHint().height(), opened.height()) << when;
  };
  expectFits("with nothing open");
  showAt(opened);
  EXPECT_EQ(window_.size(), opened);
  openFuseAndScore();
  expectFits("with the demo fused and scored");
  // Every panel shown in turn (each tab raised) still fits.
  for (QDockWidget* panel : window_.findChildren<QDockWidget*>()) {
    panel->raise();
    expectFits(panel->objectName().toLocal8Bit().constData());
  }
  settle();
  EXPECT_EQ(window_.size(), opened);
  EXPECT_TRUE(errors_.empty());
}

TEST_F(SmallScreenTest, EveryPanelIsReadableOnA1024x768Screen) {
  openFuseAndScore();
  for (const QSize& size : {initialWindowSize(kScreenWithPanel), kWholeScreen}) {
    SCOPED_TRACE(testing::Message() << "window " << size.width() << "x" << size.height());
    showAt(size);
    ASSERT_EQ(window_.size(), size);

    // The map's labels share a tab group with the fusion settings, so that
    // the scores below keep the height they need.
    QDockWidget& labels = dock("mapLegendDock");
    EXPECT_TRUE(window_.tabifiedDockWidgets(&labels).contains(&dock("fusionDock")));
    EXPECT_TRUE(window_.tabifiedDockWidgets(&dock("evaluationDock")).contains(&dock("boxesDock")));
    EXPECT_FALSE(labels.visibleRegion().isEmpty());

    // The 3D view beside the frame images and the panels.
    EXPECT_GE(window_.sceneView().width(), kMinimumSceneWidth);
    EXPECT_GE(window_.frameImages().width(), window_.frameImages().minimumSizeHint().width());

    // Each panel, raised in its group: as wide as its content needs and at
    // least kMinimumPanelWidth, nothing cut off on the right.
    for (QDockWidget* panel : window_.findChildren<QDockWidget*>()) {
      SCOPED_TRACE(panel->objectName().toStdString());
      panel->raise();
      settle();
      EXPECT_TRUE(panel->isVisible());
      EXPECT_FALSE(panel->isFloating());
      const auto* scroll = qobject_cast<const QScrollArea*>(panel->widget());
      ASSERT_NE(scroll, nullptr);
      const QWidget& content = *scroll->widget();
      EXPECT_GE(scroll->viewport()->width(), kMinimumPanelWidth);
      EXPECT_GE(content.width(), content.minimumSizeHint().width());
      EXPECT_LE(content.width(), scroll->viewport()->width());
      const QRect shown(panel->mapTo(&window_, QPoint(0, 0)), panel->size());
      EXPECT_TRUE(window_.rect().contains(shown));
    }

    // The scores: every row, the summary, the Export button and the chart
    // whole, the chart high enough to read and the names not cut to nothing.
    dock("evaluationDock").raise();
    settle();
    EvaluationPanel& evaluation = window_.evaluationPanel();
    const ScoreChart& chart = evaluation.chart();
    EXPECT_GE(chart.height(), kMinimumChartHeight);
    expectWhollyVisible(chart, "score chart");
    expectWhollyVisible(evaluation.exportButton(), "Export report button");
    const QTableWidget& table = evaluation.table();
    ASSERT_GT(table.rowCount(), 0);
    const int last_row_bottom =
        table.rowViewportPosition(table.rowCount() - 1) + table.rowHeight(table.rowCount() - 1);
    EXPECT_LE(last_row_bottom, table.viewport()->height());
    EXPECT_GE(table.columnWidth(EvaluationPanel::Name), 8 * table.fontMetrics().averageCharWidth());
    EXPECT_LE(table.columnViewportPosition(EvaluationPanel::BoxIou) +
                  table.columnWidth(EvaluationPanel::BoxIou),
              table.viewport()->width());
  }
  EXPECT_TRUE(errors_.empty());
}

TEST_F(SmallScreenTest, OrientationAxesLettersAreReadableAndApart) {
  openFuseAndScore();
  showAt(initialWindowSize(kScreenWithPanel));
  SceneView& scene = window_.sceneView();
  const QRect marker = scene.axesMarkerRect();
  EXPECT_GE(marker.width(), SceneView::kAxesMarkerMinPixels);
  EXPECT_EQ(marker.width(), marker.height());  // square: the axes are not squeezed
  EXPECT_EQ(marker.bottomLeft(), scene.rect().bottomLeft());
  const struct {
    const char* view;
    std::function<void()> show;
  } views[] = {
      {"start", [&] { scene.resetCamera(); }},
      {"above", [&] { scene.lookFrom(SceneView::StandardView::Above); }},
      {"front", [&] { scene.lookFrom(SceneView::StandardView::Front); }},
      {"side", [&] { scene.lookFrom(SceneView::StandardView::Side); }},
      {"first camera", [&] { scene.lookFromFrame(window_.controller().sequence(), 0); }},
  };
  for (const auto& view : views) {
    SCOPED_TRACE(view.view);
    view.show();
    (void)scene.renderToImage();  // the letters are placed when the view is drawn
    const std::vector<QRect> letters = scene.axesLabelRects();
    ASSERT_EQ(letters.size(), 3u);
    for (size_t i = 0; i < letters.size(); ++i) {
      SCOPED_TRACE(testing::Message() << "XYZ"[i]);
      EXPECT_GE(letters[i].height(), kMinimumAxisLetterHeight);
      EXPECT_TRUE(marker.contains(letters[i])) << "drawn outside the marker, cut off";
      for (size_t j = i + 1; j < letters.size(); ++j)
        EXPECT_FALSE(letters[i].intersects(letters[j])) << "overlaps "
                                                        << "XYZ"[j];
    }
  }
  EXPECT_TRUE(errors_.empty());
}

}  // namespace
}  // namespace lom::ui
