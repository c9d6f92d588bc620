#pragma once
#include <QWidget>
#include <optional>

#include "lom/ui/image_conversion.hpp"

namespace lom::ui {

// Horizontal colour bar of the depth colour map with its range in metres.
class DepthLegend : public QWidget {
  Q_OBJECT

 public:
  explicit DepthLegend(QWidget* parent = nullptr);

  void setRange(std::optional<DepthRange> range);
  [[nodiscard]] QSize sizeHint() const override { return {240, 34}; }
  [[nodiscard]] QSize minimumSizeHint() const override { return {120, 34}; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  std::optional<DepthRange> range_;
};

}  // namespace lom::ui
