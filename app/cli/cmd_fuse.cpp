// labeloctomap fuse: a sequence into a LabelOctoMap .ot file.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <vector>

#include "args.hpp"
#include "commands.hpp"
#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/frame_range.hpp"
#include "lom/fusion.hpp"
#include "output_paths.hpp"
#include "segmenter_option.hpp"

namespace lom::cli {

namespace {

// A number as the options take it: "10", "0.04".
std::string formatNumber(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// The most memory this process has held in RAM so far, in KiB (0 when unknown).
long peakResidentKiB() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return usage.ru_maxrss;  // Linux reports KiB
}

// "A:B", "A:", ":B" -> [A, B) frame indices; an absent B means "to the end".
// An empty value is refused (a script's unset variable), not read as every frame.
void readFrameRange(const std::string& text, FusionOptions& options) {
  std::string expected = "A:B (first frame, end frame exclusive), A: or :B";
  const std::optional<FrameRange> range = text.find_first_not_of(" \t") == std::string::npos
                                              ? std::nullopt
                                              : parseFrameRange(text, &expected);
  if (!range) throw UsageError("option --frames expects " + expected + ", got '" + text + "'");
  options.first_frame = range->first;
  options.last_frame = range->end;
}

// The frames of [first, last) a map with the camera view record `record` was
// fused from, it seems: the first run of consecutive frames whose views sum
// to the record (sameCameraViews), each a fused view (a frame whose rotation
// is not finite adds none). nullopt when no run does, or the map records no
// views. Prefix sums: one pass, however long the sequence.
std::optional<FrameRange> framesWithCameraViews(const Sequence& sequence, size_t first, size_t last,
                                                const CameraViewRecord& record) {
  const size_t end = std::min(last, sequence.frames.size());
  if (record.views == 0 || first >= end) return std::nullopt;
  // prefix[i]: the views of frames first .. first + i - 1.
  std::vector<CameraViewRecord> prefix(1);
  for (size_t i = first; i < end; ++i) {
    prefix.push_back(prefix.back());
    addCameraView(prefix.back(), sequence.frames[i].T_world_camera.linear());
  }
  size_t b = 0;
  for (size_t a = 0; a + 1 < prefix.size(); ++a) {
    b = std::max(b, a);
    while (b < prefix.size() && prefix[b].views - prefix[a].views < record.views) ++b;
    if (b == prefix.size()) break;
    if (prefix[b].views - prefix[a].views != record.views) continue;
    CameraViewRecord window;
    window.views = record.views;
    for (int k = 0; k < 3; ++k) {
      window.up_sum[k] = prefix[b].up_sum[k] - prefix[a].up_sum[k];
      window.forward_sum[k] = prefix[b].forward_sum[k] - prefix[a].forward_sum[k];
    }
    if (sameCameraViews(window, record)) return FrameRange{first + a, first + b};
  }
  return std::nullopt;
}

// The shortest text that reads back as `value`: a refused 0.9700001 is not
// echoed as the limit 0.97 it exceeds.
std::string number(double value) {
  for (int digits = 6;; ++digits) {
    std::ostringstream text;
    text << std::setprecision(digits) << value;
    if (digits >= 17 || std::strtod(text.str().c_str(), nullptr) == value) return text.str();
  }
}

void drawProgress(const FusionProgress& progress, double seconds_per_frame) {
  constexpr int kWidth = 30;
  const int filled = progress.total ? static_cast<int>(kWidth * progress.done / progress.total) : 0;
  std::fprintf(stderr, "\r[%s%s] %zu/%zu frames  %.0f ms/frame", std::string(filled, '#').c_str(),
               std::string(kWidth - filled, '.').c_str(), progress.done, progress.total,
               seconds_per_frame * 1000.0);
  std::fflush(stderr);
}

// "frames[0], frames[4] and 7 more".
std::string listFrames(const std::vector<size_t>& frames) {
  constexpr size_t kNamed = 3;
  std::string text;
  for (size_t i = 0; i < frames.size() && i < kNamed; ++i)
    text += (i == 0                   ? ""
             : i + 1 == frames.size() ? " and "
                                      : ", ") +
            std::string("frames[") + std::to_string(frames[i]) + "]";
  if (frames.size() > kNamed) text += " and " + std::to_string(frames.size() - kNamed) + " more";
  return text;
}

// What would bring depth points outside the map's extent into it.
std::string outsideMapAdvice(const std::string& sequence_file, const FrameStats& totals,
                             double resolution, bool continued) {
  // No depth camera measures farther than the whole extent: the pixels'
  // points were put there by the intrinsics or the depth scale.
  if (totals.farthest_range > mapExtent(resolution))
    return "the depths reach " +
           (std::isfinite(totals.farthest_range) ? formatNumber(totals.farthest_range) + " m"
                                                 : std::string("without bound")) +
           " from the camera, farther than the extent: check camera.fx, camera.fy, camera.cx, "
           "camera.cy and camera.depth_scale in " +
           sequence_file;
  return std::string(continued ? "fused again without --start-from (whose map keeps its own "
                                 "resolution), "
                               : "") +
         "a coarser --resolution extends the map (" + formatNumber(2.0 * resolution) +
         " m voxels reach " + formatNumber(mapExtent(2.0 * resolution)) + " m)";
}

}  // namespace

std::string outsideMapWarning(const std::string& sequence_file, const FrameStats& totals,
                              const std::vector<size_t>& frames, double resolution,
                              bool continued) {
  if (totals.outside_map_pixels == 0) return {};
  const size_t measured = totals.valid_pixels + totals.outside_map_pixels;
  char share[32];
  std::snprintf(share, sizeof(share), "%.1f%%", 100.0 * totals.outside_map_pixels / measured);
  return sequence_file + ": " + std::to_string(totals.outside_map_pixels) + " of " +
         std::to_string(measured) + " measured depth pixels (" + share + "), in " +
         listFrames(frames) + ", lie outside the map's extent, " + describeMapExtent(resolution) +
         ": the map leaves them out, free space and all; " +
         outsideMapAdvice(sequence_file, totals, resolution, continued);
}

RangeMessage maxRangeMessage(const FrameStats& totals, double max_range, double resolution,
                             const std::string& sequence_file, bool continued) {
  // Max range drops farther surfaces without a trace: a warning when it took
  // most of the depths, a note when it took a fifth or more.
  RangeMessage message;
  const size_t measured = measuredPixels(totals);
  if (totals.valid_pixels == 0 || measured == 0) return message;
  const size_t beyond = totals.beyond_range_pixels;
  message.warning = mostDepthsBeyondMaxRange(totals, max_range);
  if (!message.warning && !(max_range > 0.0 && 5 * beyond >= measured)) return message;
  const double reach = std::ceil(totals.farthest_range * 10.0) / 10.0;
  std::string how;
  // Only settings fuse takes: a finite range, rays of at most 1000 voxels of at most 1 m.
  if (std::isfinite(reach) && reach <= kMaxFusionVoxelsPerRay * kMaxFusionResolution) {
    const double suggested = suggestedResolutionForRange(reach, resolution);
    const bool coarser = suggested > resolution + 1e-9;
    char farthest[32];
    std::snprintf(farthest, sizeof farthest, "%.1f", totals.farthest_range);
    // Past 250 m even 1 m voxels make rays longer than 250 voxels: such
    // depths suggest wrong intrinsics or depth scale more than a far wall.
    const double voxels = std::ceil(reach / suggested - 1e-9);
    const std::string why =
        voxels > 250.0
            ? " (1 m voxels, the coarsest fusion takes, and rays of " + formatNumber(voxels) +
                  " voxels; depths this far suggest wrong camera intrinsics or "
                  "depth scale in sequence.json)"
        : coarser ? " (rays of at most 250 voxels: finer voxels over that range take far more "
                    "memory)"
                  : "";
    how = std::string("The depths reach ") + farthest + " m; fuse " +
          (continued ? "again without --start-from (whose map keeps its own max range and "
                       "resolution), "
                     : "") +
          "with --max-range " + formatNumber(reach) +
          (coarser ? " --resolution " + formatNumber(suggested) : std::string()) + " to map them" +
          why;
  } else {
    how = "The depths reach farther than " +
          formatNumber(kMaxFusionVoxelsPerRay * kMaxFusionResolution) +
          " m, beyond any max range fusion takes and any depth camera measures: check "
          "camera.fx, camera.fy, camera.cx, camera.cy and camera.depth_scale in " +
          sequence_file;
  }
  char counts[160];
  std::snprintf(counts, sizeof counts,
                "%zu of %zu measured depth pixels (%.1f%%) were beyond the max range of %g m: ",
                beyond, measured, 100.0 * beyond / measured, max_range);
  // (Those outside the map's extent did not even clear free space.)
  message.text = counts + std::string("they mapped nothing, at most cleared free space. ") + how;
  return message;
}

FusionOptions fusionOptionsFromArgs(const Args& args) {
  FusionOptions options;
  options.map.resolution = args.number("resolution", options.map.resolution);
  if (options.map.resolution < kMinFusionResolution ||
      options.map.resolution > kMaxFusionResolution)
    throw UsageError("option --resolution expects a voxel size from " +
                     number(kMinFusionResolution) + " to " + number(kMaxFusionResolution) +
                     " m, got " + number(options.map.resolution) + " (docs/fusion.md, \"Limits\")");
  options.map.max_range = args.number("max-range", options.map.max_range);
  if (const auto rays = checkRayLength(options.map.max_range, options.map.resolution))
    throw UsageError("option --max-range " + number(options.map.max_range) + " with --resolution " +
                     number(options.map.resolution) + " makes rays " + number(rays->voxels) +
                     " voxels long; at most " + number(rays->limit) +
                     " voxels are allowed (a coarser --resolution or a shorter --max-range; "
                     "docs/fusion.md, \"Limits\")");
  if (args.option("frame-memory")) {
    const double gib = args.number("frame-memory", 0.0);
    if (!(gib > 0.0) || !std::isfinite(gib))
      throw UsageError(
          "option --frame-memory expects the memory a frame may take while it is "
          "fused, in GiB (more than 0; by default the memory the system has "
          "available), got " +
          number(gib));
    options.integration.frame_memory_limit_bytes = gib * 1024.0 * 1024.0 * 1024.0;
  }
  options.map.p_miss = args.number("p-miss", options.map.p_miss);
  options.map.occupancy_threshold = args.number("threshold", options.map.occupancy_threshold);
  if (auto candidates = args.option("candidates"); candidates && *candidates != "none") {
    options.candidates = parseLabelList(*candidates, "candidates");
    // Renormalised over object labels only, every pixel becomes an object.
    const auto& ids = *options.candidates;
    if (std::find(ids.begin(), ids.end(), 0) == ids.end() && !args.flag("quiet"))
      std::cerr << "note: --candidates " << *candidates
                << " leaves out 0, the background: each pixel's probabilities are renormalised "
                   "over these object labels, so background pixels are fused (and projected) "
                   "as objects\n";
  }
  if (auto frames = args.option("frames")) readFrameRange(*frames, options);
  try {
    checkMapParameters(options.map);
  } catch (const Error& e) {
    const std::string option = e.problem().field == "occupancy_threshold" ? "threshold"
                               : e.problem().field == "p_miss"            ? "p-miss"
                               : e.problem().field == "max_range"         ? "max-range"
                                                                          : e.problem().field;
    throw UsageError("option --" + option + " expects " + e.problem().expected + ", got " +
                     e.problem().found);
  }
  if (!(options.map.p_miss < 0.5))
    throw UsageError(
        "option --p-miss expects a probability below 0.5 (a miss must lower the "
        "occupancy of the voxels a ray crosses), got " +
        number(options.map.p_miss));
  return options;
}

void checkOccupancyThreshold(double threshold, const MapParameters& map,
                             const std::string& map_file) {
  const std::string clamping = "[" + number(map.clamp_min) + ", " + number(map.clamp_max) + "]";
  const std::string of_map = map_file.empty() ? "" : " of " + map_file;
  if (threshold > map.clamp_max)
    throw UsageError("option --threshold expects at most " + number(map.clamp_max) +
                     ", the upper clamping bound" + of_map + " (probabilities are clamped to " +
                     clamping + ", so above it no voxel can ever be occupied), got " +
                     number(threshold));
  if (threshold <= map.clamp_min)
    throw UsageError("option --threshold expects more than " + number(map.clamp_min) +
                     ", the lower clamping bound" + of_map + " (probabilities are clamped to " +
                     clamping +
                     ", so at or below it every observed voxel, free space included, "
                     "would be occupied), got " +
                     number(threshold));
}

namespace {

// The map fusion continues from carries its own settings: they must be ones
// fuse itself takes (a map written by another program, or edited, may hold
// any), or every frame fused into it would be wrong without a word.
void checkStartMapParameters(const MapParameters& map, const std::string& map_file) {
  const auto refuse = [&](const std::string& field, const std::string& expected, double found) {
    throw Error(map_file, field,
                expected + " (the limits of fuse's options; docs/fusion.md, \"Limits\")",
                number(found));
  };
  if (map.resolution < kMinFusionResolution || map.resolution > kMaxFusionResolution)
    refuse("resolution",
           "a voxel size from " + number(kMinFusionResolution) + " to " +
               number(kMaxFusionResolution) + " m",
           map.resolution);
  if (const auto rays = checkRayLength(map.max_range, map.resolution))
    refuse("max_range",
           "a max range of at most " + number(rays->limit) + " voxels of " +
               number(map.resolution) + " m",
           map.max_range);
  if (!(map.p_miss < 0.5)) refuse("p_miss", "a probability below 0.5", map.p_miss);
  if (map.occupancy_threshold > map.clamp_max || map.occupancy_threshold <= map.clamp_min)
    refuse("occupancy_threshold",
           "a threshold above the lower clamping bound " + number(map.clamp_min) +
               " and at most the upper " + number(map.clamp_max),
           map.occupancy_threshold);
}

}  // namespace

void checkFusionOptionsForSequence(const FusionOptions& options, const Sequence& sequence) {
  const std::string file = (sequence.root / "sequence.json").string();
  if (const auto unknown = checkCandidates(options.candidates, sequence.labels))
    throw UsageError("option --candidates: label " + std::to_string(unknown->label) +
                     " is not in " + file + " (labels 0.." +
                     std::to_string(unknown->label_count - 1) + ")");
  const size_t count = sequence.frames.size();
  const bool past_end = options.first_frame >= count ||
                        (options.last_frame != kToTheEnd && options.last_frame > count);
  if (past_end) {
    const std::string range = options.first_frame == 0 && options.last_frame == kToTheEnd
                                  ? std::string("0:")
                                  : frameRangeText({options.first_frame, options.last_frame});
    throw UsageError("option --frames " + range + " goes past the end of " + file + ", which has " +
                     std::to_string(count) + (count == 1 ? " frame" : " frames") +
                     " (A:B takes frames A to B-1; A: takes every frame from A)");
  }
}

int runFuse(const Words& words) {
  const Args args(words, {"quiet"});
  args.expectOnly({"out", "resolution", "max-range", "p-miss", "threshold", "candidates", "frames",
                   "frame-memory", "quiet", "start-from", kSegmenterOption},
                  1);
  const std::string sequence_path = args.positional(0, "SEQ (a sequence folder)");
  const std::filesystem::path out = args.required("out");
  // --start-from MAP.ot: the frames are fused into that map, with its own parameters.
  const std::optional<std::string> start_from = args.option("start-from");
  if (start_from)
    for (const char* own : {"resolution", "max-range", "p-miss"})
      if (args.option(own))
        throw UsageError(std::string("option --") + own +
                         " cannot be given with --start-from: the frames are " + "fused into " +
                         *start_from + " with its own " + own + " (labeloctomap info " +
                         *start_from + " shows it)");
  FusionOptions options = fusionOptionsFromArgs(args);
  if (!start_from) checkOccupancyThreshold(options.map.occupancy_threshold, options.map, "");

  // Fail before the long part if the result could not be written, or would replace an input.
  CommandInputs inputs;
  inputs.addSequencePath(sequence_path);
  if (const auto model = args.option(kSegmenterOption))
    inputs.addFile(*model, "the segmenter model");
  if (start_from) inputs.addFile(*start_from, "the map to start from");
  const std::string what = "the LabelOctoMap map";
  checkOutputFile(out, "out", ".ot", what, inputs);
  options.segmenter = segmenterFromArgs(args);
  const Sequence sequence = loadSequence(sequence_path);
  inputs.addSequence(sequence);
  checkOutputFile(out, "out", ".ot", what, inputs);
  checkFusionOptionsForSequence(options, sequence);
  std::optional<LabelMap> earlier;
  if (start_from) {
    earlier.emplace(LabelMap::load(*start_from));
    checkMapMatchesSequence(*earlier, sequence, *start_from);
    if (args.option("threshold")) {
      checkOccupancyThreshold(options.map.occupancy_threshold, earlier->parameters(), *start_from);
      earlier->setOccupancyThreshold(options.map.occupancy_threshold);
    }
    checkStartMapParameters(earlier->parameters(), *start_from);
    options.map = earlier->parameters();  // what the checks and messages below speak of
    // Its frames were restricted to some labels: the new ones are too, unless
    // --candidates says otherwise (the map's record widens to both).
    const FusedCandidates& recorded = earlier->fusedCandidates();
    if (!args.option("candidates") && recorded.recorded && recorded.labels) {
      options.candidates = recorded.labels;
      std::string ids;
      for (const int id : *recorded.labels) ids += (ids.empty() ? "" : ",") + std::to_string(id);
      if (!args.flag("quiet"))
        std::cerr << "note: fusing with the candidates " << *start_from << " was fused with ("
                  << ids << "), as it records; --candidates chooses others\n";
    }
    const CameraViewRecord& views = earlier->cameraViews();
    if (const auto again =
            framesWithCameraViews(sequence, options.first_frame, options.last_frame, views)) {
      const size_t end = std::min(options.last_frame, sequence.frames.size());
      if (again->first == options.first_frame && again->end == end)
        std::cerr << "warning: " << *start_from
                  << " was fused from these very frames already, it seems (it records as many "
                     "camera views as they are, looking the same ways): fusing them again counts "
                     "each of their observations twice, which makes the map surer than the data "
                     "are; fuse other frames into it, or leave out --start-from (cameras that "
                     "only moved, never turned, look alike: then ignore this)\n";
      else
        std::cerr << "warning: " << *start_from << " was fused from frames "
                  << frameRangeText(*again)
                  << " of these already, it seems (it records as many camera views as they "
                     "are, looking the same ways): fusing them again counts each of their "
                     "observations twice, which makes the map surer than the data are; leave "
                     "them out with --frames "
                  << (again->first == options.first_frame
                          ? frameRangeText({again->end, options.last_frame})
                          : frameRangeText({options.first_frame, again->first}) +
                                (again->end < end ? " (and fuse the frames after them too)" : ""))
                  << " (cameras that only moved, never turned, look alike: then ignore this)\n";
    }
    // Probabilities of another source (a segmenter where the map has the
    // frames' own, or another model) make a map of both, recorded as both.
    const FusedEvidence& before = earlier->fusedEvidence();
    const FusedEvidence now =
        evidenceOf(sequence, options.first_frame, options.last_frame, options.segmenter.get());
    const bool widens =
        (now.own_probabilities && !before.own_probabilities) ||
        std::any_of(now.models.begin(), now.models.end(), [&](const std::string& model) {
          return std::find(before.models.begin(), before.models.end(), model) ==
                 before.models.end();
        });
    if (before.recorded && !before.empty() && widens)
      std::cerr << "warning: " << *start_from << " was fused from other probabilities ("
                << describeEvidence(before) << ") than these frames give (" << describeEvidence(now)
                << "): the map mixes both, and records both (labeloctomap info shows it); a "
                   "score --map of it warns when its projection baselines read other "
                   "probabilities\n";
  }
  // Before the jumps: a camera outside the map is the wrong pose, not its neighbours.
  checkCamerasInsideMap(sequence, options.map.resolution, options.first_frame, options.last_frame);
  for (const auto& jump : cameraJumps(sequence, 10.0, options.first_frame, options.last_frame))
    std::cerr << "warning: " << jump << ": the map will span that distance\n";
  const std::vector<std::string> camera_warnings =
      implausibleIntrinsics(sequence, options.first_frame, options.last_frame);
  for (const auto& camera : camera_warnings)
    std::cerr << "warning: " << (sequence.root / "sequence.json").string() << ": " << camera << "\n";

  const bool show_progress = !args.flag("quiet") && ::isatty(STDERR_FILENO);
  std::vector<double> frame_seconds;
  FrameStats totals;
  std::vector<size_t> frames_outside_map;
  const auto start = std::chrono::steady_clock::now();
  const auto note = [&](const FusionProgress& progress) {
    frame_seconds.push_back(progress.stats.seconds);
    totals = progress.totals;
    if (progress.stats.outside_map_pixels > 0) frames_outside_map.push_back(progress.frame_index);
    if (show_progress) drawProgress(progress, progress.stats.seconds);
    return true;
  };
  LabelMap map = earlier ? std::move(*earlier) : LabelMap(sequence.labels, options.map);
  fuseSequenceInto(map, sequence, options, note);
  const double total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (show_progress) std::fprintf(stderr, "\n");
  // A map with nothing in it would only make every later command fail.
  if (totals.valid_pixels == 0 && totals.outside_map_pixels > 0)
    throw Error((sequence.root / "sequence.json").string(), "depth",
                "depth points inside the map's extent, " +
                    describeMapExtent(options.map.resolution) + ", to map",
                "none in the " + std::to_string(frame_seconds.size()) + " frames fused: all " +
                    std::to_string(totals.outside_map_pixels) +
                    " measured depth pixels lie outside it; " +
                    outsideMapAdvice((sequence.root / "sequence.json").string(), totals,
                                     options.map.resolution, start_from.has_value()));
  if (totals.valid_pixels == 0)
    throw Error((sequence.root / "sequence.json").string(), "depth",
                "frames with valid depths (finite, > 0) to map",
                "none in the " + std::to_string(frame_seconds.size()) +
                    " frames fused: every depth pixel is 0 (no measurement) or invalid");
  if (const RangeMessage range =
          maxRangeMessage(totals, options.map.max_range, options.map.resolution,
                          (sequence.root / "sequence.json").string(), start_from.has_value());
      range.warning || (!args.flag("quiet") && !range.text.empty()))
    // Rays of wrong intrinsics fan out too wide and run long: the range is
    // not what to change first.
    std::fprintf(stderr, "%s: %s%s\n", range.warning ? "warning" : "note", range.text.c_str(),
                 camera_warnings.empty()
                     ? ""
                     : " (but the camera's intrinsics look wrong, warned above: correct them "
                       "before changing --max-range)");
  if (const std::string warning =
          outsideMapWarning((sequence.root / "sequence.json").string(), totals, frames_outside_map,
                            options.map.resolution, start_from.has_value());
      !warning.empty())
    std::cerr << "warning: " << warning << "\n";
  if (const std::string warning =
          nearDepthWarning(sequence, options.first_frame, options.last_frame, totals);
      !warning.empty())
    std::cerr << "warning: " << warning << "\n";
  // fuseSequenceInto has pruned the map; writing a large one takes a while
  // of its own, reported beside the fusion's time.
  const auto save_start = std::chrono::steady_clock::now();
  map.save(out);
  const double save_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - save_start).count();

  std::vector<double> sorted = frame_seconds;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  std::cout << "fused " << frame_seconds.size()
            << (frame_seconds.size() == 1 ? " frame of " : " frames of ") << sequence_path << " in "
            << std::fixed << std::setprecision(2) << total_seconds << " s (median "
            << std::setprecision(1) << median * 1000.0 << " ms/frame integration); written in "
            << std::setprecision(2) << save_seconds << " s\n";
  std::cout << std::defaultfloat << "map: resolution " << map.parameters().resolution << " m, "
            << map.numNodes()
            << " nodes, " << map.numLeaves() << " leaves, " << map.memoryBytes() / 1024
            << " KiB\n";
  // The map's own bytes leave out the frames in memory, the work buffers of
  // integration and the allocator's free lists: what the run needed is its peak.
  if (const long peak_kib = peakResidentKiB(); peak_kib > 0)
    std::cout << "memory: peak resident " << (peak_kib + 512) / 1024
              << " MiB for the whole run (frames, work buffers and the map)\n";
  const size_t occupied = printOccupiedPerLabel(map, "occupied voxels: ", std::cout);
  if (options.segmenter) std::cout << segmenterSummary(*options.segmenter) << "\n";
  // Depths were mapped, yet the network's probabilities made no voxel occupied:
  // most likely flattened by a softmax applied to probabilities (docs/segmenter.md).
  if (options.segmenter && occupied == 0) {
    const SegmenterStats stats = options.segmenter->stats();
    // The advice depends on how its output was read: a softmax over
    // probabilities flattens them; probabilities already never reached it.
    const bool read_as_scores = options.segmenter->config().output.value_or(
                                    SegmenterOutput::Scores) == SegmenterOutput::Scores;
    if (stats.inferences + stats.memory_hits + stats.disk_hits > 0)
      std::cerr
          << "warning: no voxel is occupied: the probabilities of the segmenter "
          << options.segmenter->modelPath().filename().string()
          << " never made one so (is it the model for these labels? "
          << (read_as_scores
                  ? "its output was read as scores and went through a softmax: a model "
                    "whose output is already probabilities needs \"output\": "
                    "\"probabilities\" in " +
                        segmenterConfigPath(options.segmenter->modelPath()).filename().string()
                  : std::string("its output was read as probabilities, and no label's "
                                "reached the occupancy threshold: check its labels, "
                                "channel order and normalisation (docs/segmenter.md)"))
          << ")\n";
  }
  std::cout << "wrote " << out.string() << "\n";
  return 0;
}

}  // namespace lom::cli
