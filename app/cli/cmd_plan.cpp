// labeloctomap plan: which objects to remove, in which order, before picking a
// target, with grasps and placements (docs/planning.md).
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>

#include "args.hpp"
#include "commands.hpp"
#include "lom/box_fit.hpp"
#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/label_map.hpp"
#include "lom/planning.hpp"
#include "lom/sequence.hpp"
#include "output_paths.hpp"

namespace lom::cli {

namespace {

namespace fs = std::filesystem;

OrientedBox parseBin(const std::string& text) {
  const std::string expected = "an axis-aligned box cx,cy,cz,dx,dy,dz (centre and sizes in metres, sizes > 0)";
  const auto v = parseNumbers(text, 6, "empty-bin", expected);
  OrientedBox bin;
  bin.center = {v[0], v[1], v[2]};
  bin.size = {v[3], v[4], v[5]};
  if (!(bin.size.array() > 0.0).all()) throw UsageError("option --empty-bin expects " + expected + ", got '" + text + "'");
  return bin;
}

// The items of "8,19,bunny_book"; an empty item (",8", "8,,19", "8,") is a
// malformed command line, refused before any file is read.
std::vector<std::string> candidateItems(const std::string& text) {
  std::vector<std::string> items;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    items.push_back(
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (items.back().empty())
      throw UsageError(
          "option --candidates expects a comma-separated list of labels (ids or names), got '" +
          text + "' (an empty item)");
    if (comma == std::string::npos) return items;
    start = comma + 1;
  }
}

// "8,19,bunny_book" -> label ids (ids or names of the map's labels).
std::vector<int> parseCandidates(const std::string& text, const LabelSet& labels, const std::string& map_file) {
  std::vector<int> ids;
  for (const std::string& item : candidateItems(text))
    ids.push_back(resolveObjectLabel(labels, item, map_file, "--candidates"));
  // Each label once, in ascending order (plan.json lists them so).
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace

std::string boxesOnWorldZNote(const LabelMap& map, const std::string& map_file, bool up_given) {
  if (up_given || map.camerasUp()) return {};
  return map_file +
         " does not record which way up its cameras were (a map of an older version, or "
         "cameras that disagree): the object boxes stand on the world's +z axis; --sequence SEQ, "
         "the recording it was fused from, stands them level with the scene, as score does";
}

int runPlan(const Words& words) {
  const Args args(words, {"all-clusters", "transitive"});
  args.expectOnly({"target", "approach", "sequence", "out", "empty-bin", "all-clusters",
                   "candidates", "cluster-tolerance", "min-cluster-voxels", "overlap-margin",
                   "transitive", "gap", "threshold", "occluders"},
                  1);
  const fs::path map_path = args.positional(0, "MAP.ot (a fused map)");
  const std::string target_text = args.required("target");
  if (const auto candidates = args.option("candidates")) (void)candidateItems(*candidates);

  PlanOptions options;
  options.objects.map_file = map_path.string();
  options.objects.all_clusters = args.flag("all-clusters");
  options.objects.cluster_tolerance_voxels =
      args.number("cluster-tolerance", options.objects.cluster_tolerance_voxels);
  if (!(options.objects.cluster_tolerance_voxels > 0.0) ||
      options.objects.cluster_tolerance_voxels > kMaxClusterTolerance)
    throw UsageError("option --cluster-tolerance expects a number of voxel edges above 0 and " +
                     ("at most " + std::to_string(static_cast<int>(kMaxClusterTolerance))) +
                     ", got '" + *args.option("cluster-tolerance") + "' (docs/planning.md)");
  const long min_voxels =
      args.integer("min-cluster-voxels", static_cast<long>(kDefaultMinObjectVoxels), 1, INT_MAX);
  options.objects.min_cluster_voxels = static_cast<size_t>(min_voxels);
  options.overlap_margin_voxels = args.number("overlap-margin", options.overlap_margin_voxels);
  if (!(options.overlap_margin_voxels >= 0.0))
    throw UsageError("option --overlap-margin expects a number of voxel edges >= 0, got '" +
                     *args.option("overlap-margin") + "'");
  options.placement_gap = args.number("gap", options.placement_gap);
  if (!(options.placement_gap >= 0.0))
    throw UsageError("option --gap expects a number of metres >= 0, got '" + *args.option("gap") + "'");
  options.transitive = args.flag("transitive");
  if (const auto rule = args.option("occluders")) {
    if (*rule == "centroid")
      options.occluder_rule = OccluderRule::Centroid;
    else if (*rule != "path")
      throw UsageError(
          "option --occluders expects path (boxes in the target's path, the "
          "default) or centroid (the paper's rule: centroids nearer the cameras "
          "than the target's), got '" +
          *rule + "'");
  }
  if (const auto bin = args.option("empty-bin")) options.empty_bin = parseBin(*bin);
  if (args.option("approach") && args.option("sequence"))
    throw UsageError("give either --approach or --sequence, not both");
  if (const auto approach = args.option("approach")) {
    options.approach = parseDirection(*approach, "approach");
    options.approach_source = ApproachSource::Given;
  }
  const std::optional<std::string> out = args.option("out");
  CommandInputs inputs;
  inputs.addFile(map_path, "the input map");
  if (const auto sequence_path = args.option("sequence")) inputs.addSequenceJson(*sequence_path);
  const std::string what = "the plan";
  if (out) checkOutputFile(*out, "out", ".json", what, inputs);

  // The sequence is read before the map: it is the cheaper file to get wrong.
  std::optional<Sequence> sequence;
  if (const auto sequence_path = args.option("sequence")) {
    sequence = loadSequence(*sequence_path);
    inputs.addSequenceFiles(*sequence);
    if (out) checkOutputFile(*out, "out", ".json", what, inputs);
    options.approach = meanViewingDirection(*sequence);
    options.approach_source = ApproachSource::Sequence;
    options.objects.cameras_up = camerasUpOf(*sequence);  // for a map that records none
  }

  LabelMap map = LabelMap::load(map_path);
  // --threshold: the map read as `fuse --threshold` or the studio's Threshold
  // would read it (a plan the studio saved names its threshold).
  if (args.option("threshold")) {
    const double threshold = args.number("threshold", map.parameters().occupancy_threshold);
    checkOccupancyThreshold(threshold, map.parameters(), map_path.string());
    map.setOccupancyThreshold(threshold);
  }
  // The approach comes from the sequence's cameras: only meaningful when the
  // map was fused from them (in the same world frame).
  if (sequence)
    if (const std::string warning = poorMapFitWarning(mapFitOf(map, *sequence), map_path.string());
        !warning.empty())
      std::cerr << "warning: " << warning << " The approach from --sequence may point anywhere.\n";
  if (map.numLabels() < 2)
    throw Error(map_path.string(), "--target", "a map with object labels (1 and up) to plan for",
                "a map whose only label is the background (0), so it has no objects");
  const int target = resolveObjectLabel(map.labels(), target_text, map_path.string(), "--target");
  if (const auto candidates = args.option("candidates"))
    options.objects.labels = parseCandidates(*candidates, map.labels(), map_path.string());
  // The bin's placements stack along +z: a map whose up is far from it (the
  // world of a recording is often its first camera's) puts them on a wall.
  if (options.empty_bin)
    if (const auto up = map.upDirection(); up && up->z() < std::cos(30.0 * M_PI / 180.0)) {
      char text[160];
      std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f), %.0f deg from +z", up->x(), up->y(),
                    up->z(), std::acos(std::clamp(up->z(), -1.0, 1.0)) * 180.0 / M_PI);
      std::cerr << "warning: --empty-bin places the objects along the map's +z, but up in "
                << map_path.string() << " is " << text
                << " (its level plane or cameras): the placements assume z up and may lie on "
                   "their side (docs/planning.md)\n";
    }
  if (options.empty_bin)
    if (const std::string warning = binContentsWarning(map, *options.empty_bin, map_path.string());
        !warning.empty())
      std::cerr << "warning: " << warning << "\n";
  if (const std::string note =
          boxesOnWorldZNote(map, map_path.string(), options.objects.cameras_up.has_value());
      !note.empty())
    std::cerr << "note: " << note << "\n";
  const PickPlan plan = planPick(map, target, options);
  if (plan.approach_source == ApproachSource::FreeSpace)
    std::cerr << "note: the approach direction was guessed from the map's observed free space "
                 "(no --approach or --sequence given, and the map records no camera views); it can "
                 "point the wrong way when the cameras went round the objects. --sequence SEQ uses "
                 "the recorded cameras' viewing direction, --approach x,y,z sets it\n";
  // The file first: a run that cannot write it fails without printing a plan
  // as though it had succeeded.
  if (out) writePlanJson(plan, *out, map_path.string());
  std::cout << planTable(plan);
  if (out) std::cout << "wrote " << *out << "\n";
  return 0;
}

}  // namespace lom::cli
