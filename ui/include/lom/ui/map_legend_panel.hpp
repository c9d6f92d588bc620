#pragma once
// The map's legend: every label with voxels, its colour, name and voxel
// count, a visibility checkbox, and "show only" / "show all".
#include <QWidget>
#include <vector>

class QTableWidget;

namespace lom::ui {

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

 signals:
  void currentLabelChanged(int label);

 private:
  void rebuild();
  void onItemChanged();

  StudioSession& session_;
  QTableWidget* table_;
};

}  // namespace lom::ui
