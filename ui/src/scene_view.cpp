#include "lom/ui/scene_view.hpp"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkAxesActor.h>
#include <vtkCamera.h>
#include <vtkCaptionActor2D.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkImageData.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderLargeImage.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkTextActor.h>

#include <QPainter>
#include <QResizeEvent>
#include <QSurfaceFormat>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <string>

#include "lom/ui/frame_labels.hpp"
#include "scene_state.hpp"

namespace lom::ui {

void setDefaultSurfaceFormat() {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
}

namespace {

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

constexpr int kFocusFrameWidth = 2;

}  // namespace

void SceneView::paintEvent(QPaintEvent* /*event*/) {
  QPainter painter(this);
  const QColor colour = vtk_widget_->hasFocus() ? palette().color(QPalette::Highlight)
                                                : palette().color(QPalette::Window);
  painter.fillRect(rect(), colour);
}

bool SceneView::eventFilter(QObject* watched, QEvent* event) {
  if (watched == vtk_widget_ &&
      (event->type() == QEvent::FocusIn || event->type() == QEvent::FocusOut))
    update();
  return QWidget::eventFilter(watched, event);
}

SceneView::SceneView(QWidget* parent)
    : QWidget(parent), scene_(std::make_unique<Scene>()), vtk_widget_(new QVTKOpenGLNativeWidget) {
  setObjectName("sceneView");
  setMinimumSize(320, 240);
  auto* layout = new QVBoxLayout(this);
  // Room for the focus frame (paintEvent).
  layout->setContentsMargins(kFocusFrameWidth, kFocusFrameWidth, kFocusFrameWidth,
                             kFocusFrameWidth);
  layout->addWidget(vtk_widget_);
  vtk_widget_->installEventFilter(this);
  vtk_widget_->setAccessibleName(tr("3D view"));
  vtk_widget_->setAccessibleDescription(
      tr("The map, the camera frustums and the boxes; Tab and Shift+Tab choose a box"));
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
  scene_->handles->onClicked([this](int x, int y) { pickAt(x, y); });
  scene_->axes_widget->SetOrientationMarker(scene_->axes);
  scene_->axes_widget->SetInteractor(interactor);
  scene_->axes_widget->SetEnabled(1);
  scene_->axes_widget->InteractiveOff();
  // The axes larger in their square than VTK draws them (it leaves room for
  // them turned every way), their letters still inside it.
  scene_->axes_widget->SetZoom(1.25);
  placeAxesMarker();
}

SceneView::~SceneView() = default;

void SceneView::resizeEvent(QResizeEvent* event) {
  QWidget::resizeEvent(event);
  placeAxesMarker();
}

void SceneView::placeAxesMarker() {
  // A square of a fixed number of pixels: a share of the view's width and
  // height would squeeze the axes in a narrow view until their letters
  // overlap, and blow them up in a wide one.
  const int side =
      std::clamp(std::min(width(), height()) / 4, kAxesMarkerMinPixels, kAxesMarkerMaxPixels);
  scene_->axes_widget->SetViewport(0.0, 0.0, std::min(1.0, side / std::max(1.0, 1.0 * width())),
                                   std::min(1.0, side / std::max(1.0, 1.0 * height())));
}

QRect SceneView::axesMarkerRect() const {
  const double* viewport = scene_->axes_widget->GetViewport();
  const QPoint bottom_left(static_cast<int>(std::lround(viewport[0] * width())),
                           static_cast<int>(std::lround((1.0 - viewport[1]) * height())));
  const QPoint top_right(static_cast<int>(std::lround(viewport[2] * width())),
                         static_cast<int>(std::lround((1.0 - viewport[3]) * height())));
  return QRect(QPoint(bottom_left.x(), top_right.y()), QPoint(top_right.x(), bottom_left.y()))
      .adjusted(0, 0, -1, -1);
}

std::vector<QRect> SceneView::axesLabelRects() const {
  // The marker is drawn by a renderer of the orientation widget's own: the
  // render window's renderer that holds the axes.
  vtkRenderer* marker = nullptr;
  vtkRendererCollection* renderers = scene_->render_window->GetRenderers();
  renderers->InitTraversal();
  while (vtkRenderer* renderer = renderers->GetNextItem())
    if (renderer->HasViewProp(scene_->axes)) marker = renderer;
  if (!marker) return {};
  const int window_height = scene_->render_window->GetSize()[1];
  const double scale = devicePixelRatioF();
  std::vector<QRect> rects;
  for (vtkCaptionActor2D* caption :
       {scene_->axes->GetXAxisCaptionActor2D(), scene_->axes->GetYAxisCaptionActor2D(),
        scene_->axes->GetZAxisCaptionActor2D()}) {
    vtkTextActor* text = caption->GetTextActor();
    // Where the caption put its text at the last render, and the text's box
    // around that point (display pixels from the window's bottom-left corner).
    const int* anchor = text->GetPositionCoordinate()->GetComputedDisplayValue(marker);
    double box[4];
    text->GetBoundingBox(marker, box);
    const QRectF device(anchor[0] + box[0], window_height - (anchor[1] + box[3]), box[1] - box[0],
                        box[3] - box[2]);
    rects.push_back(QRectF(device.topLeft() / scale, device.size() / scale).toAlignedRect());
  }
  return rects;
}

bool SceneView::emptyHintShown() const { return scene_->empty_hint->GetVisibility() != 0; }

void SceneView::showSequence(const Sequence& sequence) {
  scene_->empty_hint->SetVisibility(false);
  scene_->frustum_depth = scene::frustumDepth(sequence);
  scene_->home_viewpoint.reset();
  if (!sequence.frames.empty()) scene_->home_viewpoint = scene::viewpointOf(sequence, 0);
  scene_->cloud.show(nullptr);
  scene_->point_count = 0;
  // The previous sequence's map goes with it: its reset reaches the view only
  // later, through the map worker, and the first frame's framing (showFrame)
  // must not include voxels of another scene, which would leave this one a
  // speck in the middle.
  scene_->snapshot = MapSnapshot{};
  scene_->bulk.reset();
  scene_->voxel_count = scene_->voxels.show(scene_->snapshot, scene_->labels, {}, false);
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
  for (scene::PolyActor* part :
       {&scene_->cloud, &scene_->other_frustums, &scene_->current_frustum, &scene_->boxes})
    part->show(nullptr);
  scene_->snapshot = MapSnapshot{};
  scene_->bulk.reset();
  scene_->voxel_count = scene_->voxels.show(scene_->snapshot, scene_->labels, {}, false);
  scene_->handles->show(nullptr);
  scene_->object_boxes.show(nullptr);
  scene_->object_box_count = 0;
  for (const auto& label : scene_->plan_labels) scene_->overlay->RemoveActor(label);
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
  restoreViewAngle();
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
  // Everything shown, the map's voxels by their bulk (specks far from the
  // scene would leave it small in the view).
  double bounds[6];
  vtkActor* voxels = scene_->voxels.actor();
  const bool voxels_visible = voxels->GetVisibility() != 0;
  voxels->SetVisibility(false);
  scene_->renderer->ComputeVisiblePropBounds(bounds);
  voxels->SetVisibility(voxels_visible);
  double map[6];
  if (voxels_visible && mapBounds(map)) {
    for (int axis = 0; axis < 3; ++axis) {
      bounds[2 * axis] = std::min(bounds[2 * axis], map[2 * axis]);
      bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], map[2 * axis + 1]);
    }
  }
  if (bounds[0] <= bounds[1])
    scene_->renderer->ResetCamera(bounds);
  else
    scene_->renderer->ResetCamera();
  scene_->renderer->ResetCameraClippingRange();
  render();
}

bool SceneView::mapBounds(double bounds[6]) const {
  const MapBulk* bulk = shownBulk();
  if (bulk == nullptr || bulk->box.isEmpty()) return false;
  for (int axis = 0; axis < 3; ++axis) {
    bounds[2 * axis] = bulk->box.min()[axis];
    bounds[2 * axis + 1] = bulk->box.max()[axis];
  }
  return true;
}

const MapBulk* SceneView::shownBulk() const {
  if (scene_->voxel_count == 0) return nullptr;
  if (!scene_->bulk) scene_->bulk = mapBulk(scene_->snapshot, scene_->hidden);
  return *scene_->bulk ? &**scene_->bulk : nullptr;
}

void SceneView::zoomToMap(bool with_current_camera) {
  if (scene_->voxel_count == 0) return;
  double bounds[6];
  if (!mapBounds(bounds)) return;
  if (with_current_camera && scene_->cameras_visible &&
      scene_->current_frustum.actor->GetVisibility()) {
    double camera[6];
    scene_->current_frustum.actor->GetBounds(camera);
    for (int axis = 0; axis < 3; ++axis) {
      bounds[2 * axis] = std::min(bounds[2 * axis], camera[2 * axis]);
      bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], camera[2 * axis + 1]);
    }
  }
  vtkCamera* camera = scene_->renderer->GetActiveCamera();
  if (!with_current_camera)
    restoreViewAngle();  // Look from Current Camera leaves a camera's angle, maybe horizontal
  camera->SetWindowCenter(0.0, 0.0);  // the map in the middle (Look from Current Camera shifts it)
  scene_->renderer->ResetCamera(bounds);
  if (!with_current_camera) {
    // Closer: ResetCamera leaves room for the bounds' sphere, wider than the
    // map. The camera keeps its direction and moves to where the bulk's
    // voxels (not the corners of the box around them: a room turned against
    // the world's axes is far smaller than its box) fill 90 % of the view
    // across or up, whatever the view's shape, as `render` frames a map.
    if (const MapBulk* bulk = shownBulk()) frameCubes(*bulk);
    scene_->renderer->ResetCameraClippingRange();
  } else {
    // ResetCamera fits the bounds' sphere, but not always across a view
    // narrower than high (the docks take the sides): back off until the
    // camera's frustum is wholly in the picture.
    for (int step = 0; step < 12 && !currentCameraInView(); ++step) camera->Dolly(0.9);
    scene_->renderer->ResetCameraClippingRange();
  }
  render();
}

void SceneView::frameCubes(const MapBulk& bulk) {
  vtkCamera* camera = scene_->renderer->GetActiveCamera();
  double position[3], focal[3], view_up[3];
  camera->GetPosition(position);
  camera->GetFocalPoint(focal);
  camera->GetViewUp(view_up);
  const Eigen::Vector3d back = (Eigen::Vector3d(position[0], position[1], position[2]) -
                                Eigen::Vector3d(focal[0], focal[1], focal[2]))
                                   .normalized();
  Eigen::Vector3d up(view_up[0], view_up[1], view_up[2]);
  up = (up - up.dot(back) * back).normalized();
  const Eigen::Vector3d right = up.cross(back);
  const int* size = scene_->renderer->GetSize();
  const double aspect = size[0] > 0 && size[1] > 0 ? static_cast<double>(size[0]) / size[1] : 1.0;
  const double tan_up = 0.9 * std::tan(0.5 * camera->GetViewAngle() * M_PI / 180.0);
  const double tan_across = tan_up * aspect;
  if (!back.allFinite() || !up.allFinite() || !(tan_up > 0.0) || bulk.centres.empty()) return;
  // A cube of half edge h reaches h (|u.x| + |u.y| + |u.z|) from its centre along u.
  const double h = 0.5 * bulk.edge;
  const auto reach = [h](const Eigen::Vector3d& u) { return h * u.cwiseAbs().sum(); };
  const double reach_back = reach(back), reach_up = reach(up), reach_right = reach(right);
  Eigen::Vector3d centre = bulk.box.center();
  double distance = 0.0;
  // From `centre`: the distance at which every cube is in view (a cube at p
  // is when |p . up| + its reach <= (D - p . back - its reach) tan, and so
  // across); then the picture's middle is moved onto the middle of what it
  // shows, and the distance worked out again.
  for (int pass = 0; pass < 3; ++pass) {
    distance = 0.0;
    for (const Eigen::Vector3d& point : bulk.centres) {
      const Eigen::Vector3d p = point - centre;
      const double towards_eye = p.dot(back) + reach_back;
      distance = std::max({distance, towards_eye + (std::abs(p.dot(up)) + reach_up) / tan_up,
                           towards_eye + (std::abs(p.dot(right)) + reach_right) / tan_across});
    }
    if (pass == 2) break;
    double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
    for (const Eigen::Vector3d& point : bulk.centres) {
      const Eigen::Vector3d p = point - centre;
      const double depth = std::max(1e-9, distance - p.dot(back) - reach_back);
      x_lo = std::min(x_lo, (p.dot(right) - reach_right) / depth);
      x_hi = std::max(x_hi, (p.dot(right) + reach_right) / depth);
      y_lo = std::min(y_lo, (p.dot(up) - reach_up) / depth);
      y_hi = std::max(y_hi, (p.dot(up) + reach_up) / depth);
    }
    centre += distance * (0.5 * (x_lo + x_hi) * right + 0.5 * (y_lo + y_hi) * up);
  }
  if (!(distance > 0.0) || !std::isfinite(distance)) return;
  const Eigen::Vector3d eye = centre + distance * back;
  camera->SetFocalPoint(centre.data());
  camera->SetPosition(eye.data());
}

double SceneView::boxesExtentInView(const std::vector<Eigen::Vector3d>& centres,
                                    const Eigen::Vector3d& half) const {
  // The largest |x| or |y| of the boxes' corners in the view's normalised
  // coordinates (-1 to 1 across the picture); infinity for a corner behind
  // the camera.
  vtkCamera* camera = scene_->renderer->GetActiveCamera();
  const int* size = scene_->renderer->GetSize();
  const double aspect = size[0] > 0 && size[1] > 0 ? static_cast<double>(size[0]) / size[1] : 1.0;
  vtkMatrix4x4* matrix = camera->GetCompositeProjectionTransformMatrix(aspect, -1.0, 1.0);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = matrix->GetElement(r, c);
  double extent = 0.0;
  for (const Eigen::Vector3d& centre : centres)
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d p =
          centre + half.cwiseProduct(Eigen::Vector3d(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1,
                                                     corner & 4 ? 1 : -1));
      const Eigen::Vector4d v = m * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
      if (!(v.w() > 0.0)) return std::numeric_limits<double>::infinity();  // behind the camera
      extent = std::max({extent, std::abs(v.x() / v.w()), std::abs(v.y() / v.w())});
    }
  return extent;
}

double SceneView::mapExtentInView() const {
  const MapBulk* bulk = shownBulk();
  if (bulk == nullptr) return 0.0;
  return boxesExtentInView(bulk->centres, Eigen::Vector3d::Constant(0.5 * bulk->edge));
}

double SceneView::boxExtentInView(const double bounds[6]) const {
  const Eigen::Vector3d low(bounds[0], bounds[2], bounds[4]), high(bounds[1], bounds[3], bounds[5]);
  return boxesExtentInView({0.5 * (low + high)}, 0.5 * (high - low));
}

bool SceneView::currentCameraInView() const {
  if (!scene_->cameras_visible || !scene_->current_frustum.actor->GetVisibility()) return false;
  double bounds[6];
  scene_->current_frustum.actor->GetBounds(bounds);
  // Every corner of the frustum's box inside the picture.
  for (int corner = 0; corner < 8; ++corner) {
    double point[4] = {bounds[corner & 1], bounds[2 + ((corner >> 1) & 1)],
                       bounds[4 + ((corner >> 2) & 1)], 1.0};
    scene_->renderer->SetWorldPoint(point);
    scene_->renderer->WorldToDisplay();
    double display[3];
    scene_->renderer->GetDisplayPoint(display);
    const int* size = scene_->renderer->GetSize();
    if (display[0] < 0 || display[1] < 0 || display[0] > size[0] || display[1] > size[1])
      return false;
  }
  return true;
}

void SceneView::lookFrom(StandardView view) {
  restoreViewAngle();
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
  if (!mapBounds(bounds)) scene_->renderer->ComputeVisiblePropBounds(bounds);
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

Eigen::Vector2d SceneView::displayPointOf(const Eigen::Vector3d& world) const {
  vtkRenderer* renderer = scene_->renderer;
  renderer->SetWorldPoint(world.x(), world.y(), world.z(), 1.0);
  renderer->WorldToDisplay();
  const double* display = renderer->GetDisplayPoint();
  return {display[0], display[1]};
}

QSize SceneView::viewPixels() const {
  const int* size = scene_->renderer->GetSize();
  return {size[0], size[1]};
}

void SceneView::lookFromFrame(const Sequence& sequence, size_t index) {
  if (index >= sequence.frames.size()) return;
  const scene::Viewpoint view = scene::viewpointOf(sequence, index);
  vtkCamera* camera = scene_->renderer->GetActiveCamera();
  const Eigen::Vector3d focal = view.position + view.forward;
  camera->SetPosition(view.position.data());
  camera->SetFocalPoint(focal.data());
  camera->SetViewUp(view.up.data());
  // The whole picture the camera took fits the view, centred: along the
  // image's height, or along its width when the view is narrower than the
  // image (the default layout's 3D view is: the sides were cut off). The
  // picture's middle is off the optical axis by the principal point's offset
  // from the image centre; the window centre shifts the view by as much.
  const CameraIntrinsics& intrinsics = sequence.cameraOf(index);
  const double half_width = 0.5 * intrinsics.width / intrinsics.fx;  // tan of half the angle
  const double half_height = 0.5 * intrinsics.height / intrinsics.fy;
  // The picture's middle, as tangents right of and below the optical axis
  // (pixel centres at integer coordinates: the image spans [-0.5, size - 0.5]).
  const double middle_right = (0.5 * intrinsics.width - (intrinsics.cx + 0.5)) / intrinsics.fx;
  const double middle_down = (0.5 * intrinsics.height - (intrinsics.cy + 0.5)) / intrinsics.fy;
  const int* size = scene_->renderer->GetSize();
  const double view_aspect = size[0] > 0 && size[1] > 0 ? static_cast<double>(size[0]) / size[1]
                                                        : half_width / half_height;
  const bool fit_width = view_aspect < half_width / half_height;
  // The view's half extents, as tangents.
  const double view_half_width = fit_width ? half_width : half_height * view_aspect;
  const double view_half_height = fit_width ? half_width / view_aspect : half_height;
  camera->SetUseHorizontalViewAngle(fit_width ? 1 : 0);
  camera->SetViewAngle(2.0 * std::atan(fit_width ? half_width : half_height) * 180.0 / M_PI);
  // The optical axis lands at normalised view coordinates -WindowCenter.
  camera->SetWindowCenter(middle_right / view_half_width, -middle_down / view_half_height);
  render();
}

void SceneView::restoreViewAngle() {
  // A camera's view angle (lookFromFrame) is not the overview's.
  vtkCamera* camera = scene_->renderer->GetActiveCamera();
  camera->SetUseHorizontalViewAngle(0);
  camera->SetViewAngle(30.0);
  camera->SetWindowCenter(0.0, 0.0);
}

void SceneView::showVoxels(const MapSnapshot& snapshot, const LabelSet& labels,
                           const std::set<int>& hidden) {
  const bool first_voxels = scene_->snapshot.empty() && !snapshot.empty();
  scene_->snapshot = snapshot;
  scene_->labels = labels;
  scene_->hidden = hidden;
  scene_->bulk.reset();
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
  scene_->shown_boxes = boxes;
  scene_->selected_box = selected;
  scene_->box_labels = labels;
  scene_->boxes.show(scene::boxOutlines(boxes, labels, selected));
  scene_->boxes.actor->SetVisibility(scene_->boxes_visible && !boxes.boxes.empty());
  const bool has_selection =
      scene_->boxes_visible && selected >= 0 && selected < static_cast<int>(boxes.boxes.size());
  scene_->handles->show(
      has_selection ? &scene_->shown_boxes.boxes[static_cast<size_t>(selected)].box : nullptr);
  render();
}

void SceneView::setCamerasVisible(bool on) {
  scene_->cameras_visible = on;
  // Out of the renderer while hidden: show() of a new frame's frustums sets
  // their visibility, and hidden parts must not be framed.
  for (scene::PolyActor* part : {&scene_->other_frustums, &scene_->current_frustum})
    if (on)
      scene_->renderer->AddActor(part->actor);
    else
      scene_->renderer->RemoveActor(part->actor);
  render();
}

void SceneView::setAxesVisible(bool on) {
  scene_->axes_visible = on;
  scene_->axes_widget->SetEnabled(on ? 1 : 0);
  if (on) scene_->axes_widget->InteractiveOff();
  render();
}

void SceneView::setBoxesVisible(bool on) {
  scene_->boxes_visible = on;
  // The objects' boxes (Objects panel) go with the ground-truth boxes.
  scene_->object_boxes.actor->SetVisibility(on && scene_->object_box_count > 0);
  const Annotations boxes = scene_->shown_boxes;
  const LabelSet labels = scene_->box_labels;
  showBoxes(boxes, scene_->selected_box, labels);
}

bool SceneView::camerasVisible() const { return scene_->cameras_visible; }
bool SceneView::axesVisible() const { return scene_->axes_visible; }
bool SceneView::boxesVisible() const { return scene_->boxes_visible; }

size_t SceneView::voxelCount() const { return scene_->voxel_count; }

QRect SceneView::drawingRect() const { return vtk_widget_->geometry(); }

bool SceneView::boxHandlesVisible() const { return scene_->handles->visible(); }

QImage SceneView::renderToImage(int magnification) {
  render();
  if (magnification <= 1) return vtk_widget_->grabFramebuffer();
  magnification = std::min(magnification, 4);
  // vtkRenderLargeImage renders tiles of the window's size with the camera
  // narrowed to each: a gradient background and the axes' own viewport would
  // be drawn whole in every tile.
  vtkRenderer* renderer = scene_->renderer;
  double low[3], high[3];
  renderer->GetBackground(low);
  renderer->GetBackground2(high);
  renderer->GradientBackgroundOff();
  renderer->SetBackground(0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1]),
                          0.5 * (low[2] + high[2]));
  const bool axes = scene_->axes_visible;
  if (axes) scene_->axes_widget->SetEnabled(0);
  vtkNew<vtkRenderLargeImage> large;
  large->SetInput(renderer);
  large->SetMagnification(magnification);
  large->Update();
  renderer->SetBackground(low);
  renderer->GradientBackgroundOn();
  if (axes) {
    scene_->axes_widget->SetEnabled(1);
    scene_->axes_widget->InteractiveOff();
  }
  render();
  vtkImageData* image = large->GetOutput();
  int size[3] = {0, 0, 0};
  image->GetDimensions(size);
  const int components = image->GetNumberOfScalarComponents();
  if (size[0] <= 0 || size[1] <= 0 || components < 3 || !image->GetScalarPointer()) return {};
  QImage picture(size[0], size[1], QImage::Format_RGB888);
  const auto* pixels = static_cast<const unsigned char*>(image->GetScalarPointer());
  for (int y = 0; y < size[1]; ++y) {  // VTK's rows go up from the bottom
    unsigned char* row = picture.scanLine(size[1] - 1 - y);
    for (int x = 0; x < size[0]; ++x)
      for (int c = 0; c < 3; ++c)
        row[3 * x + c] = pixels[(static_cast<size_t>(y) * size[0] + x) * components + c];
  }
  return picture;
}

void SceneView::render() {
  // Rendering before the widget has its OpenGL context does nothing useful.
  if (!scene_ || !vtk_widget_->isValid()) return;
  scene_->renderer->ResetCameraClippingRange();
  scene_->render_window->Render();
  ++scene_->renders;
}

size_t SceneView::renderCount() const { return scene_->renders; }

}  // namespace lom::ui
