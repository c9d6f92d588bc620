#include "lom/ui/annotation_files.hpp"

#include <QCoreApplication>
#include <QCryptographicHash>
#include <QDateTime>
#include <QDir>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLockFile>
#include <QMessageBox>
#include <QStandardPaths>
#include <QStringList>
#include <QTimer>
#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include "lom/atomic_file.hpp"
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

QString studioDataFolder() {
  QString base = QStandardPaths::writableLocation(QStandardPaths::AppDataLocation);
  if (base.isEmpty()) base = QDir::tempPath() + "/labeloctomap-studio";
  return base;
}

// The labels of `boxes` that score refuses: ids the sequence lacks, and 0.
std::set<int> unscorableLabels(const Annotations& boxes, const LabelSet& labels) {
  std::set<int> found;
  for (const GroundTruthBox& box : boxes.boxes)
    if (box.label == 0 || !labels.contains(box.label)) found.insert(box.label);
  return found;
}

// `reported`: boxes whose warnings the user has just seen (the file a
// restored recovery copy replaces); only what they did not hold is reported.
void reportUnknownLabels(StudioSession& session, const Annotations& boxes, const QString& file,
                         const Annotations* reported = nullptr) {
  if (!session.sequence()) return;
  const LabelSet& labels = session.sequence()->labels;
  bool seen = false;
  if (reported) {
    const std::set<int> before = unscorableLabels(*reported, labels);
    const std::set<int> now = unscorableLabels(boxes, labels);
    seen = std::includes(before.begin(), before.end(), now.begin(), now.end());
  }
  const QString message = seen ? QString() : unknownLabelsMessage(boxes, labels, file);
  if (!message.isEmpty())
    emit session.controller().warningOccurred(QObject::tr("Boxes with unknown labels"), message);
  // `labeloctomap score` refuses boxes of another frame; the studio keeps them
  // for editing but says how it reads them, and what saving will write.
  const std::string& frame = session.sequence()->frame_id;
  if (boxes.frame_id != frame && !(reported && reported->frame_id == boxes.frame_id))
    emit session.controller().warningOccurred(
        QObject::tr("Boxes in another frame"),
        QObject::tr("%1: frame_id is \"%2\", the sequence's frame is \"%3\". The boxes are "
                    "shown and scored as if they were in \"%3\", and saving writes frame_id "
                    "\"%3\".")
            .arg(file, QString::fromStdString(boxes.frame_id), QString::fromStdString(frame)));
}

// A recovery file holds the boxes (as annotations v1, under "boxes") and the
// file they were to be saved to: boxes opened from another file must not be
// saved over the sequence's own once restored. Older recovery files are the
// bare annotations file.
constexpr const char* kRecoveryFormat = "labeloctomap-studio-recovery";

struct RecoveredBoxes {
  Annotations boxes;
  std::optional<QString> save_to;  // none in an older recovery file
  std::map<QString, QByteArray> known_files;
};

void writeRecoveryFile(const Annotations& boxes, const QString& save_to,
                       const std::map<QString, QByteArray>& known_files, const QString& sequence,
                       const QString& path) {
  // The boxes are written by the core, as Save Boxes writes them, then wrapped.
  const QString boxes_file = path + ".boxes";
  saveAnnotations(boxes, toPath(boxes_file));
  QFile written(boxes_file);
  const bool read = written.open(QIODevice::ReadOnly);
  const QJsonDocument annotations = QJsonDocument::fromJson(written.readAll());
  written.close();
  written.remove();
  if (!read || !annotations.isObject()) throw std::runtime_error("recovery copy not written");
  // The boxes files as this studio saw them: restored, Save Boxes still asks
  // before replacing what another program wrote there before the copy.
  QJsonObject known;
  for (const auto& [file, digest] : known_files)
    known.insert(file, QString::fromLatin1(digest.toHex()));
  // The sequence (its canonical path) tells a copy whose sequence has gone.
  const QJsonObject recovery{{"format", kRecoveryFormat},
                             {"sequence", sequence},
                             {"save_to", save_to},
                             {"known_files", known},
                             {"boxes", annotations.object()}};
  writeTextFileAtomically(toPath(path), QJsonDocument(recovery).toJson().toStdString());
}

RecoveredBoxes readRecoveryFile(const QString& path) {
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly)) return {loadAnnotations(toPath(path)), std::nullopt, {}};
  const QJsonObject recovery = QJsonDocument::fromJson(file.readAll()).object();
  if (recovery.value("format").toString() != QLatin1String(kRecoveryFormat))
    return {loadAnnotations(toPath(path)), std::nullopt, {}};
  // Read back through the core, which checks every field of the boxes.
  const QString boxes_file = path + ".boxes";
  writeTextFileAtomically(toPath(boxes_file),
                          QJsonDocument(recovery.value("boxes").toObject()).toJson().toStdString());
  RecoveredBoxes recovered;
  try {
    recovered.boxes = loadAnnotations(toPath(boxes_file));
  } catch (...) {
    QFile::remove(boxes_file);
    throw;
  }
  QFile::remove(boxes_file);
  recovered.save_to = recovery.value("save_to").toString();
  const QJsonObject known = recovery.value("known_files").toObject();
  for (auto it = known.begin(); it != known.end(); ++it)
    recovered.known_files[it.key()] = QByteArray::fromHex(it.value().toString().toLatin1());
  return recovered;
}

bool isSequenceJson(const QFileInfo& info) {
  return info.isFile() && info.fileName() == QLatin1String("sequence.json");
}
}  // namespace

QString saveBoxes(StudioSession& session, const QString& path) {
  const QString absolute = QFileInfo(path).absoluteFilePath();
  // The studio's own boxes folder (of a converted recording) is created on
  // first use; a sequence's folder that was moved or deleted is not made
  // again: the boxes stay unsaved and the error says where they were to go.
  if (session.controller().isConverted() && absolute == boxesFileOf(session.controller()))
    QDir().mkpath(QFileInfo(absolute).path());
  try {
    saveAnnotations(boxesToSave(session), toPath(path));
  } catch (const std::exception& error) {
    return QString::fromStdString(error.what());
  }
  session.annotations().markSaved(absolute);
  return {};
}

namespace {

// Boxes that have no file of their own yet (imported, or another sequence's):
// unsaved, and saved to the sequence's file, while an annotations.json that
// could not be read stays protected from being saved over unasked.
void adoptAsUnsaved(AnnotationsModel& model, const Annotations& boxes) {
  if (!model.unreadablePath().isEmpty())
    model.resetUnreadable(boxes, model.unreadablePath(), model.unreadableError());
  else
    model.reset(boxes, QString());
  model.undoStack().resetClean();
}

// The folder of the sequence that `boxes_file` lies beside, when that is not
// `sequence` (the boxes are then another sequence's ground truth).
QString otherSequenceOf(const QString& boxes_file,
                        const std::shared_ptr<const Sequence>& sequence) {
  const QFileInfo beside(QFileInfo(boxes_file).dir(), QStringLiteral("sequence.json"));
  if (!sequence || !beside.isFile()) return {};
  std::error_code ec;
  if (std::filesystem::equivalent(toPath(beside.absoluteFilePath()),
                                  sequence->root / "sequence.json", ec))
    return {};
  return beside.absolutePath();
}

// Whether `boxes_file` lies in the studio's own recovery folder (a declined
// recovery copy, NAME.declined.json, that the restore question pointed to).
bool isRecoveryCopy(const QString& boxes_file) {
  const QString folder = QDir(studioDataFolder() + "/recovery").canonicalPath();
  return !folder.isEmpty() && QFileInfo(boxes_file).canonicalPath() == folder;
}

}  // namespace

QString loadBoxes(StudioSession& session, const QString& path) {
  try {
    const Annotations loaded = loadAnnotations(toPath(path));
    const QString other = otherSequenceOf(path, session.sequence());
    AnnotationsModel& model = session.annotations();
    if (isRecoveryCopy(path) && session.sequence()) {
      // Recovered work, not a file to edit: saved to the sequence's boxes
      // file, never back into the copy (they stayed, clean, in a hidden
      // folder where score never looks).
      adoptAsUnsaved(model, loaded);
      emit session.controller().warningOccurred(
          QObject::tr("Recovered boxes"),
          QObject::tr("%1 is a recovery copy. Its boxes are shown as this sequence's boxes, not "
                      "yet saved: Save Boxes writes them to %2.")
              .arg(QDir::toNativeSeparators(path),
                   QDir::toNativeSeparators(defaultBoxesPath(session))));
    } else if (other.isEmpty()) {
      model.reset(loaded, QFileInfo(path).absoluteFilePath());
    } else {
      // Another sequence's boxes are a start for this one's, not a file to
      // edit: as an import, they are unsaved and Save Boxes writes this
      // sequence's file (an unreadable one stays protected), never theirs.
      adoptAsUnsaved(model, loaded);
      emit session.controller().warningOccurred(
          QObject::tr("Boxes of another sequence"),
          QObject::tr("%1 holds the boxes of the sequence in %2. They are shown as this "
                      "sequence's boxes, not yet saved: Save Boxes writes them to %3, and %1 "
                      "is left as it is.")
              .arg(QDir::toNativeSeparators(path), QDir::toNativeSeparators(other),
                   QDir::toNativeSeparators(defaultBoxesPath(session))));
    }
    reportUnknownLabels(session, loaded, path);
  } catch (const std::exception& error) {
    // A YAML box file chosen with Open Boxes…: say which item reads it.
    const QString suffix = QFileInfo(path).suffix().toLower();
    return QString::fromStdString(error.what()) +
           (suffix == "yaml" || suffix == "yml"
                ? QObject::tr("\n\nA YAML box file is read with File ▸ Import YAML Boxes….")
                : QString());
  }
  return {};
}

QString importYamlBoxes(StudioSession& session, const QString& path) {
  try {
    // With a sequence, as `labeloctomap score` reads a YAML box file
    // (loadAnnotationsFor): named with its labels and in its frame.
    const auto sequence = session.sequence();
    const Annotations imported =
        sequence ? lom::importYamlBoxes(toPath(path), sequence->labels, sequence->frame_id)
                 : lom::importYamlBoxes(toPath(path));
    // The imported boxes have no file yet: an annotations.json that could not
    // be read stays protected from being saved over unasked.
    adoptAsUnsaved(session.annotations(), imported);
    reportUnknownLabels(session, imported, path);
  } catch (const std::exception& error) {
    // An annotations JSON file chosen with Import YAML Boxes…: say which item reads it.
    return QString::fromStdString(error.what()) +
           (QFileInfo(path).suffix().toLower() == "json"
                ? QObject::tr("\n\nAn annotations JSON file is read with File ▸ Open Boxes….")
                : QString());
  }
  return {};
}

UnsavedBoxesAnswer askAboutUnsavedBoxes(QWidget* parent) {
  QMessageBox question(QMessageBox::Question, QObject::tr("Save the boxes?"),
                       QObject::tr("The boxes have unsaved changes. Save them first?"),
                       QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, parent);
  question.setDefaultButton(QMessageBox::Save);
  question.setEscapeButton(QMessageBox::Cancel);
  switch (question.exec()) {
    case QMessageBox::Save:
      return UnsavedBoxesAnswer::Save;
    case QMessageBox::Discard:
      return UnsavedBoxesAnswer::Discard;
    default:
      return UnsavedBoxesAnswer::Cancel;
  }
}

QString defaultBoxesPath(StudioSession& session) {
  if (!session.annotations().path().isEmpty()) return session.annotations().path();
  return boxesFileOf(session.controller());
}

QString canonicalSourcePath(const QString& opened_path) {
  QFileInfo info(QDir::cleanPath(QFileInfo(opened_path).absoluteFilePath()));
  if (isSequenceJson(info)) info = QFileInfo(info.absolutePath());
  const QString canonical = info.canonicalFilePath();
  return canonical.isEmpty() ? info.absoluteFilePath() : canonical;
}

QString perSourceFile(const QString& folder, const QString& opened_path) {
  const QString source = canonicalSourcePath(opened_path);
  const QString hash = QString::fromLatin1(
      QCryptographicHash::hash(source.toUtf8(), QCryptographicHash::Sha1).toHex().left(12));
  const QFileInfo info(source);
  QString name = info.isDir() ? info.fileName() : info.completeBaseName();
  if (name.isEmpty()) name = QStringLiteral("sequence");
  return studioDataFolder() + "/" + folder + "/" + name + "-" + hash + ".json";
}

QString boxesFileOf(const SequenceController& controller) {
  if (!controller.hasSequence()) return {};
  if (controller.isConverted()) return perSourceFile("annotations", controller.sequencePath());
  return QString::fromStdString((controller.sequence().root / "annotations.json").string());
}

QString legacyBoxesFileOf(const SequenceController& controller) {
  if (!controller.hasSequence() || !controller.isConverted()) return {};
  return QString::fromStdString((controller.sequence().root / "annotations.json").string());
}

void loadSequenceBoxes(StudioSession& session) {
  SequenceController& controller = session.controller();
  Annotations empty;
  if (session.sequence()) empty.frame_id = session.sequence()->frame_id;
  QString file = boxesFileOf(controller);
  const QString legacy = legacyBoxesFileOf(controller);
  if (!legacy.isEmpty() && !QFileInfo::exists(file) && QFileInfo::exists(legacy)) {
    // Boxes saved in the import cache by earlier versions move to the durable place.
    try {
      const Annotations old = loadAnnotations(toPath(legacy));
      QDir().mkpath(QFileInfo(file).path());
      saveAnnotations(old, toPath(file));
    } catch (const std::exception&) {
      file = legacy;  // unreadable or not copied: it stays the file of these boxes
    }
  }
  // What the sequence's boxes file holds now (or that there is none): Save
  // Boxes asks before replacing what another program writes there meanwhile.
  session.annotations().forgetKnownFiles();
  session.annotations().noteFile(file);
  if (file.isEmpty() || !QFileInfo::exists(file)) {
    session.annotations().reset(empty, QString());
    return;
  }
  try {
    const Annotations loaded = loadAnnotations(toPath(file));
    session.annotations().reset(loaded, file);
    reportUnknownLabels(session, loaded, file);
  } catch (const std::exception& error) {
    const QString message = QString::fromStdString(error.what());
    session.annotations().resetUnreadable(empty, file, message);
    emit controller.errorOccurred(
        QObject::tr("Cannot load the annotations"),
        QObject::tr("%1\n\nThe studio starts with no boxes and will not overwrite %2 without "
                    "asking.")
            .arg(message, file));
  }
}

QString unknownLabelsMessage(const Annotations& annotations, const LabelSet& labels,
                             const QString& file) {
  constexpr int kListed = 10;  // boxes named one per line; the rest counted
  QStringList problems;
  int unknown = 0;
  std::set<int> unknown_labels;
  for (size_t i = 0; i < annotations.boxes.size(); ++i) {
    const int label = annotations.boxes[i].label;
    // The background is no object either: `labeloctomap score` refuses both.
    if (labels.contains(label) && label != 0) continue;
    ++unknown;
    unknown_labels.insert(label);
    if (unknown > kListed) continue;
    if (label == 0)
      problems << QObject::tr("%1: boxes[%2]: label 0 is the background, not an object")
                      .arg(file)
                      .arg(i);
    else
      problems << QObject::tr("%1: boxes[%2]: label %3 is not a label of the sequence (0 to %4)")
                      .arg(file)
                      .arg(i)
                      .arg(label)
                      .arg(labels.size() - 1);
  }
  if (problems.isEmpty()) return {};
  if (unknown > kListed) {
    QStringList ids;
    for (const int label : unknown_labels) {
      if (ids.size() == kListed) {
        ids << QStringLiteral("…");
        break;
      }
      ids << QString::number(label);
    }
    problems << QObject::tr(
                    "… and %1 more boxes; in all %2 of the %3 boxes have labels the "
                    "sequence does not have (%4)")
                    .arg(unknown - kListed)
                    .arg(unknown)
                    .arg(annotations.boxes.size())
                    .arg(ids.join(QStringLiteral(", ")));
  }
  return problems.join('\n') +
         QObject::tr(
             "\n\nThese boxes are kept but cannot be scored: change their label or delete "
             "them.");
}

BoxesAutosave::BoxesAutosave(StudioSession& session, std::function<bool(const QString&)> offer,
                             int interval_ms, int edit_delay_ms)
    : QObject(&session),
      session_(session),
      offer_(std::move(offer)),
      timer_(new QTimer(this)),
      after_edit_(new QTimer(this)) {
  timer_->setInterval(interval_ms);
  connect(timer_, &QTimer::timeout, this, &BoxesAutosave::writeNow);
  timer_->start();
  // Not restarted by later edits: a drag of many small edits is written
  // while it goes on, at most edit_delay_ms behind.
  after_edit_->setSingleShot(true);
  after_edit_->setInterval(edit_delay_ms);
  connect(after_edit_, &QTimer::timeout, this, &BoxesAutosave::writeNow);
  connect(&session_.annotations(), &AnnotationsModel::boxesChanged, this, [this] {
    if (!after_edit_->isActive()) after_edit_->start();
  });
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          &BoxesAutosave::onSequenceChanged);
  // Clean boxes need no recovery: a file left behind would offer boxes that
  // were saved, undone or discarded.
  connect(&session_.annotations(), &AnnotationsModel::dirtyChanged, this, [this](bool dirty) {
    if (!dirty && !restoring_) discard();
  });
  connect(&session_.annotations(), &AnnotationsModel::saved, this, &BoxesAutosave::discard);
}

QString BoxesAutosave::recoveryPath(const QString& sequence_path) {
  return perSourceFile("recovery", sequence_path);
}

QString BoxesAutosave::declinedPath(const QString& recovery_path) {
  QString base = recovery_path;
  if (base.endsWith(QStringLiteral(".json"))) base.chop(5);
  return base + QStringLiteral(".declined.json");
}

void BoxesAutosave::writeNow() {
  // Only for the sequence this studio was locked out of (another may be
  // opening meanwhile, a dialog up): the other studio may have closed, and
  // the copies are then ours.
  if (!locked_out_of_.isEmpty() && session_.controller().hasSequence() && !leave_files_alone_ &&
      recoveryPath(session_.controller().sequencePath()) == locked_out_of_) {
    const QString path = locked_out_of_;
    if (takeLock(path, nullptr)) {
      locked_out_of_.clear();
      recovery_path_ = path;
      if (QFileInfo::exists(path)) {  // its unsaved boxes, left by a crash: kept, never replaced
        const QString kept = keepAsDeclined(path);
        emit session_.controller().warningOccurred(
            QObject::tr("Unsaved boxes of another studio"),
            QObject::tr("The other LabelOctoMap Studio on this sequence ended with unsaved "
                        "boxes. They are kept as %1 (File ▸ Open Boxes… opens them).")
                .arg(QDir::toNativeSeparators(kept)));
      }
    }
  }
  if (recovery_path_.isEmpty() || !offered_path_.isEmpty() || !session_.annotations().isDirty())
    return;
  // While another sequence opens (a warning about its boxes may be up), the
  // boxes shown may already be the new sequence's: never written to the
  // previous sequence's recovery file.
  if (!session_.controller().hasSequence() ||
      recoveryPath(session_.controller().sequencePath()) != recovery_path_)
    return;
  QDir().mkpath(QFileInfo(recovery_path_).path());
  try {
    writeRecoveryFile(boxesToSave(session_), session_.annotations().path(),
                      session_.annotations().knownFiles(),
                      canonicalSourcePath(session_.controller().sequencePath()), recovery_path_);
    copy_failing_ = false;
  } catch (const std::exception& error) {
    // The next tick retries; the user hears once that a crash would now
    // lose the boxes (a full disk, a folder that takes no files).
    if (copy_failing_) return;
    copy_failing_ = true;
    emit session_.controller().warningOccurred(
        QObject::tr("Unsaved boxes not backed up"),
        QObject::tr("The recovery copy of the unsaved boxes could not be written, so a crash "
                    "would lose them: %1\n\nSave the boxes (File ▸ Save Boxes) to keep them; "
                    "the studio keeps trying to write the copy.")
            .arg(QString::fromStdString(error.what())));
  }
}

QString BoxesAutosave::keepAsDeclined(const QString& path) {
  // Not offered again, but not lost either (the question says where the
  // copy stays): a plain boxes file that Open Boxes… and `labeloctomap
  // score` read. A copy that cannot be read is kept as it is. An earlier
  // declined copy stays too: the next free name.
  QString kept = declinedPath(path);
  for (int n = 2; QFileInfo::exists(kept); ++n) {
    kept = declinedPath(path);
    kept.chop(5);  // ".json"
    kept += QStringLiteral("-%1.json").arg(n);
  }
  bool written = false;
  try {
    saveAnnotations(readRecoveryFile(path).boxes, toPath(kept));
    written = true;
  } catch (const std::exception&) {
  }
  if (written) {
    QFile::remove(path);
    return kept;
  }
  QString raw = path + QStringLiteral(".declined");  // kept as it is; never deleted
  for (int n = 2; QFileInfo::exists(raw); ++n) raw = path + QStringLiteral(".declined-%1").arg(n);
  QFile::rename(path, raw);
  return raw;
}

bool BoxesAutosave::takeLock(const QString& path, qint64* holder) {
  QDir().mkpath(QFileInfo(path).path());
  auto lock = std::make_unique<QLockFile>(path + QStringLiteral(".lock"));
  lock->setStaleLockTime(0);  // a studio that ended without unlocking is detected by its pid
  if (lock->tryLock(0)) {
    lock_ = std::move(lock);
    return true;
  }
  qint64 pid = 0;
  QString host, application;
  // A studio is one window per process: a lock of this process is an
  // earlier window's that has not closed yet (a restart, as tests play it).
  // A lock that cannot be made at all (a read-only folder) locks nobody out.
  if (lock->error() != QLockFile::LockFailedError ||
      (lock->getLockInfo(&pid, &host, &application) && pid == QCoreApplication::applicationPid()))
    return true;
  if (holder) *holder = pid;
  return false;
}

void BoxesAutosave::discard() {
  // A copy not offered yet holds the boxes of an earlier session, not these.
  if (!recovery_path_.isEmpty() && offered_path_.isEmpty()) QFile::remove(recovery_path_);
}

void BoxesAutosave::onSequenceChanged() {
  // The previous sequence's boxes were discarded (or clean) when the new one
  // replaced them, which removed its recovery file; from now on the file is
  // the new sequence's.
  lock_.reset();
  locked_out_of_.clear();
  offered_path_.clear();  // an offer still waiting was the previous sequence's
  recovery_path_ = session_.controller().hasSequence() && !leave_files_alone_
                       ? recoveryPath(session_.controller().sequencePath())
                       : QString();
  const QString path = recovery_path_;
  if (path.isEmpty()) return;
  qint64 holder = 0;
  if (!takeLock(path, &holder)) {
    recovery_path_.clear();  // the other studio's: never offered, written or removed here
    locked_out_of_ = path;
    emit session_.controller().warningOccurred(
        QObject::tr("Sequence open in another studio"),
        QObject::tr("This sequence is also open in another LabelOctoMap Studio (process %1). "
                    "Boxes saved in one window replace those saved in the other (Save Boxes "
                    "asks first when the file changed on disk). While the other one is open, "
                    "this window keeps no recovery copy of its unsaved boxes.")
            .arg(holder));
    return;
  }
  // Copies left by crashes of earlier runs, looked for once per studio, when
  // it opens its first sequence (before the offer of that one's own copy).
  static bool orphans_looked_for = false;
  if (!orphans_looked_for) {
    orphans_looked_for = true;
    keepOrphanedCopies();
  }
  if (!QFileInfo::exists(path)) return;
  // Offered once the switch has reached every view: the question waits for
  // an answer, and meanwhile the window shows the sequence it names (the
  // status bar and the frame too). Until then the file is neither written
  // nor removed here.
  offered_path_ = path;
  QTimer::singleShot(0, this, [this, path] {
    if (offered_path_ != path) return;  // another sequence opened first
    offered_path_.clear();
    offerRecovery(path);
  });
}

void BoxesAutosave::keepOrphanedCopies() {
  // Copies are found by the sequence's path: one moved, renamed or on a
  // drive mounted elsewhere since its studio ended is never offered again.
  // Each is kept as a plain boxes file, once, and said where.
  const QDir folder(QFileInfo(recovery_path_).path());
  for (const QString& name : folder.entryList({QStringLiteral("*.json")}, QDir::Files)) {
    const QString copy = folder.filePath(name);
    if (copy == recovery_path_ || name.contains(QStringLiteral(".declined"))) continue;
    QFile file(copy);
    if (!file.open(QIODevice::ReadOnly)) continue;
    const QJsonObject recovery = QJsonDocument::fromJson(file.readAll()).object();
    file.close();
    // The sequence it was of; copies written before that was recorded say
    // where their boxes were to be saved, beside the sequence.
    QString sequence = recovery.value("sequence").toString();
    if (sequence.isEmpty() && !recovery.value("save_to").toString().isEmpty())
      sequence = QFileInfo(recovery.value("save_to").toString()).absolutePath();
    if (recovery.value("format").toString() != QLatin1String(kRecoveryFormat) ||
        sequence.isEmpty() || QFileInfo::exists(sequence))
      continue;
    QLockFile lock(copy + QStringLiteral(".lock"));  // a studio still open keeps its copy
    lock.setStaleLockTime(0);
    if (!lock.tryLock(0)) continue;
    const QString kept = keepAsDeclined(copy);
    lock.unlock();
    emit session_.controller().warningOccurred(
        QObject::tr("Unsaved boxes of a sequence not found"),
        QObject::tr("A studio ended with unsaved boxes of the sequence %1, which is no longer "
                    "there (moved, renamed, or on a drive not mounted). They are kept as %2: "
                    "File ▸ Open Boxes… opens them as the open sequence's unsaved boxes.")
            .arg(QDir::toNativeSeparators(sequence), QDir::toNativeSeparators(kept)));
  }
}

void BoxesAutosave::offerRecovery(const QString& path) {
  if (recovery_path_ != path || !QFileInfo::exists(path)) return;
  if (!offer_ || !offer_(path)) {
    keepAsDeclined(path);
    return;
  }
  const QDateTime copied = QFileInfo(path).lastModified();
  AnnotationsModel& model = session_.annotations();
  const QString saved_path = model.path();
  const QString unreadable_path = model.unreadablePath();
  const QString unreadable_error = model.unreadableError();
  // The boxes loaded from the file (and warned about) just before this offer.
  const Annotations loaded = model.annotations();
  const bool loaded_from_file = !saved_path.isEmpty();
  restoring_ = true;
  try {
    // The file the boxes were to be saved to stays their save target (the
    // file just loaded, for older recovery files); the restored boxes are unsaved.
    const RecoveredBoxes recovered = readRecoveryFile(path);
    const Annotations& restored = recovered.boxes;
    const QString target = recovered.save_to.value_or(saved_path);
    const bool unreadable_target =
        !unreadable_path.isEmpty() &&
        (target.isEmpty() ||
         QFileInfo(target).absoluteFilePath() == QFileInfo(unreadable_path).absoluteFilePath());
    if (unreadable_target)
      model.resetUnreadable(restored, unreadable_path, unreadable_error);
    else
      model.reset(restored, target);
    model.undoStack().resetClean();
    for (const auto& [file, digest] : recovered.known_files) model.setKnownFile(file, digest);
    reportUnknownLabels(session_, restored, path, loaded_from_file ? &loaded : nullptr);
    // A save target written after the copy was made holds newer boxes than
    // the ones restored: Save would replace them.
    if (!target.isEmpty() && QFileInfo::exists(target) && QFileInfo(target).lastModified() > copied)
      emit session_.controller().warningOccurred(
          QObject::tr("Restored boxes are older than their file"),
          QObject::tr("%1 was changed after these unsaved boxes were copied (%2). Save Boxes "
                      "would replace it with them: use Save Boxes As… to keep both, or Open "
                      "Boxes… to go back to the file.")
              .arg(QDir::toNativeSeparators(target), copied.toString(Qt::ISODate)));
  } catch (const std::exception& error) {
    // Unreadable: nothing restored. The copy is kept (renamed, so that it is
    // not offered again) for the user to look into, and the message says where.
    QString kept = path + QStringLiteral(".unreadable");  // an earlier one stays too
    for (int n = 2; QFileInfo::exists(kept); ++n)
      kept = path + QStringLiteral(".unreadable-%1").arg(n);
    const bool moved = QFile::rename(path, kept);
    emit session_.controller().warningOccurred(
        QObject::tr("Boxes not restored"),
        QObject::tr("The unsaved boxes could not be restored: %1%2")
            .arg(
                QString::fromStdString(error.what()),
                moved
                    ? QObject::tr("\n\nThe copy is kept as %1.").arg(QDir::toNativeSeparators(kept))
                    : QString()));
  }
  restoring_ = false;
}

}  // namespace lom::ui
