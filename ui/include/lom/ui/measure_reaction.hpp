#pragma once
// View > Measure Distance: while on, each click on the map in the 3D view
// places a point on the surface clicked; two points show the distance between
// them (also along and across the map's up) in the view and the status bar.
// A third click starts a new measurement.
#include <Eigen/Core>
#include <QString>
#include <optional>
#include <vector>

#include "lom/ui/reaction.hpp"

namespace lom::ui {

// "Distance 23.4 cm ..." for the status bar: the length from `a` to `b`, and
// along and across `up` when the map has one.
[[nodiscard]] QString describeMeasurement(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const std::optional<Eigen::Vector3d>& up);
// The length alone, for the label in the view: centimetres below a metre, else metres.
[[nodiscard]] QString formatLength(double metres);

class MeasureReaction : public SceneToggleReaction {
  Q_OBJECT

 public:
  MeasureReaction(QAction* action, StudioSession& session, SceneView& scene);

 protected:
  void onTriggered() override;

 private:
  void addPoint(const Eigen::Vector3d& point);
  void show();

  std::vector<Eigen::Vector3d> points_;
};

}  // namespace lom::ui
