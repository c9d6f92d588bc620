// The Evaluation dock on the synthetic demo scene: the summary's wording.
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
};

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
