// SceneView: the layers drawn over the map for a purpose: one view's
// projection voxels, the score breakdown, extracted objects' boxes and a pick
// plan.
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkWorldPointPicker.h>

#include <QToolTip>
#include <algorithm>
#include <cmath>
#include <string>

#include "lom/ui/frame_labels.hpp"
#include "scene_state.hpp"

namespace lom::ui {

void SceneView::showProjectionVoxels(const MapSnapshot* voxels, const LabelSet& labels) {
  // Nothing shown, nothing to hide: no redraw (this is asked on every frame
  // step, which redraws the view itself; a second redraw halved playback).
  if (!voxels && scene_->projection_count == 0) return;
  scene_->projection_count =
      scene_->projection.show(voxels ? *voxels : MapSnapshot{}, labels, {}, false);
  render();
}

size_t SceneView::projectionVoxelCount() const { return scene_->projection_count; }

void SceneView::showScoreBreakdown(const std::vector<ScoreBreakdown>& breakdowns) {
  std::vector<scene::Cube> cubes;
  for (const ScoreBreakdown& breakdown : breakdowns) {
    // A little larger than the map's cubes (0.96 of a voxel), so that these
    // cover the label's own cubes instead of flickering with them.
    for (size_t i = 0; i < breakdown.centres.size(); ++i) {
      const Rgb colour = scoreShareColour(breakdown.shares[i]);
      cubes.push_back(
          {breakdown.centres[i], breakdown.resolution, QColor(colour[0], colour[1], colour[2])});
    }
  }
  scene_->breakdown_count = scene_->breakdown.showCubes(cubes);
  render();
}

size_t SceneView::scoreBreakdownCount() const { return scene_->breakdown_count; }

bool SceneView::objectBoxesVisible() const {
  return scene_->object_boxes.actor->GetVisibility() != 0;
}

void SceneView::showObjectBoxes(const std::vector<ObjectInstance>& objects,
                                const LabelSet& labels) {
  std::vector<OrientedBox> boxes;
  std::vector<QColor> colors;
  for (const ObjectInstance& object : objects) {
    boxes.push_back(object.box);
    const QColor base = labelColor(labels, object.label);
    // Half way to white, as the ground-truth boxes: dark colours stay visible.
    colors.emplace_back((base.red() + 255) / 2, (base.green() + 255) / 2, (base.blue() + 255) / 2);
  }
  scene_->object_box_count = boxes.size();
  scene_->object_boxes.show(boxes.empty() ? nullptr : scene::boxWireframes(boxes, colors).Get());
  scene_->object_boxes.actor->SetVisibility(!boxes.empty() && scene_->boxes_visible);
  render();
}

size_t SceneView::objectBoxCount() const { return scene_->object_box_count; }

void SceneView::showPickPlan(const PickPlan* plan) {
  for (const auto& label : scene_->plan_labels) scene_->overlay->RemoveActor(label);
  scene_->plan_labels.clear();
  scene_->plan_box_count = 0;
  scene_->plan_arrow_count = 0;
  if (!plan || plan->objects.empty()) {
    scene_->plan_boxes.show(nullptr);
    scene_->plan_arrows.show(nullptr);
    render();
    return;
  }
  std::vector<OrientedBox> boxes;
  std::vector<QColor> box_colors;
  for (size_t index : plan->occluders) {
    if (index >= plan->objects.size()) continue;
    boxes.push_back(plan->objects[index].box);
    box_colors.emplace_back(240, 40, 40);
  }
  if (plan->target < plan->objects.size()) {
    boxes.push_back(plan->objects[plan->target].box);
    box_colors.emplace_back(40, 230, 80);
  }
  scene_->plan_box_count = boxes.size();
  scene_->plan_boxes.show(scene::boxWireframes(boxes, box_colors).Get());

  // Arrows as long as the median-ish object: a fraction of the largest box edge.
  double length = 0.05;
  for (const OrientedBox& box : boxes) length = std::max(length, 0.6 * box.size.maxCoeff());
  std::vector<Eigen::Vector3d> tips;
  std::vector<Eigen::Vector3d> directions;
  std::vector<QColor> colors;
  const size_t steps = plan->steps.size();
  for (size_t i = 0; i < steps; ++i) {
    const PlanStep& step = plan->steps[i];
    tips.push_back(step.grasp.position);
    directions.push_back(step.grasp.approach);
    // First step yellow, last green: the order reads from the colours too.
    const double t = steps > 1 ? static_cast<double>(i) / static_cast<double>(steps - 1) : 1.0;
    const QColor color(static_cast<int>(255 * (1.0 - t) + 40 * t), 220,
                       static_cast<int>(40 + 40 * t));
    colors.push_back(color);
    auto text = vtkSmartPointer<vtkBillboardTextActor3D>::New();
    text->SetInput(std::to_string(i + 1).c_str());
    const Eigen::Vector3d at = step.grasp.position - step.grasp.approach.normalized() * length;
    text->SetPosition(at.x(), at.y(), at.z());
    text->GetTextProperty()->SetFontSize(18);
    text->GetTextProperty()->SetBold(true);
    text->GetTextProperty()->SetColor(color.redF(), color.greenF(), color.blueF());
    scene_->overlay->AddActor(text);  // over the map, as the arrows
    scene_->plan_labels.push_back(text);
  }
  scene_->plan_arrow_count = tips.size();
  scene_->plan_arrows.show(scene::graspArrows(tips, directions, colors, length).Get());
  render();
}

bool SceneView::pickPlanVisible() const {
  return scene_->plan_boxes.actor->GetVisibility() != 0 && scene_->plan_box_count > 0;
}

size_t SceneView::pickPlanBoxCount() const { return scene_->plan_box_count; }

size_t SceneView::pickPlanArrowCount() const { return scene_->plan_arrow_count; }

}  // namespace lom::ui
