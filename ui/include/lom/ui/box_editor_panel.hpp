#pragma once
// The boxes dock: the list of ground-truth boxes, the selected box's label and
// numeric fields (centre, size, roll/pitch/yaw in degrees) kept in sync with
// the 3D handles and the keys, the label for new boxes and the key step sizes.
#include <QWidget>
#include <array>

class QComboBox;
class QDoubleSpinBox;
class QListWidget;

namespace lom::ui {

class StudioSession;
struct BoxSteps;

class BoxEditorPanel : public QWidget {
  Q_OBJECT

 public:
  BoxEditorPanel(StudioSession& session, BoxSteps& steps, QWidget* parent = nullptr);

  // Fields: 0-2 centre x/y/z, 3-5 size x/y/z, 6-8 roll/pitch/yaw (degrees).
  [[nodiscard]] QDoubleSpinBox& field(int index) { return *fields_[static_cast<size_t>(index)]; }
  [[nodiscard]] QListWidget& boxList() { return *list_; }
  [[nodiscard]] QComboBox& newBoxLabel() { return *new_label_; }
  // The selected box's label; labels other boxes have are disabled.
  [[nodiscard]] QComboBox& boxLabel() { return *box_label_; }

 private:
  void rebuildLabels();
  void rebuildList();
  void showSelected();
  void onFieldEdited();
  void onBoxLabelChosen(int combo_index);

  StudioSession& session_;
  BoxSteps& steps_;
  QListWidget* list_;
  QComboBox* box_label_;
  QComboBox* new_label_;
  std::array<QDoubleSpinBox*, 9> fields_{};
  bool updating_ = false;
};

}  // namespace lom::ui
