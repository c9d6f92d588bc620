#pragma once
// The map's legend: every label with voxels, its colour, name and voxel
// count, a visibility checkbox, and "show only" / "show all"; above them, while
// the 3D view colours voxels by height, the height colour bar.
#include <QWidget>
#include <optional>
#include <utility>
#include <vector>

class QPushButton;
class QTableWidget;

namespace lom::ui {

class ColourBar;
class StudioSession;

class MapLegendPanel : public QWidget {
  Q_OBJECT

 public:
  explicit MapLegendPanel(StudioSession& session, QWidget* parent = nullptr);

  // Labels listed, in table order, and the text of a row's name cell.
  [[nodiscard]] std::vector<int> listedLabels() const;
  [[nodiscard]] QString nameOf(int row) const;
  // The label of the current row, or -1.
  [[nodiscard]] int currentLabel() const;
  void showOnly(int label);
  void showAll();
  // Heights (metres) of the height colours' ends; none hides the bar.
  void showHeightColours(std::optional<std::pair<double, double>> range);
  [[nodiscard]] std::optional<std::pair<double, double>> heightBarRange() const;

 signals:
  void currentLabelChanged(int label);

 private:
  void rebuild();
  void onItemChanged();

  StudioSession& session_;
  QTableWidget* table_;
  ColourBar* height_bar_;
  QPushButton* show_only_;  // both enabled only with labels to show
  QPushButton* show_all_;
};

}  // namespace lom::ui
