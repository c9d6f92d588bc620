#pragma once
// Grouped bar chart of the per-object IU_3d: Projection (Mean), Projection
// (Max) and LabelOctoMap side by side for each object.
#include <QWidget>

#include "lom/evaluation.hpp"

namespace lom::ui {

class ScoreChart : public QWidget {
  Q_OBJECT

 public:
  explicit ScoreChart(QWidget* parent = nullptr);
  void setObjects(std::vector<ObjectScore> objects);
  [[nodiscard]] QSize sizeHint() const override { return {320, 170}; }
  // Colours of the three methods, in the order above.
  [[nodiscard]] static QColor methodColor(int method);

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  std::vector<ObjectScore> objects_;
};

}  // namespace lom::ui
