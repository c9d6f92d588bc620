#include "lom/ui/measure_reaction.hpp"

#include <QAction>
#include <cmath>

#include "lom/ui/map_worker.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

QString formatLength(double metres) {
  if (std::abs(metres) < 1.0) return QObject::tr("%1 cm").arg(metres * 100.0, 0, 'f', 1);
  return QObject::tr("%1 m").arg(metres, 0, 'f', 3);
}

QString describeMeasurement(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const std::optional<Eigen::Vector3d>& up) {
  const Eigen::Vector3d d = b - a;
  auto point = [](const Eigen::Vector3d& p) {
    return QString("(%1, %2, %3)")
        .arg(p.x(), 0, 'f', 3)
        .arg(p.y(), 0, 'f', 3)
        .arg(p.z(), 0, 'f', 3);
  };
  QString text =
      QObject::tr("Distance %1 from %2 to %3").arg(formatLength(d.norm()), point(a), point(b));
  if (up && up->norm() > 0.0) {
    const double along = d.dot(up->normalized());
    text += QObject::tr("; %1 along the map's up, %2 across it")
                .arg(formatLength(std::abs(along)),
                     formatLength(std::sqrt(std::max(d.squaredNorm() - along * along, 0.0))));
  }
  return text + QObject::tr(" (to within a voxel: points lie on the voxels' faces).");
}

MeasureReaction::MeasureReaction(QAction* action, StudioSession& session, SceneView& scene)
    : SceneToggleReaction(action, session, scene) {
  connect(&scene_, &SceneView::surfacePicked, this, [this](const Eigen::Vector3d& point) {
    if (this->action()->isChecked()) addPoint(point);
  });
  // Another sequence is another world: its measurements start afresh.
  connect(&session_.controller(), &SequenceController::sequenceChanged, this, [this] {
    points_.clear();
    if (this->action()->isChecked()) show();
  });
}

void MeasureReaction::onTriggered() {
  points_.clear();
  if (action()->isChecked()) {
    show();
  } else {
    scene_.showMeasurement({}, QString());
    emit status(QString());
  }
}

void MeasureReaction::addPoint(const Eigen::Vector3d& point) {
  if (points_.size() == 2) points_.clear();
  points_.push_back(point);
  show();
}

void MeasureReaction::show() {
  if (points_.size() < 2) {
    scene_.showMeasurement(points_, QString());
    emit status(points_.empty() ? tr("Measure: click the first point on the map.")
                                : tr("Measure: click the second point."));
    return;
  }
  const auto snapshot = session_.worker().snapshot();
  const std::optional<Eigen::Vector3d> up = snapshot ? snapshot->up : std::nullopt;
  scene_.showMeasurement(points_, formatLength((points_[1] - points_[0]).norm()));
  emit status(describeMeasurement(points_[0], points_[1], up));
}

}  // namespace lom::ui
