#pragma once
#include <QString>
#include <QStringList>
#include <QWidget>
#include <functional>
#include <optional>
#include <utility>

class QColor;

namespace lom::ui {

// Horizontal bar of a colour scale with its range in metres under it: the
// depth colour map of the depth pane, the height colours of the 3D view.
class ColourBar : public QWidget {
  Q_OBJECT

 public:
  // `colour` maps 0..1 (low to high) to a colour; `caption` names the quantity
  // and `unit` follows the ends' values (" m" for metres, "" for a probability).
  ColourBar(std::function<QColor(double)> colour, QString caption, QWidget* parent = nullptr,
            QString unit = QStringLiteral(" m"));

  // Low and high ends in metres; nothing is drawn without a range.
  void setRange(std::optional<std::pair<double, double>> range);
  [[nodiscard]] std::optional<std::pair<double, double>> range() const { return range_; }
  // The texts drawn under the bar at its width: low end, caption and high
  // end; without the caption when they would overlap; none when even the ends
  // would (and none without a range).
  [[nodiscard]] QStringList shownTexts() const;
  [[nodiscard]] QSize sizeHint() const override { return {240, 34}; }
  [[nodiscard]] QSize minimumSizeHint() const override { return {120, 34}; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  std::function<QColor(double)> colour_;
  QString caption_;
  QString unit_;
  std::optional<std::pair<double, double>> range_;
};

}  // namespace lom::ui
