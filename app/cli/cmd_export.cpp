// labeloctomap export: meshes, point clouds, octrees and object boxes for other tools.
#include <fcntl.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <new>
#include <system_error>

#include "args.hpp"
#include "commands.hpp"
#include "lom/box_fit.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"
#include "lom/fusion.hpp"
#include "lom/label_map.hpp"
#include "output_paths.hpp"

namespace lom::cli {

namespace {

namespace fs = std::filesystem;

// Keeps stderr quiet while it lives: OctoMap's binary writer prints progress of its own there.
class QuietStderr {
 public:
  QuietStderr() {
    std::fflush(stderr);
    saved_ = ::dup(STDERR_FILENO);
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) ::dup2(null, STDERR_FILENO);
    if (null >= 0) ::close(null);
  }
  ~QuietStderr() {
    std::fflush(stderr);
    if (saved_ < 0) return;
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_ = -1;
};

std::string extensionOf(ExportFormat format) {
  return format == ExportFormat::Objects ? ".json" : std::string(".") + exportFormatName(format);
}

bool isMesh(const ExportOptions& o) {
  return o.format == ExportFormat::Obj || o.format == ExportFormat::Stl ||
         (o.format == ExportFormat::Ply && !o.points);
}

bool isPointCloud(const ExportOptions& o) {
  return o.format == ExportFormat::Pcd || (o.format == ExportFormat::Ply && o.points);
}

// Switches that do not apply to the format are mistakes in the call, found before the map is read.
void checkSwitches(const ExportOptions& o) {
  const std::string format = exportFormatName(o.format);
  if (o.smooth && !isMesh(o))
    throw UsageError("option --smooth applies to the mesh formats (ply, obj, stl), not to format " +
                     format + (o.points ? " with --points" : ""));
  if (o.per_label && !isMesh(o) && !isPointCloud(o))
    throw UsageError(
        "option --per-label applies to the mesh and point cloud formats (ply, obj, "
        "stl, pcd), not to format " +
        format);
  if (o.points && o.format != ExportFormat::Ply)
    throw UsageError(
        "option --points applies to format ply (pcd is always points), not to format " + format);
  if (o.native && o.format != ExportFormat::Ot)
    throw UsageError("option --native applies to format ot, not to format " + format);
  if (o.native && o.labels)
    throw UsageError(
        "option --labels does not go with --native (the native map keeps every label)");
  if (!o.merge_coplanar && (!isMesh(o) || o.smooth))
    throw UsageError(
        "option --no-merge applies to the voxel meshes of formats ply, obj and stl (without "
        "--smooth or --points), not to " +
        (isMesh(o) ? std::string("--smooth")
                   : "format " + format + (o.points ? " with --points" : "")));
}

// The files that a per-label export writes into `folder` for the labels with voxels.
std::vector<fs::path> perLabelFiles(const LabelMap& map, const ExportOptions& options,
                                    const std::map<int, size_t>& counts, const fs::path& folder) {
  std::vector<fs::path> files;
  for (const auto& [label, count] : counts) {
    if (options.labels && !options.labels->count(label)) continue;
    const fs::path file = folder / (labelFileStem(map.labels().at(label), map.numLabels()) +
                                    extensionOf(options.format));
    files.push_back(file);
    if (options.format == ExportFormat::Obj)
      files.push_back(fs::path(file).replace_extension(".mtl"));
  }
  return files;
}

std::string labelNames(const LabelMap& map, const std::set<int>& labels) {
  std::string text;
  for (const int label : labels) {
    if (!text.empty()) text += ", ";
    text += std::to_string(label) + " (" + map.labels().at(label).name + ")";
  }
  return text;
}

// Meshes, point clouds and objects need occupied voxels of the selected labels; says which
// of the map's voxels there are when there are none.
void checkSomethingToExport(const LabelMap& map, const fs::path& map_path,
                            const ExportOptions& options, const std::map<int, size_t>& counts) {
  if (options.labels)
    for (const int label : *options.labels)
      if (!map.labels().contains(label))
        throw Error(map_path.string(), "--labels",
                    "label ids of the map, 0 to " + std::to_string(map.numLabels() - 1),
                    std::to_string(label));
  const bool octree = options.format == ExportFormat::Ot || options.format == ExportFormat::Bt;
  // Octrees carry free space too: only a map with no voxel at all has nothing.
  if (octree && map.numLeaves() == 0)
    throw Error(map_path.string(), "map", "at least one known voxel to export",
                "an empty map (no voxel was ever observed)");
  if (octree && !options.labels) return;
  size_t occupied = 0;
  for (const auto& [label, count] : counts) occupied += count;
  if (options.labels) {
    for (const int label : *options.labels)
      if (counts.count(label)) return;
    std::string present;
    for (const auto& [label, count] : counts)
      present += (present.empty() ? "" : ", ") + std::to_string(label);
    throw Error(map_path.string(), "--labels",
                "labels with occupied voxels in the map" +
                    (present.empty() ? std::string(" (the map has none)") : " (" + present + ")"),
                (options.labels->size() == 1 ? "label " : "labels ") +
                    labelNames(map, *options.labels) + " without any occupied voxel");
  }
  if (occupied == 0)
    throw Error(map_path.string(), "map", "at least one occupied voxel to export",
                "no occupied voxel");
  if (options.format == ExportFormat::Objects && counts.size() == 1 && counts.count(0))
    throw Error(map_path.string(), "map", "occupied voxels of object labels (1 and up)",
                std::to_string(occupied) +
                    " occupied voxels, all of the background (label 0), which the objects export "
                    "leaves out; add --labels 0 to export the background as an object");
}

// Runs the export; failures of the writers that do not name the output are made to.
ExportSummary runExportTo(const LabelMap& map, const ExportOptions& options, const fs::path& out,
                          const std::string& option) {
  const std::string format = exportFormatName(options.format);
  try {
    if (options.format == ExportFormat::Bt) {
      const QuietStderr quiet;
      return exportMap(map, options, out);
    }
    return exportMap(map, options, out);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const fs::filesystem_error& e) {
    throw Error(out.string(), "--" + option,
                options.per_label ? "a folder that can be created for the per-label files"
                                  : "a writable " + format + " file",
                e.code().message() + (e.path1().empty() ? "" : " (" + e.path1().string() + ")"));
  } catch (const std::exception& e) {
    std::string message = e.what();
    const auto start = message.find_first_not_of(": ");
    message = start == std::string::npos ? "an unknown failure" : message.substr(start);
    throw Error(out.string(), "--" + option, "a writable " + format + " file", message);
  }
}

}  // namespace

int runExport(const Words& words) {
  const Args args(words, {"per-label", "smooth", "points", "native", "no-merge", "level"});
  args.expectOnly({"voxels", "format", "out", "labels", "per-label", "smooth", "points", "native",
                   "no-merge", "sequence", "level"},
                  1);
  const fs::path map_path = args.positional(0, "MAP.ot");
  auto format_name = args.option("format");
  auto out = args.option("out");
  std::string out_option = "out";
  // The older spelling of a PCD export.
  if (const auto voxels = args.option("voxels")) {
    if (out) throw UsageError("give either --voxels OUT.pcd or --out PATH, not both");
    if (format_name && *format_name != "pcd")
      throw UsageError(
          "--voxels OUT.pcd means --format pcd --out OUT.pcd; it does not go with --format " +
          *format_name);
    format_name = "pcd";
    out = voxels;
    out_option = "voxels";
  }
  if (!format_name)
    throw UsageError("missing option --format (ply, obj, stl, pcd, ot, bt or objects)");
  const auto format = parseExportFormat(*format_name);
  if (!format)
    throw UsageError("option --format expects ply, obj, stl, pcd, ot, bt or objects, got '" +
                     *format_name + "'");
  if (!out) throw UsageError("missing option --out PATH");
  const fs::path out_path = *out;

  ExportOptions options;
  options.format = *format;
  options.per_label = args.flag("per-label");
  options.smooth = args.flag("smooth");
  options.points = args.flag("points");
  options.native = args.flag("native");
  options.merge_coplanar = !args.flag("no-merge");
  if (const auto labels = args.option("labels")) {
    const auto list = parseLabelList(*labels, "labels");
    options.labels = std::set<int>(list.begin(), list.end());
  }
  checkSwitches(options);
  const bool level = args.flag("level");
  if (level && !isMesh(options) && !isPointCloud(options))
    throw UsageError(
        "option --level applies to the mesh and point cloud formats (ply, obj, stl, pcd), not "
        "to format " +
        std::string(exportFormatName(*format)) +
        " (octrees and object boxes stay in the map's frame, where the sequence's poses are)");
  const auto sequence_path = args.option("sequence");
  if (sequence_path && *format != ExportFormat::Objects && !level)
    throw UsageError(
        "option --sequence goes only with --format objects or --level (it gives the up of "
        "the cameras the map was fused from)");

  CommandInputs inputs;
  inputs.addFile(map_path, "the input map");
  if (sequence_path) inputs.addSequenceJson(*sequence_path);
  const std::string format_text = std::string("format ") + exportFormatName(*format);
  if (options.per_label) {
    checkOutputFolder(out_path, out_option, "the per-label files", inputs);
  } else {
    checkOutputFile(out_path, out_option, extensionOf(*format), format_text, inputs);
    // Only --native writes a labelled map: a colour octree over one (the
    // fused map of another sequence, say) would leave a file no command reads
    // back as a map, every label's probabilities gone.
    if (!options.native && LabelMap::isMapFile(out_path))
      throw UsageError("option --" + out_option + " '" + out_path.string() +
                       "' holds a labelled map (LabelOcTree): format " + exportFormatName(*format) +
                       " would replace it without its labels; choose another name (--native "
                       "writes the labelled map itself)");
    if (*format == ExportFormat::Obj)
      checkOutputFile(fs::path(out_path).replace_extension(".mtl"), out_option, ".mtl",
                      "the OBJ materials", inputs);
  }

  // The sequence is read before the map: it is the cheaper file to get wrong.
  if (sequence_path) {
    const Sequence sequence = loadSequence(*sequence_path);
    inputs.addSequenceFiles(sequence);
    if (!options.per_label)
      checkOutputFile(out_path, out_option, extensionOf(*format), format_text, inputs);
    options.cameras_up = camerasUpOf(sequence);
  }
  const LabelMap map = LabelMap::load(map_path);
  const auto counts = map.occupiedCountPerLabel();
  checkSomethingToExport(map, map_path, options, counts);
  if (level) {
    options.rotation = levellingRotation(map);
    // A map that records no camera: the sequence's cameras, levelled by the
    // map's largest plane, as its boxes are (sceneLevelOf).
    if (!options.rotation && options.cameras_up) {
      const Eigen::Vector3d up = sceneLevelOf(map, options.cameras_up).up;
      options.rotation =
          Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    }
    if (!options.rotation)
      throw Error(map_path.string(), "--level",
                  "a map that records the cameras it was fused from (or --sequence SEQ, the "
                  "sequence it was fused from), whose up turns onto +z",
                  "a map that records no camera");
  }
  if (options.per_label)
    for (const auto& file : perLabelFiles(map, options, counts, out_path)) {
      checkOutputInFolder(file, out_option, inputs);
      checkNotASequenceFile(file, out_option);
    }

  if (options.format == ExportFormat::Obj && !options.per_label &&
      fs::path(out_path).filename().string().find_first_of(" \t") != std::string::npos)
    std::cerr << "note: OBJ readers split the mtllib line at spaces: they will not find "
              << fs::path(out_path).replace_extension(".mtl").filename().string()
              << " (the label colours); a file name without spaces keeps them\n";
  if (*format == ExportFormat::Objects)
    if (const std::string note =
            boxesOnWorldZNote(map, map_path.string(), options.cameras_up.has_value());
        !note.empty())
      std::cerr << "note: " << note << "\n";
  const ExportSummary summary = runExportTo(map, options, out_path, out_option);
  for (const std::string& note : summary.notes) std::cerr << "note: " << note << "\n";
  for (const int label : summary.empty_labels)
    std::cerr << "note: label " << label << " (" << map.labels().at(label).name
              << ") has no occupied voxel; nothing written for it\n";
  if (!summary.earlier_files.empty()) {
    // Left alone (they may be the user's), but the folder is not one map's.
    const size_t shown = std::min<size_t>(summary.earlier_files.size(), 5);
    std::cerr << "note: " << summary.earlier_files.size() << " file"
              << (summary.earlier_files.size() == 1 ? " in " : "s in ") << out_path.string()
              << " named like per-label files are not from this export (an earlier one's?), "
                 "left as they were: ";
    for (size_t i = 0; i < shown; ++i)
      std::cerr << (i ? ", " : "") << summary.earlier_files[i].filename().string();
    if (shown < summary.earlier_files.size())
      std::cerr << " and " << summary.earlier_files.size() - shown << " more";
    std::cerr << "; remove them, or export into an empty folder, to keep the folder one map's\n";
  }
  if (const auto& r = options.rotation) {
    const Eigen::Vector3d up = r->transpose() * Eigen::Vector3d::UnitZ();  // the map's up
    char text[240];
    std::snprintf(text, sizeof text,
                  "levelled: the map's up (%.4f, %.4f, %.4f) turned onto +z about the origin, "
                  "x' = R x with R = [%.6f %.6f %.6f; %.6f %.6f %.6f; %.6f %.6f %.6f]",
                  up.x(), up.y(), up.z(), (*r)(0, 0), (*r)(0, 1), (*r)(0, 2), (*r)(1, 0),
                  (*r)(1, 1), (*r)(1, 2), (*r)(2, 0), (*r)(2, 1), (*r)(2, 2));
    std::cout << text << "\n";
  }
  std::cout << "wrote " << summary.items << " " << summary.item_name;
  if (options.format == ExportFormat::Pcd || options.points) std::cout << " (occupied voxels)";
  if (summary.files.size() == 1) {
    std::cout << " to " << summary.files.front().string() << "\n";
  } else {
    std::cout << " to " << summary.files.size() << " files:\n";
    for (const auto& file : summary.files) std::cout << "  " << file.string() << "\n";
  }
  return 0;
}

}  // namespace lom::cli
