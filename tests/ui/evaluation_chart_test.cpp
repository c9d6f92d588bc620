// The Evaluation dock's bar chart: the label ids under the bars stay
// readable (thinned out, never overlapping, inside the widget) however many
// objects there are.
#include <gtest/gtest.h>

#include <QString>
#include <algorithm>
#include <string>
#include <vector>

#include "lom/evaluation.hpp"
#include "lom/ui/score_chart.hpp"

namespace lom::ui {
namespace {

std::vector<ObjectScore> objectsLabelled(int count) {
  std::vector<ObjectScore> objects(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    ObjectScore& object = objects[static_cast<size_t>(i)];
    object.label = i + 1;
    object.name = "object " + std::to_string(i + 1);
    object.iou_3d = {0.2, 0.5, 0.8};
  }
  return objects;
}

TEST(EvaluationChartTest, AxisLabelsNeverOverlapAndStayInsideTheChart) {
  for (int count : {1, 6, 39, 120}) {
    for (int width : {120, 200, 320, 640, 1200}) {
      SCOPED_TRACE(testing::Message() << count << " objects, " << width << " px wide");
      ScoreChart chart;
      chart.resize(width, 170);
      chart.setObjects(objectsLabelled(count));
      const std::vector<ScoreChart::AxisLabel> labels = chart.axisLabels();
      ASSERT_FALSE(labels.empty());
      EXPECT_EQ(labels.front().object, 0u);
      for (size_t i = 0; i < labels.size(); ++i) {
        const QRect& rect = labels[i].rect;
        EXPECT_TRUE(chart.rect().contains(rect)) << "label " << labels[i].object + 1;
        EXPECT_GE(rect.width(),
                  chart.fontMetrics().horizontalAdvance(QString::number(labels[i].object + 1)));
        if (i == 0) continue;
        EXPECT_GT(labels[i].object, labels[i - 1].object);
        EXPECT_LT(labels[i - 1].rect.right(), rect.left() - 1) << "label " << labels[i].object + 1;
      }
      // There is room for every label of a few objects.
      if (count <= 6 && width >= 200) {
        EXPECT_EQ(labels.size(), static_cast<size_t>(count));
      }
      // And for a fair share of many.
      if (width >= 320) {
        EXPECT_GE(labels.size(), std::min<size_t>(static_cast<size_t>(count), 8u));
      }
    }
  }
}

TEST(EvaluationChartTest, PercentLabelsNeverOverlapInAShortChart) {
  for (int height : {76, 90, 120, 170, 400}) {
    SCOPED_TRACE(testing::Message() << height << " px high");
    ScoreChart chart;
    chart.resize(320, height);
    chart.setObjects(objectsLabelled(4));
    const std::vector<ScoreChart::GridLabel> labels = chart.gridLabels();
    ASSERT_GE(labels.size(), 2u);
    EXPECT_EQ(labels.front().percent, 0);
    EXPECT_EQ(labels.back().percent, 100);
    for (size_t i = 0; i < labels.size(); ++i) {
      EXPECT_TRUE(chart.rect().contains(labels[i].rect)) << labels[i].percent;
      if (i > 0) {
        EXPECT_LT(labels[i].rect.bottom(), labels[i - 1].rect.top()) << labels[i].percent;
      }
    }
    // A tall chart labels every quarter.
    if (height >= 170) {
      EXPECT_EQ(labels.size(), 5u);
    }
  }
}

}  // namespace
}  // namespace lom::ui
