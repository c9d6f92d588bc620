// The window's one-key shortcuts against the control with the focus: a list,
// table or drop-down keeps the keys it has a use for (typing a name, Delete,
// Home/End), and the focus never works in a panel nobody sees.
#include <gtest/gtest.h>

#include <QApplication>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QTableView>
#include <QTest>
#include <QToolButton>
#include <cstdlib>

#include "demo_window_fixture.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/frame_images_view.hpp"
#include "lom/ui/image_pane.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {
namespace {

class FocusedKeysTest : public fixture::DemoWindowTest {
 protected:
  void SetUp() override {
    fixture::DemoWindowTest::SetUp();
    openAndFuse();
    window_.activateWindow();
    ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
    ASSERT_GT(boxes().boxCount(), 0);
    boxes().select(0);
  }
  void TearDown() override { boxes().undoStack().setClean(); }
  AnnotationsModel& boxes() { return window_.session().annotations(); }
  QDockWidget& dock(const char* name) { return *window_.findChild<QDockWidget*>(name); }
  // Its panel to the front, then the focus to it.
  static void focus(QWidget& widget) {
    for (QWidget* up = &widget; up; up = up->parentWidget())
      if (auto* panel = qobject_cast<QDockWidget*>(up)) panel->raise();
    widget.setFocus();
    ASSERT_TRUE(QTest::qWaitFor([&] { return widget.hasFocus(); }, 5000));
  }
};

// Tabbing into Map Labels chooses no label: the probability shown stays the
// selected box's label, and the table starts on that label's row; the arrows
// then choose as they move.
TEST_F(FocusedKeysTest, TabbingIntoMapLabelsKeepsTheLabelShown) {
  auto* legend = window_.findChild<QTableView*>("mapLegendTable");
  ASSERT_NE(legend, nullptr);
  const int label = boxes().box(0).label;
  ASSERT_GT(label, 0);
  ASSERT_EQ(window_.session().selectedLabel(), label);
  const QString caption = window_.frameImages().heatPane().caption();
  ASSERT_FALSE(caption.contains("__background__")) << caption.toStdString();
  ASSERT_FALSE(legend->currentIndex().isValid());
  for (QWidget* up = legend; up; up = up->parentWidget())
    if (auto* panel = qobject_cast<QDockWidget*>(up)) panel->raise();
  legend->setFocus(Qt::TabFocusReason);
  ASSERT_TRUE(QTest::qWaitFor([&] { return legend->hasFocus(); }, 5000));
  EXPECT_EQ(window_.frameImages().heatPane().caption(), caption);
  EXPECT_EQ(window_.session().selectedLabel(), label);
  ASSERT_TRUE(legend->currentIndex().isValid());
  EXPECT_EQ(legend->currentIndex().data(Qt::UserRole + 1).toInt(), label);
  EXPECT_TRUE(legend->selectionModel()->selectedRows().isEmpty());
  // An arrow moves to another row and shows that label's probability.
  QTest::keyClick(legend, legend->currentIndex().row() == 0 ? Qt::Key_Down : Qt::Key_Up);
  EXPECT_NE(window_.frameImages().heatPane().caption(), caption);
}

// The timeline's buttons (Play, the frame steps) show where the keyboard
// focus is: drawn otherwise when Tab reaches them than without the focus.
TEST_F(FocusedKeysTest, TheTimelineButtonsShowTheKeyboardFocus) {
  auto* play = window_.findChild<QToolButton*>("playButton");
  ASSERT_NE(play, nullptr);
  ASSERT_TRUE(play->isEnabled());
  window_.frameImages().setFocus(Qt::OtherFocusReason);
  QApplication::processEvents();
  const QImage without = play->grab().toImage();
  play->setFocus(Qt::TabFocusReason);  // as Tab gives it
  ASSERT_TRUE(QTest::qWaitFor([&] { return play->hasFocus(); }, 5000));
  QApplication::processEvents();
  const QImage with = play->grab().toImage();
  if (const char* keep = std::getenv("LOM_KEEP_SHOTS")) {
    with.save(QString(keep) + "/play_with.png");
    without.save(QString(keep) + "/play_without.png");
  }
  EXPECT_NE(with, without) << "the focused Play button looks as it does without the focus";
}

TEST_F(FocusedKeysTest, ListsAndTablesKeepLettersDeleteAndHomeEnd) {
  auto* legend = window_.findChild<QTableView*>("mapLegendTable");
  ASSERT_NE(legend, nullptr);
  focus(*legend);
  const GroundTruthBox before = boxes().box(0);
  const int edits = boxes().undoStack().count();
  const int boxes_before = boxes().boxCount();
  const int frame = window_.controller().currentFrame();
  ASSERT_GE(window_.controller().frameCount(), 2);
  for (const Qt::Key key :
       {Qt::Key_K, Qt::Key_W, Qt::Key_B, Qt::Key_Delete, Qt::Key_End, Qt::Key_PageDown})
    QTest::keyClick(legend, key);
  EXPECT_EQ(boxes().undoStack().count(), edits);
  EXPECT_EQ(boxes().boxCount(), boxes_before);
  EXPECT_EQ(boxes().box(0).box.size, before.box.size);
  EXPECT_EQ(boxes().box(0).box.center, before.box.center);
  EXPECT_EQ(window_.controller().currentFrame(), frame);

  // The Evaluation table's rows are the boxes: there the letters edit the
  // selected one, as in the box list.
  auto* scores = window_.findChild<QTableView*>("evaluationTable");
  ASSERT_NE(scores, nullptr);
  focus(*scores);
  boxes().select(0);
  QTest::keyClick(scores, Qt::Key_W);
  EXPECT_EQ(boxes().undoStack().count(), edits + 1);
  EXPECT_NE(boxes().box(0).box.center, before.box.center);
}

TEST_F(FocusedKeysTest, TheFocusBringsItsPanelToTheFront) {
  QDockWidget& evaluation = dock("evaluationDock");
  QDockWidget& box_panel = dock("boxesDock");
  ASSERT_TRUE(window_.tabifiedDockWidgets(&evaluation).contains(&box_panel));
  evaluation.raise();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !evaluation.visibleRegion().isEmpty(); }, 5000));
  ASSERT_TRUE(box_panel.visibleRegion().isEmpty());
  auto* centre_x = window_.findChild<QDoubleSpinBox*>("boxField0");
  ASSERT_NE(centre_x, nullptr);
  centre_x->setFocus(Qt::TabFocusReason);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !box_panel.visibleRegion().isEmpty(); }, 5000))
      << "the Boxes panel stayed behind the Evaluation panel";
  EXPECT_TRUE(centre_x->hasFocus());
}

}  // namespace
}  // namespace lom::ui
