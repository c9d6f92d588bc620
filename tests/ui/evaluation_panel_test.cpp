// The Evaluation dock on the synthetic demo scene: the score columns and
// every row in view at the default window size, the table and the bar chart
// in the same order, and the summary's wording.
#include "lom/ui/evaluation_panel.hpp"

#include <gtest/gtest.h>

#include <QApplication>
#include <QComboBox>
#include <QFontMetrics>
#include <QHeaderView>
#include <QListWidget>
#include <QScrollBar>
#include <QStyle>
#include <QTableWidget>
#include <QTest>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <memory>
#include <thread>
#include <vector>

#include "demo_window_fixture.hpp"
#include "dialog_answerer.hpp"
#include "lom/evaluation.hpp"
#include "lom/sequence.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/demo_scene.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/score_chart.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;
using fixture::qPath;

class EvaluationPanelTest : public fixture::DemoWindowTest {
 protected:
  EvaluationPanel& panel() { return window_.evaluationPanel(); }
  void waitForScores() {
    ASSERT_TRUE(
        QTest::qWaitFor([&] { return !panel().isBusy() && panel().canExport(); }, kTimeoutMs))
        << panel().summaryText().toStdString();
  }
  // The labels of the table's rows, top to bottom.
  std::vector<int> tableLabels() {
    std::vector<int> labels;
    QTableWidget& table = panel().table();
    for (int row = 0; row < table.rowCount(); ++row)
      labels.push_back(table.item(row, EvaluationPanel::Label)->data(Qt::DisplayRole).toInt());
    return labels;
  }
  std::vector<int> chartLabels() {
    std::vector<int> labels;
    for (const ObjectScore& object : panel().chart().objects()) labels.push_back(object.label);
    return labels;
  }
};

TEST_F(EvaluationPanelTest, ScoresAndEveryRowAreInViewAtTheDefaultWindowSize) {
  // The demo the studio opens with --demo has six objects.
  SynthOptions six = fixture::smallDemo();
  six.objects = 6;
  const auto folder = temp_.path() / "six";
  prepareDemoScene(qPath(folder), six);
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder)));
  waitForFusion();
  waitForScores();
  window_.resize(1280, 800);  // MainWindow's own size
  QTest::qWait(100);
  QApplication::processEvents();

  QTableWidget& table = panel().table();
  ASSERT_TRUE(table.isVisible());
  ASSERT_EQ(table.rowCount(), 6);
  auto expectAllColumnsInView = [&] {
    EXPECT_FALSE(table.horizontalScrollBar()->isVisible());
    const int width = table.viewport()->width();
    for (int column = 0; column < EvaluationPanel::Columns; ++column) {
      const auto header = table.horizontalHeaderItem(column)->text().toStdString();
      EXPECT_GE(table.columnViewportPosition(column), 0) << header;
      EXPECT_LE(table.columnViewportPosition(column) + table.columnWidth(column), width) << header;
      // Numbers (and the sort arrow) are never cut: only the object name gives way.
      if (column != EvaluationPanel::Name) {
        const QAbstractItemView& view = table;  // sizeHintForColumn is public there
        EXPECT_GE(table.columnWidth(column), view.sizeHintForColumn(column)) << header;
        EXPECT_GE(table.columnWidth(column), table.horizontalHeader()->sectionSizeHint(column))
            << header;
        // The header is drawn bold while a row is selected (always, once
        // scored): its text and the style's margins fit in bold too.
        QFont bold = table.horizontalHeader()->font();
        bold.setBold(true);
        const int margin = table.style()->pixelMetric(QStyle::PM_HeaderMargin, nullptr, &table);
        EXPECT_GE(table.columnWidth(column),
                  QFontMetrics(bold).horizontalAdvance(table.horizontalHeaderItem(column)->text()) +
                      2 * margin)
            << header;
      }
    }
  };
  expectAllColumnsInView();
  EXPECT_FALSE(table.verticalScrollBar()->isVisible());
  for (int column = 0; column < EvaluationPanel::Columns; ++column)
    EXPECT_FALSE(table.horizontalHeaderItem(column)->toolTip().isEmpty()) << column;
  EXPECT_TRUE(table.horizontalHeaderItem(EvaluationPanel::LabelOctoMap)
                  ->toolTip()
                  .contains("LabelOctoMap"));
  const int last = table.rowCount() - 1;
  EXPECT_LE(table.rowViewportPosition(last) + table.rowHeight(last), table.viewport()->height());
  for (int row = 0; row < table.rowCount(); ++row) {
    const QTableWidgetItem* name = table.item(row, EvaluationPanel::Name);
    EXPECT_EQ(name->toolTip(), name->text());
  }

  // Sorted by another column, which then shows the sort arrow.
  ASSERT_TRUE(table.isSortingEnabled());
  table.horizontalHeader()->setSortIndicator(EvaluationPanel::LabelOctoMap, Qt::DescendingOrder);
  QApplication::processEvents();
  expectAllColumnsInView();
}

// A depth_scale ten times too small fuses a map ten times too small: the
// studio's scores say so, as score's do.
TEST_F(EvaluationPanelTest, ScoresOfDepthsNearerThanCamerasMeasureSaySo) {
  Sequence sequence = loadSequence(folder_);
  sequence.camera.depth_scale /= 10.0;
  saveSequence(sequence, folder_);
  openAndFuse();
  waitForScores();
  const std::string expected = (folder_ / "sequence.json").string() +
                               ": camera.depth_scale: the farthest measured point of the " +
                               std::to_string(sequence.frames.size()) + " frames fused lies ";
  const auto& warnings = panel().report()->warnings;
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [&](const std::string& warning) {
    return warning.rfind(expected, 0) == 0;
  })) << ::testing::PrintToString(warnings);
}

TEST_F(EvaluationPanelTest, TableAndChartListTheObjectsInTheSameOrder) {
  openAndFuse();
  waitForScores();
  // Ascending label by default, in both.
  const std::vector<int> labels = tableLabels();
  ASSERT_GE(labels.size(), 2u);
  EXPECT_TRUE(std::is_sorted(labels.begin(), labels.end()));
  EXPECT_EQ(chartLabels(), labels);
  EXPECT_EQ(panel().table().horizontalHeader()->sortIndicatorSection(), EvaluationPanel::Label);
  EXPECT_EQ(panel().table().horizontalHeader()->sortIndicatorOrder(), Qt::AscendingOrder);

  // Sorted by another column (as a header click does), the chart follows.
  panel().table().horizontalHeader()->setSortIndicator(EvaluationPanel::Voxels,
                                                       Qt::DescendingOrder);
  std::vector<double> voxels;
  for (int row = 0; row < panel().table().rowCount(); ++row)
    voxels.push_back(
        panel().table().item(row, EvaluationPanel::Voxels)->data(Qt::DisplayRole).toDouble());
  EXPECT_TRUE(std::is_sorted(voxels.rbegin(), voxels.rend()));
  EXPECT_EQ(chartLabels(), tableLabels());

  // New scores keep the user's order.
  window_.session().annotations().removeBox(0);
  waitForScores();
  EXPECT_EQ(panel().table().rowCount(), static_cast<int>(labels.size()) - 1);
  EXPECT_EQ(chartLabels(), tableLabels());
}

// The selection stays on the box the user last saw selected: new scores
// rebuild the table without moving it, and undo and redo of a delete keep the
// model and the table on the same box.
TEST_F(EvaluationPanelTest, NewScoresAndUndoNeverMoveTheSelectionToAnotherBox) {
  openAndFuse();
  waitForScores();
  AnnotationsModel& boxes = window_.session().annotations();
  ASSERT_GE(boxes.boxCount(), 4);
  const auto selectedLabel = [&] {
    return boxes.selected() < 0 ? -1 : boxes.box(boxes.selected()).label;
  };
  const auto tableSelectedLabel = [&] {
    const QList<QTableWidgetItem*> items = panel().table().selectedItems();
    return items.isEmpty() ? -1
                           : panel()
                                 .table()
                                 .item(items.front()->row(), EvaluationPanel::Label)
                                 ->data(Qt::DisplayRole)
                                 .toInt();
  };
  // The boxes in an order other than the table's, so that the rows move.
  std::vector<GroundTruthBox> shuffled;
  for (const int i : {2, 0, 3, 1}) shuffled.push_back(boxes.box(i));
  for (int i = 4; i < boxes.boxCount(); ++i) shuffled.push_back(boxes.box(i));
  for (int i = boxes.boxCount() - 1; i >= 0; --i) boxes.removeBox(i);
  for (const GroundTruthBox& box : shuffled) boxes.addBox(box);
  waitForScores();

  for (int deleted = 0; deleted < 3; ++deleted) {
    SCOPED_TRACE(deleted);
    boxes.select(1);
    const int removed = selectedLabel();
    boxes.removeBox(1);
    EXPECT_TRUE(panel().summaryText().startsWith("Updating the scores…"))
        << panel().summaryText().toStdString();
    const int successor = selectedLabel();
    ASSERT_NE(successor, removed);
    waitForScores();
    EXPECT_EQ(selectedLabel(), successor) << "new scores moved the selection";
    EXPECT_EQ(tableSelectedLabel(), successor);

    boxes.undoStack().undo();  // the box comes back, selected
    EXPECT_EQ(selectedLabel(), removed);
    // Its row comes with the new scores; until then no other row is selected.
    EXPECT_EQ(tableSelectedLabel(), -1) << "the table stayed on another box";
    waitForScores();
    EXPECT_EQ(selectedLabel(), removed);
    EXPECT_EQ(tableSelectedLabel(), removed);

    // Redo while a later box is selected: that box stays selected.
    boxes.select(boxes.boxCount() - 1);
    const int last = selectedLabel();
    boxes.undoStack().redo();
    EXPECT_EQ(selectedLabel(), last);
    EXPECT_EQ(tableSelectedLabel(), last);
    waitForScores();
    EXPECT_EQ(selectedLabel(), last);
    boxes.undoStack().undo();
    waitForScores();
  }
}

// Delete in the sorted table selects the next row as sorted (the row above
// for the last row), not the deleted box's successor in the boxes file; from
// elsewhere (the 3D view) it is the successor in the file.
TEST_F(EvaluationPanelTest, DeleteInTheSortedTableSelectsTheNextRow) {
  openAndFuse();
  waitForScores();
  AnnotationsModel& boxes = window_.session().annotations();
  ASSERT_GE(boxes.boxCount(), 4);
  QTableWidget& table = panel().table();
  const auto selectedLabel = [&] {
    return boxes.selected() < 0 ? -1 : boxes.box(boxes.selected()).label;
  };
  const auto fileSuccessorLabel = [&](int label) {
    const int index = boxes.indexOfLabel(label);
    return boxes.box(index + 1 < boxes.boxCount() ? index + 1 : index - 1).label;
  };
  window_.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window_));
  // Descending labels: the next row is the box before in the file.
  table.sortItems(EvaluationPanel::Label, Qt::DescendingOrder);
  std::vector<int> rows = tableLabels();
  ASSERT_EQ(rows.size(), static_cast<size_t>(boxes.boxCount()));
  table.setFocus();
  boxes.select(boxes.indexOfLabel(rows[1]));
  ASSERT_EQ(table.currentRow(), 1);
  ASSERT_NE(fileSuccessorLabel(rows[1]), rows[2]) << "the test needs orders that differ";
  QTest::keyClick(&table, Qt::Key_Delete);
  EXPECT_EQ(boxes.indexOfLabel(rows[1]), -1);
  EXPECT_EQ(selectedLabel(), rows[2]);
  waitForScores();
  EXPECT_EQ(selectedLabel(), rows[2]);
  EXPECT_EQ(tableLabels()[static_cast<size_t>(table.currentRow())], rows[2]);

  // The last row: the one above it.
  rows = tableLabels();
  boxes.select(boxes.indexOfLabel(rows.back()));
  table.setFocus();
  QTest::keyClick(&table, Qt::Key_Delete);
  EXPECT_EQ(selectedLabel(), rows[rows.size() - 2]);
  // Undo brings the deleted box back, selected.
  boxes.undoStack().undo();
  EXPECT_EQ(selectedLabel(), rows.back());
  waitForScores();

  // From the 3D view: the successor in the boxes file.
  rows = tableLabels();
  boxes.select(boxes.indexOfLabel(rows[1]));
  const int in_file = fileSuccessorLabel(rows[1]);
  window_.sceneView().setFocus();
  QTest::keyClick(QApplication::focusWidget() ? QApplication::focusWidget() : &window_,
                  Qt::Key_Delete);
  EXPECT_EQ(selectedLabel(), in_file);
}

// Export report asks before replacing a report the folder holds, and never
// writes into the sequence's own files.
TEST_F(EvaluationPanelTest, ExportReportAsksBeforeReplacingAReport) {
  openAndFuse();
  waitForScores();
  const auto out = temp_.path() / "reports";
  std::filesystem::create_directories(out);
  std::ofstream(out / "report.md") << "my notes\n";
  {
    test::DialogAnswerer answer("Cancel");
    EXPECT_FALSE(panel().exportReportTo(qPath(out)));
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions.front().contains("already holds report.md"))
        << answer.questions.front().toStdString();
  }
  EXPECT_EQ(lom::test::slurp(out / "report.md"), "my notes\n");
  EXPECT_FALSE(std::filesystem::exists(out / "report.json"));
  {
    test::DialogAnswerer answer("Replace");
    EXPECT_TRUE(panel().exportReportTo(qPath(out)));
    EXPECT_EQ(answer.questions.size(), 1);
  }
  EXPECT_TRUE(std::filesystem::exists(out / "report.json"));
  EXPECT_NE(lom::test::slurp(out / "report.md"), "my notes\n");
  {
    test::DialogAnswerer answer("Replace");  // four files now, one question
    EXPECT_TRUE(panel().exportReportTo(qPath(out)));
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions.front().contains("report.json, report.csv, report.md, report.svg"))
        << answer.questions.front().toStdString();
  }
}

TEST_F(EvaluationPanelTest, ProjectionScoresNameEachViewAndADoubleClickShowsTheBest) {
  openAndFuse();
  waitForScores();
  const EvaluationReport& report = *panel().report();
  ASSERT_GE(report.views.size(), 2u);
  QTableWidget& table = panel().table();
  // Sorted by the best projection, so that row order and report order differ.
  table.sortItems(EvaluationPanel::ProjectionMax, Qt::DescendingOrder);
  for (int row = 0; row < table.rowCount(); ++row) {
    const int label = table.item(row, EvaluationPanel::Label)->text().toInt();
    const auto object = std::find_if(report.objects.begin(), report.objects.end(),
                                     [&](const ObjectScore& o) { return o.label == label; });
    ASSERT_NE(object, report.objects.end());
    const size_t best =
        static_cast<size_t>(std::max_element(object->per_view.begin(), object->per_view.end()) -
                            object->per_view.begin());
    const size_t frame = report.views[best];
    const QString tip = table.item(row, EvaluationPanel::ProjectionMax)->toolTip();
    // Frames as the timeline numbers them (from 1), the best also as in sequence.json.
    EXPECT_TRUE(tip.contains(QString("Best: frame %1 (frames[%2]).").arg(frame + 1).arg(frame)))
        << tip.toStdString();
    EXPECT_TRUE(tip.contains(QString("%1: %2")
                                 .arg(report.views.front() + 1)
                                 .arg(object->per_view.front() * 100.0, 0, 'f', 1)))
        << tip.toStdString();
    EXPECT_EQ(table.item(row, EvaluationPanel::ProjectionMean)->toolTip(), tip);
    // Elsewhere first, then a double-click on the score goes to the best view.
    window_.controller().setCurrentFrame(frame == 0 ? 1 : 0);
    emit table.cellDoubleClicked(row, EvaluationPanel::ProjectionMax);
    EXPECT_EQ(window_.controller().currentFrame(), static_cast<int>(frame)) << "label " << label;
  }
  // A double-click on another column leaves the frame alone.
  window_.controller().setCurrentFrame(1);
  emit table.cellDoubleClicked(0, EvaluationPanel::LabelOctoMap);
  EXPECT_EQ(window_.controller().currentFrame(), 1);
}

// Voxel centres instead of exact volumes: the scores and the score breakdown
// count as `labeloctomap score --iou center` does, and back.
TEST_F(EvaluationPanelTest, VoxelCentresScoreAsScoreWithIouCenter) {
  openAndFuse();
  waitForScores();
  ASSERT_EQ(panel().report()->iou_mode, IouMode::Exact);
  QComboBox& mode = panel().iouModeBox();
  ASSERT_EQ(mode.count(), 2);
  EXPECT_EQ(mode.currentText(), "Exact volumes");
  const EvaluationReport exact = *panel().report();
  mode.setCurrentIndex(mode.findText("Voxel centres"));
  EXPECT_EQ(window_.session().iouMode(), IouMode::Center);
  waitForScores();
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return panel().report()->iou_mode == IouMode::Center; }, kTimeoutMs));
  const EvaluationReport& centres = *panel().report();
  const Sequence sequence = loadSequence(folder_);
  EvaluationOptions options;
  options.fusion = window_.session().fusionOptions();
  options.iou_mode = IouMode::Center;
  const EvaluationReport expected =
      evaluate(sequence, truth_, fuseSequence(sequence, options.fusion), options);
  ASSERT_EQ(centres.objects.size(), expected.objects.size());
  bool differs = false;
  for (size_t i = 0; i < expected.objects.size(); ++i) {
    EXPECT_DOUBLE_EQ(centres.objects[i].iou_3d.labeloctomap,
                     expected.objects[i].iou_3d.labeloctomap);
    EXPECT_DOUBLE_EQ(centres.objects[i].iou_3d.projection_max,
                     expected.objects[i].iou_3d.projection_max);
    differs =
        differs || centres.objects[i].iou_3d.labeloctomap != exact.objects[i].iou_3d.labeloctomap;
  }
  EXPECT_TRUE(differs) << "centre counts should move some score";
  // Back to exact volumes: the first scores again.
  mode.setCurrentIndex(mode.findText("Exact volumes"));
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        return !panel().isBusy() && panel().canExport() &&
               panel().report()->iou_mode == IouMode::Exact;
      },
      kTimeoutMs));
  for (size_t i = 0; i < exact.objects.size(); ++i)
    EXPECT_DOUBLE_EQ(panel().report()->objects[i].iou_3d.labeloctomap,
                     exact.objects[i].iou_3d.labeloctomap);
}

TEST_F(EvaluationPanelTest, SummarySaysOneObjectInTheSingular) {
  openAndFuse();
  waitForScores();
  EXPECT_TRUE(panel().summaryText().startsWith(
      QString("Mean over %1 objects — ").arg(panel().report()->summary.objects)))
      << panel().summaryText().toStdString();

  // Keep one box of an object the cameras see.
  AnnotationsModel& boxes = window_.session().annotations();
  const auto& all = boxes.annotations().boxes;
  const auto kept = std::find_if(all.begin(), all.end(), [](const GroundTruthBox& box) {
    return box.label != kSynthTransparentLabel;
  });
  ASSERT_NE(kept, all.end());
  const int kept_label = kept->label;
  for (int index = boxes.boxCount() - 1; index >= 0; --index)
    if (boxes.annotations().boxes[static_cast<size_t>(index)].label != kept_label)
      boxes.removeBox(index);
  ASSERT_EQ(boxes.boxCount(), 1);
  waitForScores();
  ASSERT_EQ(panel().report()->summary.objects, 1u);
  const QString summary = panel().summaryText();
  EXPECT_TRUE(summary.startsWith("Mean over 1 object — ")) << summary.toStdString();
  EXPECT_TRUE(summary.endsWith(" of 1.")) << summary.toStdString();
  EXPECT_FALSE(summary.contains("1 objects")) << summary.toStdString();
}

// What `labeloctomap score` warns about is said under the summary too: here a
// box whose name in the boxes file is not its label's (drawn for another
// label numbering?). The Boxes list names it by the label, as the scores do.
TEST_F(EvaluationPanelTest, TheReportsWarningsAreShown) {
  openAndFuse();
  waitForScores();
  EXPECT_TRUE(panel().warningsText().isEmpty()) << panel().warningsText().toStdString();
  EXPECT_FALSE(window_.findChild<QWidget*>("evaluationWarnings")->isVisible());

  AnnotationsModel& boxes = window_.session().annotations();
  GroundTruthBox renamed = boxes.box(0);
  const std::string label_name = renamed.name;
  renamed.name = "book";
  boxes.setBox(0, renamed, "Rename");
  waitForScores();
  const QString warnings = panel().warningsText();
  EXPECT_TRUE(warnings.startsWith("Warning: ")) << warnings.toStdString();
  EXPECT_TRUE(warnings.contains("boxes[0].name is 'book'")) << warnings.toStdString();
  EXPECT_EQ(panel().report()->warnings.size(), static_cast<size_t>(warnings.count("Warning: ")));
  EXPECT_TRUE(window_.findChild<QWidget*>("evaluationWarnings")->isVisible());
  auto* list = window_.findChild<QListWidget*>("boxList");
  ASSERT_NE(list, nullptr);
  const QString row = list->item(0)->text();
  EXPECT_TRUE(row.contains(QString::fromStdString(label_name) + " (file: book)"))
      << row.toStdString();

  // Named as its label again: no warning left.
  renamed.name = label_name;
  boxes.setBox(0, renamed, "Rename");
  waitForScores();
  EXPECT_TRUE(panel().warningsText().isEmpty()) << panel().warningsText().toStdString();
}

// A box left out before a misnamed one: the warning numbers the misnamed box
// as the boxes are numbered (the scores' own count skipped the one left out).
TEST_F(EvaluationPanelTest, NameWarningsNumberTheBoxesAsTheFileDoes) {
  openAndFuse();
  waitForScores();
  AnnotationsModel& boxes = window_.session().annotations();
  Annotations edited = boxes.annotations();
  GroundTruthBox unknown = edited.boxes.front();
  unknown.label = 100;
  edited.boxes[1].name = "book";
  edited.boxes.insert(edited.boxes.begin(), unknown);
  boxes.reset(edited, {});
  waitForScores();
  const QString warnings = panel().warningsText();
  EXPECT_TRUE(warnings.contains("boxes[2].name is 'book'")) << warnings.toStdString();
  EXPECT_EQ(warnings.count("Warning: "), 1) << warnings.toStdString();
  EXPECT_TRUE(warnings.contains("the boxes in the studio (not saved)")) << warnings.toStdString();
}

TEST_F(EvaluationPanelTest, BoxesThatCannotBeScoredAreLeftOutAndNamed) {
  openAndFuse();
  waitForScores();
  const size_t objects = panel().report()->objects.size();
  ASSERT_GE(objects, 2u);

  // A box of a label the sequence lacks and a second box of a boxed label: the
  // others are still scored and the summary names the two.
  AnnotationsModel& boxes = window_.session().annotations();
  GroundTruthBox unknown = boxes.annotations().boxes.front();
  unknown.label = 100;
  GroundTruthBox twice = boxes.annotations().boxes.front();
  boxes.addBox(unknown);
  boxes.addBox(twice);
  const int count = boxes.boxCount();
  waitForScores();
  EXPECT_EQ(panel().report()->objects.size(), objects);
  EXPECT_EQ(panel().table().rowCount(), static_cast<int>(objects));
  const QString summary = panel().summaryText();
  EXPECT_TRUE(summary.contains(
      QString("Not scored: boxes[%1] (label 100 is not an object label of the sequence); "
              "boxes[%2] (label %3 is already boxed).")
          .arg(count - 2)
          .arg(count - 1)
          .arg(twice.label)))
      << summary.toStdString();
  // The exported report says so too: its means leave those boxes out.
  const auto out = temp_.path() / "left-out";
  ASSERT_TRUE(panel().exportReportTo(qPath(out)));
  EXPECT_NE(lom::test::slurp(out / "report.json").find("Not scored: boxes["), std::string::npos);
  EXPECT_NE(lom::test::slurp(out / "report.md").find("Not scored: boxes["), std::string::npos);

  // With only such boxes, nothing is scored and the panel says why.
  for (int index = boxes.boxCount() - 1; index >= 0; --index)
    if (boxes.annotations().boxes[static_cast<size_t>(index)].label != 100) boxes.removeBox(index);
  ASSERT_EQ(boxes.boxCount(), 1);
  ASSERT_TRUE(QTest::qWaitFor([&] { return panel().table().rowCount() == 0; }, kTimeoutMs));
  EXPECT_TRUE(panel().summaryText().startsWith("No box can be scored. Not scored: boxes[0]"))
      << panel().summaryText().toStdString();
  EXPECT_FALSE(panel().canExport());
}

TEST_F(EvaluationPanelTest, AMapFusedPartWayIsScoredAgainstTheViewsItFused) {
  // The worker waits after its third frame until the fusion is cancelled.
  struct Gate {
    std::atomic<size_t> reached{0};
    std::atomic<bool> released{false};
  };
  auto gate = std::make_shared<Gate>();
  MapWorker& worker = window_.session().worker();
  worker.setFrameFusedHook([gate](size_t frames) {
    gate->reached = frames;
    while (frames == 3 && !gate->released)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  const std::shared_ptr<void> open_gate(nullptr, [gate](void*) { gate->released = true; });
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return gate->reached == 3; }, kTimeoutMs));
  worker.cancel();
  gate->released = true;
  ASSERT_TRUE(QTest::qWaitFor([&] { return !worker.isFusing(); }, kTimeoutMs));
  QTest::qWait(50);  // the last snapshot arrives through the event loop
  worker.setFrameFusedHook({});
  ASSERT_EQ(worker.snapshot()->frames_fused, 3u);
  const size_t frames = window_.controller().sequence().frames.size();
  ASSERT_GT(frames, 3u);

  waitForScores();
  const std::vector<size_t>& views = panel().report()->views;
  ASSERT_FALSE(views.empty());
  for (size_t view : views) EXPECT_LT(view, 3u);
  EXPECT_TRUE(panel().summaryText().contains(
      QString("Partial map (3 of %1 frames fused): the baselines use the views among them.")
          .arg(frames)))
      << panel().summaryText().toStdString();
  const auto out = temp_.path() / "partial";
  ASSERT_TRUE(panel().exportReportTo(qPath(out)));
  EXPECT_NE(lom::test::slurp(out / "report.md").find("Partial map (3 of"), std::string::npos)
      << lom::test::slurp(out / "report.md");
  // report.json names the frames fused, as score --frames does.
  EXPECT_NE(lom::test::slurp(out / "report.json").find("\"frames\": [0, 2]"), std::string::npos)
      << lom::test::slurp(out / "report.json");
  ASSERT_TRUE(panel().report()->fused_frames);
  EXPECT_EQ(*panel().report()->fused_frames, std::make_pair(size_t{0}, size_t{2}));

  // A complete fusion says nothing of the kind.
  openAndFuse();
  waitForScores();
  ASSERT_TRUE(panel().report()->fused_frames);
  EXPECT_EQ(panel().report()->fused_frames->second, frames - 1);
  EXPECT_FALSE(panel().summaryText().contains("Partial map"))
      << panel().summaryText().toStdString();
  EXPECT_GT(panel().report()->views.back(), 2u);
}

// A map opened from a file is reported as that file, with how well it fits
// the sequence, as `score --map` reports it (the report said the map was
// fused from the sequence with its settings).
TEST_F(EvaluationPanelTest, AMapOpenedFromAFileIsReportedAsThatFile) {
  openAndFuse();
  waitForScores();
  EXPECT_TRUE(panel().report()->map_file.empty());
  const auto file = temp_.path() / "saved.ot";
  fuseSequence(loadSequence(folder_), FusionOptions{}).save(file);
  {
    test::DialogAnswerer answer("Discard Map");
    window_.session().openMap(qPath(file));
  }
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        return !window_.session().isOpeningMap() && !window_.session().worker().isFusing() &&
               panel().report() && !panel().report()->map_file.empty();
      },
      kTimeoutMs));
  waitForScores();
  EXPECT_EQ(panel().report()->map_file, file.string());
  ASSERT_TRUE(panel().report()->map_fit.has_value());
  EXPECT_GT(panel().report()->map_fit->fraction(), 0.5);
  const auto out = temp_.path() / "from-file";
  ASSERT_TRUE(panel().exportReportTo(qPath(out)));
  const std::string markdown = lom::test::slurp(out / "report.md");
  EXPECT_NE(markdown.find("saved.ot"), std::string::npos) << markdown;
  EXPECT_EQ(markdown.find("fused from the sequence"), std::string::npos) << markdown;
}

// Most depths beyond the max range: the panel and the report warn, as `score`
// does (they said nothing).
TEST_F(EvaluationPanelTest, AMapThatLeftMostDepthsBeyondTheMaxRangeIsWarnedAbout) {
  FusionOptions options = window_.session().fusionOptions();
  options.map.max_range = 0.4;
  window_.session().setFusionOptions(options);
  openAndFuse();
  waitForScores();
  EXPECT_TRUE(panel().warningsText().contains("beyond the max range of 0.40 m"))
      << panel().warningsText().toStdString();
  const auto out = temp_.path() / "near";
  ASSERT_TRUE(panel().exportReportTo(qPath(out)));
  EXPECT_NE(lom::test::slurp(out / "report.json").find("beyond the max range of 0.40 m"),
            std::string::npos);
}

// Scores of the map being replaced are neither shown nor exportable while the
// new map is fused, also when they were still being computed when it started.
TEST_F(EvaluationPanelTest, ScoresOfTheMapBeingReplacedAreDroppedWhenFusionStarts) {
  openAndFuse();
  // The scores fusion asked for come first: the evaluation below is the one
  // this test asks for (waiting for the first one's start could miss it, its
  // start having been delivered while the fusion's end was awaited).
  waitForScores();
  // The new fusion waits after its first frame until the end of the test.
  auto released = std::make_shared<std::atomic<bool>>(false);
  MapWorker& worker = window_.session().worker();
  worker.setFrameFusedHook([released](size_t frames) {
    while (frames == 1 && !*released) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  const std::shared_ptr<void> release(nullptr, [released](void*) { *released = true; });
  // Fused again as soon as new scores of the fused map are asked for: before
  // they can arrive.
  bool refused = false;
  QObject guard;
  QObject::connect(
      &worker, &MapWorker::evaluationStarted, &guard,
      [&] {
        if (refused) return;
        refused = true;
        window_.session().fuse();
      },
      Qt::QueuedConnection);
  panel().requestUpdate();
  ASSERT_TRUE(QTest::qWaitFor([&] { return refused && !worker.isEvaluating(); }, kTimeoutMs));
  QTest::qWait(50);
  ASSERT_TRUE(worker.isFusing());
  EXPECT_FALSE(panel().report().has_value());
  EXPECT_FALSE(panel().canExport());
  EXPECT_EQ(panel().table().rowCount(), 0);
  EXPECT_TRUE(panel().summaryText().contains("Fusing")) << panel().summaryText().toStdString();
  *released = true;
  waitForFusion();
  waitForScores();
}

}  // namespace
}  // namespace lom::ui
