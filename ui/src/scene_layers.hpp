#pragma once
// VTK layers of the 3D view beyond the frame cloud: the map's voxels, the
// ground-truth boxes and the box handles. Only scene_*.cpp include this.
#include <vtkActor.h>
#include <vtkBoxRepresentation.h>
#include <vtkBoxWidget2.h>
#include <vtkGlyph3DMapper.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkSmartPointer.h>
#include <vtkTransform.h>

#include <Eigen/Core>
#include <QColor>
#include <functional>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "lom/annotations.hpp"
#include "lom/height_colours.hpp"
#include "lom/labels.hpp"
#include "lom/ui/map_snapshot.hpp"

class vtkRenderer;
class vtkRenderWindowInteractor;

namespace lom::ui::scene {

// One cube of a VoxelLayer: centre, edge and colour (with alpha).
struct Cube {
  Eigen::Vector3d center;
  double size = 0.0;
  QColor colour;
};

// Occupied voxels as instanced cubes coloured by label or by height.
class VoxelLayer {
 public:
  VoxelLayer();
  [[nodiscard]] vtkActor* actor() { return actor_; }
  // Draws exactly these cubes; returns how many.
  size_t showCubes(const std::vector<Cube>& cubes);
  // Returns the number of voxels drawn.
  // Height colours span the drawn voxels along the snapshot's up (+z when it has none).
  size_t show(const MapSnapshot& snapshot, const LabelSet& labels, const std::set<int>& hidden,
              bool opacity_by_probability, VoxelColouring colouring = VoxelColouring::Labels);
  // The heights the ramp spans after show() coloured voxels by height (else none).
  [[nodiscard]] std::optional<std::pair<double, double>> heightRange() const {
    return height_range_;
  }

 private:
  vtkNew<vtkGlyph3DMapper> mapper_;
  vtkNew<vtkPolyData> data_;  // the one data set the mapper draws (showCubes)
  vtkNew<vtkActor> actor_;
  std::optional<std::pair<double, double>> height_range_;
};

// Wireframes of all boxes, each in its label's colour.
[[nodiscard]] vtkSmartPointer<vtkPolyData> boxOutlines(const Annotations& boxes,
                                                       const LabelSet& labels, int skip);

// Wireframes of oriented boxes, all edges in one colour per box.
[[nodiscard]] vtkSmartPointer<vtkPolyData> boxWireframes(const std::vector<OrientedBox>& boxes,
                                                         const std::vector<QColor>& colors);

// Grasp arrows: a shaft of `length` ending at each grasp position along its
// approach direction, with a four-line head; one colour per arrow.
[[nodiscard]] vtkSmartPointer<vtkPolyData> graspArrows(const std::vector<Eigen::Vector3d>& tips,
                                                       const std::vector<Eigen::Vector3d>& directions,
                                                       const std::vector<QColor>& colors, double length);

// The 3D handles of the selected box (move, rotate, resize).
class BoxHandles {
 public:
  explicit BoxHandles(vtkRenderWindowInteractor* interactor, vtkRenderer* renderer);
  ~BoxHandles();
  BoxHandles(const BoxHandles&) = delete;
  BoxHandles& operator=(const BoxHandles&) = delete;
  void show(const OrientedBox* box);  // null hides the handles
  // Called with the edited box when a drag ends.
  void onEdited(std::function<void(const OrientedBox&)> callback) { edited_ = std::move(callback); }
  // Called with the display position of a click on the box or its handles
  // that did not drag: a click the handles took from the view (a pick, a
  // measured point), not an edit.
  void onClicked(std::function<void(int, int)> callback) { clicked_ = std::move(callback); }
  [[nodiscard]] bool visible() const { return visible_; }

 private:
  vtkNew<vtkBoxWidget2> widget_;
  vtkNew<vtkBoxRepresentation> representation_;
  std::function<void(const OrientedBox&)> edited_;
  std::function<void(int, int)> clicked_;
  vtkSmartPointer<vtkRenderWindowInteractor> interactor_;
  std::vector<unsigned long> press_observers_;
  int press_[2] = {0, 0};
  bool left_press_ = false;
  vtkNew<vtkTransform> transform_at_press_;
  bool visible_ = false;
};

}  // namespace lom::ui::scene
