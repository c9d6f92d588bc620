#include "lom/ui/sequence_controller.hpp"

#include <QDir>
#include <QEventLoop>
#include <QFileInfo>
#include <QMetaObject>
#include <QSettings>
#include <QThreadPool>
#include <QTimer>
#include <algorithm>
#include <atomic>
#include <climits>
#include <exception>
#include <filesystem>
#include <thread>
#include <utility>

#include "lom/error.hpp"
#include "lom/segmenter.hpp"
#include "lom/sequence_files.hpp"
#include "lom/ui/frame_labels.hpp"

namespace lom::ui {

namespace {

std::filesystem::path toPath(const QString& path) {
  return std::filesystem::path(path.toStdString());
}

// The labels and camera a recording was last converted with (--labels,
// --intrinsics), by its canonical path: opened again without them, its boxes
// would name labels the conversion does not have.
const char* const kConversionKey = "conversionOptions";

// The recording's path however it is reached (symbolic links resolved).
QString conversionPathOf(const QString& recording) {
  const QFileInfo info(recording);
  const QString canonical = info.canonicalFilePath();
  return canonical.isEmpty() ? info.absoluteFilePath() : canonical;
}

QString conversionKeyOf(const QString& recording) {
  // QSettings keys treat '/' and '\\' as group separators: the path is hashed.
  const QByteArray path = conversionPathOf(recording).toUtf8();
  return QString(kConversionKey) + "/" + QString::number(qHash(path), 16) + "-" +
         QString::number(path.size());
}

void rememberConversion(const QString& recording, const ImportOptions& options) {
  QSettings settings;
  const QString key = conversionKeyOf(recording);
  settings.remove(key);
  if (!options.labels && !options.intrinsics) return;
  settings.setValue(key + "/path", conversionPathOf(recording));
  if (options.labels) {
    QVariantList labels;
    for (const LabelInfo& label : options.labels->all())
      labels.push_back(QVariant(QVariantList{QString::fromStdString(label.name), label.color[0],
                                             label.color[1], label.color[2]}));  // one entry
    settings.setValue(key + "/labels", labels);
  }
  if (const auto& k = options.intrinsics)
    settings.setValue(key + "/intrinsics", QVariantList{k->width, k->height, k->fx, k->fy, k->cx,
                                                        k->cy, k->depth_scale});
}

// What the settings remember for `recording`, filling what `options` lacks;
// the names of what was taken ("labels", "intrinsics").
QStringList recallConversion(const QString& recording, ImportOptions& options) {
  const QSettings settings;
  const QString key = conversionKeyOf(recording);
  QStringList taken;
  if (settings.value(key + "/path").toString() != conversionPathOf(recording))
    return taken;  // another recording's (a hash collision) or none
  if (!options.labels) {
    std::vector<LabelInfo> labels;
    for (const QVariant& entry : settings.value(key + "/labels").toList()) {
      const QVariantList fields = entry.toList();
      if (fields.size() != 4) return taken;
      LabelInfo label;
      label.id = static_cast<int>(labels.size());
      label.name = fields[0].toString().toStdString();
      for (int c = 0; c < 3; ++c)
        label.color[static_cast<size_t>(c)] =
            static_cast<std::uint8_t>(std::clamp(fields[c + 1].toInt(), 0, 255));
      labels.push_back(std::move(label));
    }
    if (!labels.empty()) {
      options.labels = LabelSet(std::move(labels));
      taken << "labels";
    }
  }
  if (!options.intrinsics) {
    const QVariantList k = settings.value(key + "/intrinsics").toList();
    if (k.size() == 7) {
      CameraIntrinsics camera;
      camera.width = k[0].toInt();
      camera.height = k[1].toInt();
      camera.fx = k[2].toDouble();
      camera.fy = k[3].toDouble();
      camera.cx = k[4].toDouble();
      camera.cy = k[5].toDouble();
      camera.depth_scale = k[6].toDouble();
      options.intrinsics = camera;
      taken << "intrinsics";
    }
  }
  return taken;
}

// The core's messages already name the file and field; other exceptions get
// the path so the user still knows what was being read.
QString describeFailure(const std::exception& error, const QString& path) {
  if (dynamic_cast<const Error*>(&error) || dynamic_cast<const ValidationError*>(&error))
    return QString::fromStdString(error.what());
  return path + ": " + QString::fromStdString(error.what());
}

// The importer's messages name its command-line options; say how to give them
// to the studio.
QString withStudioHint(QString message) {
  if (message.contains("--intrinsics"))
    message += QObject::tr(
        "\n\nThe studio takes the same option when it starts: labeloctomap-studio --intrinsics "
        "fx,fy,cx,cy (or a file with the camera matrix) PATH. Or convert the recording first with "
        "labeloctomap import and open the sequence it writes.");
  return message;
}

int clampToInt(size_t value) {
  return static_cast<int>(std::min<size_t>(value, static_cast<size_t>(INT_MAX)));
}

// Resets a flag when the scope ends, however it ends.
class FlagGuard {
 public:
  explicit FlagGuard(bool& flag) : flag_(flag) { flag_ = true; }
  ~FlagGuard() { flag_ = false; }
  FlagGuard(const FlagGuard&) = delete;
  FlagGuard& operator=(const FlagGuard&) = delete;

 private:
  bool& flag_;
};

}  // namespace

// What the GUI thread and the conversion's worker thread share.
struct SequenceController::Conversion {
  std::atomic<bool> cancel{false};
  std::atomic<size_t> done{0};
  std::atomic<size_t> total{0};
  std::atomic<int> read_per_mille{-1};  // -1: not reading (frames, or not yet)
  // A progress call is queued to the GUI thread and has not run yet: later
  // progress is picked up by it instead of queuing another.
  std::atomic<bool> progress_queued{false};
};

SequenceController::SequenceController(QObject* parent)
    : QObject(parent),
      segment_pool_(new QThreadPool(this)),
      frame_generation_(std::make_shared<std::atomic<unsigned>>(0)) {
  segment_pool_->setMaxThreadCount(1);
}

SequenceController::~SequenceController() {
  if (conversion_) conversion_->cancel = true;
  // A segmentation under way finishes before the controller it reports to goes.
  ++*frame_generation_;
  segment_pool_->clear();
  segment_pool_->waitForDone();
}

void SequenceController::cancelConversion() {
  if (conversion_) conversion_->cancel = true;
}

bool SequenceController::openSequence(const QString& folder_or_json) {
  if (opening_) return false;
  const FlagGuard opening(opening_);
  const QString absolute = QFileInfo(folder_or_json).absoluteFilePath();
  const auto failed = [&](const std::exception& error) {
    emit errorOccurred(tr("Cannot open sequence"),
                       withStudioHint(describeFailure(error, absolute)));
    return false;
  };
  // A sequence opens as it is; a ROS bag or a dataset folder that the importer
  // recognises is converted once into the import cache and opened from there.
  // What cannot be opened at all (gone, unreadable, no sequence) is said
  // before the unsaved work is asked about: saving or discarding it for an
  // open that then fails would be for nothing. A plain sequence is loaded
  // first too (only its sequence.json is read); a conversion runs after the
  // question, which may cancel it.
  std::optional<OpenedSource> opened;
  try {
    const std::optional<SourceKind> kind = detectSource(toPath(absolute)).kind;
    if (kind && *kind != SourceKind::Sequence) {
      if (!QFileInfo(absolute).isReadable())
        throw Error(absolute.toStdString(), "", "a recording the studio may read",
                    "no permission to read it");
    } else {
      opened = openSource(toPath(absolute), import_options_);  // throws for no known layout
    }
  } catch (const std::exception& error) {
    return failed(error);
  }
  if (hasUnsavedWork() && discard_guard_ && !discard_guard_()) return false;
  if (!opened) {
    try {
      opened = convert(absolute);
      if (!opened) return false;  // cancelled: the open sequence stays
    } catch (const std::exception& error) {
      return failed(error);
    }
  }
  // Views holding the old sequence or frame let go of them before they are freed.
  emit sequenceAboutToChange();
  sequence_ = std::make_unique<Sequence>(std::move(opened->sequence));
  sequence_path_ = absolute;
  converted_ = opened->converted;
  reported_broken_frames_.clear();
  current_frame_ = sequence_->frames.empty() ? -1 : 0;
  loadCurrentFrame();
  emit sequenceChanged();
  emit currentFrameChanged(current_frame_);
  // Said once the window shows the sequence (its own messages come first).
  if (!conversion_note_.isEmpty()) emit noteOccurred(std::exchange(conversion_note_, QString()));
  if (const auto jumps = cameraJumps(*sequence_); !jumps.empty()) {
    QStringList lines;
    for (const auto& jump : jumps) lines << QString::fromStdString(jump);
    emit warningOccurred(
        tr("Camera jumps"),
        lines.join('\n') + tr("\nThe map will span that distance, and a view that fits all of "
                              "it shows the voxels smaller than a pixel: check these poses."));
  }
  if (const auto cameras = implausibleIntrinsics(*sequence_); !cameras.empty()) {
    QStringList lines;
    for (const auto& camera : cameras) lines << QString::fromStdString(camera);
    emit warningOccurred(tr("Unusual camera intrinsics"),
                         lines.join('\n') + tr("\nFused with these intrinsics, the depths land far "
                                               "from where they were measured: check the camera "
                                               "in sequence.json."));
  }
  if (!opened->colour_left_out.empty())
    emit warningOccurred(tr("Colour images left out"),
                         QString::fromStdString(opened->colour_left_out) +
                             tr("These frames are open without colour (colour is shown, never "
                                "fused). Repair or replace the files and open the recording "
                                "again to see it."));
  if (!opened->skipped_frames.empty())
    emit warningOccurred(tr("Frames left out"),
                         QString::fromStdString(opened->skipped_frames) +
                             tr("\nThe other frames are open. Repair or replace these files and "
                                "open the recording again to convert them."));
  // What `labeloctomap import` warns about, such as every frame at one pose,
  // makes a wrong map without a frame left out: said on every open too.
  if (!opened->warnings.empty()) {
    QStringList lines;
    for (const std::string& warning : opened->warnings)
      lines << QStringLiteral("• ") + QString::fromStdString(warning);
    emit warningOccurred(
        tr("Check the conversion"),
        tr("The conversion of %1 warns:\n\n%2\n\nIt is open as converted; labeloctomap import "
           "says the same. All the conversion's notes are in %3.")
            .arg(sequenceName(), lines.join('\n'),
                 QString::fromStdString((opened->folder / kImportNotesFile).string())));
  }
  return true;
}

std::optional<OpenedSource> SequenceController::convert(const QString& path) {
  const auto conversion = std::make_shared<Conversion>();
  conversion_ = conversion;
  conversion_name_ = QFileInfo(QDir::cleanPath(path)).fileName();
  const QString name = conversion_name_;

  // The worker's calls arrive through `receiver`, on this thread; the worker
  // is joined before any of these locals goes.
  QEventLoop loop;
  bool finished = false;
  bool delay_passed = progress_delay_ms_ <= 0;
  OpenedSource opened;
  std::exception_ptr failure;
  QObject receiver;
  const SourceOpener opener =
      source_opener_ ? source_opener_
                     : [](const std::filesystem::path& source, const ImportOptions& options,
                          const ImportProgressCallback& progress) {
                         return openSource(source, options, {}, progress);
                       };
  const ImportProgressCallback progress = [this, conversion,
                                           &receiver](const ImportProgress& step) {
    conversion->done = step.done;
    conversion->total = step.total;
    conversion->read_per_mille =
        step.total == 0 && step.read_total > 0
            ? static_cast<int>(std::min(step.read, step.read_total) * 1000 / step.read_total)
            : -1;
    if (!conversion->progress_queued.exchange(true))
      QMetaObject::invokeMethod(
          &receiver,
          [this, conversion] {
            conversion->progress_queued = false;
            if (const int per_mille = conversion->read_per_mille; per_mille >= 0)
              emit conversionReading(per_mille);
            else
              emit conversionProgress(clampToInt(conversion->done), clampToInt(conversion->total));
          },
          Qt::QueuedConnection);
    return !conversion->cancel;
  };
  ImportOptions with = import_options_;
  const QStringList recalled =
      remembers_conversions_ ? recallConversion(path, with) : QStringList();
  auto run = [&, opener, progress, source = toPath(path), options = with] {
    try {
      opened = opener(source, options, progress);
    } catch (...) {
      failure = std::current_exception();
    }
    QMetaObject::invokeMethod(
        &receiver,
        [&] {
          finished = true;
          loop.quit();
        },
        Qt::QueuedConnection);
  };
  std::thread worker;
  // However this returns, the worker has stopped before the locals it uses go.
  struct Stopper {
    SequenceController& controller;
    Conversion& conversion;
    std::thread& worker;
    ~Stopper() {
      if (worker.joinable()) {
        conversion.cancel = true;
        worker.join();
      }
      controller.conversion_.reset();
    }
  } stopper{*this, *conversion, worker};
  worker = std::thread(std::move(run));

  QTimer delay;
  delay.setSingleShot(true);
  connect(&delay, &QTimer::timeout, &loop, [&] {
    delay_passed = true;
    loop.quit();
  });
  if (delay_passed)
    emit conversionStarted(name);
  else
    delay.start(progress_delay_ms_);
  while (!finished) {
    // Until the progress is shown, clicks and keys wait: the open sequence
    // must not change under a conversion that replaces it.
    const bool before_delay = !delay_passed;
    loop.exec(before_delay ? QEventLoop::ExcludeUserInputEvents : QEventLoop::AllEvents);
    if (finished) break;
    if (before_delay && delay_passed) {
      emit conversionStarted(name);
      continue;
    }
    // The wait was ended from outside (the application quits): stop converting.
    conversion->cancel = true;
    break;
  }
  worker.join();
  conversion_.reset();

  // A cancel the conversion no longer saw still keeps the open sequence (the
  // finished conversion stays in the cache for the next open).
  const bool cancelled = conversion->cancel || (!failure && opened.report.cancelled);
  emit conversionFinished(name, cancelled);
  if (cancelled) return std::nullopt;
  if (failure) std::rethrow_exception(failure);
  if (remembers_conversions_) rememberConversion(path, with);
  if (!recalled.isEmpty())
    conversion_note_ = (tr("%1 was converted with the %2 it was converted with before (its boxes "
                           "name those labels); --labels and --intrinsics given at start-up take "
                           "precedence.")
                            .arg(name, recalled.join(tr(" and "))));
  return opened;
}

QString SequenceController::outputFolder() const {
  if (!sequence_) return {};
  if (converted_) return QFileInfo(QDir::cleanPath(sequence_path_)).absolutePath();
  return QString::fromStdString(sequence_->root.parent_path().string());
}

QString SequenceController::proposedOutput(const QString& suffix) const {
  if (!sequence_) return {};
  QString name = sequenceName();
  // "recording.bag.ot" would read as a bag's.
  if (converted_ && QFileInfo(sequence_path_).isFile()) name = QFileInfo(name).completeBaseName();
  if (name.isEmpty()) name = QStringLiteral("sequence");
  return QDir(outputFolder()).filePath(name + suffix);
}

QString SequenceController::sequenceName() const {
  if (!sequence_) return {};
  // A converted recording is known by its own name, not by its cache folder's
  // (which carries a hash).
  if (converted_) return QFileInfo(QDir::cleanPath(sequence_path_)).fileName();
  return QString::fromStdString(sequence_->root.filename().string());
}

int SequenceController::frameCount() const {
  return sequence_ ? static_cast<int>(sequence_->frames.size()) : 0;
}

void SequenceController::setCurrentFrame(int index) {
  if (frameCount() == 0) return;
  index = std::clamp(index, 0, frameCount() - 1);
  if (index == current_frame_) return;
  current_frame_ = index;
  loadCurrentFrame();
  emit currentFrameChanged(current_frame_);
}

void SequenceController::stepFrames(int delta) {
  if (frameCount() == 0) return;
  setCurrentFrame(current_frame_ + delta);
}

void SequenceController::loadCurrentFrame() {
  ++*frame_generation_;
  segment_pool_->clear();  // segmentations of frames left before their turn
  frame_uses_segmenter_ = false;
  segmenting_ = false;
  segmenter_problem_.clear();
  frame_data_.reset();
  frame_labels_.reset();
  if (!sequence_ || current_frame_ < 0) return;
  try {
    frame_data_ = loadFrame(*sequence_, static_cast<size_t>(current_frame_));
    startFrameSegmentation();
    frame_labels_ = labelsOfFrame(*frame_data_);
  } catch (const std::exception& error) {
    frame_data_.reset();
    frame_labels_.reset();
    // Reported once the frame change has reached the views: the message box
    // waits for an answer, and meanwhile the window must show the frame it
    // names, not the one before.
    if (reported_broken_frames_.insert(current_frame_).second)
      QMetaObject::invokeMethod(
          this,
          [this,
           title =
               tr("Cannot load frame %1 (frames[%2])").arg(current_frame_ + 1).arg(current_frame_),
           message = describeFailure(error, sequence_path_)] {
            emit errorOccurred(title, message);
          },
          Qt::QueuedConnection);
  }
}

void SequenceController::setFrameSegmenter(std::shared_ptr<const Segmenter> segmenter) {
  if (segmenter == frame_segmenter_) return;
  frame_segmenter_ = std::move(segmenter);
  if (!sequence_ || current_frame_ < 0) return;
  // The frame read again: its own probabilities, or the new segmenter's. (A
  // sequence being opened announces its frame itself, once every view knows
  // the sequence.)
  loadCurrentFrame();
  if (!opening_) emit currentFrameDataChanged();
}

QString SequenceController::frameSegmenterName() const {
  if (!frame_uses_segmenter_ || !frame_segmenter_) return {};
  return QString::fromStdString(frame_segmenter_->modelPath().filename().string());
}

void SequenceController::startFrameSegmentation() {
  const auto index = static_cast<size_t>(current_frame_);
  if (!frame_data_ || !segmenterRunsOn(*sequence_, index, frame_segmenter_.get())) return;
  frame_uses_segmenter_ = true;
  frame_data_->proba.reset();  // a proba made from the label image is no segmenter's output
  if (!frame_data_->color) {
    segmenter_problem_ = tr("the frame has no colour image for the segmenter to run on");
    return;
  }
  segmenting_ = true;
  struct Job {
    std::shared_ptr<const Segmenter> segmenter;
    ColorImage color;
    int width = 0, height = 0;
    LabelSet labels;
    std::filesystem::path cache;
  };
  auto job = std::make_shared<Job>(
      Job{frame_segmenter_, *frame_data_->color, frame_data_->depth.width,
          frame_data_->depth.height, sequence_->labels, frame_segmenter_->cacheDirFor(*sequence_)});
  const unsigned generation = *frame_generation_;
  segment_pool_->start([this, job, generation, current = frame_generation_] {
    if (*current != generation) return;  // the frame was left before its turn
    auto proba = std::make_shared<std::optional<ProbabilityImage>>();
    QString problem;
    try {
      *proba =
          job->segmenter->segment(job->color, job->width, job->height, job->labels, job->cache);
    } catch (const std::exception& error) {
      problem = QString::fromStdString(error.what());
    }
    QMetaObject::invokeMethod(
        this,
        [this, proba, problem, generation] {
          if (*frame_generation_ != generation || !frame_data_) return;
          segmenting_ = false;
          if (*proba) {
            frame_data_->proba = std::move(**proba);
            frame_labels_ = labelsOfFrame(*frame_data_);
          } else {
            segmenter_problem_ = problem;
          }
          emit currentFrameDataChanged();
        },
        Qt::QueuedConnection);
  });
}

QString SequenceController::sequenceFileAt(const QString& path) const {
  namespace fs = std::filesystem;
  const fs::path target = path.toStdString();
  // Any sequence's own files: its sequence.json, boxes and frames (another
  // sequence's too, when the path lies in its folder).
  if (const std::optional<OwnedSequenceFile> owned = lom::sequenceFileAt(target))
    return QString::fromStdString(owned->file.string());
  if (!sequence_) return {};
  std::vector<fs::path> files = frameFilesOf(*sequence_);
  files.push_back(sequence_->root / "sequence.json");
  for (const fs::path& file : files) {
    std::error_code ec;
    if (fs::equivalent(target, file, ec)) return QString::fromStdString(file.string());
  }
  if (converted_) {
    // A converted recording's own files are the sequence's too: the bag, and
    // every file already in the dataset folder (its images, poses, intrinsics).
    std::error_code ec;
    const fs::path source = sequence_path_.toStdString();
    if (fs::equivalent(target, source, ec)) return sequence_path_;
    if (fs::is_directory(source, ec) && fs::exists(target, ec)) {
      const fs::path folder = fs::canonical(source, ec);
      const fs::path file = fs::canonical(target, ec);
      if (!ec && !folder.empty()) {
        const auto [end, ignored] =
            std::mismatch(folder.begin(), folder.end(), file.begin(), file.end());
        if (end == folder.end()) return QString::fromStdString(file.string());
      }
    }
  }
  return {};
}

}  // namespace lom::ui
