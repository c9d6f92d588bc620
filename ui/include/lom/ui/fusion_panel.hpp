#pragma once
// Fusion parameters: the threshold re-thresholds the current map at once; the
// others (resolution, max range, p_miss, candidates) need a new fusion, which
// the panel offers with its "Re-fuse" button.
#include <QWidget>

class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;

namespace lom::ui {

class StudioSession;

class FusionPanel : public QWidget {
  Q_OBJECT

 public:
  explicit FusionPanel(StudioSession& session, QWidget* parent = nullptr);

  [[nodiscard]] QDoubleSpinBox& thresholdBox() { return *threshold_; }
  [[nodiscard]] QDoubleSpinBox& resolutionBox() { return *resolution_; }
  [[nodiscard]] QPushButton& refuseButton() { return *refuse_; }
  // Whether the fields differ from the parameters of the current map.
  [[nodiscard]] bool hasPendingChanges() const;

 private:
  void loadFromSession();
  void onEdited();
  void refuse();

  StudioSession& session_;
  QDoubleSpinBox* resolution_;
  QDoubleSpinBox* max_range_;
  QDoubleSpinBox* p_miss_;
  QDoubleSpinBox* threshold_;
  QLineEdit* candidates_;
  QLabel* note_;
  QPushButton* refuse_;
};

}  // namespace lom::ui
