// labeloctomap info / validate: look at a sequence without fusing it.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "args.hpp"
#include "commands.hpp"
#include "lom/annotations.hpp"
#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/label_map.hpp"
#include "lom/sequence.hpp"
#include "lom/text_columns.hpp"

namespace lom::cli {

namespace {

std::string fileKind(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? "(no extension)" : path.substr(dot);
}

// How many frames have the file: a name in sequence.json whose file is gone (or is
// not a regular file) is counted apart, so that the line never promises a file
// that fusion would fail to read.
std::string availability(const Sequence& sequence, std::string FrameRecord::*member) {
  std::map<std::string, size_t> kinds;
  size_t present = 0;
  size_t missing = 0;
  for (const auto& frame : sequence.frames) {
    const std::string& path = frame.*member;
    if (path.empty()) continue;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(sequence.pathOf(path), ec)) {
      ++missing;
      continue;
    }
    ++present;
    ++kinds[fileKind(path)];
  }
  std::ostringstream out;
  out << present << "/" << sequence.frames.size();
  if (present) {
    out << " (";
    bool first = true;
    for (const auto& [kind, count] : kinds) {
      out << (first ? "" : ", ") << count << " " << kind;
      first = false;
    }
    out << ")";
  }
  if (missing)
    out << "; " << missing << (missing == 1 ? " file" : " files")
        << " named in sequence.json missing or not a regular file (labeloctomap validate lists "
           "them)";
  return out.str();
}

void printProbaLabels(const Sequence& sequence, std::ostream& out) {
  std::set<int> used;
  for (const auto& frame : sequence.frames) {
    if (frame.proba.empty()) continue;
    if (frame.proba_labels.empty())
      for (int id = 0; id < sequence.labels.size(); ++id) used.insert(id);
    used.insert(frame.proba_labels.begin(), frame.proba_labels.end());
  }
  out << "labels in proba:  ";
  if (used.empty()) {
    out << "none (no frame has a proba file)\n";
    return;
  }
  out << used.size() << "\n";
  for (int id : used)
    out << "  " << std::setw(5) << id << "  " << singleLineText(sequence.labels.at(id).name)
        << "\n";
}

void printTimeSpan(const Sequence& sequence, std::ostream& out) {
  std::optional<double> first, last;
  size_t stamped = 0;
  for (const auto& frame : sequence.frames) {
    if (!frame.stamp) continue;
    ++stamped;
    first = std::min(first.value_or(*frame.stamp), *frame.stamp);
    last = std::max(last.value_or(*frame.stamp), *frame.stamp);
  }
  out << "time span:        ";
  if (!stamped) {
    out << "none (the frames have no time stamps)\n";
    return;
  }
  // Stamps of real recordings are seconds since 1970: every digit of the
  // start and the end is shown (to the microsecond), the span as before.
  out << fixedDigits(*first, 6) << " .. " << fixedDigits(*last, 6) << " (" << *last - *first
      << " s";
  if (stamped < sequence.frames.size())
    out << "; " << stamped << " of " << sequence.frames.size() << " frames have a time stamp";
  out << ")\n";
}

void printCameraPath(const Sequence& sequence, std::ostream& out) {
  Eigen::Vector3d low = sequence.frames.front().T_world_camera.translation();
  Eigen::Vector3d high = low;
  double length = 0.0;
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    const Eigen::Vector3d p = sequence.frames[i].T_world_camera.translation();
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
    if (i) length += (p - sequence.frames[i - 1].T_world_camera.translation()).norm();
  }
  // To the millimetre, however far from the origin (site coordinates).
  const auto metres = [](double v) { return fixedDigits(v, 3); };
  out << "camera path:      ";
  const char* axes = "xyz";
  for (int k = 0; k < 3; ++k)
    out << (k ? "  " : "") << axes[k] << " " << metres(low[k]) << " .. " << metres(high[k]);
  out << " m (" << sequence.frame_id << "), length " << length << " m\n";
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
  return text;
}

std::string depthRange(const DepthFigures& figures) {
  std::ostringstream out;
  out << std::setprecision(3) << figures.min << " .. " << figures.max << " m, median "
      << figures.median << " m";
  return out.str();
}

// The depths of the first, middle and last frames: enough to see a wrong
// depth_scale (the map would come out that many times too small or large),
// while reading every frame is validate's work (seconds for a long recording).
// Returns the warning about implausible depths ("" when plausible).
std::string printSampledDepths(const Sequence& sequence, std::ostream& out) {
  return sampledDepthWarning(sequence, &out);
}

}  // namespace

std::string sampledDepthWarning(const Sequence& sequence, std::ostream* out_or_null) {
  std::ostringstream discarded;
  std::ostream& out = out_or_null ? *out_or_null : discarded;
  const size_t count = sequence.frames.size();
  std::vector<size_t> sampled;
  for (const size_t i : {size_t{0}, count / 2, count - 1})
    if (std::find(sampled.begin(), sampled.end(), i) == sampled.end()) sampled.push_back(i);
  std::vector<float> metres;
  std::vector<size_t> read;
  std::vector<std::string> unreadable;
  for (const size_t i : sampled) {
    try {
      const FrameData frame = loadFrame(sequence, i, FrameParts{false, false, false, false});
      metres.insert(metres.end(), frame.depth.metres.begin(), frame.depth.metres.end());
      read.push_back(i);
    } catch (const Error&) {
      unreadable.push_back("frames[" + std::to_string(i) + "]");
    }
  }
  const DepthFigures figures =
      depthFigures(DepthImage{static_cast<int>(metres.size()), 1, std::move(metres)});
  out << "depth (sampled):  ";
  if (!read.empty()) {
    out << (read.size() == 1 ? "frame" : "frames");
    for (size_t k = 0; k < read.size(); ++k) out << (k ? ", " : " ") << read[k];
    if (figures.valid)
      out << ": " << percent(figures.validFraction()) << " of pixels valid, "
          << depthRange(figures);
    else
      out << ": no valid depth (every pixel 0 or invalid)";
  }
  if (!unreadable.empty()) {
    out << (read.empty() ? "" : "; ");
    for (size_t k = 0; k < unreadable.size(); ++k) out << (k ? ", " : "") << unreadable[k];
    out << " unreadable (labeloctomap validate says why)";
  }
  out << "\n";
  return implausibleDepthWarning(sequence, read, figures, true);
}

namespace {

// Returns the warnings, for stderr (stdout stays the summary).
std::vector<std::string> printInfo(const Sequence& sequence, std::ostream& out) {
  std::vector<std::string> warnings;
  const auto& frames = sequence.frames;
  const auto& cam = sequence.camera;
  const size_t views = static_cast<size_t>(
      std::count_if(frames.begin(), frames.end(), [](const FrameRecord& f) { return f.view; }));
  const size_t overrides = static_cast<size_t>(std::count_if(
      frames.begin(), frames.end(), [](const FrameRecord& f) { return f.camera.has_value(); }));

  out << std::setprecision(6);
  out << "sequence:         " << (sequence.root / "sequence.json").string() << "\n";
  out << "frame_id:         " << sequence.frame_id << "\n";
  out << "labels:           " << sequence.labels.size()
      << (sequence.labels == apc2016Labels() ? " (the APC 2016 set)" : "") << "\n";
  printProbaLabels(sequence, out);
  out << "camera:           " << cam.width << " x " << cam.height << "  fx " << cam.fx << "  fy "
      << cam.fy << "  cx " << cam.cx << "  cy " << cam.cy << "  depth_scale " << cam.depth_scale
      << "\n";
  if (overrides) out << "camera overrides: " << overrides << " frame(s) have their own camera\n";
  out << "frames:           " << frames.size() << "\n";
  out << "views:            " << views << "\n";
  printTimeSpan(sequence, out);
  out << "depth:            " << availability(sequence, &FrameRecord::depth) << "\n";
  if (std::string depth = printSampledDepths(sequence, out); !depth.empty())
    warnings.push_back(std::move(depth));
  const size_t from_label = static_cast<size_t>(std::count_if(
      frames.begin(), frames.end(), [](const FrameRecord& f) { return f.proba_from_label; }));
  out << "proba:            " << availability(sequence, &FrameRecord::proba);
  if (from_label) out << ", " << from_label << " made from the label images";
  out << "\n";
  const size_t placeholders = static_cast<size_t>(std::count_if(
      frames.begin(), frames.end(), [](const FrameRecord& f) { return f.label_placeholder; }));
  out << "label:            " << availability(sequence, &FrameRecord::label);
  if (placeholders)
    out << ", " << placeholders << " placeholders (all background, no ground truth)";
  out << "\n";
  out << "color:            " << availability(sequence, &FrameRecord::color) << "\n";
  printCameraPath(sequence, out);
  return warnings;
}

std::string lowerExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

// A file that starts like an OctoMap tree file (.ot or .bt), whatever its name.
bool isMapFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  // A .ot file is read as a map, so that a broken one gets the map reader's
  // message (its header) rather than the sequence reader's (JSON).
  if (lowerExtension(path) == ".ot") return true;
  std::ifstream in(path, std::ios::binary);
  std::string first_line;
  std::getline(in, first_line);
  return first_line.rfind("# Octomap OcTree", 0) == 0;
}

void printMapInfo(const std::filesystem::path& path, std::ostream& out) {
  const LabelMap map = LabelMap::load(path);
  const MapParameters& p = map.parameters();
  out << std::setprecision(6);
  out << "map:              " << path.string() << "\n";
  out << "resolution:       " << p.resolution << " m\n";
  out << "labels:           " << map.numLabels()
      << (map.labels() == apc2016Labels() ? " (the APC 2016 set)" : "") << "\n";
  out << "parameters:       p_miss " << p.p_miss << "  threshold " << p.occupancy_threshold
      << "  clamping [" << p.clamp_min << ", " << p.clamp_max << "]  max range ";
  if (p.max_range > 0.0)
    out << p.max_range << " m\n";
  else
    out << "unlimited\n";
  out << "candidates:       ";
  if (!map.fusedCandidates().recorded) {
    out << "not recorded (a map of data version 1 or 2)\n";
  } else if (const auto& ids = map.fusedCandidates().labels) {
    for (size_t i = 0; i < ids->size(); ++i) out << (i ? "," : "") << (*ids)[i];
    out << " (the labels its frames were fused with)\n";
  } else {
    out << "every label\n";
  }
  out << "probabilities:    ";
  if (!map.fusedEvidence().recorded)
    out << "not recorded (a map of data version 1 to 3)\n";
  else
    out << describeEvidence(map.fusedEvidence()) << "\n";
  out << "world frame:      ";
  if (!map.worldFrame().recorded)
    out << "not recorded (a map of data version 1 to 4)\n";
  else if (map.worldFrame().frame_id.empty())
    out << "none yet (no frame fused)\n";
  else
    out << map.worldFrame().frame_id << " (the frame its fused poses were in)\n";
  out << "camera views:     " << map.cameraViews().views;
  if (const auto up = map.camerasUp())
    out << ", mean up (" << up->x() << ", " << up->y() << ", " << up->z() << ")";
  else if (map.cameraViews().views > 0)
    out << ", their up directions disagree";
  out << "\n";
  if (const auto plane = map.levelPlane()) {
    const Eigen::Vector3d& n = plane->normal;
    out << "up:               (" << n.x() << ", " << n.y() << ", " << n.z()
        << "), the normal of the largest level plane (" << plane->voxels << " of " << plane->sampled
        << " occupied voxels), " << std::fixed << std::setprecision(1)
        << std::acos(std::clamp(n.dot(*map.camerasUp()), -1.0, 1.0)) * 180.0 / M_PI
        << std::defaultfloat << std::setprecision(6) << " deg from the cameras' mean up\n";
  }
  out << "tree:             " << map.numNodes() << " nodes, " << map.numLeaves() << " leaves, "
      << map.memoryBytes() / 1024 << " KiB\n";
  if (const auto bounds = map.bounds()) {
    out << "known voxels:     ";
    const char* axes = "xyz";
    for (int k = 0; k < 3; ++k)
      out << (k ? "  " : "") << axes[k] << " " << bounds->first[k] << " .. " << bounds->second[k];
    out << " m\n";
  }
  printOccupiedPerLabel(map, "occupied voxels:  ", out);
}

// "depth: ..." for validate: what every frame's depths are, so that a scale
// off by a factor that still looks plausible can be seen; "" when none was read.
std::string depthSummary(const SequenceCheck& check) {
  size_t read = 0;
  std::optional<double> low_fraction, high_fraction, low_median, high_median;
  for (const auto& frame : check.frame_depths) {
    if (!frame) continue;
    ++read;
    low_fraction = std::min(low_fraction.value_or(1.0), frame->validFraction());
    high_fraction = std::max(high_fraction.value_or(0.0), frame->validFraction());
    if (!frame->valid) continue;
    low_median = std::min(low_median.value_or(frame->median), frame->median);
    high_median = std::max(high_median.value_or(frame->median), frame->median);
  }
  if (read == 0) return "";
  std::ostringstream out;
  out << std::setprecision(3) << "depth: " << percent(check.depths.validFraction())
      << " of the pixels of " << read << (read == 1 ? " frame" : " frames") << " read valid";
  if (read > 1)
    out << " (" << percent(*low_fraction) << " .. " << percent(*high_fraction) << " per frame)";
  if (check.depths.valid) {
    out << ", " << depthRange(check.depths);
    if (read > 1) out << " (frame medians " << *low_median << " .. " << *high_median << " m)";
  }
  return out.str();
}

// The sequence's boxes (annotations.json, or the YAML box file of the
// original experiments, beside sequence.json), read as score and the studio
// read them: a file that does not load, or boxes that score refuses
// (labels the sequence does not have, another frame), are problems; what
// score only warns about is a warning.
void checkSequenceBoxes(const Sequence& sequence, std::vector<Problem>& problems,
                        std::vector<std::string>& warnings) {
  const std::string json_file = (sequence.root / "sequence.json").string();
  for (const char* name : {"annotations.json", "annotations.yaml", "annotations.yml"}) {
    const std::filesystem::path file = sequence.root / name;
    std::error_code ec;
    // A folder or a dangling link of that name gets the loader's message.
    if (!std::filesystem::exists(std::filesystem::symlink_status(file, ec))) continue;
    Annotations annotations;
    try {
      annotations = loadAnnotationsFor(file, sequence.labels, sequence.frame_id);
    } catch (const Error& e) {
      // The loader stops at the first problem of a file.
      problems.push_back(e.problem());
      continue;
    }
    if (auto problem = frameIdProblem(sequence, annotations, file.string()))
      problems.push_back(std::move(*problem));
    if (annotations.boxes.empty())
      warnings.push_back(file.string() + ": boxes: none (score needs at least one box)");
    // Every box score would refuse, not only the first as score says.
    for (Problem& problem : boxLabelProblems(annotations, sequence.labels.size(), file.string(),
                                             "the sequence " + json_file))
      problems.push_back(std::move(problem));
    for (auto& warning : boxNameWarnings(annotations, sequence.labels, file.string(), json_file))
      warnings.push_back(std::move(warning));
  }
}

}  // namespace

int runInfo(const Words& words) {
  const Args args(words, {});
  args.expectOnly({}, 1);
  const std::string path = args.positional(0, "SEQ (a sequence folder or sequence.json) or MAP.ot");
  // A missing MAP.ot (a mistyped name) gets the map reader's message, not
  // the sequence reader's.
  const std::string extension = lowerExtension(path);
  std::error_code ec;
  const bool missing_map =
      (extension == ".ot" || extension == ".bt") && !std::filesystem::exists(path, ec);
  if (missing_map || isMapFile(path)) {
    printMapInfo(path, std::cout);
    return 0;
  }
  const Sequence sequence = loadSequence(path);
  const std::vector<std::string> warnings = printInfo(sequence, std::cout);
  std::cout.flush();
  for (const auto& warning : warnings) std::cerr << "warning: " << warning << "\n";
  return 0;
}

int runValidate(const Words& words) {
  const Args args(words, {});
  args.expectOnly({}, 1);
  const std::string path = args.positional(0, "SEQ (a sequence folder or sequence.json)");
  std::vector<Problem> problems;
  std::vector<std::string> warnings;
  std::string depths;
  size_t frames = 0;
  try {
    if (isMapFile(path))
      throw Error(path, "",
                  "a sequence folder or sequence.json (validate checks sequences; "
                  "labeloctomap info MAP.ot describes a map)",
                  "a map file");
    const Sequence sequence = loadSequence(path);
    const std::string json_file = (sequence.root / "sequence.json").string();
    frames = sequence.frames.size();
    SequenceCheck check = checkSequence(sequence);
    problems = std::move(check.problems);
    depths = depthSummary(check);
    // No voxel size yet: the extents at the coarsest and the finest that fusion takes.
    CameraExtentCheck extents = checkCameraExtents(sequence);
    problems.insert(problems.end(), extents.problems.begin(), extents.problems.end());
    // The pose and camera warnings name fields of sequence.json: with its
    // path, as the problems and the other warnings are.
    if (!extents.warning.empty()) warnings.push_back(json_file + ": " + extents.warning);
    for (const auto& jump : cameraJumps(sequence)) warnings.push_back(json_file + ": " + jump);
    for (const auto& camera : implausibleIntrinsics(sequence))
      warnings.push_back(json_file + ": " + camera);
    warnings.insert(warnings.end(), check.warnings.begin(), check.warnings.end());
    checkSequenceBoxes(sequence, problems, warnings);
  } catch (const Error& e) {
    problems.push_back(e.problem());
  }
  if (!depths.empty()) std::cout << depths << "\n";
  // Poses are valid numbers either way: a jump, or a camera that only coarser
  // voxels hold, is worth a look, not a failure.
  for (const auto& warning : warnings) std::cout << "warning: " << warning << "\n";
  if (problems.empty()) {
    std::cout << "OK: " << frames << " frames valid";
    if (!warnings.empty())
      std::cout << " (" << warnings.size() << (warnings.size() == 1 ? " warning" : " warnings")
                << ")";
    std::cout << "\n";
    return 0;
  }
  for (const auto& problem : problems) std::cout << problem.message() << "\n";
  std::cerr << "labeloctomap validate: " << problems.size()
            << (problems.size() == 1 ? " problem" : " problems") << " found in " << path << "\n";
  return 1;
}

size_t printOccupiedPerLabel(const LabelMap& map, const std::string& heading, std::ostream& out) {
  const auto counts = map.occupiedCountPerLabel();
  size_t occupied = 0;
  for (const auto& [label, count] : counts) occupied += count;
  out << heading << occupied << "\n";
  for (const auto& [label, count] : counts)
    out << "  " << padLeft(std::to_string(label), 5) << "  "
        << padRight(singleLineText(map.labels().at(label).name), 36)
        << padLeft(std::to_string(count), 8) << "\n";
  return occupied;
}

}  // namespace lom::cli
