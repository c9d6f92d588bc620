// The Evaluation dock on the synthetic demo scene: the table and the bar
// chart in the same order, and the summary's wording.
#include "lom/ui/evaluation_panel.hpp"

#include <gtest/gtest.h>

#include <QApplication>
#include <QHeaderView>
#include <QScrollBar>
#include <QTableWidget>
#include <QTest>
#include <algorithm>
#include <vector>

#include "demo_window_fixture.hpp"
#include "lom/evaluation.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/demo_scene.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
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

}  // namespace
}  // namespace lom::ui
