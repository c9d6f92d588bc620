#pragma once
// Saving and loading the session's ground-truth boxes (annotations v1 JSON,
// written atomically), importing the original experiments' YAML boxes, where
// a sequence's boxes live, and the crash-recovery copy written by the autosave.
#include <QLockFile>
#include <QObject>
#include <QString>
#include <functional>
#include <memory>

#include "lom/annotations.hpp"
#include "lom/labels.hpp"

class QTimer;
class QWidget;

namespace lom::ui {

class SequenceController;
class StudioSession;

// Each returns an empty string on success, else a message naming the file.
QString saveBoxes(StudioSession& session, const QString& path);
// Replaces the boxes (clean state); boxes whose label the sequence does not
// have are loaded too and reported through the controller's errorOccurred.
QString loadBoxes(StudioSession& session, const QString& path);
QString importYamlBoxes(StudioSession& session, const QString& path);  // replaces, unsaved
// The question before unsaved boxes are replaced (closing, opening another
// sequence or boxes file): save them first, discard them, or stay.
enum class UnsavedBoxesAnswer { Save, Discard, Cancel };
[[nodiscard]] UnsavedBoxesAnswer askAboutUnsavedBoxes(QWidget* parent);
// Where boxes are saved by default: the file they came from, else the
// sequence's boxes file (boxesFileOf).
[[nodiscard]] QString defaultBoxesPath(StudioSession& session);

// What was opened, independent of how its path was typed: the canonical path
// of the sequence folder (also when its sequence.json was named, with or
// without a trailing slash, through a symbolic link or a relative path), or of
// the ROS bag or dataset folder that was converted.
[[nodiscard]] QString canonicalSourcePath(const QString& opened_path);
// <AppDataLocation>/<folder>/<name>-<hash of canonicalSourcePath>.json: a file
// of the studio's own that belongs to one sequence or recording.
[[nodiscard]] QString perSourceFile(const QString& folder, const QString& opened_path);
// The boxes of the open sequence: annotations.json beside its sequence.json,
// or for a converted bag or dataset folder (whose sequence is only a cache
// entry, rebuilt whenever the recording changes) the per-source file under
// <AppDataLocation>/annotations. Empty without a sequence.
[[nodiscard]] QString boxesFileOf(const SequenceController& controller);
// Where earlier versions kept the boxes of a converted recording: beside the
// converted sequence in the import cache (empty for a plain sequence).
[[nodiscard]] QString legacyBoxesFileOf(const SequenceController& controller);

// Loads the open sequence's boxes file into the session: empty boxes when it
// has none; when it cannot be read, empty boxes that remember the file as
// unreadable (so it is not overwritten unasked). A converted recording whose
// boxes are still in the legacy place gets them copied to boxesFileOf first.
// Problems go to the controller's errorOccurred.
void loadSequenceBoxes(StudioSession& session);

// "FILE: boxes[i]: label N is not a label of the sequence ..." for each of the
// first 10 boxes whose label `labels` does not have (or the background, 0,
// which is no object), then how many more there are and their labels; empty
// when all are object labels of `labels`.
[[nodiscard]] QString unknownLabelsMessage(const Annotations& annotations, const LabelSet& labels,
                                           const QString& file);

// Writes the unsaved boxes of the open sequence to a recovery file every
// `interval_ms` and `edit_delay_ms` after an edit (so that a studio ended by
// a signal or a crash loses at most the last seconds of editing), and removes it as soon as the
// boxes in memory are clean again (saved, undone back to the saved state, replaced by other boxes,
// or discarded with the sequence once another one opened). Opening a sequence with a recovery file
// asks `offer` whether to restore it; a declined copy is kept as declinedPath (not offered again,
// not lost), and a restore warns when the boxes' file was written after the copy.
class BoxesAutosave : public QObject {
  Q_OBJECT

 public:
  // offer(recovery_file) returns true to restore.
  BoxesAutosave(StudioSession& session, std::function<bool(const QString&)> offer,
                int interval_ms = 60'000, int edit_delay_ms = 2'000);
  // perSourceFile("recovery", sequence_path)
  [[nodiscard]] static QString recoveryPath(const QString& sequence_path);
  // Where the boxes of a recovery file go when its offer is declined: a plain
  // boxes file (name.declined.json) beside it.
  [[nodiscard]] static QString declinedPath(const QString& recovery_path);
  [[nodiscard]] QString currentRecoveryPath() const { return recovery_path_; }
  // Keeps as declined (keepAsDeclined) the recovery copies of sequences that
  // are gone (moved, renamed, a drive not mounted), with a warning naming
  // each; copies a live studio holds are left alone. Done once per studio,
  // when it opens its first sequence.
  void keepOrphanedCopies();
  void setOffer(std::function<bool(const QString&)> offer) { offer_ = std::move(offer); }
  // From now on no recovery file is offered, written or removed: for a run
  // with no one to answer the offer (a screenshot), whose boxes are not the
  // unsaved ones of the session that left the file.
  void leaveRecoveryFilesAlone() { leave_files_alone_ = true; }
  void writeNow();
  void discard();  // removes the recovery file of the open sequence
  // Whether the recovery file of the sequence just opened is still to be
  // offered: the offer comes once the switch to it has finished.
  [[nodiscard]] bool isOfferPending() const { return !offered_path_.isEmpty(); }

 private:
  void onSequenceChanged();
  // Asks whether to restore the boxes of `path` (the open sequence's recovery
  // file) and restores them, or keeps them as a boxes file.
  void offerRecovery(const QString& path);
  // Keeps a recovery file that is not restored as a plain boxes file beside
  // it (NAME.declined.json, or the next free name); returns where it went.
  QString keepAsDeclined(const QString& path);
  // Takes the lock of the recovery file `path` (true), or says which process
  // holds it (false, `holder`).
  bool takeLock(const QString& path, qint64* holder);

  StudioSession& session_;
  std::function<bool(const QString&)> offer_;
  QTimer* timer_;
  QTimer* after_edit_;     // single shot, started by an edit unless already running
  QString recovery_path_;  // of the open sequence; empty while another studio has it
  // Held while this studio keeps the open sequence's recovery file: a second
  // studio on the same sequence neither offers, writes nor removes it.
  std::unique_ptr<QLockFile> lock_;
  QString locked_out_of_;  // the recovery file whose lock another studio holds
  QString offered_path_;   // the recovery file about to be offered
  bool restoring_ = false;
  bool leave_files_alone_ = false;
  // A recovery copy failed since the last one written: said once, not at
  // every retry.
  bool copy_failing_ = false;
};

}  // namespace lom::ui
