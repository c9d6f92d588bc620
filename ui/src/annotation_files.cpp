#include "lom/ui/annotation_files.hpp"

#include <QCryptographicHash>
#include <QDir>
#include <QFileInfo>
#include <QStandardPaths>
#include <QTimer>
#include <filesystem>

#include "lom/annotations.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

namespace {
std::filesystem::path toPath(const QString& path) { return std::filesystem::path(path.toStdString()); }

Annotations boxesToSave(StudioSession& session) {
  Annotations annotations = session.annotations().annotations();
  if (session.sequence()) annotations.frame_id = session.sequence()->frame_id;
  return annotations;
}
}  // namespace

QString saveBoxes(StudioSession& session, const QString& path) {
  try {
    saveAnnotations(boxesToSave(session), toPath(path));
  } catch (const std::exception& error) {
    return QString::fromStdString(error.what());
  }
  session.annotations().markSaved(QFileInfo(path).absoluteFilePath());
  return {};
}

QString loadBoxes(StudioSession& session, const QString& path) {
  try {
    const Annotations loaded = loadAnnotations(toPath(path));
    session.annotations().reset(loaded, QFileInfo(path).absoluteFilePath());
  } catch (const std::exception& error) {
    return QString::fromStdString(error.what());
  }
  return {};
}

QString importYamlBoxes(StudioSession& session, const QString& path) {
  try {
    const LabelSet labels = session.sequence() ? session.sequence()->labels : LabelSet{};
    Annotations imported = lom::importYamlBoxes(toPath(path), labels);
    if (session.sequence()) imported.frame_id = session.sequence()->frame_id;
    session.annotations().reset(imported, QString());
    session.annotations().undoStack().resetClean();
  } catch (const std::exception& error) {
    return QString::fromStdString(error.what());
  }
  return {};
}

QString defaultBoxesPath(StudioSession& session) {
  if (!session.annotations().path().isEmpty()) return session.annotations().path();
  if (!session.sequence()) return {};
  return QString::fromStdString((session.sequence()->root / "annotations.json").string());
}

BoxesAutosave::BoxesAutosave(StudioSession& session, std::function<bool(const QString&)> offer,
                             int interval_ms)
    : QObject(&session), session_(session), offer_(std::move(offer)), timer_(new QTimer(this)) {
  timer_->setInterval(interval_ms);
  connect(timer_, &QTimer::timeout, this, &BoxesAutosave::writeNow);
  timer_->start();
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          &BoxesAutosave::onSequenceChanged);
  connect(&session_.annotations(), &AnnotationsModel::saved, this, &BoxesAutosave::discard);
}

QString BoxesAutosave::recoveryPath(const QString& sequence_path) {
  QString base = QStandardPaths::writableLocation(QStandardPaths::AppDataLocation);
  if (base.isEmpty()) base = QDir::tempPath() + "/labeloctomap-studio";
  const QString absolute = QFileInfo(sequence_path).absoluteFilePath();
  const QString hash = QString::fromLatin1(
      QCryptographicHash::hash(absolute.toUtf8(), QCryptographicHash::Sha1).toHex().left(12));
  QString name = QFileInfo(absolute).fileName();
  if (name == "sequence.json") name = QFileInfo(QFileInfo(absolute).path()).fileName();
  return base + "/recovery/" + name + "-" + hash + ".json";
}

QString BoxesAutosave::currentRecoveryPath() const {
  if (!session_.controller().hasSequence()) return {};
  return recoveryPath(session_.controller().sequencePath());
}

void BoxesAutosave::writeNow() {
  const QString path = currentRecoveryPath();
  if (path.isEmpty() || !session_.annotations().isDirty()) return;
  QDir().mkpath(QFileInfo(path).path());
  try {
    saveAnnotations(boxesToSave(session_), toPath(path));
  } catch (const std::exception&) {
    // A failed recovery copy must not interrupt the work; the next tick retries.
  }
}

void BoxesAutosave::discard() {
  const QString path = currentRecoveryPath();
  if (!path.isEmpty()) QFile::remove(path);
}

void BoxesAutosave::onSequenceChanged() {
  const QString path = currentRecoveryPath();
  if (path.isEmpty() || !QFileInfo::exists(path)) return;
  if (!offer_ || !offer_(path)) {
    QFile::remove(path);
    return;
  }
  const QString saved_path = session_.annotations().path();
  try {
    // The real file stays the save target; the restored boxes are unsaved.
    session_.annotations().reset(loadAnnotations(toPath(path)), saved_path);
    session_.annotations().undoStack().resetClean();
  } catch (const std::exception&) {
    QFile::remove(path);  // unreadable: nothing to restore
  }
}

}  // namespace lom::ui
