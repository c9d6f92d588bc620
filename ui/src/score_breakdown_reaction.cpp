#include "lom/ui/score_breakdown_reaction.hpp"

#include <QAction>
#include <map>
#include <set>
#include <vector>

#include "lom/ui/annotations_model.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

QString describeScoreBreakdown(const ScoreBreakdown& breakdown, const QString& name) {
  const QString object = QObject::tr("%1 (label %2)").arg(name).arg(breakdown.label);
  if (breakdown.centres.empty())
    return QObject::tr("Score breakdown of %1: the map has no voxels of this label.").arg(object);
  const IouVolumes& v = breakdown.volumes;
  const double covered = v.ground_truth > 0.0 ? v.true_positive / v.ground_truth : 0.0;
  // The score first: a narrow status bar cuts the end of the line.
  return QObject::tr(
             "%1: IU_3d %2 %, the voxels fill %3 % of the box; %4 voxels inside it (green), "
             "%5 partly (red to amber to green by how much), %6 outside (red).")
      .arg(object)
      .arg(v.iou() * 100.0, 0, 'f', 1)
      .arg(covered * 100.0, 0, 'f', 1)
      .arg(breakdown.inside)
      .arg(breakdown.partly)
      .arg(breakdown.outside);
}

QString describeScoreBreakdowns(const std::vector<ScoreBreakdown>& breakdowns) {
  if (breakdowns.empty())
    return QObject::tr("Score breakdown: no box to score; add one (Annotate menu).");
  size_t inside = 0, partly = 0, outside = 0;
  for (const ScoreBreakdown& b : breakdowns)
    inside += b.inside, partly += b.partly, outside += b.outside;
  return QObject::tr(
             "Score breakdown of all %1 boxes: %2 voxels inside their box (green), %3 partly "
             "(red to amber to green by how much), %4 outside (red). Select a box for its own.")
      .arg(breakdowns.size())
      .arg(inside)
      .arg(partly)
      .arg(outside);
}

ScoreBreakdownReaction::ScoreBreakdownReaction(QAction* action, StudioSession& session,
                                               SceneView& scene)
    : SceneToggleReaction(action, session, scene) {
  AnnotationsModel& boxes = session_.annotations();
  connect(&boxes, &AnnotationsModel::boxesChanged, this, &ScoreBreakdownReaction::refresh);
  connect(&boxes, &AnnotationsModel::selectionChanged, this, &ScoreBreakdownReaction::refresh);
  connect(&session_.worker(), &MapWorker::snapshotChanged, this, &ScoreBreakdownReaction::refresh);
  connect(&session_, &StudioSession::iouModeChanged, this, &ScoreBreakdownReaction::refresh);
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          &ScoreBreakdownReaction::refresh);
}

void ScoreBreakdownReaction::onTriggered() {
  refresh();
  if (!action()->isChecked()) emit status(QString());
}

void ScoreBreakdownReaction::refresh() {
  if (!action()->isChecked() || !session_.sequence()) {
    if (scene_.scoreBreakdownCount() > 0) scene_.showScoreBreakdown({});
    return;
  }
  try {
    showBreakdowns();
  } catch (const std::exception& error) {  // a map whose leaves stand for too many voxels
    scene_.showScoreBreakdown({});
    emit status(tr("Score breakdown: %1").arg(QString::fromStdString(error.what())));
  }
}

void ScoreBreakdownReaction::showBreakdowns() {
  const AnnotationsModel& boxes = session_.annotations();
  const auto sequence = session_.sequence();
  // As the Evaluation panel scores (exact volumes unless voxel centres are chosen).
  const IouMode mode = session_.iouMode();
  const MapSnapshot& snapshot = *session_.worker().snapshot();
  const int selected = boxes.selected();
  if (selected >= 0) {
    const GroundTruthBox& box = boxes.box(selected);
    const ScoreBreakdown breakdown =
        scoreBreakdown(snapshot.voxels, snapshot.resolution, box, mode);
    scene_.showScoreBreakdown({breakdown});
    const QString name = QString::fromStdString(!box.name.empty() ? box.name
                                                : sequence->labels.contains(box.label)
                                                    ? sequence->labels.at(box.label).name
                                                    : std::string("?"));
    emit status(describeScoreBreakdown(breakdown, name));
    return;
  }
  // No box selected: every box that is scored (lom::unscorableBoxes says
  // which are not), each against its own label's voxels, gathered in one pass.
  std::set<size_t> left_out;
  for (const UnscorableBox& box : unscorableBoxes(boxes.annotations(), sequence->labels.size()))
    left_out.insert(box.index);
  std::map<int, std::vector<OccupiedVoxel>> leaves_of_label;
  for (const OccupiedVoxel& leaf : snapshot.voxels) leaves_of_label[leaf.label].push_back(leaf);
  std::vector<ScoreBreakdown> breakdowns;
  for (int i = 0; i < boxes.boxCount(); ++i) {
    if (left_out.count(static_cast<size_t>(i))) continue;
    const GroundTruthBox& box = boxes.box(i);
    breakdowns.push_back(
        scoreBreakdown(leaves_of_label[box.label], snapshot.resolution, box, mode));
  }
  scene_.showScoreBreakdown(breakdowns);
  emit status(describeScoreBreakdowns(breakdowns));
}

}  // namespace lom::ui
