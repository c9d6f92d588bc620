#pragma once
// What the studio's widgets share: the sequence (through its controller), the
// map (through the worker that owns it), the fusion parameters, the
// ground-truth boxes with their undo stack, and the label visibility.
#include <Eigen/Core>
#include <QObject>
#include <QString>
#include <functional>
#include <memory>
#include <optional>
#include <set>

#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"

namespace lom::ui {

class AnnotationsModel;
class MapWorker;
class MapFileReader;
class SequenceController;

class StudioSession : public QObject {
  Q_OBJECT

 public:
  explicit StudioSession(QObject* parent = nullptr);
  ~StudioSession() override;

  [[nodiscard]] SequenceController& controller() { return *controller_; }
  [[nodiscard]] const SequenceController& controller() const { return *controller_; }
  [[nodiscard]] MapWorker& worker() { return *worker_; }
  [[nodiscard]] AnnotationsModel& annotations() { return *annotations_; }
  [[nodiscard]] std::shared_ptr<const Sequence> sequence() const { return sequence_; }

  // Parameters used by the next fusion (the threshold applies at once).
  [[nodiscard]] const FusionOptions& fusionOptions() const { return options_; }
  void setFusionOptions(const FusionOptions& options);  // not re-fused until fuse()
  void setOccupancyThreshold(double threshold);
  // Whether opening a sequence starts fusing it.
  void setAutoFuse(bool on) { auto_fuse_ = on; }
  // The fusion settings carry over from one sequence to the next (sequences
  // are compared at one setting). When those in use differ from the ones the
  // studio started with (its command line's, else the defaults), a sentence
  // that says them, for the window to show as another sequence opens; else
  // empty.
  [[nodiscard]] QString carriedOverSettingsNote() const;

  void fuse();        // (re)starts fusion of the whole sequence
  void resetMap();    // cancels and drops the map (after the map guard, below)
  // Asked before Reset Map or Open Map drops a map with unsaved work
  // (MapWorker::hasUnsavedMap), with what is about to replace it; false
  // cancels. A new fusion replaces the map unasked: it is the map of the same
  // sequence, fused again with the settings the Fusion panel shows.
  void setMapDiscardGuard(std::function<bool(const QString& replaced_by)> guard) {
    map_discard_guard_ = std::move(guard);
  }
  // Reads a map fused earlier (a .ot file, e.g. by `labeloctomap fuse`) in the
  // background and, when it has the open sequence's labels, makes it the map
  // instead of fusing: a fusion in progress is cancelled and the fusion
  // parameters become the map's. The map stands for the whole sequence (as
  // `labeloctomap score --map`). mapOpenFailed says why not otherwise; a
  // sequence opened meanwhile, or another map asked for, drops the result.
  void openMap(const QString& path);
  [[nodiscard]] bool isOpeningMap() const;
  // Changes whenever the map is replaced (another sequence, a new fusion, a
  // reset): results computed from an older map are stale.
  [[nodiscard]] unsigned mapGeneration() const { return map_generation_; }

  // The label new boxes get and the heat map shows (-1 for none).
  [[nodiscard]] int selectedLabel() const { return selected_label_; }
  void setSelectedLabel(int label);
  // The last point clicked in the 3D view.
  [[nodiscard]] const std::optional<Eigen::Vector3d>& pickedPoint() const { return picked_point_; }
  void setPickedPoint(const Eigen::Vector3d& point);

  // How IU_3d counts voxels in the box, for the scores and their breakdown
  // (as `labeloctomap score --iou`): exact volumes by default.
  [[nodiscard]] IouMode iouMode() const { return iou_mode_; }
  void setIouMode(IouMode mode);

  // Labels hidden in the 3D view.
  [[nodiscard]] const std::set<int>& hiddenLabels() const { return hidden_labels_; }
  void setHiddenLabels(std::set<int> hidden);

 signals:
  void fusionOptionsChanged();
  void iouModeChanged();
  void hiddenLabelsChanged();
  void selectedLabelChanged(int label);
  void pickedPointChanged();
  void mapOpenStarted(const QString& path);  // the file is being read
  void mapOpened(const QString& path);
  void mapOpenFailed(const QString& title, const QString& message);
  // A fusion failed or was cancelled before its first frame: the map it was
  // to replace stays, and the fusion options are that map's again (the
  // Fusion panel keeps the values typed for the next try).
  void previousMapKept();

 private:
  void onSequenceChanged();
  // False when the map holds unsaved work and the guard says to keep it.
  [[nodiscard]] bool mayDropMap(const QString& replaced_by) const;

  SequenceController* controller_;
  MapWorker* worker_;
  AnnotationsModel* annotations_;
  std::shared_ptr<const Sequence> sequence_;
  FusionOptions options_;
  // The options the map shown was fused with (or read with), and those of the
  // map the fusion in progress replaces: the options again when that
  // fusion keeps it (MapWorker::previousMapKept).
  FusionOptions map_options_, replaced_options_;
  // The map parameters when the first sequence opened: the command line's or
  // the defaults (nothing else sets them before there is a sequence).
  std::optional<MapParameters> startup_map_;
  bool auto_fuse_ = true;
  unsigned map_generation_ = 0;
  std::set<int> hidden_labels_;
  int selected_label_ = -1;
  IouMode iou_mode_ = EvaluationOptions().iou_mode;
  std::optional<Eigen::Vector3d> picked_point_;
  MapFileReader* map_reader_;
  std::function<bool(const QString&)> map_discard_guard_;
};

}  // namespace lom::ui
