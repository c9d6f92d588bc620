#include "scene_adapters.hpp"

#include <vtkCellArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>

#include "lom/ui/frame_labels.hpp"

namespace lom::ui::scene {

namespace {

constexpr unsigned char kUncolouredGrey = 170;

bool sameSize(int width, int height, const DepthImage& depth) {
  return width == depth.width && height == depth.height;
}

}  // namespace

vtkSmartPointer<vtkPolyData> frameCloud(const Sequence& sequence, size_t index,
                                        const FrameData& frame, const LabelImage* labels) {
  const DepthImage& depth = frame.depth;
  const CameraIntrinsics& camera = sequence.cameraOf(index);
  const Eigen::Isometry3d& T_world_camera = sequence.frames[index].T_world_camera;
  const bool use_labels = labels && sameSize(labels->width, labels->height, depth);
  const ColorImage* color = frame.color && sameSize(frame.color->width, frame.color->height, depth)
                                ? &*frame.color
                                : nullptr;

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToFloat();
  auto vertices = vtkSmartPointer<vtkCellArray>::New();
  auto colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colors->SetName("colors");
  colors->SetNumberOfComponents(3);

  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const float z = depth.at(u, v);
      if (!std::isfinite(z) || z <= 0.f) continue;
      const Eigen::Vector3d p = T_world_camera * camera.backProject(u, v, z);
      const vtkIdType id = points->InsertNextPoint(p.x(), p.y(), p.z());
      vertices->InsertNextCell(1, &id);

      const int label = use_labels ? labels->at(u, v) : 0;
      unsigned char rgb[3] = {kUncolouredGrey, kUncolouredGrey, kUncolouredGrey};
      if (label != 0) {
        const QColor c = labelColor(sequence.labels, label);
        rgb[0] = static_cast<unsigned char>(c.red());
        rgb[1] = static_cast<unsigned char>(c.green());
        rgb[2] = static_cast<unsigned char>(c.blue());
      } else if (color) {
        const std::uint8_t* pixel =
            color->rgb.data() + (static_cast<size_t>(v) * depth.width + u) * 3;
        std::copy(pixel, pixel + 3, rgb);
      }
      colors->InsertNextTypedTuple(rgb);
    }
  }

  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(points);
  cloud->SetVerts(vertices);
  cloud->GetPointData()->SetScalars(colors);
  return cloud;
}

vtkSmartPointer<vtkPolyData> frustums(const Sequence& sequence, const std::vector<size_t>& indices,
                                      double depth) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto add_line = [&](vtkIdType a, vtkIdType b) {
    const vtkIdType ends[2] = {a, b};
    lines->InsertNextCell(2, ends);
  };

  for (size_t index : indices) {
    const CameraIntrinsics& camera = sequence.cameraOf(index);
    const Eigen::Isometry3d& T = sequence.frames[index].T_world_camera;
    auto add_point = [&](const Eigen::Vector3d& p) {
      return points->InsertNextPoint(p.x(), p.y(), p.z());
    };
    auto add_pixel = [&](double u, double v) {
      return add_point(T * camera.backProject(u, v, depth));
    };
    const double w = camera.width, h = camera.height;
    const vtkIdType centre = add_point(T.translation());
    const vtkIdType corners[4] = {add_pixel(0, 0), add_pixel(w, 0), add_pixel(w, h),
                                  add_pixel(0, h)};
    for (int i = 0; i < 4; ++i) {
      add_line(centre, corners[i]);
      add_line(corners[i], corners[(i + 1) % 4]);
    }
    // Marks which way is up in the image, so mirrored or rolled poses show.
    const vtkIdType top[3] = {add_pixel(0.35 * w, 0), add_pixel(0.5 * w, -0.15 * h),
                              add_pixel(0.65 * w, 0)};
    add_line(top[0], top[1]);
    add_line(top[1], top[2]);
  }

  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  return poly;
}

double frustumDepth(const Sequence& sequence) {
  // Never smaller than a typical RGB-D near range allows, so the frustums of
  // a short trajectory still read as cameras.
  constexpr double kSmallest = 0.1;
  if (sequence.frames.size() < 2) return kSmallest;
  Eigen::Vector3d low = sequence.frames.front().T_world_camera.translation();
  Eigen::Vector3d high = low;
  for (const auto& frame : sequence.frames) {
    low = low.cwiseMin(frame.T_world_camera.translation());
    high = high.cwiseMax(frame.T_world_camera.translation());
  }
  return std::clamp(0.15 * (high - low).norm(), kSmallest, 0.5);
}

Viewpoint viewpointOf(const Sequence& sequence, size_t index) {
  const Eigen::Isometry3d& T = sequence.frames[index].T_world_camera;
  return {T.translation(), T.linear() * Eigen::Vector3d::UnitZ(),
          T.linear() * -Eigen::Vector3d::UnitY()};
}

}  // namespace lom::ui::scene
