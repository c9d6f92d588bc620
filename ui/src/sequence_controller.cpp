#include "lom/ui/sequence_controller.hpp"

#include <QFileInfo>
#include <algorithm>
#include <filesystem>
#include <utility>

#include "lom/error.hpp"
#include "lom/ui/frame_labels.hpp"

namespace lom::ui {

namespace {

std::filesystem::path toPath(const QString& path) {
  return std::filesystem::path(path.toStdString());
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

}  // namespace

SequenceController::SequenceController(QObject* parent) : QObject(parent) {}

SequenceController::~SequenceController() = default;

bool SequenceController::openSequence(const QString& folder_or_json) {
  if (hasUnsavedWork() && discard_guard_ && !discard_guard_()) return false;
  const QString absolute = QFileInfo(folder_or_json).absoluteFilePath();
  OpenedSource opened;
  try {
    // A sequence opens as it is; a ROS bag or a dataset folder that the importer
    // recognises is converted once into the import cache and opened from there.
    opened = openSource(toPath(absolute), import_options_);
  } catch (const std::exception& error) {
    emit errorOccurred(tr("Cannot open sequence"),
                       withStudioHint(describeFailure(error, absolute)));
    return false;
  }
  // Views holding the old sequence or frame let go of them before they are freed.
  emit sequenceAboutToChange();
  sequence_ = std::make_unique<Sequence>(std::move(opened.sequence));
  sequence_path_ = absolute;
  converted_ = opened.converted;
  reported_broken_frames_.clear();
  current_frame_ = sequence_->frames.empty() ? -1 : 0;
  loadCurrentFrame();
  emit sequenceChanged();
  emit currentFrameChanged(current_frame_);
  return true;
}

QString SequenceController::sequenceName() const {
  if (!sequence_) return {};
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
  frame_data_.reset();
  frame_labels_.reset();
  if (!sequence_ || current_frame_ < 0) return;
  try {
    frame_data_ = loadFrame(*sequence_, static_cast<size_t>(current_frame_));
    frame_labels_ = labelsOfFrame(*frame_data_);
  } catch (const std::exception& error) {
    frame_data_.reset();
    frame_labels_.reset();
    if (reported_broken_frames_.insert(current_frame_).second)
      emit errorOccurred(tr("Cannot load frame %1").arg(current_frame_),
                         describeFailure(error, sequence_path_));
  }
}

}  // namespace lom::ui
