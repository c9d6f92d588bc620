// labeloctomap export: meshes, point clouds, octrees and object boxes for other tools.
#include <iostream>
#include <system_error>

#include "args.hpp"
#include "commands.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"
#include "lom/label_map.hpp"
#include "output_paths.hpp"

namespace lom::cli {

namespace {

namespace fs = std::filesystem;

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

}  // namespace

int runExport(const Words& words) {
  const Args args(words, {"per-label", "smooth", "points", "native", "no-merge"});
  args.expectOnly(
      {"voxels", "format", "out", "labels", "per-label", "smooth", "points", "native", "no-merge"},
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

  CommandInputs inputs;
  inputs.addFile(map_path, "the input map");
  const std::string format_text = std::string("format ") + exportFormatName(*format);
  if (options.per_label) {
    checkOutputFolder(out_path, out_option, "the per-label files", inputs);
  } else {
    checkOutputFile(out_path, out_option, extensionOf(*format), format_text, inputs);
    if (*format == ExportFormat::Obj)
      checkOutputFile(fs::path(out_path).replace_extension(".mtl"), out_option, ".mtl",
                      "the OBJ materials", inputs);
  }

  const LabelMap map = LabelMap::load(map_path);
  const auto counts = map.occupiedCountPerLabel();
  if (options.per_label)
    for (const auto& file : perLabelFiles(map, options, counts, out_path))
      checkOutputInFolder(file, out_option, inputs);

  const ExportSummary summary = exportMap(map, options, out_path);
  for (const int label : summary.empty_labels)
    std::cerr << "note: label " << label << " (" << map.labels().at(label).name
              << ") has no occupied voxel; nothing written for it\n";
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
