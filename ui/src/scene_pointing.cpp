// SceneView: what the mouse points at. Clicks and the resting mouse find the
// first voxel along the line of sight by a ray cast over the map's voxels
// (firstVoxelHit); measurements are drawn over the scene.
#include <QVTKOpenGLNativeWidget.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkWorldPointPicker.h>

#include <QToolTip>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "scene_state.hpp"

namespace lom::ui {

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

std::optional<Eigen::Vector3d> SceneView::framePointAt(int x, int y) const {
  if (!scene_->cloud_visible || !scene_->cloud.actor->GetVisibility()) return std::nullopt;
  vtkPolyData* cloud = scene_->cloud.mapper->GetInput();
  if (!cloud || cloud->GetNumberOfPoints() == 0) return std::nullopt;
  vtkRenderer* renderer = scene_->renderer;
  auto world = [renderer](double px, double py, double depth) {
    renderer->SetDisplayPoint(px, py, depth);
    renderer->DisplayToWorld();
    const double* w = renderer->GetWorldPoint();
    return Eigen::Vector3d(w[0] / w[3], w[1] / w[3], w[2] / w[3]);
  };
  // The ray through the pixel, and one through a pixel two to the side: at
  // each depth their distance is how far a point may be from the ray and
  // still be drawn under the cursor (points are drawn 3 pixels wide).
  const Eigen::Vector3d near0 = world(x, y, 0.0), ray0 = world(x, y, 1.0) - near0;
  const Eigen::Vector3d near1 = world(x + 2, y, 0.0), ray1 = world(x + 2, y, 1.0) - near1;
  const double length2 = ray0.squaredNorm();
  if (!(length2 > 0.0) || !std::isfinite(length2)) return std::nullopt;
  std::optional<Eigen::Vector3d> best;
  double best_s = std::numeric_limits<double>::infinity();
  vtkPoints* points = cloud->GetPoints();
  for (vtkIdType i = 0, n = points->GetNumberOfPoints(); i < n; ++i) {
    Eigen::Vector3d p;
    points->GetPoint(i, p.data());
    const double s = (p - near0).dot(ray0) / length2;
    if (s < 0.0 || s > 1.0 || s >= best_s) continue;
    const Eigen::Vector3d on_ray = near0 + s * ray0;
    const double reach = ((near1 + s * ray1) - on_ray).norm();
    if ((p - on_ray).squaredNorm() > reach * reach) continue;
    best_s = s;
    best = p;
  }
  return best;
}

void SceneView::pickAt(int x, int y) {
  vtkRenderer* renderer = scene_->renderer;
  if (const auto hit = voxelAt(x, y)) {
    // The voxel under the cursor is the one picked: its centre (a point
    // nudged from the face along the view ray could fall in a neighbour
    // near edges and at grazing angles).
    emit surfacePicked(hit->point);
    emit pointPicked(scene_->snapshot.voxels[hit->voxel].center);
    return;
  }
  // No voxel there: the frame's points (an empty map, a map still to come),
  // found by a ray through the pixel as the voxels are; else whatever else the
  // depth buffer holds, when it can be read.
  Eigen::Vector3d point;
  if (const auto frame_point = framePointAt(x, y)) {
    point = *frame_point;
  } else {
    if (renderer->GetZ(x, y) >= 1.0) return;  // background, or an unreadable buffer
    vtkNew<vtkWorldPointPicker> picker;
    picker->Pick(x, y, 0.0, renderer);
    picker->GetPickPosition(point.data());
  }
  emit surfacePicked(point);
  Eigen::Vector3d eye;
  renderer->GetActiveCamera()->GetPosition(eye.data());
  const double step = scene_->snapshot.resolution > 0 ? 0.3 * scene_->snapshot.resolution : 0.003;
  Eigen::Vector3d inside = point;
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
               .arg(voxel.center.x(), 0, 'f', coordinateDecimals(voxel.size))
               .arg(voxel.center.y(), 0, 'f', coordinateDecimals(voxel.size))
               .arg(voxel.center.z(), 0, 'f', coordinateDecimals(voxel.size));
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

}  // namespace lom::ui
