#pragma once
// Grouped bar chart of the per-object IU_3d: Projection (Mean), Projection
// (Max) and LabelOctoMap side by side for each object.
#include <QRect>
#include <QWidget>
#include <vector>

#include "lom/evaluation.hpp"

namespace lom::ui {

class ScoreChart : public QWidget {
  Q_OBJECT

 public:
  // One label id drawn under the bars.
  struct AxisLabel {
    size_t object = 0;  // index into objects()
    QRect rect;         // where its text is drawn, in widget coordinates
  };

  explicit ScoreChart(QWidget* parent = nullptr);
  // The objects left to right, in the order given.
  void setObjects(std::vector<ObjectScore> objects);
  [[nodiscard]] const std::vector<ObjectScore>& objects() const { return objects_; }
  // The label ids drawn under the bars at the current size: when they do not
  // all fit, only every n-th is drawn so that none overlap, and all lie
  // inside the widget.
  [[nodiscard]] std::vector<AxisLabel> axisLabels() const;
  // The percentages written beside the grid lines at the current height
  // (0 to 100 by 25, or by 50 or only 0 and 100 when the plot is short), with
  // where each is drawn: they never overlap.
  struct GridLabel {
    int percent = 0;
    QRect rect;
  };
  [[nodiscard]] std::vector<GridLabel> gridLabels() const;
  // The legend, the axis labels and a plot of about 70 pixels between them,
  // with grid lines every 25 %: the bars of a few percent stay apart from 0.
  static constexpr int kMinimumHeight = 120;
  [[nodiscard]] QSize sizeHint() const override { return {320, 160}; }
  // Colours of the three methods, in the order above.
  [[nodiscard]] static QColor methodColor(int method);

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  [[nodiscard]] QRect plotRect() const;

  std::vector<ObjectScore> objects_;
};

}  // namespace lom::ui
