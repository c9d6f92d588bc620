#include "lom/ui/scene_view.hpp"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkAxesActor.h>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkNew.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include <QSurfaceFormat>
#include <QVBoxLayout>
#include <numeric>

#include "scene_adapters.hpp"

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

}  // namespace

struct SceneView::Scene {
  vtkNew<vtkGenericOpenGLRenderWindow> render_window;
  vtkNew<vtkRenderer> renderer;
  PolyActor cloud;
  PolyActor other_frustums;
  PolyActor current_frustum;
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
    for (PolyActor* part : {&cloud, &other_frustums, &current_frustum}) {
      part->show(nullptr);
      renderer->AddActor(part->actor);
    }
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
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  interactor->SetInteractorStyle(style);
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
  for (PolyActor* part : {&scene_->cloud, &scene_->other_frustums, &scene_->current_frustum})
    part->show(nullptr);
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

size_t SceneView::framePointCount() const { return scene_->point_count; }

QImage SceneView::renderToImage() {
  render();
  return vtk_widget_->grabFramebuffer();
}

void SceneView::render() {
  scene_->renderer->ResetCameraClippingRange();
  scene_->render_window->Render();
}

}  // namespace lom::ui
