// labeloctomap import: a ROS 1 bag or a dataset folder into a v1 sequence.
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>

#include "args.hpp"
#include "commands.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/import.hpp"
#include "lom/sequence.hpp"
#include "output_paths.hpp"

namespace lom::cli {

namespace {

const char* const kHelp =
    "usage: labeloctomap import KIND SRC --out SEQ [options]\n"
    "\n"
    "KIND: auto, rosbag, frames, tum, quaternion, scannet, apc-shelf (docs/import.md)\n"
    "\n"
    "camera and depth:\n"
    "  --intrinsics fx,fy,cx,cy|FILE  camera override (FILE: 4 numbers, 3x3 or 4x4 matrix)\n"
    "  --depth-scale S        metres per unit of 16-bit depth (default: the layout's own)\n"
    "  --min-depth M          drop nearer depths (default 0.1 m)\n"
    "  --max-depth M          drop farther depths (default: no limit)\n"
    "  --flying-ratio R       flying-pixel filter: drop a pixel whose neighbour differs by\n"
    "                         more than R x its depth (default 0.05)\n"
    "  --flying-radius N      neighbourhood of the flying-pixel filter (default 1)\n"
    "  --no-flying-filter     keep flying pixels\n"
    "  --bilateral N          edge-preserving smoothing with radius N pixels (default 0: off)\n"
    "labels:\n"
    "  --labels FILE|apc2016  label names, one per line, label 0 (background) first\n"
    "  --label-confidence C   one-hot confidence of label images (default 0.9)\n"
    "frames and time:\n"
    "  --first N --every N --max-frames N   frame subset (defaults 0, 1, all; --max-frames 0\n"
    "                         also means all)\n"
    "  --time-tolerance S     matching of images and poses by stamp (default 0.02 s)\n"
    "  --time-offset S        added to image stamps before the pose lookup (default 0)\n"
    "ROS bags (topics are detected when not given):\n"
    "  --depth-topic T --color-topic T --camera-info-topic T --proba-topic T --label-topic T\n"
    "  --fixed-frame F        world frame (default: root of the camera's tf tree)\n"
    "  --camera-frame F       camera optical frame (default: the depth images' frame_id)\n"
    "  --max-pose-gap S       skip a frame whose pose tf would interpolate between samples\n"
    "                         of a moving link more than S apart (default 0.5 s; give a\n"
    "                         large number to allow any gap)\n"
    "output:\n"
    "  --no-color             leave colour images out\n"
    "  --overwrite            replace a sequence already in SEQ\n"
    "  --quiet                no progress bar\n";

LabelSet labelsFromOption(const std::string& value) {
  try {
    return labelsOption(value);
  } catch (const Error& e) {
    Problem problem = e.problem();
    problem.field = problem.field.empty() ? "--labels" : "--labels, " + problem.field;
    throw Error(problem);
  }
}

size_t nonNegative(const Args& args, const std::string& name, size_t fallback) {
  return static_cast<size_t>(
      args.integer(name, static_cast<long>(fallback), 0, std::numeric_limits<long>::max()));
}

// True when `text` can only have been meant as fx,fy,cx,cy (digits, signs, points,
// exponents, commas and blanks, or four comma-separated fields such as
// "nan,519,325.5,253.5"), not as a file name.
bool looksLikeNumbers(const std::string& text) {
  if (text.empty()) return false;
  if (text.find_first_not_of("0123456789+-.eE, \t") == std::string::npos) return true;
  return std::count(text.begin(), text.end(), ',') == 3 && text.find('/') == std::string::npos;
}

// --intrinsics: numbers that do not fit are a mistake in the call; a file that is
// missing or does not hold a camera matrix is an input problem.
CameraIntrinsics intrinsicsOption(const std::string& value) {
  std::error_code ec;
  if (std::filesystem::exists(value, ec) || !looksLikeNumbers(value)) {
    if (!std::filesystem::exists(value, ec))
      throw Error(value, "--intrinsics", "fx,fy,cx,cy or an existing camera matrix file",
                  "no such file");
    return parseIntrinsics(value);
  }
  try {
    return parseIntrinsics(value);
  } catch (const Error& e) {
    throw UsageError("option --intrinsics expects fx,fy,cx,cy or a camera matrix file: " +
                     std::string(e.what()));
  }
}

// Options only a ROS bag reads: given for another source they would be ignored without a word.
const char* const kRosbagOnlyOptions[] = {"depth-topic",  "color-topic", "camera-info-topic",
                                          "proba-topic",  "label-topic", "fixed-frame",
                                          "camera-frame", "max-pose-gap"};

void refuseRosbagOptionsFor(const Args& args, const std::optional<SourceKind>& kind,
                            const std::string& source) {
  for (const char* option : kRosbagOnlyOptions) {
    if (!args.option(option)) continue;
    std::optional<SourceKind> read_as = kind;
    if (!read_as) read_as = detectSource(source).kind;
    // A source that is not recognised fails on its own, with what was looked for.
    if (!read_as || *read_as == SourceKind::RosBag) return;
    throw UsageError(std::string("option --") + option + " applies to ROS bags only; " + source +
                     " is read as " + sourceKindName(*read_as) +
                     (kind ? " (the KIND given)" : " (detected)") + ": leave the option out");
  }
}

// The signal that asked the import to stop (0: none). Written by the handler, read
// by the progress callback between frames, where the import can stop and remove
// what it wrote: a process killed halfway would leave a half-written folder.
volatile std::sig_atomic_t g_stop_signal = 0;

// A second signal stops the process at once (an import stuck before its next
// frame), removing what it had written so far.
extern "C" void onStopSignal(int signal) {
  if (g_stop_signal) removePendingOutputsAndDie(signal);
  g_stop_signal = signal;
}

// SIGINT and SIGTERM stop the import for as long as it runs; the earlier
// handlers come back afterwards. A signal the process was started to ignore
// (a background job of a script) stays ignored.
class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    struct sigaction action {};
    action.sa_handler = onStopSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    for (size_t i = 0; i < 2; ++i) {
      installed_[i] = sigaction(kSignals[i], nullptr, &previous_[i]) == 0 &&
                      previous_[i].sa_handler != SIG_IGN &&
                      sigaction(kSignals[i], &action, nullptr) == 0;
    }
  }
  ~StopSignals() {
    for (size_t i = 0; i < 2; ++i)
      if (installed_[i]) sigaction(kSignals[i], &previous_[i], nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  static constexpr int kSignals[2] = {SIGINT, SIGTERM};
  struct sigaction previous_[2]{};
  bool installed_[2] = {false, false};
};

const char* signalName(int signal) { return signal == SIGINT ? "SIGINT" : "SIGTERM"; }

}  // namespace

const char* importHelp() { return kHelp; }

int runImport(const Words& words) {
  const Args args(words, {"no-flying-filter", "no-color", "overwrite", "quiet"});
  args.expectOnly({"out",
                   "intrinsics",
                   "depth-scale",
                   "min-depth",
                   "max-depth",
                   "flying-ratio",
                   "flying-radius",
                   "no-flying-filter",
                   "bilateral",
                   "labels",
                   "label-confidence",
                   "first",
                   "every",
                   "max-frames",
                   "time-tolerance",
                   "time-offset",
                   "depth-topic",
                   "color-topic",
                   "camera-info-topic",
                   "proba-topic",
                   "label-topic",
                   "fixed-frame",
                   "camera-frame",
                   "max-pose-gap",
                   "no-color",
                   "overwrite",
                   "quiet"},
                  2);
  const std::string kind_name = args.positional(0, "KIND (auto, rosbag, frames, tum, quaternion, scannet, apc-shelf)");
  const std::string source = args.positional(1, "SRC (a bag file or dataset folder)");
  const std::string out = args.required("out");
  CommandInputs inputs;
  inputs.addFile(source, "the import source");
  // A dataset folder stays as it was: the sequence goes beside it, not into it.
  if (std::error_code ec; std::filesystem::is_directory(source, ec))
    inputs.addFolder(source, "the import source folder");
  checkOutputFolder(out, "out", "the sequence", inputs);
  checkHoldsNoFramesOfSequencesAbove(out, "out", "the import");
  // The import replaces OUT's sequence.json and frame folders: a source among
  // them would be deleted with them (a mistake in the call, as --out inside
  // the source is).
  for (const char* part : {"sequence.json", "depth", "color", "proba", "label"})
    if (isSameOrInside(source, std::filesystem::path(out) / part))
      throw UsageError(
          "SRC " + source + " lies in " + (std::filesystem::path(out) / part).string() +
          ", which the import into --out " + out + " replaces; move the recording out of it first");

  std::optional<SourceKind> kind;
  if (kind_name != "auto") {
    kind = sourceKindFromName(kind_name);
    if (!kind || *kind == SourceKind::Sequence)
      throw UsageError("unknown KIND '" + kind_name +
                       "' (auto, rosbag, frames, tum, quaternion, scannet, apc-shelf)");
  }

  refuseRosbagOptionsFor(args, kind, source);

  ImportOptions options;
  if (args.option("depth-scale")) options.depth_scale = args.number("depth-scale", 0.001);
  auto& filter = options.depth_filter;
  filter.min_depth = args.number("min-depth", filter.min_depth);
  filter.max_depth = args.number("max-depth", filter.max_depth);
  filter.flying_pixel_ratio = args.number("flying-ratio", filter.flying_pixel_ratio);
  filter.flying_pixel_radius =
      static_cast<int>(args.integer("flying-radius", filter.flying_pixel_radius));
  filter.flying_pixels = !args.flag("no-flying-filter");
  filter.bilateral_radius = static_cast<int>(args.integer("bilateral", filter.bilateral_radius));
  options.label_confidence = args.number("label-confidence", options.label_confidence);
  options.first_frame = nonNegative(args, "first", 0);
  options.frame_step =
      static_cast<size_t>(args.integer("every", 1, 1, std::numeric_limits<long>::max()));
  options.max_frames = nonNegative(args, "max-frames", 0);
  options.time_tolerance = args.number("time-tolerance", options.time_tolerance);
  options.time_offset = args.number("time-offset", options.time_offset);
  options.rosbag.depth_topic = args.option("depth-topic").value_or("");
  options.rosbag.color_topic = args.option("color-topic").value_or("");
  options.rosbag.camera_info_topic = args.option("camera-info-topic").value_or("");
  options.rosbag.proba_topic = args.option("proba-topic").value_or("");
  options.rosbag.label_topic = args.option("label-topic").value_or("");
  options.rosbag.fixed_frame = args.option("fixed-frame").value_or("");
  options.rosbag.camera_frame = args.option("camera-frame").value_or("");
  options.rosbag.max_pose_gap = args.number("max-pose-gap", options.rosbag.max_pose_gap);
  if (!(options.rosbag.max_pose_gap > 0.0))
    throw UsageError(
        "option --max-pose-gap expects a positive number of seconds (a large one "
        "allows any gap), got '" +
        *args.option("max-pose-gap") + "'");
  options.write_color = !args.flag("no-color");
  options.overwrite = args.flag("overwrite");
  // Files named by options are read once the call itself is known to be right.
  if (auto value = args.option("intrinsics")) options.intrinsics = intrinsicsOption(*value);
  if (auto value = args.option("labels")) options.labels = labelsFromOption(*value);

  const bool show_progress = !args.flag("quiet") && ::isatty(STDERR_FILENO);
  ImportReport report;
  StopSignals stop_signals;
  try {
    report = importSource(kind, source, out, options, [&](const ImportProgress& progress) {
      if (g_stop_signal) return false;
      if (show_progress) {
        constexpr int kWidth = 30;
        const int filled =
            progress.total ? static_cast<int>(kWidth * progress.done / progress.total) : 0;
        std::fprintf(stderr, "\r[%s%s] %zu/%zu frames", std::string(filled, '#').c_str(),
                     std::string(kWidth - filled, '.').c_str(), progress.done, progress.total);
        std::fflush(stderr);
      }
      return true;
    });
  } catch (const Error& e) {
    if (show_progress) std::fprintf(stderr, "\n");
    // Option values out of range are usage errors; the rest is about the data.
    if (e.problem().file.empty()) {
      const std::string& field = e.problem().field;
      const std::string option = field == "time_tolerance"        ? "time-tolerance"
                                 : field == "time_offset"         ? "time-offset"
                                 : field == "max_pose_gap"        ? "max-pose-gap"
                                 : field == "label_confidence"    ? "label-confidence"
                                 : field == "depth_scale"         ? "depth-scale"
                                 : field == "min_depth"           ? "min-depth"
                                 : field == "max_depth"           ? "max-depth"
                                 : field == "flying_pixel_ratio"  ? "flying-ratio"
                                 : field == "flying_pixel_radius" ? "flying-radius"
                                 : field == "bilateral_radius"    ? "bilateral"
                                                                  : field;
      throw UsageError("option --" + option + " expects " + e.problem().expected + ", got " +
                       e.problem().found);
    }
    throw;
  }
  if (show_progress) std::fprintf(stderr, "\n");
  if (const int signal = g_stop_signal; signal && report.cancelled) {
    std::cerr << "labeloctomap import: interrupted by " << signalName(signal) << " after "
              << report.frames_written << " frames; nothing was kept: the files written to " << out
              << " were removed"
              << (options.overwrite ? " (a sequence it held before is as it was)" : "") << "\n";
    return 128 + signal;
  }
  if (g_stop_signal)
    std::cerr << "note: " << signalName(g_stop_signal)
              << " came after the last frame was written: the sequence is complete and kept\n";
  std::cout << report.text();
  std::cout << "wrote " << out << "/sequence.json\n";
  // Intrinsics no depth camera has (given in millimetres, or for another image size).
  const Sequence written = loadSequence(out);
  for (const auto& camera : implausibleIntrinsics(written))
    std::cerr << "warning: " << out << "/sequence.json: " << camera << "\n";
  // A --depth-scale (or a recording's own) that no depth camera measures.
  if (const std::string depth = sampledDepthWarning(written); !depth.empty())
    std::cerr << "warning: " << depth << "\n";
  return 0;
}

}  // namespace lom::cli
