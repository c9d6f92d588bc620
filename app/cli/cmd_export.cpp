// labeloctomap export: meshes, point clouds, octrees and object boxes for other tools.
#include <iostream>
#include <system_error>

#include "args.hpp"
#include "commands.hpp"
#include "lom/export.hpp"
#include "lom/label_map.hpp"

namespace lom::cli {

int runExport(const Words& words) {
  const Args args(words, {"per-label", "smooth", "points", "native", "no-merge"});
  args.expectOnly(
      {"voxels", "format", "out", "labels", "per-label", "smooth", "points", "native", "no-merge"},
      1);
  const std::filesystem::path map_path = args.positional(0, "MAP.ot");
  auto format_name = args.option("format");
  auto out = args.option("out");
  // The older spelling of a PCD export.
  if (const auto voxels = args.option("voxels")) {
    if (out) throw UsageError("give either --voxels OUT.pcd or --out PATH, not both");
    if (format_name && *format_name != "pcd")
      throw UsageError(
          "--voxels OUT.pcd means --format pcd --out OUT.pcd; it does not go with --format " +
          *format_name);
    format_name = "pcd";
    out = voxels;
  }
  if (!format_name)
    throw UsageError("missing option --format (ply, obj, stl, pcd, ot, bt or objects)");
  const auto format = parseExportFormat(*format_name);
  if (!format)
    throw UsageError("option --format expects ply, obj, stl, pcd, ot, bt or objects, got '" +
                     *format_name + "'");
  if (!out) throw UsageError("missing option --out PATH");
  std::error_code ec;
  if (std::filesystem::equivalent(map_path, *out, ec))
    throw UsageError("--out " + *out + " is the input map itself; choose another path");

  ExportOptions options;
  options.format = *format;
  options.per_label = args.flag("per-label");
  options.smooth = args.flag("smooth");
  options.points = args.flag("points");
  options.native = args.flag("native");
  options.merge_coplanar = !args.flag("no-merge");
  if (const auto labels = args.option("labels")) {
    const auto list = parseIntList(*labels, "labels");
    options.labels = std::set<int>(list.begin(), list.end());
  }

  const LabelMap map = LabelMap::load(map_path);
  const ExportSummary summary = exportMap(map, options, *out);
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
