#pragma once
// The 3D view's VTK state, shared by the files that implement SceneView
// (scene_view.cpp: cameras, frames, voxels and boxes; scene_overlays.cpp:
// extra layers; scene_pointing.cpp: clicks, hovering and measuring). Only
// scene_*.cpp include this.
#include <vtkActor.h>
#include <vtkAxesActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCaptionActor2D.h>
#include <vtkCoordinate.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <QString>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "lom/ui/scene_view.hpp"
#include "scene_adapters.hpp"
#include "scene_layers.hpp"

namespace lom::ui {

namespace scene {

struct PolyActor {
  vtkNew<vtkPolyDataMapper> mapper;
  vtkNew<vtkActor> actor;

  PolyActor() { actor->SetMapper(mapper); }
  void show(vtkPolyData* data) {
    mapper->SetInputData(data);
    actor->SetVisibility(data != nullptr);
  }
};

}  // namespace scene

struct SceneView::Scene {
  vtkNew<vtkGenericOpenGLRenderWindow> render_window;
  vtkNew<vtkRenderer> renderer;
  scene::PolyActor cloud;
  scene::PolyActor other_frustums;
  scene::PolyActor current_frustum;
  scene::PolyActor boxes;
  scene::PolyActor object_boxes;
  scene::PolyActor plan_boxes;
  scene::PolyActor plan_arrows;
  std::vector<vtkSmartPointer<vtkBillboardTextActor3D>> plan_labels;
  size_t object_box_count = 0;
  size_t plan_box_count = 0;
  size_t plan_arrow_count = 0;
  scene::VoxelLayer voxels;
  scene::VoxelLayer projection;
  size_t projection_count = 0;
  size_t renders = 0;  // redraws of the window (SceneView::render)
  scene::VoxelLayer breakdown;
  size_t breakdown_count = 0;
  // Drawn by a renderer of its own on top of the scene's (same camera).
  vtkNew<vtkRenderer> overlay;
  scene::PolyActor measurement;
  vtkNew<vtkBillboardTextActor3D> measurement_text;
  size_t measurement_points = 0;
  QString measurement_label;
  std::unique_ptr<scene::BoxHandles> handles;
  MapSnapshot snapshot;
  LabelSet labels;
  std::set<int> hidden;
  // mapBulk(snapshot, hidden), worked out when first needed after either changed.
  std::optional<std::optional<MapBulk>> bulk;
  bool opacity_by_probability = false;
  VoxelColouring colouring = VoxelColouring::Labels;
  bool cloud_visible = true;
  bool cameras_visible = true;
  bool axes_visible = true;
  bool boxes_visible = true;
  // The boxes last shown (showBoxes), shown again when they are turned on.
  Annotations shown_boxes;
  int selected_box = -1;
  LabelSet box_labels;
  size_t voxel_count = 0;
  vtkNew<vtkAxesActor> axes;
  vtkNew<vtkOrientationMarkerWidget> axes_widget;
  // What to do in an empty window, centred in the view until a sequence opens.
  vtkNew<vtkTextActor> empty_hint;

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

    // Short lines: the view may be as narrow as 320 pixels.
    empty_hint->SetInput(
        "No sequence open\n\nFile > Open Sequence... (Ctrl+O),\nor drop a sequence folder,\n"
        "a dataset folder or a ROS bag here");
    vtkTextProperty* hint_text = empty_hint->GetTextProperty();
    hint_text->SetJustificationToCentered();
    hint_text->SetVerticalJustificationToCentered();
    hint_text->SetFontSize(15);
    hint_text->SetColor(0.85, 0.87, 0.92);
    empty_hint->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    empty_hint->GetPositionCoordinate()->SetValue(0.5, 0.5);
    renderer->AddActor2D(empty_hint);

    // The axes' letters in a fixed size, tinted like their axes and centred
    // a little beyond their tips: VTK fits them to a share of the marker (too
    // small to read in a small marker) and starts them at the tips, where the
    // letters of two axes pointing alike run into each other.
    axes->SetNormalizedLabelPosition(1.2, 1.2, 1.2);
    const double tints[3][3] = {{1.0, 0.55, 0.55}, {0.55, 1.0, 0.55}, {0.6, 0.75, 1.0}};
    vtkCaptionActor2D* captions[3] = {axes->GetXAxisCaptionActor2D(),
                                      axes->GetYAxisCaptionActor2D(),
                                      axes->GetZAxisCaptionActor2D()};
    for (int axis = 0; axis < 3; ++axis) {
      captions[axis]->GetTextActor()->SetTextScaleModeToNone();
      captions[axis]->SetPadding(0);
      vtkTextProperty* text = captions[axis]->GetCaptionTextProperty();
      text->SetFontSize(SceneView::kAxesLabelFontSize);
      text->SetItalic(false);
      text->SetBold(true);
      text->SetShadow(true);
      text->SetJustificationToCentered();
      text->SetVerticalJustificationToCentered();
      text->SetColor(tints[axis]);
    }

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
    for (scene::PolyActor* part : {&object_boxes, &plan_boxes, &plan_arrows}) {
      part->mapper->SetScalarModeToUseCellData();
      part->mapper->SetColorModeToDirectScalars();
      part->actor->GetProperty()->LightingOff();
    }
    object_boxes.actor->GetProperty()->SetLineWidth(1.5);
    plan_boxes.actor->GetProperty()->SetLineWidth(4);
    plan_arrows.actor->GetProperty()->SetLineWidth(3);
    for (scene::PolyActor* part : {&cloud, &other_frustums, &current_frustum, &boxes, &object_boxes,
                                   &plan_boxes, &plan_arrows}) {
      part->show(nullptr);
      // The grasp arrows (and their numbers) over the map: the target's
      // grasp faces the approach, so it is behind the objects to remove,
      // hidden exactly when there is something to remove.
      (part == &plan_arrows ? overlay.Get() : renderer.Get())->AddActor(part->actor);
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

}  // namespace lom::ui
