#include "lom/ui/scene_view.hpp"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkAxesActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkTextProperty.h>
#include <vtkWorldPointPicker.h>

#include <QSurfaceFormat>
#include <QTimer>
#include <QToolTip>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <string>

#include "lom/ui/frame_labels.hpp"
#include "scene_adapters.hpp"
#include "scene_layers.hpp"

namespace lom::ui {

void setDefaultSurfaceFormat() {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
}

namespace {

struct PolyActor {
  vtkNew<vtkPolyDataMapper> mapper;
  vtkNew<vtkActor> actor;

  PolyActor() { actor->SetMapper(mapper); }
  void show(vtkPolyData* data) {
    mapper->SetInputData(data);
    actor->SetVisibility(data != nullptr);
  }
};

// Trackball camera whose keys are left to the studio's actions (VTK's own
// key bindings would switch to wireframe or quit), and that reports clicks.
class StudioInteractorStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static StudioInteractorStyle* New();
  vtkTypeMacro(StudioInteractorStyle, vtkInteractorStyleTrackballCamera);

  std::function<void(int, int)> on_click;
  // The mouse moved with no button down (not turning or moving the view).
  std::function<void(int, int)> on_hover;

  void OnLeftButtonDown() override {
    const int* position = GetInteractor()->GetEventPosition();
    press_[0] = position[0];
    press_[1] = position[1];
    ++buttons_down_;
    vtkInteractorStyleTrackballCamera::OnLeftButtonDown();
  }
  void OnLeftButtonUp() override {
    vtkInteractorStyleTrackballCamera::OnLeftButtonUp();
    buttons_down_ = std::max(buttons_down_ - 1, 0);
    const int* position = GetInteractor()->GetEventPosition();
    if (std::abs(position[0] - press_[0]) + std::abs(position[1] - press_[1]) <= 3 && on_click)
      on_click(position[0], position[1]);
  }
  void OnMiddleButtonDown() override {
    ++buttons_down_;
    vtkInteractorStyleTrackballCamera::OnMiddleButtonDown();
  }
  void OnMiddleButtonUp() override {
    buttons_down_ = std::max(buttons_down_ - 1, 0);
    vtkInteractorStyleTrackballCamera::OnMiddleButtonUp();
  }
  void OnRightButtonDown() override {
    ++buttons_down_;
    vtkInteractorStyleTrackballCamera::OnRightButtonDown();
  }
  void OnRightButtonUp() override {
    buttons_down_ = std::max(buttons_down_ - 1, 0);
    vtkInteractorStyleTrackballCamera::OnRightButtonUp();
  }
  void OnMouseMove() override {
    vtkInteractorStyleTrackballCamera::OnMouseMove();
    const int* position = GetInteractor()->GetEventPosition();
    if (buttons_down_ == 0 && on_hover) on_hover(position[0], position[1]);
  }
  void OnChar() override {}
  void OnKeyPress() override {}
  void OnKeyRelease() override {}

 private:
  int press_[2] = {0, 0};
  int buttons_down_ = 0;
};
vtkStandardNewMacro(StudioInteractorStyle);

}  // namespace

struct SceneView::Scene {
  vtkNew<vtkGenericOpenGLRenderWindow> render_window;
  vtkNew<vtkRenderer> renderer;
  PolyActor cloud;
  PolyActor other_frustums;
  PolyActor current_frustum;
  PolyActor boxes;
  PolyActor object_boxes;
  PolyActor plan_boxes;
  PolyActor plan_arrows;
  std::vector<vtkSmartPointer<vtkBillboardTextActor3D>> plan_labels;
  size_t object_box_count = 0;
  size_t plan_box_count = 0;
  size_t plan_arrow_count = 0;
  scene::VoxelLayer voxels;
  scene::VoxelLayer projection;
  size_t projection_count = 0;
  scene::VoxelLayer breakdown;
  size_t breakdown_count = 0;
  // Drawn by a renderer of its own on top of the scene's (same camera).
  vtkNew<vtkRenderer> overlay;
  PolyActor measurement;
  vtkNew<vtkBillboardTextActor3D> measurement_text;
  size_t measurement_points = 0;
  QString measurement_label;
  std::unique_ptr<scene::BoxHandles> handles;
  MapSnapshot snapshot;
  LabelSet labels;
  std::set<int> hidden;
  bool opacity_by_probability = false;
  VoxelColouring colouring = VoxelColouring::Labels;
  bool cloud_visible = true;
  size_t voxel_count = 0;
  vtkNew<vtkAxesActor> axes;
  vtkNew<vtkOrientationMarkerWidget> axes_widget;

  std::optional<scene::Viewpoint> home_viewpoint;  // first frame's camera
  double frustum_depth = 0.1;
  bool camera_needs_reset = false;
  size_t point_count = 0;

  Scene() {
    render_window->AddRenderer(renderer);
    // ParaView-like dark blue-grey gradient: label colours and the grey
    // background points both stay readable on it.
    renderer->GradientBackgroundOn();
    renderer->SetBackground(0.10, 0.11, 0.15);
    renderer->SetBackground2(0.32, 0.34, 0.43);

    // Points carry their final colour (label or image): no shading on them.
    cloud.mapper->SetScalarModeToUsePointData();
    cloud.mapper->SetColorModeToDirectScalars();
    cloud.actor->GetProperty()->SetPointSize(3);
    cloud.actor->GetProperty()->LightingOff();
    other_frustums.actor->GetProperty()->SetColor(0.75, 0.75, 0.80);
    other_frustums.actor->GetProperty()->LightingOff();
    current_frustum.actor->GetProperty()->SetColor(1.0, 0.70, 0.0);
    current_frustum.actor->GetProperty()->SetLineWidth(3);
    current_frustum.actor->GetProperty()->LightingOff();
    boxes.mapper->SetScalarModeToUseCellData();
    boxes.mapper->SetColorModeToDirectScalars();
    boxes.actor->GetProperty()->SetLineWidth(2);
    boxes.actor->GetProperty()->LightingOff();
    for (PolyActor* part : {&object_boxes, &plan_boxes, &plan_arrows}) {
      part->mapper->SetScalarModeToUseCellData();
      part->mapper->SetColorModeToDirectScalars();
      part->actor->GetProperty()->LightingOff();
    }
    object_boxes.actor->GetProperty()->SetLineWidth(1.5);
    plan_boxes.actor->GetProperty()->SetLineWidth(4);
    plan_arrows.actor->GetProperty()->SetLineWidth(3);
    for (PolyActor* part : {&cloud, &other_frustums, &current_frustum, &boxes, &object_boxes,
                            &plan_boxes, &plan_arrows}) {
      part->show(nullptr);
      renderer->AddActor(part->actor);
    }
    renderer->AddActor(voxels.actor());
    renderer->AddActor(projection.actor());
    renderer->AddActor(breakdown.actor());
    render_window->SetNumberOfLayers(2);
    overlay->SetLayer(1);
    overlay->InteractiveOff();
    overlay->SetActiveCamera(renderer->GetActiveCamera());
    render_window->AddRenderer(overlay);
    measurement.actor->GetProperty()->SetColor(1.0, 0.35, 0.9);
    measurement.actor->GetProperty()->SetLineWidth(3);
    measurement.actor->GetProperty()->SetPointSize(11);
    measurement.actor->GetProperty()->SetRenderPointsAsSpheres(true);
    measurement.actor->GetProperty()->LightingOff();
    measurement.show(nullptr);
    overlay->AddActor(measurement.actor);
    measurement_text->GetTextProperty()->SetFontSize(16);
    measurement_text->GetTextProperty()->SetBold(true);
    measurement_text->GetTextProperty()->SetColor(1.0, 0.35, 0.9);
    measurement_text->GetTextProperty()->SetBackgroundColor(0.1, 0.1, 0.12);
    measurement_text->GetTextProperty()->SetBackgroundOpacity(0.7);
    measurement_text->SetVisibility(false);
    overlay->AddActor(measurement_text);
    projection.actor()->GetProperty()->SetRepresentationToWireframe();
    projection.actor()->GetProperty()->SetLineWidth(1.5);
    projection.actor()->GetProperty()->LightingOff();
  }
};

SceneView::SceneView(QWidget* parent)
    : QWidget(parent), scene_(std::make_unique<Scene>()), vtk_widget_(new QVTKOpenGLNativeWidget) {
  setObjectName("sceneView");
  setMinimumSize(320, 240);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(vtk_widget_);
  vtk_widget_->setRenderWindow(scene_->render_window);

  vtkRenderWindowInteractor* interactor = scene_->render_window->GetInteractor();
  vtkNew<StudioInteractorStyle> style;
  style->on_click = [this](int x, int y) { pickAt(x, y); };
  // Hovering names the voxel under the mouse, once the mouse rests a moment
  // (a ray cast over every voxel per mouse move would be wasted).
  hover_timer_ = new QTimer(this);
  hover_timer_->setSingleShot(true);
  hover_timer_->setInterval(60);
  connect(hover_timer_, &QTimer::timeout, this, [this] { hoverAt(hover_at_.x(), hover_at_.y()); });
  style->on_hover = [this](int x, int y) {
    hover_at_ = QPoint(x, y);
    hover_timer_->start();
  };
  interactor->SetInteractorStyle(style);
  scene_->handles = std::make_unique<scene::BoxHandles>(interactor, scene_->renderer);
  scene_->handles->onEdited([this](const OrientedBox& box) { emit boxEdited(box); });
  scene_->axes_widget->SetOrientationMarker(scene_->axes);
  scene_->axes_widget->SetInteractor(interactor);
  scene_->axes_widget->SetViewport(0.0, 0.0, 0.16, 0.22);
  scene_->axes_widget->SetEnabled(1);
  scene_->axes_widget->InteractiveOff();
}

SceneView::~SceneView() = default;

void SceneView::showSequence(const Sequence& sequence) {
  scene_->frustum_depth = scene::frustumDepth(sequence);
  scene_->home_viewpoint.reset();
  if (!sequence.frames.empty()) scene_->home_viewpoint = scene::viewpointOf(sequence, 0);
  scene_->cloud.show(nullptr);
  scene_->point_count = 0;
  scene_->current_frustum.show(nullptr);
  std::vector<size_t> all(sequence.frames.size());
  std::iota(all.begin(), all.end(), size_t{0});
  scene_->other_frustums.show(scene::frustums(sequence, all, scene_->frustum_depth));
  scene_->camera_needs_reset = true;
  render();
}

void SceneView::showFrame(const Sequence& sequence, size_t index, const FrameData* frame,
                          const std::optional<LabelImage>& labels) {
  std::vector<size_t> others;
  for (size_t i = 0; i < sequence.frames.size(); ++i)
    if (i != index) others.push_back(i);
  scene_->other_frustums.show(scene::frustums(sequence, others, scene_->frustum_depth));
  scene_->current_frustum.show(scene::frustums(sequence, {index}, scene_->frustum_depth));

  if (frame) {
    auto cloud = scene::frameCloud(sequence, index, *frame, labels ? &*labels : nullptr);
    scene_->point_count = static_cast<size_t>(cloud->GetNumberOfPoints());
    scene_->cloud.show(cloud);
    scene_->cloud.actor->SetVisibility(scene_->cloud_visible);
  } else {
    scene_->point_count = 0;
    scene_->cloud.show(nullptr);
  }
  // The first frame of a new sequence decides the initial framing; later
  // frames keep whatever view the user chose.
  if (scene_->camera_needs_reset) {
    scene_->camera_needs_reset = false;
    resetCamera();
  }
  render();
}

void SceneView::clear() {
  for (PolyActor* part : {&scene_->cloud, &scene_->other_frustums, &scene_->current_frustum,
                          &scene_->boxes})
    part->show(nullptr);
  scene_->snapshot = MapSnapshot{};
  scene_->voxel_count = scene_->voxels.show(scene_->snapshot, scene_->labels, {}, false);
  scene_->handles->show(nullptr);
  scene_->object_boxes.show(nullptr);
  scene_->object_box_count = 0;
  for (const auto& label : scene_->plan_labels) scene_->renderer->RemoveActor(label);
  scene_->plan_labels.clear();
  scene_->plan_boxes.show(nullptr);
  scene_->plan_arrows.show(nullptr);
  scene_->plan_box_count = 0;
  scene_->plan_arrow_count = 0;
  scene_->point_count = 0;
  scene_->home_viewpoint.reset();
  render();
}

void SceneView::resetCamera() {
  vtkCamera* camera = scene_->renderer->GetActiveCamera();
  if (scene_->home_viewpoint) {
    // Start from the first camera's own view, then turn a little so the
    // cloud's relief and the trajectory read as 3D.
    const scene::Viewpoint& home = *scene_->home_viewpoint;
    const Eigen::Vector3d focal = home.position + home.forward;
    camera->SetPosition(home.position.data());
    camera->SetFocalPoint(focal.data());
    camera->SetViewUp(home.up.data());
    camera->Azimuth(30);
    camera->Elevation(20);
    camera->OrthogonalizeViewUp();
  }
  scene_->renderer->ResetCamera();
  scene_->renderer->ResetCameraClippingRange();
  render();
}

void SceneView::zoomToMap() {
  if (scene_->voxel_count == 0) return;
  double bounds[6];
  scene_->voxels.actor()->GetBounds(bounds);
  scene_->renderer->ResetCamera(bounds);
  scene_->renderer->GetActiveCamera()->Dolly(1.25);
  render();
}

void SceneView::lookFrom(StandardView view) {
  Eigen::Vector3d up = scene_->snapshot.up.value_or(
      scene_->home_viewpoint ? scene_->home_viewpoint->up : Eigen::Vector3d::UnitZ());
  up.normalize();
  // The first camera's viewing direction, levelled; any level direction when
  // it looked straight down or up.
  Eigen::Vector3d forward =
      scene_->home_viewpoint ? scene_->home_viewpoint->forward : Eigen::Vector3d::UnitX();
  forward -= forward.dot(up) * up;
  if (forward.norm() < 1e-6) forward = up.unitOrthogonal();
  forward.normalize();
  const Eigen::Vector3d right = forward.cross(up);
  Eigen::Vector3d direction = forward, view_up = up;
  if (view == StandardView::Above) {
    direction = -up;
    view_up = forward;
  } else if (view == StandardView::Side) {
    direction = -right;  // standing on the right, looking left
  }
  double bounds[6];
  if (scene_->voxel_count > 0)
    scene_->voxels.actor()->GetBounds(bounds);
  else
    scene_->renderer->ComputeVisiblePropBounds(bounds);
  if (!(bounds[0] <= bounds[1])) return;  // nothing to look at
  const Eigen::Vector3d centre(0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
                               0.5 * (bounds[4] + bounds[5]));
  vtkCamera* camera = scene_->renderer->GetActiveCamera();
  const Eigen::Vector3d position = centre - direction;
  camera->SetFocalPoint(centre.data());
  camera->SetPosition(position.data());
  camera->SetViewUp(view_up.data());
  if (scene_->voxel_count > 0) return zoomToMap();  // keeps the direction, frames the map
  scene_->renderer->ResetCamera(bounds);
  render();
}

Eigen::Vector3d SceneView::cameraDirection() const {
  double d[3];
  scene_->renderer->GetActiveCamera()->GetDirectionOfProjection(d);
  return Eigen::Vector3d(d[0], d[1], d[2]).normalized();
}

Eigen::Vector3d SceneView::cameraViewUp() const {
  double u[3];
  scene_->renderer->GetActiveCamera()->GetViewUp(u);
  return Eigen::Vector3d(u[0], u[1], u[2]).normalized();
}

size_t SceneView::framePointCount() const { return scene_->point_count; }

void SceneView::lookFromFrame(const Sequence& sequence, size_t index) {
  if (index >= sequence.frames.size()) return;
  const scene::Viewpoint view = scene::viewpointOf(sequence, index);
  vtkCamera* camera = scene_->renderer->GetActiveCamera();
  const Eigen::Vector3d focal = view.position + view.forward;
  camera->SetPosition(view.position.data());
  camera->SetFocalPoint(focal.data());
  camera->SetViewUp(view.up.data());
  const CameraIntrinsics& intrinsics = sequence.cameraOf(index);
  camera->SetViewAngle(2.0 * std::atan(0.5 * intrinsics.height / intrinsics.fy) * 180.0 / M_PI);
  render();
}

void SceneView::showVoxels(const MapSnapshot& snapshot, const LabelSet& labels,
                           const std::set<int>& hidden) {
  const bool first_voxels = scene_->snapshot.empty() && !snapshot.empty();
  scene_->snapshot = snapshot;
  scene_->labels = labels;
  scene_->hidden = hidden;
  scene_->voxel_count = scene_->voxels.show(snapshot, labels, hidden,
                                            scene_->opacity_by_probability, scene_->colouring);
  emit heightColoursShown(scene_->voxels.heightRange());
  if (first_voxels && !scene_->home_viewpoint) resetCamera();
  render();
}

void SceneView::setOpacityByProbability(bool on) {
  scene_->opacity_by_probability = on;
  showVoxels(MapSnapshot(scene_->snapshot), scene_->labels, scene_->hidden);
}

void SceneView::setVoxelColouring(VoxelColouring colouring) {
  scene_->colouring = colouring;
  showVoxels(MapSnapshot(scene_->snapshot), scene_->labels, scene_->hidden);
}

VoxelColouring SceneView::voxelColouring() const { return scene_->colouring; }

void SceneView::setFrameCloudVisible(bool on) {
  scene_->cloud_visible = on;
  scene_->cloud.actor->SetVisibility(on && scene_->point_count > 0);
  render();
}

void SceneView::showBoxes(const Annotations& boxes, int selected, const LabelSet& labels) {
  scene_->boxes.show(scene::boxOutlines(boxes, labels, selected));
  const bool has_selection = selected >= 0 && selected < static_cast<int>(boxes.boxes.size());
  scene_->handles->show(has_selection ? &boxes.boxes[static_cast<size_t>(selected)].box : nullptr);
  render();
}

void SceneView::showProjectionVoxels(const MapSnapshot* voxels, const LabelSet& labels) {
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

void SceneView::showMeasurement(const std::vector<Eigen::Vector3d>& points, const QString& label) {
  scene_->measurement_points = points.size();
  scene_->measurement_label = points.size() >= 2 ? label : QString();
  if (points.empty()) {
    scene_->measurement.show(nullptr);
  } else {
    auto data = vtkSmartPointer<vtkPolyData>::New();
    auto vertices = vtkSmartPointer<vtkPoints>::New();
    auto markers = vtkSmartPointer<vtkCellArray>::New();
    for (const Eigen::Vector3d& p : points) {
      const vtkIdType id = vertices->InsertNextPoint(p.x(), p.y(), p.z());
      markers->InsertNextCell(1, &id);
    }
    data->SetPoints(vertices);
    data->SetVerts(markers);
    if (points.size() >= 2) {
      auto lines = vtkSmartPointer<vtkCellArray>::New();
      const vtkIdType ends[2] = {0, 1};
      lines->InsertNextCell(2, ends);
      data->SetLines(lines);
    }
    scene_->measurement.show(data);
  }
  scene_->measurement_text->SetVisibility(!scene_->measurement_label.isEmpty());
  if (points.size() >= 2) {
    const Eigen::Vector3d middle = 0.5 * (points[0] + points[1]);
    scene_->measurement_text->SetPosition(middle.x(), middle.y(), middle.z());
    scene_->measurement_text->SetInput(scene_->measurement_label.toStdString().c_str());
  }
  render();
}

size_t SceneView::measurementPointCount() const { return scene_->measurement_points; }

QString SceneView::measurementLabel() const { return scene_->measurement_label; }

size_t SceneView::voxelCount() const { return scene_->voxel_count; }

bool SceneView::boxHandlesVisible() const { return scene_->handles->visible(); }

void SceneView::showObjectBoxes(const std::vector<ObjectInstance>& objects, const LabelSet& labels) {
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
  render();
}

size_t SceneView::objectBoxCount() const { return scene_->object_box_count; }

void SceneView::showPickPlan(const PickPlan* plan) {
  for (const auto& label : scene_->plan_labels) scene_->renderer->RemoveActor(label);
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
    const QColor color(static_cast<int>(255 * (1.0 - t) + 40 * t), 220, static_cast<int>(40 + 40 * t));
    colors.push_back(color);
    auto text = vtkSmartPointer<vtkBillboardTextActor3D>::New();
    text->SetInput(std::to_string(i + 1).c_str());
    const Eigen::Vector3d at = step.grasp.position - step.grasp.approach.normalized() * length;
    text->SetPosition(at.x(), at.y(), at.z());
    text->GetTextProperty()->SetFontSize(18);
    text->GetTextProperty()->SetBold(true);
    text->GetTextProperty()->SetColor(color.redF(), color.greenF(), color.blueF());
    scene_->renderer->AddActor(text);
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

std::optional<VoxelHit> SceneView::voxelAt(int x, int y) const {
  // The voxels drawn are hit by a ray through the pixel, computed here: the
  // depth buffer that a world-point picker reads is not always readable
  // (multisampled, as under Xvfb's Mesa), and this finds exactly the voxel seen.
  vtkRenderer* renderer = scene_->renderer;
  auto world = [renderer, x, y](double depth) {
    renderer->SetDisplayPoint(x, y, depth);
    renderer->DisplayToWorld();
    const double* w = renderer->GetWorldPoint();
    return Eigen::Vector3d(w[0] / w[3], w[1] / w[3], w[2] / w[3]);
  };
  const Eigen::Vector3d near_point = world(0.0);
  return firstVoxelHit(scene_->snapshot, scene_->hidden, near_point, world(1.0) - near_point);
}

void SceneView::pickAt(int x, int y) {
  vtkRenderer* renderer = scene_->renderer;
  std::optional<Eigen::Vector3d> point;
  if (const auto hit = voxelAt(x, y)) {
    point = hit->point;
  } else {
    // No voxel there: whatever else the depth buffer holds (the frame's points).
    if (renderer->GetZ(x, y) >= 1.0) return;  // background, or an unreadable buffer
    vtkNew<vtkWorldPointPicker> picker;
    picker->Pick(x, y, 0.0, renderer);
    point.emplace();
    picker->GetPickPosition(point->data());
  }
  emit surfacePicked(*point);
  Eigen::Vector3d eye;
  renderer->GetActiveCamera()->GetPosition(eye.data());
  const double step = scene_->snapshot.resolution > 0 ? 0.3 * scene_->snapshot.resolution : 0.003;
  Eigen::Vector3d inside = *point;
  if ((inside - eye).norm() > 0) inside += (inside - eye).normalized() * step;
  emit pointPicked(inside);
}

void SceneView::hoverAt(int x, int y) {
  QString text;
  if (const auto hit = voxelAt(x, y)) {
    const OccupiedVoxel& voxel = scene_->snapshot.voxels[hit->voxel];
    const QString name = scene_->labels.contains(voxel.label)
                             ? QString::fromStdString(scene_->labels.at(voxel.label).name)
                             : tr("label %1").arg(voxel.label);
    const QString size = voxel.size < 1.0 ? tr("%1 cm").arg(voxel.size * 100.0, 0, 'g', 3)
                                          : tr("%1 m").arg(voxel.size, 0, 'g', 3);
    text = tr("%1 (label %2), p = %3\n%4 voxel at (%5, %6, %7)")
               .arg(name)
               .arg(voxel.label)
               .arg(voxel.probability, 0, 'f', 2)
               .arg(size)
               .arg(voxel.center.x(), 0, 'f', 3)
               .arg(voxel.center.y(), 0, 'f', 3)
               .arg(voxel.center.z(), 0, 'f', 3);
  }
  hover_text_ = text;
  if (text.isEmpty()) {
    QToolTip::hideText();
    return;
  }
  // VTK counts pixels from the bottom, in device pixels.
  const double ratio = vtk_widget_->devicePixelRatioF();
  const QPoint at(static_cast<int>(x / ratio), vtk_widget_->height() - static_cast<int>(y / ratio));
  QToolTip::showText(vtk_widget_->mapToGlobal(at + QPoint(12, 12)), text, vtk_widget_);
}

QImage SceneView::renderToImage() {
  render();
  return vtk_widget_->grabFramebuffer();
}

void SceneView::render() {
  // Rendering before the widget has its OpenGL context does nothing useful.
  if (!scene_ || !vtk_widget_->isValid()) return;
  scene_->renderer->ResetCameraClippingRange();
  scene_->render_window->Render();
}

}  // namespace lom::ui
