#include "lom/render/map_render.hpp"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPerspectiveTransform.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "lom/box_fit.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"
#include "lom/score_breakdown.hpp"
#include "lom/sequence.hpp"

namespace lom::render {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The centre of the unit square a triangle of an unmerged voxel surface is half
// of: the middle of its longest side (the square's diagonal).
Eigen::Vector3d faceCentre(const SurfaceMesh& mesh, const std::array<std::uint32_t, 3>& t) {
  const Eigen::Vector3d& a = mesh.vertices[t[0]];
  const Eigen::Vector3d& b = mesh.vertices[t[1]];
  const Eigen::Vector3d& c = mesh.vertices[t[2]];
  const double ab = (a - b).squaredNorm(), bc = (b - c).squaredNorm(), ca = (c - a).squaredNorm();
  if (ab >= bc && ab >= ca) return 0.5 * (a + b);
  return bc >= ca ? 0.5 * (b + c) : 0.5 * (c + a);
}

// Colours of a label's unit faces by the share of each face's voxel inside
// the label's box (the face's outward normal points away from its voxel);
// grey for a label without a box.
std::vector<Rgb> scoreColours(const SurfaceMesh& mesh, double resolution,
                              const ScoreColours& score) {
  const auto box = std::find_if(score.boxes.begin(), score.boxes.end(),
                                [&](const GroundTruthBox& b) { return b.label == mesh.label; });
  if (box == score.boxes.end()) {
    const Rgb grey = mesh.label == 0 ? kShadedBackgroundColour : Rgb{195, 195, 200};
    return std::vector<Rgb>(mesh.triangles.size(), grey);
  }
  std::vector<Eigen::Vector3d> voxels;
  voxels.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d normal =
        (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).normalized();
    const Eigen::Vector3d inside = faceCentre(mesh, t) - 0.5 * resolution * normal;
    // Snapped onto the voxel centres (voxelCenter's arithmetic).
    voxels.push_back(((inside / resolution).array().floor() + 0.5).matrix() * resolution);
  }
  std::vector<Rgb> colours;
  colours.reserve(voxels.size());
  for (const double share : voxelSharesInBox(voxels, resolution, box->box, score.mode))
    colours.push_back(scoreShareColour(share));
  return colours;
}

// The voxel surfaces of the selected labels, coloured per triangle: by label,
// by the height of the triangle's centre or by its voxel's share inside its
// label's box (unit faces, so that colours change from one voxel to the next).
using KeysByLabel = std::map<int, std::vector<VoxelKey>>;

vtkSmartPointer<vtkPolyData> labelSurfaces(const LabelMap& map, const KeysByLabel& selected,
                                           const RenderOptions& options, VoxelColouring colouring) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto triangles = vtkSmartPointer<vtkCellArray>::New();
  auto colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colors->SetNumberOfComponents(3);
  colors->SetName("voxel colour");
  const bool by_height = colouring == VoxelColouring::Height;
  std::vector<SurfaceMesh> meshes;
  for (const auto& [label, keys] : selected) {
    VoxelSurfaceOptions surface;
    surface.merge_coplanar = !by_height && !options.score;
    meshes.push_back(voxelSurface(keys, map.parameters().resolution, surface));
    meshes.back().label = label;
  }
  std::vector<Eigen::Vector3d> all_vertices;
  if (by_height)
    for (const SurfaceMesh& mesh : meshes)
      all_vertices.insert(all_vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
  const HeightColours heights = HeightColours::spanning(all_vertices, orbitUp(map, options));
  for (const SurfaceMesh& mesh : meshes) {
    // Shaded, as the studio draws it (the background grey, black labels dark
    // grey: black would hide all shading); flat, exactly the label's colour.
    Rgb color = options.shading ? shadedLabelColour(map.labels(), mesh.label)
                                : map.labels().at(mesh.label).color;
    const vtkIdType offset = points->GetNumberOfPoints();
    for (const auto& v : mesh.vertices) points->InsertNextPoint(v.x(), v.y(), v.z());
    const std::vector<Rgb> by_score =
        options.score ? scoreColours(mesh, map.parameters().resolution, *options.score)
                      : std::vector<Rgb>();
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
      const auto& t = mesh.triangles[i];
      const vtkIdType ids[3] = {offset + t[0], offset + t[1], offset + t[2]};
      triangles->InsertNextCell(3, ids);
      if (options.score)
        color = by_score[i];
      else if (by_height)
        color = heights.colour(faceCentre(mesh, t));
      colors->InsertNextTypedTuple(color.data());
    }
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(triangles);
  poly->GetCellData()->SetScalars(colors);
  return poly;
}

// VTK camera equal to a pinhole camera seeing a width x height image.
void placePinhole(vtkCamera* camera, const PinholeView& view, int width, int height) {
  const CameraIntrinsics& k = view.intrinsics;
  const double sx = static_cast<double>(width) / k.width;
  const double sy = static_cast<double>(height) / k.height;
  const double fx = k.fx * sx;
  const double fy = k.fy * sy;
  // Pixel centres sit at integer coordinates: the image spans [-0.5, size - 0.5].
  const double cx = (k.cx + 0.5) * sx;
  const double cy = (k.cy + 0.5) * sy;
  const Eigen::Vector3d origin = view.T_world_camera.translation();
  const Eigen::Matrix3d R = view.T_world_camera.linear();
  const Eigen::Vector3d forward = R.col(2), down = R.col(1);
  camera->SetPosition(origin.data());
  const Eigen::Vector3d focal = origin + forward;
  camera->SetFocalPoint(focal.data());
  camera->SetViewUp(-down.x(), -down.y(), -down.z());
  // The view angle gives both axes fy: x is then scaled by fx / fy after the
  // projection (the user transform acts on normalised viewport coordinates),
  // so that a point lands at u = fx X / Z + cx, v = fy Y / Z + cy.
  camera->SetViewAngle(2.0 * std::atan(0.5 * height / fy) * 180.0 / kPi);
  const double x_scale = fx / fy;
  vtkNew<vtkPerspectiveTransform> stretch;
  stretch->Scale(x_scale, 1.0, 1.0);
  camera->SetUserTransform(stretch.Get());
  // The optical axis lands at normalised viewport coordinates -WindowCenter
  // (x before the stretch, which scales it too).
  camera->SetWindowCenter((1.0 - 2.0 * cx / width) / x_scale, 2.0 * cy / height - 1.0);
}

// The centres of the framed voxels (their cubes reach half an edge further).
std::vector<Eigen::Vector3d> framedCentres(const std::vector<VoxelKey>& keys, double resolution) {
  std::vector<Eigen::Vector3d> centres;
  centres.reserve(keys.size());
  for (const VoxelKey& key : keys) centres.push_back(voxelCenter(key, resolution));
  return centres;
}

// The orbit camera: looking along azimuth and elevation at the centre of the
// bounds of the cubes of edge `edge` about `centres`, from far enough that
// every corner is in front of it and in view; then the picture is narrowed
// and shifted (view angle and window centre, as a pinhole camera's principal
// point) onto what the cubes cover, with a 5 % margin, so that the map fills
// it whatever its shape.
void placeOrbit(vtkCamera* camera, const std::vector<Eigen::Vector3d>& centres, double edge,
                double azimuth_deg, double elevation_deg, const Eigen::Vector3d& up,
                double aspect) {
  Eigen::Vector3d lo = centres.front(), hi = centres.front();
  for (const Eigen::Vector3d& c : centres) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  // Every cube's corners, one at a time (a large map holds millions of cubes).
  const double half = 0.5 * edge;
  const auto forEachCorner = [&](const auto& visit) {
    for (const Eigen::Vector3d& c : centres)
      for (int corner = 0; corner < 8; ++corner)
        visit(Eigen::Vector3d(c.x() + (corner & 1 ? half : -half),
                              c.y() + (corner & 2 ? half : -half),
                              c.z() + (corner & 4 ? half : -half)) -
              centre);
  };
  const double view_angle = 30.0;
  const double az = azimuth_deg * kPi / 180.0, el = elevation_deg * kPi / 180.0;
  // Azimuth 0 lies along world x laid flat across up (z when x is nearly up).
  Eigen::Vector3d front = Eigen::Vector3d::UnitX() - up.x() * up;
  if (front.norm() < 0.1) front = Eigen::Vector3d::UnitZ() - up.z() * up;
  front.normalize();
  const Eigen::Vector3d side = up.cross(front);
  const Eigen::Vector3d direction =
      std::cos(el) * (std::cos(az) * front + std::sin(az) * side) + std::sin(el) * up;
  // Straight down or up: "up" in the picture is the direction across up away from the camera.
  Eigen::Vector3d view_up = up;
  if (std::abs(std::cos(el)) < 1e-6)
    view_up = -std::sin(el) * (std::cos(az) * front + std::sin(az) * side);
  // The picture's axes: `direction` points from the centre to the eye.
  const Eigen::Vector3d picture_up = (view_up - view_up.dot(direction) * direction).normalized();
  const Eigen::Vector3d picture_right = picture_up.cross(direction);
  const double tan_vertical = std::tan(0.5 * view_angle * kPi / 180.0);
  const double tan_horizontal = tan_vertical * aspect;
  // Far enough for every corner to be within the 30 degree view.
  double distance = 1e-3;
  forEachCorner([&](const Eigen::Vector3d& p) {
    const double towards_eye = p.dot(direction);
    distance = std::max({distance, towards_eye + std::abs(p.dot(picture_up)) / tan_vertical,
                         towards_eye + std::abs(p.dot(picture_right)) / tan_horizontal});
  });
  distance *= 1.05;
  // Where the corners land from there, in normalised picture coordinates
  // (-1 to 1 across the view): the picture is fitted to that.
  const double inf = std::numeric_limits<double>::infinity();
  double x_lo = inf, x_hi = -inf, y_lo = inf, y_hi = -inf;
  forEachCorner([&](const Eigen::Vector3d& p) {
    const double depth = distance - p.dot(direction);
    const double x = p.dot(picture_right) / (depth * tan_horizontal);
    const double y = p.dot(picture_up) / (depth * tan_vertical);
    x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x);
    y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
  });
  const double scale = std::max(1e-3, 1.05 * 0.5 * std::max(x_hi - x_lo, y_hi - y_lo));
  const Eigen::Vector3d eye = centre + distance * direction;
  camera->SetFocalPoint(centre.data());
  camera->SetPosition(eye.data());
  camera->SetViewUp(view_up.data());
  camera->SetViewAngle(2.0 * std::atan(scale * tan_vertical) * 180.0 / kPi);
  camera->SetWindowCenter(0.5 * (x_lo + x_hi) / scale, 0.5 * (y_lo + y_hi) / scale);
}

}  // namespace

namespace {

OrbitFraming framingOf(const KeysByLabel& selected, bool frame_all) {
  OrbitFraming framing;
  for (const auto& [label, keys] : selected)
    framing.framed.insert(framing.framed.end(), keys.begin(), keys.end());
  std::sort(framing.framed.begin(), framing.framed.end());
  framing.selected_voxels = framing.framed.size();
  if (frame_all) return framing;
  framing.framed = bulkVoxels(framing.framed, kFramedPartVoxels);
  return framing;
}

}  // namespace

OrbitFraming orbitFraming(const LabelMap& map, const RenderOptions& options) {
  return framingOf(occupiedVoxelsByLabel(map, options.labels), options.frame_all);
}

Eigen::Vector3d orbitUp(const LabelMap& map, const RenderOptions& options) {
  if (options.up) {
    const double length = options.up->norm();
    if (!std::isfinite(length) || length < 1e-9)
      throw Error("", "up", "a finite, non-zero direction",
                  "(" + std::to_string(options.up->x()) + ", " + std::to_string(options.up->y()) +
                      ", " + std::to_string(options.up->z()) + ")");
    return *options.up / length;
  }
  return map.upDirection().value_or(Eigen::Vector3d::UnitZ());
}

VoxelColouring colouringFor(const LabelMap& map, const RenderOptions& options) {
  if (options.colouring) return *options.colouring;
  return map.numLabels() == 1 ? VoxelColouring::Height : VoxelColouring::Labels;
}

ColorImage renderMap(const LabelMap& map, const RenderOptions& options, OrbitFraming* framing) {
  if (options.width <= 0 || options.height <= 0 || options.width > kMaxRenderSide ||
      options.height > kMaxRenderSide ||
      static_cast<long long>(options.width) * options.height > kMaxRenderPixels)
    throw Error("", "size",
                "a picture size from 1x1 to 16384x16384 of at most 134217728 pixels (16384x8192)",
                std::to_string(options.width) + "x" + std::to_string(options.height));
  if (const auto problem = displayProblem()) throw RenderUnavailable(*problem);
  // One pass over the map for the surfaces and the framing.
  const KeysByLabel selected = occupiedVoxelsByLabel(map, options.labels);
  const vtkSmartPointer<vtkPolyData> surfaces =
      labelSurfaces(map, selected, options, colouringFor(map, options));
  if (surfaces->GetNumberOfPolys() == 0)
    throw Error("", "map", "at least one occupied voxel to render",
                options.labels ? "no occupied voxel of the selected labels" : "an empty map");

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(surfaces);
  mapper->SetScalarModeToUseCellData();
  mapper->SetColorModeToDirectScalars();
  mapper->ScalarVisibilityOn();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetInterpolationToFlat();
  if (options.shading) {
    actor->GetProperty()->SetAmbient(0.35);
    actor->GetProperty()->SetDiffuse(0.65);
    actor->GetProperty()->SetSpecular(0.0);
  } else {
    actor->GetProperty()->LightingOff();
  }

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->SetBackground(options.background[0] / 255.0, options.background[1] / 255.0,
                          options.background[2] / 255.0);
  vtkCamera* camera = renderer->GetActiveCamera();
  if (options.camera) {
    placePinhole(camera, *options.camera, options.width, options.height);
  } else {
    OrbitFraming framed = framingOf(selected, options.frame_all);
    placeOrbit(camera, framedCentres(framed.framed, map.parameters().resolution),
               map.parameters().resolution, options.azimuth_deg, options.elevation_deg,
               orbitUp(map, options), static_cast<double>(options.width) / options.height);
    if (framing) *framing = std::move(framed);
  }
  renderer->ResetCameraClippingRange();

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(options.shading ? 4 : 0);
  window->SetSize(options.width, options.height);
  window->AddRenderer(renderer);
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* image = grab->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] != options.width || dims[1] != options.height ||
      image->GetNumberOfScalarComponents() != 3)
    throw RenderUnavailable("render: the X server returned a " + std::to_string(dims[0]) + "x" +
                            std::to_string(dims[1]) + " picture instead of " +
                            std::to_string(options.width) + "x" + std::to_string(options.height));
  ColorImage out;
  out.width = dims[0];
  out.height = dims[1];
  out.rgb.resize(static_cast<size_t>(out.width) * out.height * 3);
  const auto* pixels = static_cast<const unsigned char*>(image->GetScalarPointer());
  const size_t row = static_cast<size_t>(out.width) * 3;
  // VTK's rows go bottom-up, image rows top-down.
  for (int y = 0; y < out.height; ++y)
    std::memcpy(out.rgb.data() + static_cast<size_t>(y) * row,
                pixels + static_cast<size_t>(out.height - 1 - y) * row, row);
  // A picture black all over, where neither the background nor any voxel can
  // be black, was not drawn (a driver that cannot render this size reads back
  // zeros).
  bool black_possible = options.background == Rgb{0, 0, 0};
  if (!options.shading && colouringFor(map, options) == VoxelColouring::Labels && !options.score)
    for (int label = 0; label < map.numLabels(); ++label)
      black_possible |= map.labels().at(label).color == Rgb{0, 0, 0};
  if (!black_possible &&
      std::all_of(out.rgb.begin(), out.rgb.end(), [](unsigned char c) { return c == 0; })) {
    window->Finalize();
    throw Error("", "size", "a picture the graphics driver can draw",
                "an all-black " + std::to_string(out.width) + "x" + std::to_string(out.height) +
                    " picture read back (nothing was drawn, not even the background); "
                    "try a smaller size");
  }
  // A recorded camera of another sequence, or one facing away, sees nothing:
  // a blank picture with a success would look like an empty map. Told by
  // the depth buffer (a voxel drawn in the background colour still counts).
  if (options.camera) {
    vtkNew<vtkFloatArray> depth;
    window->GetZbufferData(0, 0, options.width - 1, options.height - 1, depth);
    bool blank = true;
    for (vtkIdType i = 0; i < depth->GetNumberOfValues() && blank; ++i)
      blank = depth->GetValue(i) >= 1.0f;
    if (blank) {
      window->Finalize();
      // Only the selected labels are drawn: the map may be in view without them.
      throw Error("", "--camera",
                  options.labels ? "a camera that sees part of the selected labels (--labels)"
                                 : "a camera that sees part of the map",
                  options.labels
                      ? "no voxel of the selected labels in its view (they lie out of its "
                        "picture, behind it, or the camera looks away from them)"
                      : "no voxel of the map in its view (the camera looks away from the map, or "
                        "the map lies behind it or out of its picture)");
    }
  }
  window->Finalize();
  return out;
}

void renderMapToPng(const LabelMap& map, const RenderOptions& options,
                    const std::filesystem::path& png, OrbitFraming* framing) {
  const ColorImage image = renderMap(map, options, framing);
  writeColorPng(png, image);
}

}  // namespace lom::render
