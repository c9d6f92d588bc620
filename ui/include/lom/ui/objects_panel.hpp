#pragma once
// The objects dock: the map's extracted objects (lom::extractObjects, as
// `labeloctomap objects`) with their boxes drawn in the 3D view, and "Plan
// pick" for a chosen target (lom::planPick with the sequence's mean viewing
// direction, as `labeloctomap plan --sequence`): the ordered steps in a table,
// the occluders highlighted and the grasp arrows in 3D. The extraction and the
// plan run on the map worker's thread.
#include <QString>
#include <QWidget>
#include <functional>
#include <optional>
#include <vector>

#include "lom/objects.hpp"
#include "lom/planning.hpp"

class QCheckBox;
class QComboBox;
class QLabel;
class QPushButton;
class QTableWidget;

namespace lom::ui {

class StudioSession;

class ObjectsPanel : public QWidget {
  Q_OBJECT

 public:
  enum Column { Label, Name, Voxels, MeanProbability, Columns };
  enum StepColumn { Step, Action, Object, StepColumns };

  explicit ObjectsPanel(StudioSession& session, QWidget* parent = nullptr);
  // The panel takes the height of its dock (its two tables share it, each
  // keeping a few rows), not the height its wrapped status line and full
  // tables would like: a dock that scrolled to that height hid the plan.
  [[nodiscard]] bool hasHeightForWidth() const override { return false; }
  [[nodiscard]] int heightForWidth(int /*width*/) const override { return -1; }

  [[nodiscard]] QTableWidget& table() { return *table_; }
  [[nodiscard]] QTableWidget& stepsTable() { return *steps_; }
  [[nodiscard]] QComboBox& targetCombo() { return *target_; }
  [[nodiscard]] QCheckBox& showBoxesCheck() { return *show_boxes_; }
  [[nodiscard]] QPushButton& planButton() { return *plan_button_; }
  [[nodiscard]] QPushButton& savePlanButton() { return *save_plan_button_; }
  [[nodiscard]] const std::vector<ObjectInstance>& objects() const { return objects_; }
  [[nodiscard]] const std::optional<PickPlan>& plan() const { return plan_; }
  [[nodiscard]] bool isBusy() const { return busy_ > 0; }
  [[nodiscard]] QString statusText() const;
  // Labels listed in the table, in row order.
  [[nodiscard]] std::vector<int> listedLabels() const;

 public slots:
  void refresh();    // extracts the objects of the current map
  void planPick();   // for the target chosen in the combo
  void savePlan();   // asks where (the chooser) and writes plan.json there

 public:
  // Writes the plan shown as `labeloctomap plan --out` writes plan.json
  // (atomically; "map" names the .ot file the map was opened from, empty for
  // a map fused here). Returns what went wrong, empty on success: there is no
  // plan, or `path` is a file of the sequence, or it could not be written.
  QString savePlanTo(const QString& path);
  // For tests: replaces the save dialog (given the proposed file, returns the
  // chosen one, empty for cancel).
  void setPlanFileChooser(std::function<QString(const QString& start)> chooser) {
    plan_file_chooser_ = std::move(chooser);
  }

 signals:
  // The boxes to draw changed: `objects` is empty when they are hidden.
  void objectBoxesChanged(const std::vector<lom::ObjectInstance>& objects);
  // A plan was made (or dropped: null).
  void pickPlanChanged(const lom::PickPlan* plan);
  void objectsShown();
  void planShown();

 private:
  void showObjects(std::vector<ObjectInstance> objects);
  void clearObjects(const QString& message);
  void showPlan(PickPlan plan);
  void showMessage(const QString& message);
  void clearPlan();
  void emitBoxes();

  StudioSession& session_;
  QTableWidget* table_;
  QCheckBox* show_boxes_;
  QComboBox* target_;
  QPushButton* refresh_;
  QPushButton* plan_button_;
  QPushButton* save_plan_button_;
  QTableWidget* steps_;
  QLabel* status_;
  std::vector<ObjectInstance> objects_;
  std::optional<PickPlan> plan_;
  // The mean viewing direction of the cameras the map was fused from, when it
  // records them (a map of some frames is viewed from those frames).
  std::optional<Eigen::Vector3d> map_approach_;
  QString map_source_;  // the .ot file the map was opened from; empty when fused here
  std::function<QString(const QString&)> plan_file_chooser_;
  int busy_ = 0;
  unsigned generation_ = 0;
};

}  // namespace lom::ui
