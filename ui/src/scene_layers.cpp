#include "scene_layers.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCubeSource.h>
#include <vtkFloatArray.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkTransform.h>
#include <vtkUnsignedCharArray.h>

#include <Eigen/SVD>
#include <algorithm>

#include "lom/ui/frame_labels.hpp"

namespace lom::ui::scene {

VoxelLayer::VoxelLayer() {
  vtkNew<vtkCubeSource> cube;
  cube->SetXLength(1.0);
  cube->SetYLength(1.0);
  cube->SetZLength(1.0);
  mapper_->SetSourceConnection(cube->GetOutputPort());
  mapper_->SetScaleArray("size");
  mapper_->SetScaleModeToScaleByMagnitude();
  mapper_->ScalingOn();
  mapper_->OrientOff();
  mapper_->SetScalarModeToUsePointFieldData();
  mapper_->SelectColorArray("colors");
  mapper_->SetColorModeToDirectScalars();
  mapper_->ScalarVisibilityOn();
  actor_->SetMapper(mapper_);
  actor_->GetProperty()->SetAmbient(0.35);
  actor_->GetProperty()->SetDiffuse(0.75);
  actor_->SetVisibility(false);
}

size_t VoxelLayer::show(const MapSnapshot& snapshot, const LabelSet& labels,
                        const std::set<int>& hidden, bool opacity_by_probability,
                        VoxelColouring colouring) {
  const double low = snapshot.occupancy_threshold;
  const bool by_height = colouring == VoxelColouring::Height;
  std::vector<Eigen::Vector3d> centres;
  if (by_height)
    for (const OccupiedVoxel& voxel : snapshot.voxels)
      if (!hidden.count(voxel.label)) centres.push_back(voxel.center);
  const HeightColours heights =
      HeightColours::spanning(centres, snapshot.up.value_or(Eigen::Vector3d::UnitZ()));
  height_range_.reset();
  if (by_height && !centres.empty())
    height_range_ = std::make_pair(heights.lowest(), heights.highest());
  std::vector<Cube> cubes;
  cubes.reserve(snapshot.voxels.size());
  for (const OccupiedVoxel& voxel : snapshot.voxels) {
    if (hidden.count(voxel.label)) continue;
    // The background's palette colour is black; grey keeps the shelf readable
    // (the rule `labeloctomap render` draws with).
    const Rgb shaded = shadedLabelColour(labels, voxel.label);
    QColor c(shaded[0], shaded[1], shaded[2]);
    if (by_height) {
      const Rgb rgb = heights.colour(voxel.center);
      c = QColor(rgb[0], rgb[1], rgb[2]);
    }
    double alpha = 1.0;
    if (opacity_by_probability && low < 1.0)
      alpha = 0.15 + 0.85 * std::clamp((voxel.probability - low) / (1.0 - low), 0.0, 1.0);
    c.setAlpha(static_cast<int>(alpha * 255.0 + 0.5));
    cubes.push_back({voxel.center, voxel.size * 0.96, c});
  }
  return showCubes(cubes);
}

size_t VoxelLayer::showCubes(const std::vector<Cube>& cubes) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToFloat();
  auto sizes = vtkSmartPointer<vtkFloatArray>::New();
  sizes->SetName("size");
  auto colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colors->SetName("colors");
  colors->SetNumberOfComponents(4);
  for (const Cube& cube : cubes) {
    points->InsertNextPoint(cube.center.x(), cube.center.y(), cube.center.z());
    sizes->InsertNextValue(static_cast<float>(cube.size));
    const unsigned char rgba[4] = {static_cast<unsigned char>(cube.colour.red()),
                                   static_cast<unsigned char>(cube.colour.green()),
                                   static_cast<unsigned char>(cube.colour.blue()),
                                   static_cast<unsigned char>(cube.colour.alpha())};
    colors->InsertNextTypedTuple(rgba);
  }
  // Refilled, never replaced: VTK's OpenGL glyph mapper keeps the instance
  // buffers of every data set it has drawn, keyed by the data set, until the
  // mapper goes; a new data set per map snapshot grew the studio by a map's
  // worth of graphics memory at every re-fuse.
  data_->Initialize();
  data_->SetPoints(points);
  data_->GetPointData()->AddArray(sizes);
  data_->GetPointData()->AddArray(colors);
  data_->Modified();
  mapper_->SetInputData(data_);
  actor_->SetVisibility(points->GetNumberOfPoints() > 0);
  return static_cast<size_t>(points->GetNumberOfPoints());
}

vtkSmartPointer<vtkPolyData> boxOutlines(const Annotations& boxes, const LabelSet& labels,
                                         int skip) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colors->SetName("colors");
  colors->SetNumberOfComponents(3);
  static constexpr int kEdges[12][2] = {{0, 1}, {1, 3}, {3, 2}, {2, 0}, {4, 5}, {5, 7},
                                        {7, 6}, {6, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (size_t i = 0; i < boxes.boxes.size(); ++i) {
    if (static_cast<int>(i) == skip) continue;
    const OrientedBox& box = boxes.boxes[i].box;
    vtkIdType corner[8];
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d local((c & 1 ? 0.5 : -0.5) * box.size.x(),
                                  (c & 2 ? 0.5 : -0.5) * box.size.y(),
                                  (c & 4 ? 0.5 : -0.5) * box.size.z());
      const Eigen::Vector3d p = box.center + box.rotation * local;
      corner[c] = points->InsertNextPoint(p.x(), p.y(), p.z());
    }
    // Half way to white: dark label colours stay visible as thin lines.
    const QColor base = labelColor(labels, boxes.boxes[i].label);
    const QColor color((base.red() + 255) / 2, (base.green() + 255) / 2, (base.blue() + 255) / 2);
    for (const auto& edge : kEdges) {
      const vtkIdType ends[2] = {corner[edge[0]], corner[edge[1]]};
      lines->InsertNextCell(2, ends);
      const unsigned char rgb[3] = {static_cast<unsigned char>(color.red()),
                                    static_cast<unsigned char>(color.green()),
                                    static_cast<unsigned char>(color.blue())};
      colors->InsertNextTypedTuple(rgb);
    }
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  poly->GetCellData()->SetScalars(colors);
  return poly;
}

namespace {

void insertColor(vtkUnsignedCharArray* colors, const QColor& color) {
  const unsigned char rgb[3] = {static_cast<unsigned char>(color.red()),
                                static_cast<unsigned char>(color.green()),
                                static_cast<unsigned char>(color.blue())};
  colors->InsertNextTypedTuple(rgb);
}

vtkIdType insertPoint(vtkPoints* points, const Eigen::Vector3d& p) {
  return points->InsertNextPoint(p.x(), p.y(), p.z());
}

void insertLine(vtkCellArray* lines, vtkIdType a, vtkIdType b) {
  const vtkIdType ends[2] = {a, b};
  lines->InsertNextCell(2, ends);
}

}  // namespace

vtkSmartPointer<vtkPolyData> boxWireframes(const std::vector<OrientedBox>& boxes,
                                           const std::vector<QColor>& colors) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto cell_colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  cell_colors->SetName("colors");
  cell_colors->SetNumberOfComponents(3);
  static constexpr int kEdges[12][2] = {{0, 1}, {1, 3}, {3, 2}, {2, 0}, {4, 5}, {5, 7},
                                        {7, 6}, {6, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (size_t i = 0; i < boxes.size(); ++i) {
    const OrientedBox& box = boxes[i];
    vtkIdType corner[8];
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d local((c & 1 ? 0.5 : -0.5) * box.size.x(),
                                  (c & 2 ? 0.5 : -0.5) * box.size.y(),
                                  (c & 4 ? 0.5 : -0.5) * box.size.z());
      corner[c] = insertPoint(points, box.center + box.rotation * local);
    }
    const QColor color = i < colors.size() ? colors[i] : QColor(Qt::white);
    for (const auto& edge : kEdges) {
      insertLine(lines, corner[edge[0]], corner[edge[1]]);
      insertColor(cell_colors, color);
    }
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  poly->GetCellData()->SetScalars(cell_colors);
  return poly;
}

vtkSmartPointer<vtkPolyData> graspArrows(const std::vector<Eigen::Vector3d>& tips,
                                         const std::vector<Eigen::Vector3d>& directions,
                                         const std::vector<QColor>& colors, double length) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto cell_colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  cell_colors->SetName("colors");
  cell_colors->SetNumberOfComponents(3);
  for (size_t i = 0; i < tips.size() && i < directions.size(); ++i) {
    Eigen::Vector3d d = directions[i];
    if (d.norm() < 1e-12) continue;
    d.normalize();
    const QColor color = i < colors.size() ? colors[i] : QColor(Qt::white);
    const Eigen::Vector3d& tip = tips[i];
    const vtkIdType tip_id = insertPoint(points, tip);
    insertLine(lines, insertPoint(points, tip - d * length), tip_id);
    insertColor(cell_colors, color);
    // Head: four short lines back from the tip, around the shaft.
    const Eigen::Vector3d helper =
        std::abs(d.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d u = d.cross(helper).normalized();
    const Eigen::Vector3d v = d.cross(u);
    const double head = 0.25 * length;
    for (const Eigen::Vector3d& side : {u, Eigen::Vector3d(-u), v, Eigen::Vector3d(-v)}) {
      insertLine(lines, tip_id, insertPoint(points, tip - d * head + side * (0.4 * head)));
      insertColor(cell_colors, color);
    }
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  poly->GetCellData()->SetScalars(cell_colors);
  return poly;
}

BoxHandles::~BoxHandles() {
  for (const unsigned long tag : press_observers_) interactor_->RemoveObserver(tag);
}

BoxHandles::BoxHandles(vtkRenderWindowInteractor* interactor, vtkRenderer* renderer)
    : interactor_(interactor) {
  representation_->SetPlaceFactor(1.0);
  representation_->SetRenderer(renderer);
  representation_->GetOutlineProperty()->SetColor(1.0, 0.85, 0.2);
  representation_->GetOutlineProperty()->SetLineWidth(2.5);
  representation_->SetHandleSize(4.0);
  widget_->SetInteractor(interactor);
  widget_->SetRepresentation(representation_);
  widget_->SetCurrentRenderer(renderer);
  widget_->SetRotationEnabled(true);
  widget_->SetTranslationEnabled(true);
  widget_->SetScalingEnabled(true);
  widget_->SetMoveFacesEnabled(true);

  // Every press, before the handles take it: which button, where, and the
  // box's transform then (the handles may turn the box and return it).
  vtkNew<vtkCallbackCommand> on_press;
  on_press->SetClientData(this);
  on_press->SetCallback([](vtkObject*, unsigned long event, void* client, void*) {
    auto* self = static_cast<BoxHandles*>(client);
    const int* position = self->interactor_->GetEventPosition();
    self->press_[0] = position[0];
    self->press_[1] = position[1];
    self->left_press_ = event == vtkCommand::LeftButtonPressEvent;
    self->representation_->GetTransform(self->transform_at_press_);
  });
  constexpr float kBeforeTheHandles = 1.0f;  // the widget listens at 0.5
  for (const unsigned long event :
       {vtkCommand::LeftButtonPressEvent, vtkCommand::MiddleButtonPressEvent,
        vtkCommand::RightButtonPressEvent})
    press_observers_.push_back(interactor->AddObserver(event, on_press, kBeforeTheHandles));

  vtkNew<vtkCallbackCommand> on_end;
  on_end->SetClientData(this);
  on_end->SetCallback([](vtkObject*, unsigned long, void* client, void*) {
    auto* self = static_cast<BoxHandles*>(client);
    // The handles take every press on the box (the selected box, which lies
    // over the map being picked or measured): a left click that neither
    // dragged nor changed the box is the view's click, as it is beside the
    // box (the same 3 pixels of slack; other buttons never pick).
    const int* position = self->interactor_->GetEventPosition();
    vtkNew<vtkTransform> now;
    self->representation_->GetTransform(now);
    bool unchanged = true;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        unchanged = unchanged && now->GetMatrix()->GetElement(r, c) ==
                                     self->transform_at_press_->GetMatrix()->GetElement(r, c);
    if (self->left_press_ && unchanged &&
        std::abs(position[0] - self->press_[0]) + std::abs(position[1] - self->press_[1]) <= 3 &&
        self->clicked_) {
      self->clicked_(position[0], position[1]);
      return;
    }
    vtkNew<vtkTransform> transform;
    self->representation_->GetTransform(transform);
    vtkMatrix4x4* m = transform->GetMatrix();
    Eigen::Matrix3d linear;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) linear(r, c) = m->GetElement(r, c);
    OrientedBox box;
    box.center = Eigen::Vector3d(m->GetElement(0, 3), m->GetElement(1, 3), m->GetElement(2, 3));
    for (int c = 0; c < 3; ++c) {
      box.size[c] = std::max(1e-4, linear.col(c).norm());
      linear.col(c) /= box.size[c];
    }
    // Orthonormalise what the widget left (it only scales along box axes).
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(linear, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d rotation = svd.matrixU() * svd.matrixV().transpose();
    if (rotation.determinant() < 0) rotation.col(2) *= -1.0;
    box.rotation = Eigen::Quaterniond(rotation).normalized();
    if (self->edited_) self->edited_(box);
  });
  widget_->AddObserver(vtkCommand::EndInteractionEvent, on_end);
}

void BoxHandles::show(const OrientedBox* box) {
  visible_ = box != nullptr;
  if (!box) {
    widget_->Off();
    return;
  }
  double unit[6] = {-0.5, 0.5, -0.5, 0.5, -0.5, 0.5};
  representation_->PlaceWidget(unit);
  vtkNew<vtkTransform> transform;
  transform->PostMultiply();
  transform->Scale(box->size.x(), box->size.y(), box->size.z());
  const Eigen::AngleAxisd angle_axis(box->rotation);
  transform->RotateWXYZ(angle_axis.angle() * 180.0 / EIGEN_PI, angle_axis.axis().data());
  transform->Translate(box->center.data());
  representation_->SetTransform(transform);
  widget_->On();
}

}  // namespace lom::ui::scene
