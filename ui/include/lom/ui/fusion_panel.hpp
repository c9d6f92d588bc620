#pragma once
// Fusion parameters: the threshold re-thresholds the current map at once; the
// others (resolution, max range, p_miss, candidates, the frames, the segmentation network
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
struct FrameStats;
struct FusionOptions;
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
  [[nodiscard]] QLineEdit& candidatesEdit() { return *candidates_; }
  // Frames A:B (as `fuse --frames`): empty for all of the sequence's.
  [[nodiscard]] QLineEdit& framesEdit() { return *frames_; }
  // Shown when most depths of the last fusion lay beyond max range: re-fuses
  // with a max range that reaches the farthest depth, at
  // suggestedResolutionForRange (a room at 1 cm and 10 m takes gigabytes).
  [[nodiscard]] QPushButton& extendRangeButton() { return *extend_range_; }
  // Whether the fields differ from the parameters of the current map.
  [[nodiscard]] bool hasPendingChanges() const;
  // Fusion > Fuse Sequence (F5): fuses with the settings the panel shows, its
  // changes applied first as Re-fuse applies them. False, fusing nothing, when
  // a changed field is not valid (the note says which).
  bool fuseWithShownSettings();
  // Loads an ONNX model (and its .json beside it) for the next fusion; an
  // empty path means no network. False, with the reason shown, when it fails
  // or does not fit the open sequence's labels (Segmenter::checkFits).
  bool setSegmenterModel(const QString& model_path);
  [[nodiscard]] QString noteText() const;
  // A problem the segmenter reports that does not stop it (e.g. "cannot write
  // the segmenter cache"): shown in the note until the model changes.
  void showSegmenterWarning(const QString& text);
  // What a fusion measured (MapWorker::depthRangesMeasured): a note and the
  // extend-range button when most depths lay beyond its max range.
  void showDepthRanges(const FrameStats& totals, double max_range);

  // After a fusion whose max range took most of the depths: what the panel
  // says about it; empty otherwise.
  [[nodiscard]] QString rangeNote() const { return range_note_; }

 private:
  void loadFromSession();
  // The session's options with the fields' edits: a box the user left as
  // loaded keeps the map's exact value, which it may show rounded.
  [[nodiscard]] FusionOptions effectiveOptions() const;
  void rememberShown();  // shown_ = the boxes' values
  void onEdited();
  void setNote(const QString& text);
  void refuse();
  void chooseSegmenter();

  StudioSession& session_;
  QDoubleSpinBox* resolution_;
  QDoubleSpinBox* max_range_;
  QDoubleSpinBox* p_miss_;
  QDoubleSpinBox* threshold_;
  QLineEdit* candidates_;
  QLineEdit* frames_;
  QLineEdit* segmenter_path_;
  std::shared_ptr<const Segmenter> segmenter_;  // chosen in the panel, applied on re-fuse
  QLabel* note_;
  QPushButton* refuse_;
  QPushButton* extend_range_;
  struct Shown {
    double resolution = 0.0, max_range = 0.0, p_miss = 0.0;
  } shown_;  // the boxes' values after loadFromSession
  // Boxes the user has committed a value in since the map's were loaded: their
  // value is applied, even one equal to the map's value as the box rounds it.
  struct Edited {
    bool resolution = false, max_range = false, p_miss = false;
  } edited_;
  double suggested_range_ = 0.0;  // what extend_range_ re-fuses with
  double suggested_resolution_ = 0.0;
  QString range_note_;  // why it is shown
  // Why the segmenter was refused or removed, or what it warned about.
  QString segmenter_note_;
};

}  // namespace lom::ui
