// The meshing and mesh writing done with VTK: smooth surfaces (discrete
// flying edges + windowed sinc) and binary STL. The only core file that
// includes VTK headers.
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLWriter.h>
#include <vtkSmartPointer.h>
#include <vtkWindowedSincPolyDataFilter.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"

namespace lom {

namespace {

constexpr int kKeyOffset = 32768;

SurfaceMesh meshFromPolyData(vtkPolyData* poly) {
  SurfaceMesh mesh;
  vtkPoints* points = poly->GetPoints();
  const vtkIdType n = points ? points->GetNumberOfPoints() : 0;
  mesh.vertices.reserve(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    points->GetPoint(i, p);
    mesh.vertices.emplace_back(p[0], p[1], p[2]);
  }
  vtkCellArray* polys = poly->GetPolys();
  const auto iter = vtk::TakeSmartPointer(polys->NewIterator());
  for (iter->GoToFirstCell(); !iter->IsDoneWithTraversal(); iter->GoToNextCell()) {
    vtkIdType size;
    const vtkIdType* ids;
    iter->GetCurrentCell(size, ids);
    // Flying edges emits triangles only; fan anything else for safety.
    for (vtkIdType k = 1; k + 1 < size; ++k)
      mesh.triangles.push_back({static_cast<std::uint32_t>(ids[0]),
                                static_cast<std::uint32_t>(ids[k]),
                                static_cast<std::uint32_t>(ids[k + 1])});
  }
  return mesh;
}

double signedVolume(const SurfaceMesh& mesh) {
  double six_volume = 0.0;
  for (const auto& t : mesh.triangles)
    six_volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  return six_volume / 6.0;
}

}  // namespace

namespace {

// A smoothed part that keeps less than this share of its voxels' volume has
// collapsed (windowed sinc pulls a lone voxel's surface into its centre, a
// 2x2x2 block's to a seventh of its volume): its voxel surface is used.
constexpr double kCollapsedShare = 0.5;
// A part's grid holds one byte per voxel of its extent (plus padding), and
// marching cubes' work arrays a few more: parts spanning more are refused.
constexpr double kMaxSmoothGridCells = 512.0 * 1024 * 1024;

// The 26-connected parts of a voxel set (voxels touching at a face, an edge
// or a corner are one part), each sorted.
std::vector<std::vector<VoxelKey>> connectedParts(const std::vector<VoxelKey>& keys) {
  auto pack = [](int x, int y, int z) {
    return (static_cast<std::uint64_t>(x) << 32) | (static_cast<std::uint64_t>(y) << 16) |
           static_cast<std::uint64_t>(z);
  };
  std::unordered_map<std::uint64_t, bool> seen;  // key -> already in a part
  seen.reserve(keys.size() * 2);
  for (const VoxelKey& k : keys) seen.emplace(pack(k.x, k.y, k.z), false);
  std::vector<std::vector<VoxelKey>> parts;
  std::vector<VoxelKey> stack;
  for (const VoxelKey& first : keys) {
    bool& taken = seen[pack(first.x, first.y, first.z)];
    if (taken) continue;
    taken = true;
    std::vector<VoxelKey> part;
    stack.push_back(first);
    while (!stack.empty()) {
      const VoxelKey k = stack.back();
      stack.pop_back();
      part.push_back(k);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const int x = k.x + dx, y = k.y + dy, z = k.z + dz;
            if ((dx | dy | dz) == 0 || x < 0 || y < 0 || z < 0 || x > 65535 || y > 65535 ||
                z > 65535)
              continue;
            const auto it = seen.find(pack(x, y, z));
            if (it == seen.end() || it->second) continue;
            it->second = true;
            stack.push_back({static_cast<std::uint16_t>(x), static_cast<std::uint16_t>(y),
                             static_cast<std::uint16_t>(z)});
          }
    }
    std::sort(part.begin(), part.end());
    parts.push_back(std::move(part));
  }
  return parts;
}

// Discrete marching cubes over one part's occupancy, padded by one free
// voxel, then windowed sinc smoothing; outward normals.
SurfaceMesh smoothPart(const std::vector<VoxelKey>& keys, double resolution,
                       const SmoothSurfaceOptions& options) {
  int lo[3] = {std::numeric_limits<int>::max(), std::numeric_limits<int>::max(),
               std::numeric_limits<int>::max()};
  int hi[3] = {std::numeric_limits<int>::min(), std::numeric_limits<int>::min(),
               std::numeric_limits<int>::min()};
  for (const VoxelKey& k : keys) {
    const int c[3] = {k.x - kKeyOffset, k.y - kKeyOffset, k.z - kKeyOffset};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  }
  const long nx = hi[0] - lo[0] + 3, ny = hi[1] - lo[1] + 3, nz = hi[2] - lo[2] + 3;
  if (static_cast<double>(nx) * static_cast<double>(ny) * static_cast<double>(nz) >
      kMaxSmoothGridCells)
    throw std::length_error(std::to_string(keys.size()) + " connected voxels spanning " +
                            std::to_string(nx - 2) + " x " + std::to_string(ny - 2) + " x " +
                            std::to_string(nz - 2) + " voxels");
  // One empty voxel of padding on every side closes the surface.
  vtkNew<vtkImageData> image;
  image->SetExtent(lo[0] - 1, hi[0] + 1, lo[1] - 1, hi[1] + 1, lo[2] - 1, hi[2] + 1);
  image->SetSpacing(resolution, resolution, resolution);
  image->SetOrigin(0.5 * resolution, 0.5 * resolution,
                   0.5 * resolution);  // sample i at voxel centre i
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* values = static_cast<unsigned char*>(image->GetScalarPointer());
  std::fill(values, values + nx * ny * nz, 0);
  for (const VoxelKey& k : keys) {
    const long x = k.x - kKeyOffset - lo[0] + 1, y = k.y - kKeyOffset - lo[1] + 1,
               z = k.z - kKeyOffset - lo[2] + 1;
    values[(z * ny + y) * nx + x] = 1;
  }
  image->Modified();

  vtkNew<vtkDiscreteFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, 1.0);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  vtkSmartPointer<vtkPolyData> surface;
  if (options.smoothing_iterations > 0) {
    vtkNew<vtkWindowedSincPolyDataFilter> smoother;
    smoother->SetInputConnection(contour->GetOutputPort());
    smoother->SetNumberOfIterations(options.smoothing_iterations);
    smoother->SetPassBand(options.pass_band);
    smoother->NormalizeCoordinatesOn();
    smoother->BoundarySmoothingOff();
    smoother->FeatureEdgeSmoothingOff();
    smoother->NonManifoldSmoothingOff();
    smoother->Update();
    surface = smoother->GetOutput();
  } else {
    contour->Update();
    surface = contour->GetOutput();
  }
  SurfaceMesh mesh = meshFromPolyData(surface);
  // Outward normals, whichever way the contour filter winds its triangles.
  if (signedVolume(mesh) < 0.0)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

void append(SurfaceMesh& into, const SurfaceMesh& part) {
  const auto offset = static_cast<std::uint32_t>(into.vertices.size());
  into.vertices.insert(into.vertices.end(), part.vertices.begin(), part.vertices.end());
  for (const auto& t : part.triangles)
    into.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

}  // namespace

SurfaceMesh smoothSurface(const std::vector<VoxelKey>& keys, double resolution,
                          const SmoothSurfaceOptions& options) {
  if (!(resolution > 0.0)) throw std::invalid_argument("smoothSurface: resolution must be > 0");
  SurfaceMesh mesh;
  // Part by part: each on a grid of its own extent (one grid over the whole
  // label spanned the space between far-apart parts), and a part that
  // smoothing collapses keeps its voxel surface.
  const double voxel_volume = resolution * resolution * resolution;
  for (const std::vector<VoxelKey>& part : connectedParts(keys)) {
    SurfaceMesh smooth = smoothPart(part, resolution, options);
    if (options.smoothing_iterations > 0 &&
        signedVolume(smooth) < kCollapsedShare * static_cast<double>(part.size()) * voxel_volume)
      smooth = voxelSurface(part, resolution);
    append(mesh, smooth);
  }
  return mesh;
}

void writeMeshesStl(const std::vector<SurfaceMesh>& meshes, const LabelSet& labels,
                    const std::filesystem::path& path) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  vtkNew<vtkCellArray> triangles;
  std::string header = "labeloctomap voxel surface:";
  for (const SurfaceMesh& mesh : meshes) {
    const vtkIdType offset = points->GetNumberOfPoints();
    for (const auto& v : mesh.vertices) points->InsertNextPoint(v.x(), v.y(), v.z());
    for (const auto& t : mesh.triangles) {
      const vtkIdType ids[3] = {offset + t[0], offset + t[1], offset + t[2]};
      triangles->InsertNextCell(3, ids);
    }
    header += " " + (labels.contains(mesh.label) ? singleLineText(labels.at(mesh.label).name)
                                                 : std::to_string(mesh.label));
  }
  if (triangles->GetNumberOfCells() == 0)
    throw Error(path.string(), "mesh", "at least one triangle to write", "an empty surface");
  // Binary STL headers are 80 bytes and must not start with "solid".
  if (header.size() > 79) header = header.substr(0, 76) + "...";
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(triangles);
  writePathAtomically(path, [&](const std::filesystem::path& temporary) {
    vtkNew<vtkSTLWriter> writer;
    writer->SetInputData(poly);
    writer->SetFileName(temporary.string().c_str());
    writer->SetFileTypeToBinary();
    writer->SetHeader(header.c_str());
    // VTK prints its own (coloured) error line; the Error below says it instead.
    const bool warnings = vtkObject::GetGlobalWarningDisplay();
    vtkObject::GlobalWarningDisplayOff();
    const bool written = writer->Write() == 1 && writer->GetErrorCode() == 0;
    vtkObject::SetGlobalWarningDisplay(warnings);
    if (!written)
      throw Error(path.string(), "output", "a writable STL file",
                  libraryWriteFailure(temporary, "VTK"));
  });
}

}  // namespace lom
