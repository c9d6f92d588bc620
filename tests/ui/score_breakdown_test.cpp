// View > Show Score Breakdown: the selected box's label's
// voxels coloured by how IU_3d counts them against the box, with counts that
// add up to the score the Evaluation panel shows; and one object selection
// shared by the Evaluation table and the boxes; and T, which tightens a box
// drawn roughly around an object onto the voxels it holds. (Pictures of the breakdown on
// the demo were looked at: the object's voxels green inside its box, blends
// of amber on its faces, red where they spill out.)
#include "lom/score_breakdown.hpp"

#include <gtest/gtest.h>

#include <QAction>
#include <QComboBox>
#include <QImage>
#include <QStatusBar>
#include <QTableWidget>
#include <QTest>

#include "demo_window_fixture.hpp"
#include "lom/box_fit.hpp"
#include "lom/label_map.hpp"
#include "lom/objects.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/score_breakdown_reaction.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;

class ScoreBreakdownTest : public fixture::DemoWindowTest {
 protected:
  EvaluationPanel& panel() { return window_.evaluationPanel(); }
  AnnotationsModel& boxes() { return window_.session().annotations(); }
  void openFuseAndScore() {
    openAndFuse();
    ASSERT_TRUE(
        QTest::qWaitFor([&] { return !panel().isBusy() && panel().canExport(); }, kTimeoutMs))
        << panel().summaryText().toStdString();
  }
  const ObjectScore& scoreOf(int label) {
    for (const ObjectScore& object : panel().report()->objects)
      if (object.label == label) return object;
    ADD_FAILURE() << "no score for label " << label;
    return panel().report()->objects.front();
  }
  QAction& breakdownAction() {
    QAction* action = window_.findAction("Show Score Breakdown");
    EXPECT_NE(action, nullptr);
    return *action;
  }
  QString statusMessage() { return window_.statusBar()->currentMessage(); }
  // The box of a visible object with the most voxels in the map.
  int largestBoxedObject() {
    const MapSnapshot& snapshot = *window_.session().worker().snapshot();
    int best = -1;
    size_t most = 0;
    for (int i = 0; i < boxes().boxCount(); ++i) {
      const auto it = snapshot.counts.find(boxes().box(i).label);
      if (it != snapshot.counts.end() && it->second > most) most = it->second, best = i;
    }
    return best;
  }
};

// Pixels of the picture whose colour is clearly `green` (else clearly red).
size_t countColoured(const QImage& picture, bool green) {
  size_t count = 0;
  for (int y = 0; y < picture.height(); ++y)
    for (int x = 0; x < picture.width(); ++x) {
      const QColor c = picture.pixelColor(x, y);
      const int main = green ? c.green() : c.red(), other = green ? c.red() : c.green();
      count += main > 120 && main > other + 80 && main > c.blue() + 80;
    }
  return count;
}

TEST_F(ScoreBreakdownTest, SelectedBoxsVoxelsAddUpToItsScoreAndFollowItsEdits) {
  openFuseAndScore();
  SceneView& scene = window_.sceneView();
  scene.setFrameCloudVisible(false);
  QAction& action = breakdownAction();
  EXPECT_TRUE(action.isCheckable());
  EXPECT_EQ(action.shortcut(), QKeySequence("Ctrl+E"));

  // No box selected: every box's label's voxels, each against its own box.
  boxes().select(-1);
  action.trigger();
  ASSERT_TRUE(action.isChecked());
  const MapSnapshot& map = *window_.session().worker().snapshot();
  size_t boxed_voxels = 0, inside = 0;
  for (int i = 0; i < boxes().boxCount(); ++i) {
    const ScoreBreakdown one =
        scoreBreakdown(map.voxels, map.resolution, boxes().box(i), IouMode::Exact);
    boxed_voxels += one.centres.size();
    inside += one.inside;
  }
  EXPECT_EQ(scene.scoreBreakdownCount(), boxed_voxels);
  EXPECT_TRUE(statusMessage().startsWith(
      QString("Score breakdown of all %1 boxes: %2 voxels inside their box")
          .arg(boxes().boxCount())
          .arg(inside)))
      << statusMessage().toStdString();

  const int index = largestBoxedObject();
  ASSERT_GE(index, 0);
  const GroundTruthBox box = boxes().box(index);
  action.trigger();  // off, for a picture without the breakdown
  const QImage before = scene.renderToImage();
  action.trigger();
  boxes().select(index);
  const MapSnapshot& snapshot = *window_.session().worker().snapshot();
  const ScoreBreakdown breakdown =
      scoreBreakdown(snapshot.voxels, snapshot.resolution, box, IouMode::Exact);
  // Every finest voxel of the label, each counted once.
  ASSERT_EQ(breakdown.centres.size(), snapshot.counts.at(box.label));
  EXPECT_EQ(scene.scoreBreakdownCount(), breakdown.centres.size());
  EXPECT_EQ(breakdown.inside + breakdown.partly + breakdown.outside, breakdown.centres.size());
  EXPECT_GT(breakdown.inside, 0u);
  // The same volumes as the Evaluation panel's score of the label.
  const ObjectScore& score = scoreOf(box.label);
  EXPECT_NEAR(breakdown.volumes.true_positive, score.labeloctomap_volumes.true_positive, 1e-12);
  EXPECT_NEAR(breakdown.volumes.predicted, score.labeloctomap_volumes.predicted, 1e-12);
  EXPECT_NEAR(breakdown.volumes.iou(), score.iou_3d.labeloctomap, 1e-9);
  const QString name = QString::fromStdString(score.name);
  EXPECT_EQ(statusMessage(), describeScoreBreakdown(breakdown, name));
  EXPECT_TRUE(statusMessage().contains(QString("%1 voxels inside it").arg(breakdown.inside)))
      << statusMessage().toStdString();
  // The score comes right after the object's name: a narrow status bar cuts the end.
  EXPECT_TRUE(statusMessage().startsWith(QString("%1 (label %2): IU_3d %3 %")
                                             .arg(name)
                                             .arg(box.label)
                                             .arg(score.iou_3d.labeloctomap * 100.0, 0, 'f', 1)))
      << statusMessage().toStdString();
  const QImage shown = scene.renderToImage();
  EXPECT_GT(countColoured(shown, true), countColoured(before, true) + 50)
      << "the voxels inside the box are drawn green";

  // The box moved away from its object: every voxel is outside, drawn red.
  GroundTruthBox moved = box;
  moved.box.center.x() += 2.0;
  boxes().setBox(index, moved, "move away");
  const ScoreBreakdown away =
      scoreBreakdown(snapshot.voxels, snapshot.resolution, moved, IouMode::Exact);
  EXPECT_EQ(away.outside, away.centres.size());
  EXPECT_EQ(away.volumes.iou(), 0.0);
  EXPECT_EQ(scene.scoreBreakdownCount(), away.centres.size());
  EXPECT_TRUE(statusMessage().contains("IU_3d 0.0 %")) << statusMessage().toStdString();
  const QImage spilled = scene.renderToImage();
  EXPECT_GT(countColoured(spilled, false), countColoured(shown, false) + 50)
      << "the voxels outside the box are drawn red";
  boxes().undoStack().undo();
  EXPECT_EQ(statusMessage(), describeScoreBreakdown(breakdown, name));

  // Scored by voxel centres (the Evaluation panel's choice): the breakdown
  // counts whole voxels by their centres, as the scores do.
  QComboBox& mode = window_.evaluationPanel().iouModeBox();
  mode.setCurrentIndex(mode.findText("Voxel centres"));
  const ScoreBreakdown centres =
      scoreBreakdown(snapshot.voxels, snapshot.resolution, box, IouMode::Center);
  EXPECT_EQ(centres.partly, 0u);
  EXPECT_EQ(statusMessage(), describeScoreBreakdown(centres, name));
  mode.setCurrentIndex(mode.findText("Exact volumes"));
  EXPECT_EQ(statusMessage(), describeScoreBreakdown(breakdown, name));

  // Off: the overlay goes and the status bar no longer describes it.
  action.trigger();
  EXPECT_EQ(scene.scoreBreakdownCount(), 0u);
  EXPECT_TRUE(statusMessage().isEmpty()) << statusMessage().toStdString();
  boxes().select(-1);
  EXPECT_EQ(scene.scoreBreakdownCount(), 0u) << "the breakdown stays off";
}

TEST_F(ScoreBreakdownTest, EvaluationRowsAndBoxesShareOneSelection) {
  openFuseAndScore();
  QTableWidget& table = panel().table();
  ASSERT_GE(table.rowCount(), 2);
  for (int row : {1, 0}) {
    table.selectRow(row);
    const int label = table.item(row, EvaluationPanel::Label)->text().toInt();
    ASSERT_GE(boxes().selected(), 0);
    EXPECT_EQ(boxes().box(boxes().selected()).label, label);
  }
  // The other way: selecting a box selects its row, wherever the sort put it.
  table.sortItems(EvaluationPanel::LabelOctoMap, Qt::DescendingOrder);
  for (int i = 0; i < boxes().boxCount(); ++i) {
    boxes().select(i);
    const QList<QTableWidgetItem*> selected = table.selectedItems();
    ASSERT_FALSE(selected.isEmpty());
    EXPECT_EQ(table.item(selected.front()->row(), EvaluationPanel::Label)->text().toInt(),
              boxes().box(i).label);
  }
  boxes().select(-1);
  EXPECT_TRUE(table.selectedItems().isEmpty());
  // The LabelOctoMap cell says what its score is made of.
  const QString tip = table.item(0, EvaluationPanel::LabelOctoMap)->toolTip();
  EXPECT_TRUE(tip.contains("cm³ of its voxels inside the box")) << tip.toStdString();
}

TEST_F(ScoreBreakdownTest, TightenPullsARoughBoxOntoTheVoxelsItHolds) {
  openAndFuse();
  const int index = largestBoxedObject();
  ASSERT_GE(index, 0);
  GroundTruthBox rough = boxes().box(index);
  rough.box.size += Eigen::Vector3d::Constant(0.02);  // 1 cm of slack on every side
  boxes().setBox(index, rough, "rough");
  boxes().select(index);
  QAction* tighten = window_.findAction("Tighten Box to the Voxels Inside");
  ASSERT_NE(tighten, nullptr);
  EXPECT_EQ(tighten->shortcut(), QKeySequence("T"));
  ASSERT_TRUE(tighten->isEnabled());
  tighten->trigger();

  // The object voxels (any label but the background) inside the rough box.
  const MapSnapshot& snapshot = *window_.session().worker().snapshot();
  std::vector<OccupiedVoxel> objects;
  for (const OccupiedVoxel& voxel : snapshot.voxels)
    if (voxel.label != 0) objects.push_back(voxel);
  const auto expected =
      tightenBox(rough.box, finestVoxelCentres(objects, snapshot.resolution), snapshot.resolution);
  ASSERT_TRUE(expected.has_value());
  const OrientedBox tight = boxes().box(index).box;
  EXPECT_NEAR((tight.center - expected->center).norm(), 0.0, 1e-12);
  EXPECT_NEAR((tight.size - expected->size).norm(), 0.0, 1e-12);
  EXPECT_TRUE(tight.rotation.isApprox(rough.box.rotation));
  EXPECT_LT(tight.volume(), rough.box.volume());
  EXPECT_TRUE(statusMessage().startsWith("Box tightened onto the voxels inside it: "))
      << statusMessage().toStdString();
  // One undo step gives the rough box back.
  boxes().undoStack().undo();
  EXPECT_TRUE(boxes().box(index).box.size.isApprox(rough.box.size));

  // Over no voxel: the box stays as it is, and the status bar says why.
  GroundTruthBox away = rough;
  away.box.center.z() += 5.0;
  boxes().setBox(index, away, "away");
  tighten->trigger();
  EXPECT_TRUE(boxes().box(index).box.center.isApprox(away.box.center));
  EXPECT_TRUE(
      statusMessage().startsWith("Tighten Box: no voxel of an object has its centre inside"))
      << statusMessage().toStdString();

  // A map of background only (a recording without labels) around the box:
  // moving the box cannot help, which the status bar says instead.
  boxes().setBox(index, rough, "back");
  LabelMap background(window_.session().sequence()->labels);
  ASSERT_GT(rasterizeBox(background, rough.box, 0, 0.9), 0u);
  const auto file = temp_.path() / "background.ot";
  background.save(file);
  window_.setWarningReporter([](const QString&, const QString&) {});  // "Map of another scene?"
  window_.session().openMap(fixture::qPath(file));
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        const auto shown = window_.session().worker().snapshot();
        return !window_.session().worker().isFusing() && shown && !shown->voxels.empty() &&
               shown->counts.size() == 1;
      },
      fixture::kTimeoutMs));
  tighten->trigger();
  EXPECT_TRUE(boxes().box(index).box.size.isApprox(rough.box.size));
  EXPECT_TRUE(
      statusMessage().startsWith("Tighten Box: the map has no voxel of an object, only "
                                 "background"))
      << statusMessage().toStdString();
}

}  // namespace
}  // namespace lom::ui
