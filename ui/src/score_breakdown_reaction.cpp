#include "lom/ui/score_breakdown_reaction.hpp"

#include <QAction>

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
  return QObject::tr("Score breakdown of %1: %2 voxels inside the box (green), %3 partly (red to "
                     "amber to green by how much), %4 outside (red); IU_3d %5 %, the voxels fill "
                     "%6 % of the box.")
      .arg(object)
      .arg(breakdown.inside)
      .arg(breakdown.partly)
      .arg(breakdown.outside)
      .arg(v.iou() * 100.0, 0, 'f', 1)
      .arg(covered * 100.0, 0, 'f', 1);
}

ScoreBreakdownReaction::ScoreBreakdownReaction(QAction* action, StudioSession& session,
                                               SceneView& scene)
    : Reaction(action), session_(session), scene_(scene) {
  action->setCheckable(true);
  AnnotationsModel& boxes = session_.annotations();
  connect(&boxes, &AnnotationsModel::boxesChanged, this, &ScoreBreakdownReaction::refresh);
  connect(&boxes, &AnnotationsModel::selectionChanged, this, &ScoreBreakdownReaction::refresh);
  connect(&session_.worker(), &MapWorker::snapshotChanged, this, &ScoreBreakdownReaction::refresh);
  connect(&session_.controller(), &SequenceController::sequenceChanged, this,
          &ScoreBreakdownReaction::refresh);
}

void ScoreBreakdownReaction::onTriggered() {
  refresh();
  if (!action()->isChecked()) emit status(QString());
}

void ScoreBreakdownReaction::refresh() {
  const AnnotationsModel& boxes = session_.annotations();
  const auto sequence = session_.sequence();
  if (!action()->isChecked() || !sequence) {
    if (scene_.scoreBreakdownCount() > 0) scene_.showScoreBreakdown(nullptr);
    return;
  }
  const int selected = boxes.selected();
  if (selected < 0) {
    scene_.showScoreBreakdown(nullptr);
    emit status(tr("Score breakdown: select a box (Boxes panel, Evaluation panel or Tab in the "
                   "3D view)."));
    return;
  }
  const GroundTruthBox& box = boxes.box(selected);
  // The studio scores as `labeloctomap score` does by default: exact volumes.
  const MapSnapshot& snapshot = *session_.worker().snapshot();
  const ScoreBreakdown breakdown =
      scoreBreakdown(snapshot.voxels, snapshot.resolution, box, EvaluationOptions().iou_mode);
  scene_.showScoreBreakdown(&breakdown);
  const QString name = QString::fromStdString(
      !box.name.empty() ? box.name
      : sequence->labels.contains(box.label) ? sequence->labels.at(box.label).name
                                             : std::string("?"));
  emit status(describeScoreBreakdown(breakdown, name));
}

}  // namespace lom::ui
