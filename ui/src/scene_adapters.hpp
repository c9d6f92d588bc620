#pragma once
// Core data to VTK poly data for the 3D view. Together with scene_view.cpp
// this is the only code that sees both the core types and VTK.
#include <vtkSmartPointer.h>

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "lom/sequence.hpp"

class vtkPolyData;

namespace lom::ui::scene {

// One vertex per valid depth pixel, in world coordinates, with an RGB
// "colors" array: the label colour for labelled pixels, the colour image (or
// grey) for background and unlabelled ones.
[[nodiscard]] vtkSmartPointer<vtkPolyData> frameCloud(const Sequence& sequence, size_t index,
                                                      const FrameData& frame,
                                                      const LabelImage* labels);

// Wireframe pyramids (with a small triangle marking the image's top edge) of
// the given frames, `depth` metres deep.
[[nodiscard]] vtkSmartPointer<vtkPolyData> frustums(const Sequence& sequence,
                                                    const std::vector<size_t>& indices,
                                                    double depth);

// Frustum depth that suits the extent of the camera trajectory.
[[nodiscard]] double frustumDepth(const Sequence& sequence);

// Where frame `index`'s camera is and how it looks, in world coordinates.
struct Viewpoint {
  Eigen::Vector3d position;
  Eigen::Vector3d forward;  // optical axis
  Eigen::Vector3d up;       // image up (camera -y)
};
[[nodiscard]] Viewpoint viewpointOf(const Sequence& sequence, size_t index);

}  // namespace lom::ui::scene
