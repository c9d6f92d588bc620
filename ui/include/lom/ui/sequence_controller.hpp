#pragma once
// Owns the loaded sequence and the current frame; every view follows it
// through its signals.
#include <QObject>
#include <QString>
#include <functional>
#include <memory>
#include <optional>
#include <set>

#include "lom/import.hpp"
#include "lom/sequence.hpp"

namespace lom::ui {

class SequenceController : public QObject {
  Q_OBJECT

 public:
  explicit SequenceController(QObject* parent = nullptr);
  ~SequenceController() override;

  // Loads `folder/sequence.json` (or the json itself) and goes to frame 0.
  // On failure emits errorOccurred with the core's message (which names the
  // file and field), keeps the previous sequence and returns false.
  bool openSequence(const QString& folder_or_json);

  [[nodiscard]] bool hasSequence() const { return sequence_ != nullptr; }
  [[nodiscard]] const Sequence& sequence() const { return *sequence_; }  // needs hasSequence()
  // The path it was opened from, made absolute: the sequence folder or its
  // sequence.json, or the ROS bag or dataset folder that was converted.
  [[nodiscard]] QString sequencePath() const { return sequence_path_; }
  // Whether the open sequence is the conversion of a bag or dataset folder
  // (its folder is then in the import cache, not beside the recording).
  [[nodiscard]] bool isConverted() const { return converted_; }
  // Options of the conversion of bags and dataset folders (the camera
  // intrinsics of a layout without them, for instance).
  [[nodiscard]] const ImportOptions& importOptions() const { return import_options_; }
  void setImportOptions(const ImportOptions& options) { import_options_ = options; }
  [[nodiscard]] QString sequenceName() const;
  [[nodiscard]] int frameCount() const;
  [[nodiscard]] int currentFrame() const { return current_frame_; }  // -1 without a sequence

  // Null when the current frame's files could not be read.
  [[nodiscard]] const FrameData* currentFrameData() const {
    return frame_data_ ? &*frame_data_ : nullptr;
  }
  [[nodiscard]] const std::optional<LabelImage>& currentLabels() const { return frame_labels_; }

  // Whether the work on the open sequence has unsaved changes (asked before
  // another sequence replaces it and before the window closes).
  [[nodiscard]] bool hasUnsavedWork() const { return unsaved_work_ && unsaved_work_(); }
  void setUnsavedWorkCheck(std::function<bool()> check) { unsaved_work_ = std::move(check); }
  // Asked before another sequence replaces one with unsaved work; false cancels.
  void setDiscardGuard(std::function<bool()> guard) { discard_guard_ = std::move(guard); }

 public slots:
  void setCurrentFrame(int index);  // clamped to the sequence
  void stepFrames(int delta);

 signals:
  // A newly loaded sequence is about to replace the open one (and its frame):
  // references to them must be dropped now.
  void sequenceAboutToChange();
  void sequenceChanged();
  void currentFrameChanged(int index);
  void errorOccurred(const QString& title, const QString& message);

 private:
  void loadCurrentFrame();

  std::function<bool()> discard_guard_;
  std::function<bool()> unsaved_work_;
  std::unique_ptr<Sequence> sequence_;
  QString sequence_path_;
  bool converted_ = false;
  ImportOptions import_options_;
  int current_frame_ = -1;
  std::optional<FrameData> frame_data_;
  std::optional<LabelImage> frame_labels_;
  // A broken frame is reported once, not on every pass of the slider.
  std::set<int> reported_broken_frames_;
};

}  // namespace lom::ui
