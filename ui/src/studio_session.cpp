#include "lom/ui/studio_session.hpp"

#include <QDir>
#include <QFileInfo>
#include <QStringList>
#include <algorithm>

#include "lom/annotations.hpp"
#include "lom/evaluation.hpp"
#include "lom/segmenter.hpp"
#include "lom/ui/annotation_files.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/map_file_reader.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/pending_edits.hpp"
#include "lom/ui/sequence_controller.hpp"

namespace lom::ui {

namespace {

// The labels agree by name; a map written with other colours (an edited label
// file) is drawn in the sequence's here but exported in its own. Empty when
// every colour agrees.
QString recolouredLabels(const LabelMap& map, const LabelSet& sequence_labels,
                         const QString& path) {
  const auto rgb = [](const Rgb& c) {
    return QStringLiteral("(%1, %2, %3)").arg(c[0]).arg(c[1]).arg(c[2]);
  };
  QStringList recoloured;
  for (int k = 0; k < map.numLabels(); ++k) {
    const Rgb& own = map.labels().at(k).color;
    const Rgb& shown = sequence_labels.at(k).color;
    if (own != shown)
      recoloured << StudioSession::tr("%1 %2: %3 in the map, %4 in the sequence")
                        .arg(k)
                        .arg(QString::fromStdString(map.labels().at(k).name), rgb(own), rgb(shown));
  }
  if (recoloured.isEmpty()) return {};
  const int listed = std::min<int>(static_cast<int>(recoloured.size()), 5);
  const QString more = recoloured.size() > listed
                           ? StudioSession::tr("; and %1 more").arg(recoloured.size() - listed)
                           : QString();
  return StudioSession::tr(
             "%1 records other label colours than the sequence: %2%3. The 3D view and Map "
             "Labels draw the sequence's colours; meshes exported from the map (File ▸ Export "
             "Map…, labeloctomap export) take the map's.")
      .arg(QDir::toNativeSeparators(path), recoloured.mid(0, listed).join(QStringLiteral("; ")),
           more);
}

}  // namespace

StudioSession::StudioSession(QObject* parent)
    : QObject(parent),
      controller_(new SequenceController(this)),
      worker_(new MapWorker(this)),
      annotations_(new AnnotationsModel(this)),
      map_reader_(new MapFileReader(this)) {
  // The frames show the probabilities fusion reads: the segmenter's, where it runs.
  connect(this, &StudioSession::fusionOptionsChanged, this,
          [this] { controller_->setFrameSegmenter(options_.segmenter); });
  connect(map_reader_, &MapFileReader::finished, this,
          [this](unsigned ticket, const QString& path, std::shared_ptr<LabelMap> map,
                 const QString& error, const QString& fit_warning) {
            if (ticket != map_reader_->latestTicket()) return;  // another map asked for since
            if (!map) return emit mapOpenFailed(tr("Cannot open map"), error);
            if (!sequence_) return;
            try {
              checkMapMatchesSequence(*map, *sequence_, path.toStdString());
            } catch (const Error& mismatch) {
              return emit mapOpenFailed(mismatch.problem().field == "world frame"
                                            ? tr("Map of another world frame")
                                            : tr("Map of another label set"),
                                        QString::fromStdString(mismatch.what()));
            }
            // Shown all the same: a map fused with other poses may be what the user wants to see.
            if (!fit_warning.isEmpty())
              emit controller_->warningOccurred(
                  tr("Map of another scene?"),
                  fit_warning + " " +
                      tr("It is shown all the same; its scores would mean little."));
            if (const QString recoloured = recolouredLabels(*map, sequence_->labels, path);
                !recoloured.isEmpty())
              emit controller_->warningOccurred(tr("Map colours differ"), recoloured);
            options_.map = map->parameters();
            // The projection baselines see the labels the map was fused with
            // (maps written before the record keep the panel's candidates).
            if (map->fusedCandidates().recorded)
              options_.candidates = map->fusedCandidates().labels;
            map_options_ = options_;
            emit fusionOptionsChanged();
            ++map_generation_;
            worker_->adoptMap(std::move(map), sequence_->frames.size(), path,
                              camerasUpOf(*sequence_));
            emit mapOpened(path);
          });
  controller_->setUnsavedWorkCheck([this] {
    commitPendingEdits();  // a value still being typed is part of the work
    return annotations_->isDirty() || worker_->hasUnsavedMap();
  });
  connect(controller_, &SequenceController::sequenceChanged, this, [this] {
    if (!startup_map_) startup_map_ = options_.map;
  });
  connect(worker_, &MapWorker::previousMapKept, this, [this] {
    const double threshold =
        options_.map.occupancy_threshold;  // the view's, as in setFusionOptions
    options_ = map_options_ = replaced_options_;
    options_.map.occupancy_threshold = threshold;
    emit fusionOptionsChanged();
    emit previousMapKept();
  });
  connect(controller_, &SequenceController::sequenceChanged, this,
          &StudioSession::onSequenceChanged);
}

StudioSession::~StudioSession() = default;

void StudioSession::onSequenceChanged() {
  sequence_ = std::make_shared<const Sequence>(controller_->sequence());
  hidden_labels_.clear();
  picked_point_.reset();
  emit hiddenLabelsChanged();
  emit pickedPointChanged();

  // The previous sequence's map goes first: loading the boxes may show a
  // warning, whose event loop must not deliver a box fitted to that map (or
  // its snapshots) into this sequence.
  ++map_generation_;
  map_reader_->forget();  // a map asked for with the previous sequence
  worker_->reset();
  // Class candidates name the objects of one scene: the next sequence is
  // fused with all its labels until candidates are given for it.
  if (options_.candidates) {
    options_.candidates.reset();
    emit fusionOptionsChanged();
  }
  // So do frames A:B of one recording.
  if (options_.first_frame != 0 || options_.last_frame != FusionOptions().last_frame) {
    options_.first_frame = 0;
    options_.last_frame = FusionOptions().last_frame;
    emit fusionOptionsChanged();
  }
  // The segmenter stays only if its channels fit this sequence's labels: else
  // every fusion would fail at once (the Fusion panel says why it went).
  if (options_.segmenter) {
    try {
      options_.segmenter->checkFits(sequence_->labels);
    } catch (const std::exception&) {
      options_.segmenter.reset();
      emit fusionOptionsChanged();
    }
  }

  // The boxes of the sequence, when there are any, are the ones to edit.
  loadSequenceBoxes(*this);
  const Annotations& boxes = annotations_->annotations();
  // New boxes get the first boxed label the sequence knows (else the first
  // object label) until another is chosen.
  int first_label = sequence_->labels.size() > 1 ? 1 : -1;
  for (const GroundTruthBox& box : boxes.boxes)
    if (box.label > 0 && sequence_->labels.contains(box.label)) {
      first_label = box.label;
      break;
    }
  setSelectedLabel(first_label);
  if (auto_fuse_) fuse();
}

QString StudioSession::carriedOverSettingsNote() const {
  if (!startup_map_) return {};
  const MapParameters& now = options_.map;
  const MapParameters& start = *startup_map_;
  const auto differ = [](double a, double b) { return !qFuzzyCompare(1.0 + a, 1.0 + b); };
  const bool p_miss = differ(now.p_miss, start.p_miss);
  const bool threshold = differ(now.occupancy_threshold, start.occupancy_threshold);
  const bool clamp =
      differ(now.clamp_min, start.clamp_min) || differ(now.clamp_max, start.clamp_max);
  if (!differ(now.resolution, start.resolution) && !differ(now.max_range, start.max_range) &&
      !p_miss && !threshold && !clamp)
    return {};
  // The voxel size and the range always: they are what a sequence's scores
  // depend on most; the others when they are not the start-up ones.
  const double cm = now.resolution * 100.0;
  QStringList settings{
      tr("%1 cm voxels").arg(cm, 0, 'f', cm < 1.0 ? 2 : 1),
      now.max_range > 0.0 ? tr("up to %1 m").arg(now.max_range, 0, 'f', 1) : tr("no range limit")};
  if (p_miss) settings << tr("p_miss %1").arg(now.p_miss, 0, 'g', 3);
  if (threshold) settings << tr("threshold %1").arg(now.occupancy_threshold, 0, 'g', 3);
  if (clamp) settings << tr("clamping %1 to %2").arg(now.clamp_min).arg(now.clamp_max);
  return tr("Fusing with the settings in use, not the start-up ones: %1 (Fusion panel).")
      .arg(settings.join(", "));
}

void StudioSession::setIouMode(IouMode mode) {
  if (mode == iou_mode_) return;
  iou_mode_ = mode;
  emit iouModeChanged();
}

bool StudioSession::mayDropMap(const QString& replaced_by) const {
  return !worker_->hasUnsavedMap() || !map_discard_guard_ || map_discard_guard_(replaced_by);
}

void StudioSession::openMap(const QString& path) {
  if (!sequence_) return;
  if (!mayDropMap(tr("Opening %1").arg(QFileInfo(path).fileName()))) return;
  map_reader_->read(path, sequence_);
  emit mapOpenStarted(path);
}

bool StudioSession::isOpeningMap() const { return map_reader_->isReading(); }

void StudioSession::setFusionOptions(const FusionOptions& options) {
  const double threshold = options_.map.occupancy_threshold;
  options_ = options;
  options_.map.occupancy_threshold = threshold;
  emit fusionOptionsChanged();
}

void StudioSession::setOccupancyThreshold(double threshold) {
  options_.map.occupancy_threshold = threshold;
  worker_->setOccupancyThreshold(threshold);
  emit fusionOptionsChanged();
}

void StudioSession::fuse() {
  if (!sequence_) return;
  ++map_generation_;
  map_reader_->forget();  // the map asked for last is this fusion's, not a file still being read
  replaced_options_ = map_options_;
  map_options_ = options_;
  worker_->setOccupancyThreshold(options_.map.occupancy_threshold);
  worker_->startFusion(sequence_, options_);
}

void StudioSession::resetMap() {
  if (!mayDropMap(tr("Reset Map"))) return;
  ++map_generation_;
  map_reader_->forget();  // a file still being read must not fill the map just emptied
  worker_->reset();
}

void StudioSession::setSelectedLabel(int label) {
  if (label == selected_label_) return;
  selected_label_ = label;
  emit selectedLabelChanged(label);
}

void StudioSession::setPickedPoint(const Eigen::Vector3d& point) {
  picked_point_ = point;
  emit pickedPointChanged();
}

void StudioSession::setHiddenLabels(std::set<int> hidden) {
  hidden_labels_ = std::move(hidden);
  emit hiddenLabelsChanged();
}

}  // namespace lom::ui
