#pragma once
// Fusion parameters: the threshold re-thresholds the current map at once; the
// others (resolution, max range, p_miss, candidates, the segmentation network
// run on frames without probability images) need a new fusion, which the panel
// offers with its "Re-fuse" button.
#include <QWidget>
#include <memory>

class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;

namespace lom {
class Segmenter;
}

namespace lom::ui {

class StudioSession;

class FusionPanel : public QWidget {
  Q_OBJECT

 public:
  explicit FusionPanel(StudioSession& session, QWidget* parent = nullptr);

  [[nodiscard]] QDoubleSpinBox& thresholdBox() { return *threshold_; }
  [[nodiscard]] QDoubleSpinBox& resolutionBox() { return *resolution_; }
  [[nodiscard]] QDoubleSpinBox& maxRangeBox() { return *max_range_; }
  [[nodiscard]] QPushButton& refuseButton() { return *refuse_; }
  // Whether the fields differ from the parameters of the current map.
  [[nodiscard]] bool hasPendingChanges() const;
  // Loads an ONNX model (and its .json beside it) for the next fusion; an
  // empty path means no network. False, with the reason shown, when it fails.
  bool setSegmenterModel(const QString& model_path);
  [[nodiscard]] QString noteText() const;

 private:
  void loadFromSession();
  void onEdited();
  void refuse();
  void chooseSegmenter();

  StudioSession& session_;
  QDoubleSpinBox* resolution_;
  QDoubleSpinBox* max_range_;
  QDoubleSpinBox* p_miss_;
  QDoubleSpinBox* threshold_;
  QLineEdit* candidates_;
  QLineEdit* segmenter_path_;
  std::shared_ptr<const Segmenter> segmenter_;  // chosen in the panel, applied on re-fuse
  QLabel* note_;
  QPushButton* refuse_;
};

}  // namespace lom::ui
