// exportMap: one entry point for every export format (the CLI's `export`).

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <sstream>
#include <stdexcept>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"

namespace lom {

namespace fs = std::filesystem;

namespace {

struct FormatInfo {
  ExportFormat format;
  const char* name;
  const char* extension;
};

constexpr FormatInfo kFormats[] = {
    {ExportFormat::Ply, "ply", ".ply"},
    {ExportFormat::Obj, "obj", ".obj"},
    {ExportFormat::Stl, "stl", ".stl"},
    {ExportFormat::Pcd, "pcd", ".pcd"},
    {ExportFormat::Ot, "ot", ".ot"},
    {ExportFormat::Bt, "bt", ".bt"},
    {ExportFormat::Objects, "objects", ".json"},
};

const FormatInfo& infoOf(ExportFormat format) {
  for (const auto& info : kFormats)
    if (info.format == format) return info;
  return kFormats[0];
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool isMesh(const ExportOptions& o) {
  return o.format == ExportFormat::Obj || o.format == ExportFormat::Stl ||
         (o.format == ExportFormat::Ply && !o.points);
}

bool isPointCloud(const ExportOptions& o) {
  return o.format == ExportFormat::Pcd || (o.format == ExportFormat::Ply && o.points);
}

void checkOptions(const LabelMap& map, const ExportOptions& o, const fs::path& out) {
  const std::string file = out.string();
  const std::string format = exportFormatName(o.format);
  if (o.labels) {
    if (o.labels->empty()) throw Error(file, "labels", "at least one label id", "an empty list");
    for (const int label : *o.labels)
      if (!map.labels().contains(label))
        throw Error(file, "labels",
                    "label ids of the map, 0 to " + std::to_string(map.numLabels() - 1),
                    std::to_string(label));
  }
  if (o.smooth && !isMesh(o))
    throw Error(file, "smooth", "a mesh format (ply, obj, stl)", "format " + format);
  if (o.per_label && !isMesh(o) && !isPointCloud(o))
    throw Error(file, "per-label", "a mesh or point cloud format (ply, obj, stl, pcd)",
                "format " + format);
  if (o.points && o.format != ExportFormat::Ply)
    throw Error(file, "points", "format ply (pcd is always points)", "format " + format);
  if (o.native && o.format != ExportFormat::Ot)
    throw Error(file, "native", "format ot", "format " + format);
  if (o.native && o.labels)
    throw Error(file, "labels", "no label selection with the native map (it keeps every label)",
                "a label list");
  if (o.rotation && !isMesh(o) && !isPointCloud(o))
    throw Error(file, "level", "a mesh or point cloud format (ply, obj, stl, pcd)",
                "format " + format);
  if (!o.merge_coplanar && (!isMesh(o) || o.smooth))
    throw Error(file, "no-merge",
                "the voxel meshes of formats ply, obj and stl (without smoothing)",
                o.smooth ? "a smooth surface" : "format " + format);
  if (o.per_label) {
    std::error_code ec;
    if (fs::exists(out, ec) && !fs::is_directory(out, ec))
      throw Error(file, "output path", "a folder for the per-label files", "an existing file");
    return;
  }
  const std::string extension = infoOf(o.format).extension;
  if (lower(out.extension().string()) != extension)
    throw Error(file, "output path", "a file name ending in " + extension + " for format " + format,
                out.extension().empty() ? "no extension" : "'" + out.extension().string() + "'");
}

std::set<int> selectedLabels(const LabelMap& map, const ExportOptions& o) {
  if (o.labels) return *o.labels;
  std::set<int> all;
  // Objects are the things on the background: label 0 only when asked for.
  for (int label = o.format == ExportFormat::Objects ? 1 : 0; label < map.numLabels(); ++label)
    all.insert(label);
  return all;
}

// The header line that says which frame a mesh's coordinates are in.
std::string frameComment(const LabelMap& map, const std::optional<Eigen::Matrix3d>& rotation) {
  std::ostringstream text;
  text.precision(9);
  if (rotation) {
    const Eigen::Matrix3d& r = *rotation;
    text << "frame: levelled, the map's world rotated about its origin by R = [" << r(0, 0) << " "
         << r(0, 1) << " " << r(0, 2) << "; " << r(1, 0) << " " << r(1, 1) << " " << r(1, 2) << "; "
         << r(2, 0) << " " << r(2, 1) << " " << r(2, 2) << "] (x' = R x), so that its up is +z";
  } else if (const auto up = map.upDirection()) {
    text << "frame: the map's world (the sequence's poses), metres; its up is (" << up->x() << " "
         << up->y() << " " << up->z() << ")";
  } else {
    text << "frame: the map's world (the sequence's poses), metres";
  }
  return text.str();
}

void writeMeshes(const std::vector<SurfaceMesh>& meshes, const LabelMap& map, ExportFormat format,
                 const fs::path& path, std::vector<fs::path>& files, const std::string& frame) {
  switch (format) {
    case ExportFormat::Ply:
      writeMeshesPly(meshes, map.labels(), path, frame);
      break;
    case ExportFormat::Stl:
      writeMeshesStl(meshes, map.labels(), path);
      break;
    default: {
      fs::path mtl = path;
      mtl.replace_extension(".mtl");
      writeMeshesObj(meshes, map.labels(), path, mtl, frame);
      files.push_back(mtl);
      break;
    }
  }
  files.push_back(path);
}

// Per-label files are written into a hidden folder inside the output folder
// and moved into place only once every one of them is complete, so that a
// failure (a full disk) never leaves new files of some labels beside old
// files of others. The folder is removed in any case, and so are the output
// folder and its parents that were created for the export when it fails.
class StagingFolder {
 public:
  explicit StagingFolder(const fs::path& out) : out_(out), created_(out) {
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec)
      throw Error(out.string(), "output path", "a folder for the per-label files",
                  "a folder that cannot be created: " + ec.message());
    path_ = createStagingFolder(out, "export", pending_);
  }
  StagingFolder(const StagingFolder&) = delete;
  StagingFolder& operator=(const StagingFolder&) = delete;
  ~StagingFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }

  [[nodiscard]] const fs::path& path() const { return path_; }

  // Runs `write` (which writes into path()); an error naming a staged file
  // names the file it stands for in the output folder instead, since the
  // staging folder is gone once the error is read.
  template <class Write>
  void write(const Write& write) {
    try {
      write();
    } catch (const Error& e) {
      Problem problem = e.problem();
      const fs::path file(problem.file);
      if (file.parent_path() == path_) problem.file = (out_ / file.filename()).string();
      throw Error(problem);
    }
  }

  // Moves the staged files into the output folder; returns their new paths.
  std::vector<fs::path> publish(const std::vector<fs::path>& staged) {
    created_.keep();
    std::vector<fs::path> published;
    for (const fs::path& file : staged) {
      const fs::path target = out_ / file.filename();
      std::error_code ec;
      fs::rename(file, target, ec);
      if (ec)
        throw Error(target.string(), "output", "a writable location",
                    "rename failed: " + ec.message());
      published.push_back(target);
    }
    return published;
  }

 private:
  fs::path out_;
  NewFolders created_;  // taken away again unless the files are published
  fs::path path_;
  PendingOutput pending_;  // path_, for a signal to remove
};

// The files of `folder` named like per-label files with `extension` (or an
// OBJ's .mtl) that are not among `written`, sorted.
std::vector<fs::path> earlierPerLabelFiles(const fs::path& folder,
                                           const std::vector<fs::path>& written,
                                           const std::string& extension, bool with_mtl) {
  const auto perLabelName = [&](const fs::path& file) {
    const std::string ext = lower(file.extension().string());
    if (ext != extension && !(with_mtl && ext == ".mtl")) return false;
    const std::string stem = file.stem().string();
    const size_t underscore = stem.find('_');
    if (underscore == std::string::npos || underscore < 2 || underscore + 1 == stem.size())
      return false;
    for (size_t i = 0; i < stem.size(); ++i) {
      const char c = stem[i];
      const bool ok = i < underscore ? std::isdigit(static_cast<unsigned char>(c)) != 0
                                     : (c >= 'a' && c <= 'z') ||
                                           std::isdigit(static_cast<unsigned char>(c)) != 0 ||
                                           c == '_' || c == '-';
      if (!ok) return false;
    }
    return true;
  };
  std::vector<fs::path> earlier;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& file = it->path();
    if (!it->is_regular_file(ec) || !perLabelName(file.filename())) continue;
    if (std::find(written.begin(), written.end(), file) == written.end()) earlier.push_back(file);
  }
  std::sort(earlier.begin(), earlier.end());
  return earlier;
}

}  // namespace

std::optional<Eigen::Matrix3d> levellingRotation(const LabelMap& map) {
  const std::optional<Eigen::Vector3d> up = map.upDirection();
  if (!up || !up->allFinite() || !(up->norm() > 0.0)) return std::nullopt;
  return Eigen::Quaterniond::FromTwoVectors(up->normalized(), Eigen::Vector3d::UnitZ())
      .toRotationMatrix();
}

std::optional<ExportFormat> parseExportFormat(const std::string& name) {
  for (const auto& info : kFormats)
    if (lower(name) == info.name) return info.format;
  return std::nullopt;
}

const char* exportFormatName(ExportFormat format) { return infoOf(format).name; }

std::string labelFileStem(const LabelInfo& label, int num_labels) {
  const size_t width = std::max<size_t>(2, std::to_string(std::max(num_labels - 1, 0)).size());
  std::string id = std::to_string(label.id);
  if (id.size() < width) id.insert(0, width - id.size(), '0');
  std::string name;
  for (const unsigned char c : label.name) {
    const char l = static_cast<char>(std::tolower(c));
    name += (std::isalnum(c) || l == '_' || l == '-') ? l : '_';
  }
  // A file name holds at most 255 bytes, and the temporary file written
  // beside it adds a prefix and a suffix: names of up to 255 bytes (which
  // labels may have) are cut to 200 (the id keeps stems apart).
  constexpr size_t kMaxNameBytes = 200;
  if (name.size() > kMaxNameBytes) name.resize(kMaxNameBytes);
  return name.empty() ? id : id + "_" + name;
}

ExportSummary exportMap(const LabelMap& map, const ExportOptions& options, const fs::path& out) {
  checkOptions(map, options, out);
  ExportSummary summary;
  const std::string file = out.string();

  if (options.format == ExportFormat::Ot && options.native) {
    map.save(out);
    summary.files.push_back(out);
    summary.items = map.numLeaves();
    summary.item_name = "leaves";
    return summary;
  }

  const std::set<int> selected = selectedLabels(map, options);
  if (options.format == ExportFormat::Ot || options.format == ExportFormat::Bt) {
    // A label selection keeps the free space, but needs occupied voxels of
    // its labels, as every other format does.
    if (options.labels) {
      const auto counts = map.occupiedCountPerLabel();
      for (const int label : *options.labels)
        if (!counts.count(label)) summary.empty_labels.push_back(label);
      if (summary.empty_labels.size() == options.labels->size())
        throw Error(file, "map", "at least one occupied voxel to export",
                    "no occupied voxel of the selected labels");
    }
    OctreeExportOptions octree;
    octree.labels = options.labels;
    summary.items = options.format == ExportFormat::Ot ? writeColorOcTree(map, out, octree)
                                                       : writeBinaryOcTree(map, out, octree);
    summary.item_name = "leaves";
    summary.files.push_back(out);
    return summary;
  }

  std::map<int, std::vector<VoxelKey>> voxels;
  try {
    voxels = occupiedVoxelsByLabel(map, selected);
  } catch (const Error& e) {
    Problem problem = e.problem();
    if (problem.file.empty()) problem.file = file;
    throw Error(problem);
  }
  if (options.labels)
    for (const int label : *options.labels)
      if (!voxels.count(label)) summary.empty_labels.push_back(label);
  if (voxels.empty()) {
    std::string found =
        options.labels ? "no occupied voxel of the selected labels" : "no occupied voxel";
    // Objects leave out the background: say so when only background is occupied.
    if (!options.labels && options.format == ExportFormat::Objects &&
        map.occupiedCountPerLabel().count(0))
      found =
          "no occupied voxel of a label other than the background (label 0); objects leave "
          "out the background unless --labels names it";
    throw Error(file, "map", "at least one occupied voxel to export", found);
  }

  if (options.format == ExportFormat::Objects) {
    ObjectOptions object_options;
    object_options.labels = std::vector<int>(selected.begin(), selected.end());
    object_options.map_file = file;
    object_options.min_cluster_voxels = 1;  // every label with occupied voxels has an entry
    object_options.cameras_up = options.cameras_up;
    const auto objects = extractObjects(map, object_options);
    for (const ObjectInstance& object : objects)
      if (std::string note = leftOutNote(object); !note.empty())
        summary.notes.push_back(std::move(note));
    writeObjectsJson(objects, map, out);
    summary.files.push_back(out);
    summary.items = objects.size();
    summary.item_name = "objects";
    return summary;
  }

  std::optional<StagingFolder> staging;
  if (options.per_label) staging.emplace(out);
  const auto publish = [&] {
    summary.files = staging->publish(summary.files);
    summary.earlier_files = earlierPerLabelFiles(
        out, summary.files, infoOf(options.format).extension, options.format == ExportFormat::Obj);
  };
  const auto pathFor = [&](int label) {
    return staging->path() / (labelFileStem(map.labels().at(label), map.numLabels()) +
                              infoOf(options.format).extension);
  };

  if (isPointCloud(options)) {
    summary.item_name = "points";
    const auto write = [&](const std::set<int>& labels, const fs::path& path) {
      summary.items += options.format == ExportFormat::Pcd
                           ? writeVoxelsPcd(map, labels, path, options.rotation)
                           : writeVoxelsPly(map, labels, path, options.rotation);
      summary.files.push_back(path);
    };
    if (!options.per_label) {
      write(selected, out);
    } else {
      for (const auto& [label, keys] : voxels)
        staging->write([&, label = label] { write({label}, pathFor(label)); });
      publish();
    }
    return summary;
  }

  summary.item_name = "triangles";
  const std::string frame = frameComment(map, options.rotation);
  std::vector<SurfaceMesh> meshes;
  for (const auto& [label, keys] : voxels) {
    SurfaceMesh mesh;
    if (options.smooth) {
      try {
        mesh = smoothSurface(keys, map.parameters().resolution);
      } catch (const std::length_error& e) {
        throw Error(out.string(), "--smooth",
                    "objects small enough to smooth on a voxel grid (at most 512 Mi voxels each)",
                    "label " + std::to_string(label) + ": " + e.what() +
                        " (export it without --smooth, or leave the label out with --labels)");
      }
    } else {
      mesh = voxelSurface(keys, map.parameters().resolution,
                          VoxelSurfaceOptions{options.merge_coplanar});
    }
    mesh.label = label;
    if (options.rotation)  // a rotation keeps the triangles' winding (outward normals)
      for (Eigen::Vector3d& vertex : mesh.vertices) vertex = *options.rotation * vertex;
    summary.items += mesh.triangles.size();
    if (options.per_label) {
      staging->write(
          [&] { writeMeshes({mesh}, map, options.format, pathFor(label), summary.files, frame); });
    } else {
      meshes.push_back(std::move(mesh));
    }
  }
  if (!options.per_label) writeMeshes(meshes, map, options.format, out, summary.files, frame);
  if (options.per_label) publish();
  return summary;
}

}  // namespace lom
