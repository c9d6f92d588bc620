#pragma once
// Saving and loading the session's ground-truth boxes (annotations v1 JSON,
// written atomically), importing the original experiments' YAML boxes, and
// the crash-recovery copy written by the autosave.
#include <QObject>
#include <QString>
#include <functional>

class QTimer;

namespace lom::ui {

class StudioSession;

// Each returns an empty string on success, else a message naming the file.
QString saveBoxes(StudioSession& session, const QString& path);
QString loadBoxes(StudioSession& session, const QString& path);   // replaces, clean state
QString importYamlBoxes(StudioSession& session, const QString& path);  // replaces, unsaved
// Where boxes are saved by default: the file they came from, else
// annotations.json beside sequence.json.
[[nodiscard]] QString defaultBoxesPath(StudioSession& session);

// Writes the unsaved boxes of the open sequence to a recovery file every
// `interval_ms` (and removes it once they are saved or discarded). Opening a
// sequence with a recovery file asks `offer` whether to restore it.
class BoxesAutosave : public QObject {
  Q_OBJECT

 public:
  // offer(recovery_file) returns true to restore.
  BoxesAutosave(StudioSession& session, std::function<bool(const QString&)> offer,
                int interval_ms = 60'000);
  // <AppDataLocation>/recovery/<folder name>-<hash of the sequence path>.json
  [[nodiscard]] static QString recoveryPath(const QString& sequence_path);
  [[nodiscard]] QString currentRecoveryPath() const;
  void setOffer(std::function<bool(const QString&)> offer) { offer_ = std::move(offer); }
  void writeNow();
  void discard();  // removes the recovery file of the open sequence

 private:
  void onSequenceChanged();

  StudioSession& session_;
  std::function<bool(const QString&)> offer_;
  QTimer* timer_;
};

}  // namespace lom::ui
