// The panels: View > Panels shows a closed panel again, View > Reset Layout
// puts every panel back, and a window that remembers its layout (the studio's
// interactive runs) reopens with the size and panels it was closed with, and
// with the Evaluation panel's IU_3d mode last chosen.
#include "lom/ui/panel_layout.hpp"

#include <gtest/gtest.h>

#include <QAction>
#include <QComboBox>
#include <QDataStream>
#include <QDockWidget>
#include <QMenuBar>
#include <QScreen>
#include <QSettings>
#include <QTableWidget>
#include <QTest>
#include <map>
#include <memory>

#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/recent_sequences.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {
namespace {

QDockWidget* panel(const MainWindow& window, const QString& object_name) {
  return window.findChild<QDockWidget*>(object_name);
}

std::unique_ptr<MainWindow> shownWindow(bool remember) {
  auto window = std::make_unique<MainWindow>();
  window->setMapDiscardQuestion([](const QString&) { return true; });  // see unsaved_map_test.cpp
  if (remember) window->rememberLayout();
  window->show();
  EXPECT_TRUE(QTest::qWaitForWindowExposed(window.get()));
  QTest::qWait(50);  // posted layout requests
  return window;
}

class PanelLayoutTest : public ::testing::Test {
 protected:
  void SetUp() override { clearSaved(); }
  void TearDown() override { clearSaved(); }
  static void clearSaved() {
    QSettings settings;
    settings.remove(PanelLayout::kGeometryKey);
    settings.remove(PanelLayout::kPanelsKey);
    settings.remove(PanelLayout::kPanelsHeightKey);
    settings.remove(MainWindow::kIouModeKey);
    settings.remove(MainWindow::kViewOptionsGroup);
  }
};

TEST_F(PanelLayoutTest, ClosedPanelsComeBackFromTheViewMenu) {
  auto window = shownWindow(false);
  const QStringList names{"mapLegendDock", "fusionDock",     "pickedVoxelDock",
                          "boxesDock",     "evaluationDock", "objectsDock"};
  for (const QString& name : names) {
    QDockWidget* dock = panel(*window, name);
    ASSERT_NE(dock, nullptr) << name.toStdString();
    // Each panel has a check item under View > Panels, named as its title.
    QAction* item = window->findAction(dock->windowTitle());
    ASSERT_NE(item, nullptr) << dock->windowTitle().toStdString();
    EXPECT_TRUE(item->isChecked());
  }
  QDockWidget* labels = panel(*window, "mapLegendDock");
  labels->close();  // its title bar's close button
  QTest::qWait(20);
  EXPECT_FALSE(labels->isVisible());
  QAction* item = window->findAction("Map Labels");
  EXPECT_FALSE(item->isChecked());
  item->trigger();
  QTest::qWait(20);
  EXPECT_TRUE(labels->isVisible());
  EXPECT_TRUE(item->isChecked());
}

TEST_F(PanelLayoutTest, ResetLayoutPutsEveryPanelBack) {
  auto window = shownWindow(false);
  QDockWidget* labels = panel(*window, "mapLegendDock");
  QDockWidget* objects = panel(*window, "objectsDock");
  QDockWidget* picked = panel(*window, "pickedVoxelDock");
  QDockWidget* evaluation = panel(*window, "evaluationDock");
  objects->close();
  picked->setFloating(true);
  window->addDockWidget(Qt::LeftDockWidgetArea, labels);
  QTest::qWait(20);
  ASSERT_EQ(window->dockWidgetArea(labels), Qt::LeftDockWidgetArea);

  QAction* reset = window->findAction("Reset Layout");
  ASSERT_NE(reset, nullptr);
  reset->trigger();
  QTest::qWait(50);
  for (QDockWidget* dock : window->findChildren<QDockWidget*>()) {
    SCOPED_TRACE(dock->objectName().toStdString());
    EXPECT_FALSE(dock->isHidden());
    EXPECT_FALSE(dock->isFloating());
    EXPECT_EQ(window->dockWidgetArea(dock), Qt::RightDockWidgetArea);
  }
  // The tab groups again: Fusion with Picked Voxel, Boxes with Evaluation and Objects.
  EXPECT_TRUE(window->tabifiedDockWidgets(picked).contains(panel(*window, "fusionDock")));
  EXPECT_TRUE(window->tabifiedDockWidgets(evaluation).contains(objects));
  EXPECT_TRUE(window->tabifiedDockWidgets(evaluation).contains(panel(*window, "boxesDock")));
  EXPECT_TRUE(window->tabifiedDockWidgets(labels).isEmpty());
  // Map Labels is above the Fusion group, which is above the scores.
  EXPECT_LT(labels->geometry().top(), panel(*window, "fusionDock")->geometry().top());
  EXPECT_LT(panel(*window, "fusionDock")->geometry().top(), evaluation->geometry().top());
}

TEST_F(PanelLayoutTest, AWindowThatRemembersReopensAsItWasClosed) {
  QSize closed_size;
  {
    auto window = shownWindow(true);
    panel(*window, "objectsDock")->close();
    panel(*window, "mapLegendDock")->setFloating(true);
    window->resize(1000, 700);
    QTest::qWait(50);
    closed_size = window->size();
    ASSERT_TRUE(window->close());
  }
  {
    auto window = shownWindow(true);
    EXPECT_EQ(window->size(), closed_size);
    EXPECT_TRUE(panel(*window, "objectsDock")->isHidden());
    EXPECT_TRUE(panel(*window, "mapLegendDock")->isFloating());
    EXPECT_FALSE(window->findAction("Objects")->isChecked());
    // Back to the default, and that is remembered in turn.
    window->findAction("Reset Layout")->trigger();
    ASSERT_TRUE(window->close());
  }
  auto window = shownWindow(true);
  EXPECT_FALSE(panel(*window, "objectsDock")->isHidden());
  EXPECT_FALSE(panel(*window, "mapLegendDock")->isFloating());
}

TEST_F(PanelLayoutTest, AWindowThatDoesNotRememberNeitherReadsNorWritesTheLayout) {
  {
    auto window = shownWindow(true);
    panel(*window, "objectsDock")->close();
    ASSERT_TRUE(window->close());
  }
  const QByteArray saved = QSettings().value(PanelLayout::kPanelsKey).toByteArray();
  ASSERT_FALSE(saved.isEmpty());
  {
    // As in screenshot runs and tests: the default layout, whatever was saved.
    auto window = shownWindow(false);
    EXPECT_FALSE(panel(*window, "objectsDock")->isHidden());
    window->findChild<QDockWidget*>("fusionDock")->close();
    ASSERT_TRUE(window->close());
  }
  EXPECT_EQ(QSettings().value(PanelLayout::kPanelsKey).toByteArray(), saved);
}

TEST_F(PanelLayoutTest, ALayoutSavedWithOtherPanelsIsNotRestored) {
  {
    auto window = shownWindow(false);
    panel(*window, "objectsDock")->close();
    // What a version with another set of panels would have saved.
    QSettings().setValue(PanelLayout::kPanelsKey,
                         window->saveState(PanelLayout::kPanelsVersion + 1));
  }
  auto window = shownWindow(true);
  EXPECT_FALSE(panel(*window, "objectsDock")->isHidden());
}

// Settings edited by hand, damaged, or saved on a larger screen: the window
// fits this screen and its panels keep the default layout.
TEST_F(PanelLayoutTest, ASavedSizeLargerThanTheScreenIsCutToIt) {
  {
    auto window = shownWindow(false);
    window->resize(5000, 4000);
    window->move(-3000, -2000);
    QSettings().setValue(PanelLayout::kGeometryKey, window->saveGeometry());
  }
  auto window = shownWindow(true);
  const QRect free = window->screen()->availableGeometry();
  EXPECT_LE(window->width(), free.width());
  EXPECT_LE(window->height(), free.height());
  EXPECT_TRUE(free.contains(window->pos())) << window->pos().x() << "," << window->pos().y();
}

// Panels saved in a tall window (a large monitor) and a window cut shorter
// than kShortWindowHeight (a laptop's screen; here its saved size stands for
// it): the short arrangement, not three groups squeezed into the height.
TEST_F(PanelLayoutTest, PanelsSavedInATallWindowAreArrangedAnewInAShortOne) {
  {
    auto window = shownWindow(true);
    window->resize(1200, PanelLayout::kShortWindowHeight + 150);
    QTest::qWait(50);
    ASSERT_FALSE(window->tabifiedDockWidgets(panel(*window, "mapLegendDock"))
                     .contains(panel(*window, "fusionDock")))
        << "the tall arrangement";
    ASSERT_TRUE(window->close());
  }
  {
    auto window = shownWindow(false);
    window->resize(1000, PanelLayout::kShortWindowHeight - 100);
    QTest::qWait(50);
    QSettings().setValue(PanelLayout::kGeometryKey, window->saveGeometry());
  }
  auto window = shownWindow(true);
  ASSERT_LT(window->height(), PanelLayout::kShortWindowHeight);
  EXPECT_TRUE(window->tabifiedDockWidgets(panel(*window, "mapLegendDock"))
                  .contains(panel(*window, "fusionDock")));
  EXPECT_FALSE(panel(*window, "objectsDock")->isHidden());
}

// A panel shown again from View ▸ Panels comes to the front of its tab
// group: Boxes came back behind Evaluation, out of reach of the keyboard.
TEST_F(PanelLayoutTest, APanelShownAgainComesToTheFront) {
  auto window = shownWindow(false);
  QDockWidget* boxes = panel(*window, "boxesDock");
  ASSERT_NE(boxes, nullptr);
  QAction* toggle = boxes->toggleViewAction();
  toggle->trigger();
  QTest::qWait(50);
  ASSERT_TRUE(boxes->isHidden());
  toggle->trigger();
  QTest::qWait(100);
  EXPECT_FALSE(boxes->isHidden());
  EXPECT_FALSE(boxes->visibleRegion().isEmpty()) << "in front of its tab group";
}

// Tab moves on from a table to the next field (arrow keys move between its
// rows): it walked every cell of the Map Labels table.
TEST_F(PanelLayoutTest, TablesLetTabMoveOn) {
  auto window = shownWindow(false);
  for (const char* name : {"mapLegendTable", "objectsTable", "pickStepsTable"}) {
    auto* table = window->findChild<QTableWidget*>(name);
    ASSERT_NE(table, nullptr) << name;
    EXPECT_FALSE(table->tabKeyNavigation()) << name;
  }
  for (const QTableWidget* table : window->evaluationPanel().findChildren<QTableWidget*>())
    EXPECT_FALSE(table->tabKeyNavigation());
}

TEST_F(PanelLayoutTest, ADamagedSavedLayoutLeavesTheDefaultOne) {
  std::map<QString, std::pair<bool, Qt::DockWidgetArea>> defaults;
  QByteArray damaged;
  {
    auto window = shownWindow(false);
    for (QDockWidget* dock : window->findChildren<QDockWidget*>())
      defaults[dock->objectName()] = {dock->isVisible(), window->dockWidgetArea(dock)};
    // The header of a saved layout, then bytes that are not one.
    QDataStream header(&damaged, QIODevice::WriteOnly);
    header << qint32(0xff) << qint32(PanelLayout::kPanelsVersion);
    damaged += QByteArray("hello-garbage-bytes");
  }
  QSettings().setValue(PanelLayout::kPanelsKey, damaged);
  auto window = shownWindow(true);
  for (QDockWidget* dock : window->findChildren<QDockWidget*>()) {
    const auto& [visible, area] = defaults.at(dock->objectName());
    EXPECT_EQ(dock->isVisible(), visible) << dock->objectName().toStdString();
    EXPECT_EQ(window->dockWidgetArea(dock), area) << dock->objectName().toStdString();
    EXPECT_FALSE(dock->isFloating()) << dock->objectName().toStdString();
    // Title bars below the menus, none hidden under them (the panels behind
    // another's tab are parked above the window, wholly out of sight).
    if (dock->isVisible() && dock->geometry().bottom() > 0) {
      EXPECT_GE(dock->geometry().top(), window->menuBar()->geometry().bottom())
          << dock->objectName().toStdString();
    }
  }
}

TEST_F(PanelLayoutTest, RecentSequencesListAtMostTheirLimit) {
  QStringList many;
  for (int i = 0; i < 500; ++i) many << QString("/nowhere/sequence-%1").arg(i);
  QSettings().setValue("recentSequences", many);
  EXPECT_EQ(RecentSequences().paths().size(), RecentSequences::kMaxEntries);
  EXPECT_EQ(RecentSequences().paths().front(), many.front());
  QSettings().remove("recentSequences");
}

TEST_F(PanelLayoutTest, TheIouModeChosenComesBackInTheNextSession) {
  auto combo = [](const MainWindow& window) {
    auto* box = window.findChild<QComboBox*>("evaluationIouMode");
    EXPECT_NE(box, nullptr);
    return box;
  };
  {
    auto window = shownWindow(true);
    EXPECT_EQ(window->session().iouMode(), IouMode::Exact);  // nothing saved yet
    QComboBox* mode = combo(*window);
    mode->setCurrentIndex(mode->findData(static_cast<int>(IouMode::Center)));
    ASSERT_EQ(window->session().iouMode(), IouMode::Center);
    ASSERT_TRUE(window->close());
  }
  {
    auto window = shownWindow(true);
    EXPECT_EQ(window->session().iouMode(), IouMode::Center);
    EXPECT_EQ(combo(*window)->currentData().toInt(), static_cast<int>(IouMode::Center));
  }
  {
    // Screenshots and tests keep the default and leave the saved mode alone.
    auto window = shownWindow(false);
    EXPECT_EQ(window->session().iouMode(), IouMode::Exact);
    window->session().setIouMode(IouMode::Center);
    window->session().setIouMode(IouMode::Exact);
  }
  EXPECT_EQ(QSettings().value(MainWindow::kIouModeKey).toString(), "center");
  // A value this version does not know leaves the default.
  QSettings().setValue(MainWindow::kIouModeKey, "median");
  auto window = shownWindow(true);
  EXPECT_EQ(window->session().iouMode(), IouMode::Exact);
}

// The View menu's display toggles, the 3D view picture size and the playback
// speed a user chose come back in the next session, and the view follows.
TEST_F(PanelLayoutTest, ViewOptionsChosenComeBackInTheNextSession) {
  auto speed = [](const MainWindow& window) {
    auto* box = window.findChild<QComboBox*>("playSpeed");
    EXPECT_NE(box, nullptr);
    return box;
  };
  {
    auto window = shownWindow(true);
    QAction* cameras = window->findAction("Show Camera Frustums");
    QAction* opacity = window->findAction("Opacity by Probability");
    QAction* size = window->findAction("3x");
    ASSERT_NE(cameras, nullptr);
    ASSERT_NE(opacity, nullptr);
    ASSERT_NE(size, nullptr);
    ASSERT_TRUE(cameras->isChecked());
    ASSERT_FALSE(opacity->isChecked());
    cameras->trigger();
    opacity->trigger();
    size->trigger();
    speed(*window)->setCurrentIndex(speed(*window)->findData(15));
    ASSERT_FALSE(window->sceneView().camerasVisible());
    ASSERT_TRUE(window->close());
  }
  {
    auto window = shownWindow(true);
    EXPECT_FALSE(window->findAction("Show Camera Frustums")->isChecked());
    EXPECT_FALSE(window->sceneView().camerasVisible());
    EXPECT_TRUE(window->findAction("Opacity by Probability")->isChecked());
    EXPECT_TRUE(window->findAction("Show Axes Marker")->isChecked());  // left alone
    EXPECT_TRUE(window->findAction("3x")->isChecked());
    EXPECT_FALSE(window->findAction("1x (as on screen)")->isChecked());
    EXPECT_EQ(speed(*window)->currentData().toInt(), 15);
  }
  {
    // Screenshots and tests keep the defaults.
    auto window = shownWindow(false);
    EXPECT_TRUE(window->findAction("Show Camera Frustums")->isChecked());
    EXPECT_TRUE(window->sceneView().camerasVisible());
    EXPECT_EQ(speed(*window)->currentData().toInt(), 5);
  }
  // Values this version does not know leave the defaults.
  QSettings().setValue(QString(MainWindow::kViewOptionsGroup) + "/cameraFrustums", "maybe");
  QSettings().setValue(QString(MainWindow::kViewOptionsGroup) + "/pictureSize", 9);
  QSettings().setValue(QString(MainWindow::kViewOptionsGroup) + "/playbackFps", 7);
  auto window = shownWindow(true);
  EXPECT_TRUE(window->findAction("Show Camera Frustums")->isChecked());
  EXPECT_TRUE(window->findAction("1x (as on screen)")->isChecked());
  EXPECT_EQ(speed(*window)->currentData().toInt(), 5);
}

}  // namespace
}  // namespace lom::ui
