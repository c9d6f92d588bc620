#pragma once
// Owns the loaded sequence and the current frame; every view follows it
// through its signals.
#include <QObject>
#include <QString>
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <set>

#include "lom/import.hpp"
#include "lom/sequence.hpp"

class QThreadPool;

namespace lom {
class Segmenter;
}

namespace lom::ui {

class SequenceController : public QObject {
  Q_OBJECT

 public:
  explicit SequenceController(QObject* parent = nullptr);
  ~SequenceController() override;

  // How a ROS bag or a dataset folder is converted and opened; called on a
  // worker thread with a progress callback (false from it cancels).
  using SourceOpener = std::function<OpenedSource(
      const std::filesystem::path&, const ImportOptions&, const ImportProgressCallback&)>;

  // Loads `folder/sequence.json` (or the json itself) and goes to frame 0.
  // On failure emits errorOccurred with the core's message (which names the
  // file and field), keeps the previous sequence and returns false. A path
  // that is gone or holds no sequence or recording (and a sequence.json that
  // does not load) fails before the discard guard is asked.
  //
  // A ROS bag or a dataset folder is converted (into the import cache) on a
  // worker thread while this waits in a local event loop, so the windows keep
  // repainting; it returns when the conversion has ended. Input to the windows
  // waits for the first progressDelay() ms; a conversion still running then
  // emits conversionStarted (the window shows its progress and takes no
  // other input than a close: ConversionProgress). A cancelled conversion
  // keeps the previous sequence, reports no error and returns false. While
  // one open is under way, others are refused (false).
  bool openSequence(const QString& folder_or_json);

  [[nodiscard]] bool hasSequence() const { return sequence_ != nullptr; }
  [[nodiscard]] const Sequence& sequence() const { return *sequence_; }  // needs hasSequence()
  // The path it was opened from, made absolute: the sequence folder or its
  // sequence.json, or the ROS bag or dataset folder that was converted.
  [[nodiscard]] QString sequencePath() const { return sequence_path_; }
  // Whether the open sequence is the conversion of a bag or dataset folder
  // (its folder is then in the import cache, not beside the recording).
  [[nodiscard]] bool isConverted() const { return converted_; }
  // Where file dialogs for the studio's outputs and maps start: the folder
  // that holds the sequence folder, or for a converted recording the one that
  // holds the recording (never the hidden import cache). Empty without a
  // sequence.
  [[nodiscard]] QString outputFolder() const;
  // The file or folder an output of the open sequence is proposed as: in
  // outputFolder(), named after the sequence (a bag's name without .bag)
  // followed by `suffix` ("NAME.ot", "NAME-report"), so that the outputs of
  // one sequence never replace another's unasked. Empty without a sequence.
  [[nodiscard]] QString proposedOutput(const QString& suffix) const;
  // The file of a sequence that `path` names, under any name: the sequence.json,
  // boxes (annotations.json, .yaml, .yml) or a frame file of the open sequence
  // or of any sequence whose folder holds `path` (lom::sequenceFileAt), and
  // for a converted recording the bag or any file already in the recording's
  // folder; empty when it names none. The studio never writes its outputs
  // over them (Save Boxes only over the open sequence's own boxes).
  [[nodiscard]] QString sequenceFileAt(const QString& path) const;
  // Options of the conversion of bags and dataset folders (the camera
  // intrinsics of a layout without them, for instance).
  // A recording converted with labels or intrinsics (--labels, --intrinsics)
  // is converted with them again when it is opened later without them (Open
  // Recent, a drop, another start-up): its boxes name those labels. The ones
  // given now take precedence. Remembered per recording in the settings.
  // Not in a picture run (setRemembersConversions(false)): its result must
  // not depend on earlier sessions, nor change what later ones do.
  [[nodiscard]] const ImportOptions& importOptions() const { return import_options_; }
  void setImportOptions(const ImportOptions& options) { import_options_ = options; }
  void setRemembersConversions(bool on) { remembers_conversions_ = on; }
  [[nodiscard]] QString sequenceName() const;
  [[nodiscard]] int frameCount() const;
  [[nodiscard]] int currentFrame() const { return current_frame_; }  // -1 without a sequence

  // Whether a bag or dataset folder is being converted (inside openSequence).
  [[nodiscard]] bool isConverting() const { return conversion_ != nullptr; }
  // The name (file or folder) of the recording being or last converted.
  [[nodiscard]] QString conversionName() const { return conversion_name_; }
  // How long a conversion runs before its progress is shown (300 ms by
  // default: a conversion found in the cache opens without a flash).
  [[nodiscard]] int progressDelay() const { return progress_delay_ms_; }
  void setProgressDelay(int ms) { progress_delay_ms_ = ms; }
  // Replaces lom::openSource into the default import cache (tests).
  void setSourceOpener(SourceOpener opener) { source_opener_ = std::move(opener); }

  // Null when the current frame's files could not be read.
  [[nodiscard]] const FrameData* currentFrameData() const {
    return frame_data_ ? &*frame_data_ : nullptr;
  }
  [[nodiscard]] const std::optional<LabelImage>& currentLabels() const { return frame_labels_; }

  // The segmenter fusion runs (null for none). Where it runs on the current
  // frame (lom::segmenterRunsOn: a frame without a proba of its own), the
  // frame's probabilities are its output, as fusion sees them: computed on a
  // worker thread (or found in its caches), they replace the frame's data when
  // they arrive (currentFrameDataChanged). Until then the frame has none.
  void setFrameSegmenter(std::shared_ptr<const Segmenter> segmenter);
  // Whether the current frame's probabilities are (or will be) the segmenter's.
  [[nodiscard]] bool frameUsesSegmenter() const { return frame_uses_segmenter_; }
  // The segmenter's file name, when frameUsesSegmenter().
  [[nodiscard]] QString frameSegmenterName() const;
  // Whether the segmenter is still running on the current frame.
  [[nodiscard]] bool isSegmentingFrame() const { return segmenting_; }
  // Why the segmenter gave the current frame no probabilities (empty: it did, or is running).
  [[nodiscard]] QString frameSegmenterProblem() const { return segmenter_problem_; }

  // Whether the work on the open sequence has unsaved changes (asked before
  // another sequence replaces it and before the window closes).
  [[nodiscard]] bool hasUnsavedWork() const { return unsaved_work_ && unsaved_work_(); }
  void setUnsavedWorkCheck(std::function<bool()> check) { unsaved_work_ = std::move(check); }
  // Asked before another sequence replaces one with unsaved work; false cancels.
  void setDiscardGuard(std::function<bool()> guard) { discard_guard_ = std::move(guard); }

 public slots:
  void setCurrentFrame(int index);  // clamped to the sequence
  void stepFrames(int delta);
  // Stops the conversion under way at the next frame; nothing without one.
  void cancelConversion();

 signals:
  // A newly loaded sequence is about to replace the open one (and its frame):
  // references to them must be dropped now.
  void sequenceAboutToChange();
  void sequenceChanged();
  void currentFrameChanged(int index);
  // The current frame's data changed in place (the segmenter's probabilities
  // arrived, or the segmenter changed): views showing it show it again.
  void currentFrameDataChanged();
  void errorOccurred(const QString& title, const QString& message);
  // The sequence opened, but something in it was left out (frames its
  // conversion skipped, boxes with labels it does not have).
  void warningOccurred(const QString& title, const QString& message);
  // A conversion has run for progressDelay(): show its progress now.
  void conversionStarted(const QString& name);
  // Frames converted (or skipped) so far; total is 0 while still unknown.
  void conversionProgress(int done, int total);
  // Before its frames, how far the recording has been read through (a ROS
  // bag is checked and indexed first), in thousandths.
  void conversionReading(int per_mille);
  // Something worth a line in the status bar (a conversion that took the
  // labels the recording was converted with before).
  void noteOccurred(const QString& message);
  // Every conversion ends with this (before an error is reported).
  void conversionFinished(const QString& name, bool cancelled);

 private:
  struct Conversion;
  // Runs the conversion of `path` on a worker thread and waits for it.
  // Rethrows the conversion's error; nullopt when it was cancelled.
  [[nodiscard]] std::optional<OpenedSource> convert(const QString& path);
  void loadCurrentFrame();
  // Starts the segmenter on the current frame when it runs there.
  void startFrameSegmentation();

  std::function<bool()> discard_guard_;
  std::function<bool()> unsaved_work_;
  std::unique_ptr<Sequence> sequence_;
  QString sequence_path_;
  bool converted_ = false;
  ImportOptions import_options_;
  bool remembers_conversions_ = true;
  QString conversion_note_;  // said (noteOccurred) once the converted sequence is shown
  SourceOpener source_opener_;
  bool opening_ = false;
  std::shared_ptr<Conversion> conversion_;
  QString conversion_name_;
  int progress_delay_ms_ = 300;
  int current_frame_ = -1;
  std::optional<FrameData> frame_data_;
  std::optional<LabelImage> frame_labels_;
  // A broken frame is reported once, not on every pass of the slider.
  std::set<int> reported_broken_frames_;
  std::shared_ptr<const Segmenter> frame_segmenter_;
  // One segmentation at a time; a frame left before its turn is not segmented.
  QThreadPool* segment_pool_;
  // Counts frame loads: a segmentation started for an earlier one is dropped.
  std::shared_ptr<std::atomic<unsigned>> frame_generation_;
  bool frame_uses_segmenter_ = false;
  bool segmenting_ = false;
  QString segmenter_problem_;
};

}  // namespace lom::ui
