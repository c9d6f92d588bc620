#pragma once
// Writing the fused map for other tools: voxel surface meshes (PLY, OBJ + MTL,
// STL), point clouds of voxel centres (PCD, PLY), octrees (OctoMap ColorOcTree
// .ot, native .ot, binary .bt) and fitted object boxes (JSON). Every file is
// written atomically. Formats and conventions: docs/export.md.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "lom/geometry.hpp"
#include "lom/label_map.hpp"
#include "lom/objects.hpp"

namespace lom {

// ---- Voxels of each label ----

// Finest-resolution keys of the occupied voxels of every label (pruned leaves
// expanded), sorted, in one pass over the tree. With `only`, other labels are
// left out. Labels without occupied voxels are absent.
[[nodiscard]] std::map<int, std::vector<VoxelKey>> occupiedVoxelsByLabel(
    const LabelMap& map, const std::optional<std::set<int>>& only = std::nullopt);

// ---- Surface meshes ----

// A closed triangle mesh of one label, in world metres. Triangles are
// counter-clockwise seen from outside (normals point out of the label).
struct SurfaceMesh {
  int label = 0;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

struct VoxelSurfaceOptions {
  // Merge coplanar unit faces into rectangles. Rectangle sides keep every
  // vertex another face needs there, so no T-junction appears and the mesh
  // stays watertight.
  bool merge_coplanar = true;
};

// The boundary of a set of finest-resolution voxels: the faces between a voxel
// of the set and one outside it, triangulated. Watertight in the strict sense:
// every edge is shared by exactly two triangles. Where voxels touch only along
// an edge or at a corner, the vertices there are duplicated (one copy per
// voxel side), so the surface stays a 2-manifold. Encloses exactly
// keys.size() * resolution^3.
[[nodiscard]] SurfaceMesh voxelSurface(const std::vector<VoxelKey>& keys, double resolution,
                                       const VoxelSurfaceOptions& options = {});

struct SmoothSurfaceOptions {
  int smoothing_iterations = 20;  // windowed sinc passes; 0 keeps the marching-cubes surface
  double pass_band = 0.1;
};

// A smooth surface of the voxel set: discrete marching cubes (VTK's flying
// edges) over the label's occupancy, then windowed sinc smoothing.
[[nodiscard]] SurfaceMesh smoothSurface(const std::vector<VoxelKey>& keys, double resolution,
                                        const SmoothSurfaceOptions& options = {});

// Writers for meshes of several labels; colours and names come from `labels`.
// PLY: binary, vertices with x y z (float), red green blue (label colour) and
// label (uint). OBJ: one object and one material per label, materials in
// `mtl_path` (the OBJ refers to it by file name). STL: binary, no colour.
// `frame` (one line, may be empty) is written as a header comment: which
// frame the coordinates are in.
void writeMeshesPly(const std::vector<SurfaceMesh>& meshes, const LabelSet& labels,
                    const std::filesystem::path& path, const std::string& frame = {});
void writeMeshesObj(const std::vector<SurfaceMesh>& meshes, const LabelSet& labels,
                    const std::filesystem::path& obj_path, const std::filesystem::path& mtl_path,
                    const std::string& frame = {});
void writeMeshesStl(const std::vector<SurfaceMesh>& meshes, const LabelSet& labels,
                    const std::filesystem::path& path);

// ---- Point clouds of voxel centres ----

// Occupied voxel centres as a binary PCD that PCL reads, with fields
// x y z (float, metres), rgb (packed float, the label's colour), label (uint32)
// and probability (float, of that label). Pruned leaves are written as their
// finest-resolution voxels so every point stands for one voxel. Atomic.
// Returns the number of points written.
size_t writeVoxelsPcd(const LabelMap& map, const std::filesystem::path& path);
// With `rotation`, every point is rotated by it about the origin (--level).
size_t writeVoxelsPcd(const LabelMap& map, const std::set<int>& labels,
                      const std::filesystem::path& path,
                      const std::optional<Eigen::Matrix3d>& rotation = std::nullopt);
// The same points as a binary PLY (PCL's writer): x y z, red green blue, label, probability.
size_t writeVoxelsPly(const LabelMap& map, const std::set<int>& labels,
                      const std::filesystem::path& path,
                      const std::optional<Eigen::Matrix3d>& rotation = std::nullopt);

// ---- Octrees ----

struct OctreeExportOptions {
  std::optional<std::set<int>> labels;  // occupied voxels of other labels are left out (unknown)
  bool include_free = true;             // also write the known free voxels
};

// An OctoMap ColorOcTree (.ot) that octovis opens: each node's colour is its
// label's colour, its log-odds the map's maximum label log-odds shifted so that
// OctoMap's default threshold 0.5 gives the map's occupancy. Returns the number
// of leaves written.
size_t writeColorOcTree(const LabelMap& map, const std::filesystem::path& path,
                        const OctreeExportOptions& options = {});
// An OctoMap OcTree in the compact binary format (.bt, occupied / free only).
// Returns the number of leaves written (after OctoMap merges the eight equal
// children of a node, which it does when writing this format).
size_t writeBinaryOcTree(const LabelMap& map, const std::filesystem::path& path,
                         const OctreeExportOptions& options = {});

// ---- Objects ----

// JSON "labeloctomap-objects" version 1 (docs/export.md) of objects found by
// lom::extractObjects (lom/objects.hpp): per object its label, voxel counts,
// centroid, mean probability and fitted oriented box.
void writeObjectsJson(const std::vector<ObjectInstance>& objects, const LabelMap& map,
                      const std::filesystem::path& path);

// ---- Everything at once (the CLI's export command) ----

enum class ExportFormat { Ply, Obj, Stl, Pcd, Ot, Bt, Objects };
[[nodiscard]] std::optional<ExportFormat> parseExportFormat(const std::string& name);
[[nodiscard]] const char* exportFormatName(ExportFormat format);

struct ExportOptions {
  ExportFormat format = ExportFormat::Ply;
  std::optional<std::set<int>> labels;  // default: every label (objects: every label but 0)
  bool per_label = false;  // meshes and point clouds: one file per label in the folder `out`
  bool smooth = false;     // meshes: smooth surfaces instead of voxel faces
  bool points = false;     // ply: voxel centres instead of a mesh
  bool native = false;     // ot: the map itself (LabelOcTree) instead of a ColorOcTree
  bool merge_coplanar = true;
  // objects: the up of a map that records no camera (ObjectOptions::cameras_up).
  std::optional<Eigen::Vector3d> cameras_up;
  // Meshes and point clouds: every vertex and point rotated by this about the
  // origin (levellingRotation: the map's up onto +z, for tools that take z as
  // up); written in the mesh headers.
  std::optional<Eigen::Matrix3d> rotation;
};

// The smallest rotation that turns the map's up (LabelMap::upDirection: its
// level plane's normal, else its cameras' mean up) onto +z; nullopt for a map
// that has no up (it records no camera).
[[nodiscard]] std::optional<Eigen::Matrix3d> levellingRotation(const LabelMap& map);

struct ExportSummary {
  std::vector<std::filesystem::path> files;  // in the order written
  size_t items = 0;                          // triangles, points, leaves or objects
  std::string item_name;                     // "triangles", "points", "leaves", "objects"
  std::vector<int> empty_labels;             // requested labels without occupied voxels
  // Per-label exports: files in the folder named as per-label files of the
  // same format (<id>_<name>.<ext>, and .mtl beside OBJ) that this export did
  // not write, from an earlier export of another map or other labels. They
  // are left as they were (they may be the user's); callers say so.
  std::vector<std::filesystem::path> earlier_files;
  // objects: what the boxes leave out of their labels' voxels (leftOutNote).
  std::vector<std::string> notes;
};

// File name stem of a label in a per-label folder: "08_creativity_chenille_stems"
// (zero-padded id, name in lower case with characters other than [a-z0-9_-] as '_',
// cut to its first 200 bytes: file names hold 255).
[[nodiscard]] std::string labelFileStem(const LabelInfo& label, int num_labels);

// Writes `map` in `options.format` to `out` (a file, or with per_label a
// folder created when missing). Throws lom::Error naming the path and the
// option for unusable requests (unknown labels, wrong extension, nothing to
// write, options that do not apply to the format).
ExportSummary exportMap(const LabelMap& map, const ExportOptions& options,
                        const std::filesystem::path& out);

}  // namespace lom
