// The Objects dock on the synthetic demo scene: the objects extracted after
// fusion, their boxes in 3D, and a pick plan with its steps and 3D layer.
#include "lom/ui/objects_panel.hpp"

#include <gtest/gtest.h>

#include <QCheckBox>
#include <QComboBox>
#include <QPushButton>
#include <QRegion>
#include <QStatusBar>
#include <QTableWidget>
#include <QTest>
#include <algorithm>
#include <filesystem>
#include <set>

#include "demo_window_fixture.hpp"
#include "lom/annotations.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/demo_scene.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;
using fixture::qPath;

class ObjectsPanelTest : public fixture::DemoWindowTest {
 protected:
  // Opens and fuses the demo, then waits for the objects the fusion triggers.
  void openFuseAndExtract() {
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
    StudioSession& session = window_.session();
    ASSERT_TRUE(QTest::qWaitFor([&] { return !session.worker().isFusing(); }, kTimeoutMs));
    ObjectsPanel& panel = window_.objectsPanel();
    ASSERT_TRUE(QTest::qWaitFor([&] { return !panel.isBusy() && panel.table().rowCount() > 0; },
                                kTimeoutMs))
        << panel.statusText().toStdString();
  }
};

// The fusion a sequence's opening starts is said, not "Fuse the sequence".
TEST_F(ObjectsPanelTest, SaysFusingWhileTheOpenedSequenceIsFused) {
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(window_.session().worker().isFusing());
  EXPECT_TRUE(window_.objectsPanel().statusText().startsWith("Fusing:"))
      << window_.objectsPanel().statusText().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.session().worker().isFusing(); }, kTimeoutMs));
}

// A recording of geometry only (no labels given) can have no objects: the
// panel says why, not "no objects yet".
TEST_F(ObjectsPanelTest, ARecordingOfGeometryOnlySaysWhyItHasNoObjects) {
  const lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "tiny_shelf");
  lom::test::writeFramesLayout(tiny, temp / "room");
  ASSERT_TRUE(window_.controller().openSequence(qPath(temp / "room")));
  ASSERT_EQ(window_.session().sequence()->labels.size(), 1u);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.session().worker().isFusing(); }, kTimeoutMs));
  ObjectsPanel& panel = window_.objectsPanel();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !panel.isBusy(); }, kTimeoutMs));
  EXPECT_TRUE(panel.statusText().contains("the sequence's only label is the background"))
      << panel.statusText().toStdString();
}

TEST_F(ObjectsPanelTest, ListsTheFusedObjectsAndDrawsTheirBoxes) {
  openFuseAndExtract();
  EXPECT_TRUE(errors_.empty()) << errors_.front().toStdString();
  ObjectsPanel& panel = window_.objectsPanel();
  const std::vector<int> listed = panel.listedLabels();
  // Listed by label, ascending, as the Evaluation panel lists them.
  EXPECT_TRUE(std::is_sorted(listed.begin(), listed.end()));
  EXPECT_EQ(panel.statusText(), QString("%1 objects in the map.").arg(panel.objects().size()));
  for (int row = 0; row < panel.table().rowCount(); ++row) {  // three decimals, every row
    const QString mean = panel.table().item(row, ObjectsPanel::MeanProbability)->text();
    EXPECT_EQ(mean.size() - mean.indexOf('.'), 4) << mean.toStdString();
  }
  for (int label : visibleObjectLabels())
    EXPECT_NE(std::find(listed.begin(), listed.end(), label), listed.end())
        << "objects table misses label " << label;
  EXPECT_EQ(panel.targetCombo().count() > 0, true);
  EXPECT_TRUE(panel.planButton().isEnabled());

  SceneView& scene = window_.sceneView();
  ASSERT_TRUE(panel.showBoxesCheck().isChecked());
  EXPECT_EQ(scene.objectBoxCount(), panel.objects().size());
  panel.showBoxesCheck().setChecked(false);
  EXPECT_EQ(scene.objectBoxCount(), 0u);
  panel.showBoxesCheck().setChecked(true);
  EXPECT_EQ(scene.objectBoxCount(), panel.objects().size());
}

TEST_F(ObjectsPanelTest, ThePlansFirstStepsAreInSightInAShortDock) {
  // A 1280x1024 screen: the Objects dock shares the right side with three
  // others, and its table of objects is long.
  window_.resize(1280, 1000);
  settle();
  openFuseAndExtract();
  dock("objectsDock").raise();
  settle();
  ObjectsPanel& panel = window_.objectsPanel();
  const int index = panel.targetCombo().findData(*visibleObjectLabels().begin());
  ASSERT_GE(index, 0);
  panel.targetCombo().setCurrentIndex(index);
  QTest::mouseClick(&panel.planButton(), Qt::LeftButton);
  ASSERT_TRUE(panel.plan().has_value()) << panel.statusText().toStdString();
  settle();
  QTableWidget& steps = panel.stepsTable();
  ASSERT_GE(steps.rowCount(), 1);
  for (int row = 0; row < std::min(steps.rowCount(), 2); ++row) {
    const QRect cell = steps.visualRect(steps.model()->index(row, ObjectsPanel::Action));
    // Wholly in sight (QRegion::contains only asks for an overlap).
    EXPECT_TRUE(QRegion(cell).subtracted(steps.viewport()->visibleRegion()).isEmpty())
        << "step " << row + 1 << " is hidden: the visible part of the steps is "
        << steps.viewport()->visibleRegion().boundingRect().height() << " px high";
  }
  // So are the first objects.
  QTableWidget& objects = panel.table();
  const QRect first = objects.visualRect(objects.model()->index(0, 0));
  EXPECT_TRUE(QRegion(first).subtracted(objects.viewport()->visibleRegion()).isEmpty());
}

TEST_F(ObjectsPanelTest, PlanPickEndsWithPickingTheTargetAndDrawsThePlan) {
  openFuseAndExtract();
  ObjectsPanel& panel = window_.objectsPanel();
  SceneView& scene = window_.sceneView();
  EXPECT_FALSE(scene.pickPlanVisible());

  const int target = *visibleObjectLabels().begin();
  const int index = panel.targetCombo().findData(target);
  ASSERT_GE(index, 0) << "target combo misses label " << target;
  panel.targetCombo().setCurrentIndex(index);
  QTest::mouseClick(&panel.planButton(), Qt::LeftButton);

  ASSERT_TRUE(panel.plan().has_value()) << panel.statusText().toStdString();
  const PickPlan& plan = *panel.plan();
  ASSERT_FALSE(plan.steps.empty());
  EXPECT_EQ(plan.target_label, target);
  EXPECT_EQ(plan.steps.back().action, StepAction::Pick);
  EXPECT_EQ(plan.objects[plan.steps.back().object].label, target);
  // As `labeloctomap plan` plans the map: along the cameras it was fused from.
  EXPECT_EQ(plan.approach_source, ApproachSource::MapCameras);
  EXPECT_TRUE(panel.statusText().contains("the mean viewing direction of the frames fused"))
      << panel.statusText().toStdString();

  QTableWidget& steps = panel.stepsTable();
  ASSERT_EQ(steps.rowCount(), static_cast<int>(plan.steps.size()));
  const int last = steps.rowCount() - 1;
  EXPECT_EQ(steps.item(last, ObjectsPanel::Action)->text(), QString("pick"));
  EXPECT_TRUE(steps.item(last, ObjectsPanel::Object)->text().startsWith(QString::number(target)));
  for (int row = 0; row < last; ++row)
    EXPECT_EQ(steps.item(row, ObjectsPanel::Action)->text(), QString("remove"));

  EXPECT_TRUE(scene.pickPlanVisible());
  EXPECT_EQ(scene.pickPlanBoxCount(), plan.occluders.size() + 1);
  const QString occluders =
      plan.occluders.empty() ? QString("nothing to remove first.")
      : plan.occluders.size() == 1
          ? QString("1 occluder to remove first.")
          : QString("%1 occluders to remove first.").arg(plan.occluders.size());
  EXPECT_TRUE(panel.statusText().contains(occluders)) << panel.statusText().toStdString();
  EXPECT_EQ(scene.pickPlanArrowCount(), plan.steps.size());
  EXPECT_FALSE(scene.renderToImage().isNull());

  // Re-extracting drops the plan and its layer.
  QTest::mouseClick(panel.findChild<QPushButton*>("refreshObjectsButton"), Qt::LeftButton);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !panel.isBusy(); }, kTimeoutMs));
  EXPECT_FALSE(panel.plan().has_value());
  EXPECT_FALSE(scene.pickPlanVisible());
}

// The Target drop-down is a label drop-down: letters typed into it find a
// target by name and are not the window's one-key box edits; another target
// plans again rather than leave the steps of the previous one on show.
TEST_F(ObjectsPanelTest, TheTargetIsChosenByNameAndPlannedAgain) {
  openFuseAndExtract();
  ObjectsPanel& panel = window_.objectsPanel();
  QComboBox& target = panel.targetCombo();
  ASSERT_GE(target.count(), 2);
  AnnotationsModel& boxes = window_.session().annotations();
  ASSERT_GT(boxes.boxCount(), 0);
  boxes.select(0);
  const GroundTruthBox before = boxes.box(0);
  const int edits = boxes.undoStack().count();

  target.setCurrentIndex(0);
  QTest::mouseClick(&panel.planButton(), Qt::LeftButton);
  ASSERT_TRUE(panel.plan().has_value()) << panel.statusText().toStdString();
  EXPECT_EQ(panel.plan()->target_label, target.itemData(0).toInt());

  window_.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
  target.setFocus();
  ASSERT_TRUE(QTest::qWaitFor([&] { return target.hasFocus(); }, 5000));
  const int wanted = target.count() - 1;
  const QString entry = target.itemText(wanted);
  const QString prefix = entry.mid(entry.indexOf(' ') + 1).left(4);
  ASSERT_TRUE(prefix.at(0).isLetter()) << entry.toStdString();
  QTest::keyClicks(&target, prefix);
  EXPECT_EQ(target.currentIndex(), wanted) << target.currentText().toStdString();
  QTest::keyClick(&target, Qt::Key_W);
  QTest::keyClick(&target, Qt::Key_B);
  EXPECT_EQ(boxes.undoStack().count(), edits);
  EXPECT_EQ(boxes.box(0).box.center, before.box.center);
  EXPECT_EQ(boxes.box(0).box.size, before.box.size);

  ASSERT_TRUE(panel.plan().has_value());
  EXPECT_EQ(panel.plan()->target_label, target.itemData(wanted).toInt());
  const QString steps_object =
      panel.stepsTable().item(panel.stepsTable().rowCount() - 1, ObjectsPanel::Object)->text();
  EXPECT_TRUE(steps_object.startsWith(QString::number(target.itemData(wanted).toInt()) + " "))
      << steps_object.toStdString();
}

// Save Plan… writes the plan shown as `labeloctomap plan --out` does, beside
// the sequence and named after it; it never replaces a file of the sequence,
// and there is nothing to save before a plan or after the map changed.
TEST_F(ObjectsPanelTest, SavePlanWritesThePlanShownAsPlanJson) {
  openFuseAndExtract();
  ObjectsPanel& panel = window_.objectsPanel();
  EXPECT_FALSE(panel.savePlanButton().isEnabled());
  EXPECT_FALSE(panel.savePlanTo(qPath(temp_.path() / "early.json")).isEmpty());
  EXPECT_FALSE(std::filesystem::exists(temp_.path() / "early.json"));

  const int target = *visibleObjectLabels().begin();
  panel.targetCombo().setCurrentIndex(panel.targetCombo().findData(target));
  QTest::mouseClick(&panel.planButton(), Qt::LeftButton);
  ASSERT_TRUE(panel.plan().has_value()) << panel.statusText().toStdString();
  ASSERT_TRUE(panel.savePlanButton().isEnabled());

  const auto chosen = temp_.path() / "my plan.json";
  QString offered;
  panel.setPlanFileChooser([&](const QString& start) {
    offered = start;
    return qPath(chosen);
  });
  QTest::mouseClick(&panel.savePlanButton(), Qt::LeftButton);
  EXPECT_EQ(offered, window_.controller().proposedOutput("-plan.json"));
  EXPECT_TRUE(offered.endsWith("-plan.json")) << offered.toStdString();
  ASSERT_TRUE(std::filesystem::exists(chosen)) << panel.statusText().toStdString();
  EXPECT_TRUE(panel.statusText().startsWith("Plan saved to")) << panel.statusText().toStdString();
  EXPECT_TRUE(window_.statusBar()->currentMessage().startsWith("Plan saved to"))
      << window_.statusBar()->currentMessage().toStdString();
  const std::string text = test::slurp(chosen);
  EXPECT_EQ(text, planJson(*panel.plan()));  // the map was fused here: no file to name
  EXPECT_NE(text.find("\"labeloctomap-plan\""), std::string::npos) << text;
  // The threshold the objects were read at is the view's (`plan --threshold` reproduces it).
  ASSERT_TRUE(panel.plan()->occupancy_threshold.has_value());
  EXPECT_EQ(*panel.plan()->occupancy_threshold,
            window_.session().fusionOptions().map.occupancy_threshold);
  EXPECT_NE(text.find("\"occupancy_threshold\""), std::string::npos) << text;

  // The sequence's own files are never replaced by a plan.
  const auto sequence_json = folder_ / "sequence.json";
  const std::string before = test::slurp(sequence_json);
  const QString refused = panel.savePlanTo(qPath(sequence_json));
  EXPECT_TRUE(refused.contains("is a file of the sequence")) << refused.toStdString();
  EXPECT_EQ(test::slurp(sequence_json), before);
  // Nor are its boxes, also while the file is absent (the studio makes it later).
  const auto boxes_file = folder_ / "annotations.json";
  const bool had_boxes = std::filesystem::exists(boxes_file);
  const std::string boxes_before = had_boxes ? test::slurp(boxes_file) : std::string();
  const QString boxes_refused = panel.savePlanTo(qPath(boxes_file));
  EXPECT_TRUE(boxes_refused.contains("is a file of the sequence")) << boxes_refused.toStdString();
  EXPECT_EQ(std::filesystem::exists(boxes_file), had_boxes);
  if (had_boxes) {
    EXPECT_EQ(test::slurp(boxes_file), boxes_before);
  }

  // A new fusion drops the plan, and with it what there is to save.
  window_.session().fuse();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !panel.plan().has_value(); }, kTimeoutMs));
  EXPECT_FALSE(panel.savePlanButton().isEnabled());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !window_.session().worker().isFusing(); }, kTimeoutMs));
}

}  // namespace
}  // namespace lom::ui
