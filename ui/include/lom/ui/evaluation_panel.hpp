#pragma once
// The evaluation dock: per-object IU_3d of Projection (Mean), Projection (Max)
// and LabelOctoMap plus box IU, sortable, a summary line and a bar chart.
// Recomputed by the map worker (lom::evaluate, as `labeloctomap score`) when a
// box or the map changes; "Export report" writes the same files as the CLI.
#include <QWidget>
#include <optional>

#include "lom/evaluation.hpp"

class QComboBox;
class QLabel;
class QPushButton;
class QTableWidget;
class QTimer;

namespace lom::ui {

class ScoreChart;
class StudioSession;

class EvaluationPanel : public QWidget {
  Q_OBJECT

 public:
  enum Column { Label, Name, Voxels, ProjectionMean, ProjectionMax, LabelOctoMap, BoxIou, Columns };
  // The exact value behind a score cell (the cell shows it x100).
  static constexpr int kValueRole =
      Qt::UserRole + 1;  // a number cell's exact value (number_item.hpp)

  explicit EvaluationPanel(StudioSession& session, QWidget* parent = nullptr);

  [[nodiscard]] QTableWidget& table() { return *table_; }
  // The bar chart: its objects are in the table's row order.
  [[nodiscard]] const ScoreChart& chart() const { return *chart_; }
  [[nodiscard]] const QPushButton& exportButton() const { return *export_; }
  // How IU_3d counts voxels in a box: "Exact volumes" or "Voxel centres"
  // (StudioSession::iouMode; `labeloctomap score --iou exact|center`).
  [[nodiscard]] QComboBox& iouModeBox() { return *iou_mode_; }
  [[nodiscard]] const std::optional<EvaluationReport>& report() const { return report_; }
  [[nodiscard]] QString summaryText() const;
  // The report's warnings (EvaluationReport::warnings), one "Warning: ..." line
  // each, shown under the summary; empty when there is none.
  [[nodiscard]] QString warningsText() const;
  [[nodiscard]] bool isBusy() const;
  // The least height the panel needs at `width`: a scroll area that holds it
  // takes this as the panel's height, so in a short dock the chart gives way
  // instead of the dock scrolling (the word-wrapped summary makes the panel
  // height-for-width, which would otherwise give its preferred height).
  [[nodiscard]] int heightForWidth(int width) const override;
  // Whether the report can be exported: it is of the current map and boxes.
  [[nodiscard]] bool canExport() const { return report_ && !stale_; }
  // Writes report.json/csv/md/svg into `dir`; returns an error message or ""
  // (an error when the report is missing or out of date).
  QString exportReport(const QString& dir) const;
  // What Export report… does once `dir` is chosen: asks before replacing the
  // report files `dir` already holds, refuses files of the sequence, writes
  // and reports an error in a message box. True when the report was written.
  bool exportReportTo(const QString& dir);
  // While the table has the keyboard focus: the box of the row after box
  // `box`'s row as sorted (the row before for the last row), where Delete
  // moves the selection. -1 otherwise (no focus, no such row).
  [[nodiscard]] int boxAfterIfFocused(int box) const;

 public slots:
  void requestUpdate();  // debounced

 signals:
  void reportShown();

 private:
  void evaluateNow();
  void show(const EvaluationReport& report);
  void showMessage(const QString& message);
  void clearReport(const QString& message);
  void syncChart();  // gives the chart the report's objects in the table's row order
  // A row selected by the user selects its object's box, and the selected
  // box's row is selected: one object selection across the panels.
  void selectBoxOfRow();
  void selectRowOfBox();
  // The table row of `label` (its Label column's text), -1 for none.
  [[nodiscard]] int rowOfLabel(const QString& label) const;
  // A double-click on a projection score shows the frame of the view that
  // scored highest for that object (the view behind Projection (Max)).
  void showBestView(int row, int column);

  StudioSession& session_;
  QTableWidget* table_;
  QLabel* summary_;
  QLabel* warnings_;
  ScoreChart* chart_;
  QPushButton* export_;
  QComboBox* iou_mode_;
  QTimer* debounce_;
  std::optional<EvaluationReport> report_;
  bool stale_ = true;      // report_ is not of the current map and boxes
  bool awaiting_ = false;  // an evaluation was asked for since the last clear
  bool syncing_selection_ = false;
  // Boxes left out of the scores being shown (label not an object of the
  // sequence, or a label boxed twice), for the summary.
  QString left_out_;
  std::string annotations_file_;  // as the warnings name the boxes scored
  // Says that the scores shown are of a map fused from only some frames.
  QString partial_;
};

}  // namespace lom::ui
