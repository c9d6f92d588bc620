// Scoring from files: one sequence (scoreSequence) or a batch list of them.
#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>

#include "file_checks.hpp"
#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/segmenter.hpp"

namespace lom {

namespace fs = std::filesystem;

namespace {

// Splits a list line into whitespace-separated fields; "double quotes" keep spaces.
std::vector<std::string> splitFields(const std::string& line, bool& unterminated_quote) {
  std::vector<std::string> fields;
  std::string current;
  bool in_field = false, quoted = false;
  for (char c : line) {
    if (quoted) {
      if (c == '"') quoted = false;
      else current += c;
    } else if (c == '"') {
      quoted = in_field = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      if (in_field) fields.push_back(current);
      current.clear();
      in_field = false;
    } else {
      current += c;
      in_field = true;
    }
  }
  if (in_field) fields.push_back(current);
  unterminated_quote = quoted;
  return fields;
}

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

std::string candidateList(const std::optional<std::vector<int>>& candidates) {
  if (!candidates) return "every label";
  std::string text;
  for (const int id : *candidates) text += (text.empty() ? "" : ",") + std::to_string(id);
  return "candidates " + text;
}

// Candidates as a set: sorted, once each, nullopt when every label is listed.
std::optional<std::vector<int>> candidateSet(std::optional<std::vector<int>> candidates,
                                             int label_count) {
  if (!candidates) return candidates;
  std::sort(candidates->begin(), candidates->end());
  candidates->erase(std::unique(candidates->begin(), candidates->end()), candidates->end());
  if (static_cast<int>(candidates->size()) >= label_count) candidates.reset();
  return candidates;
}

void describeMapCandidates(EvaluationReport& report, const FusedCandidates& fused, int label_count,
                           const std::string& map_file, bool from_map) {
  if (!fused.recorded) return;
  const auto used = candidateSet(report.candidates, label_count);
  if (from_map) {
    if (fused.labels)
      report.map_candidates_note = map_file + " was fused with " + candidateList(fused.labels) +
                                   "; the projection baselines and the 2D metrics use them too";
    return;
  }
  if (used == fused.labels) return;
  report.map_candidates_warning =
      map_file + " was fused with " + candidateList(fused.labels) +
      ", but the projection baselines and the 2D metrics use " + candidateList(used) +
      ": the comparison is not matched (leave out --candidates to use the map's)";
}

}  // namespace

std::string sequenceName(const fs::path& sequence_folder_or_json) {
  fs::path folder = sequence_folder_or_json;
  if (folder.extension() == ".json") folder = folder.parent_path();
  std::error_code ec;
  const fs::path absolute = fs::weakly_canonical(fs::absolute(folder.empty() ? fs::path(".") : folder), ec);
  const fs::path normal = (ec ? folder : absolute).lexically_normal();
  std::string name = normal.filename().string();
  if (name.empty() || name == ".") name = normal.parent_path().filename().string();
  return name.empty() ? "sequence" : name;
}

void checkAnnotationsFor(const ScoreInputs& inputs) {
  const Sequence sequence = loadSequence(inputs.sequence);
  const Annotations annotations =
      loadAnnotationsFor(inputs.annotations, sequence.labels, sequence.frame_id);
  checkAnnotationsForSequence(sequence, annotations, inputs.annotations.string());
}

void describeMapFile(EvaluationReport& report, const LabelMap& map, const Sequence& sequence,
                     const std::string& map_file, bool candidates_from_map, size_t first_frame,
                     size_t last_frame, const Segmenter* segmenter) {
  report.map_file = map_file;
  report.map_fit = mapFitOf(map, sequence);
  describeMapCandidates(report, map.fusedCandidates(), sequence.labels.size(), map_file,
                        candidates_from_map);
  if (!report.map_candidates_warning.empty())
    report.warnings.push_back(report.map_candidates_warning);
  if (const std::string fit = poorMapFitWarning(*report.map_fit, map_file); !fit.empty())
    report.warnings.push_back(fit + " Its scores would mean little.");
  // Every fused frame is recorded in the map (a map written before the
  // record says 0): a map fused from other frames than those scored is
  // compared with baselines that saw more, or fewer, views than it did.
  const size_t end = std::min(last_frame, sequence.frames.size());
  const size_t scored = end > first_frame ? end - first_frame : 0;
  const std::uint32_t fused = map.cameraViews().views;
  const std::string frames_text =
      "frames " + std::to_string(first_frame) + " to " + std::to_string(end == 0 ? 0 : end - 1);
  // The map's probabilities against the baselines': a map fused with a
  // segmenter scored against projections of the frames' own probabilities
  // (or the other way round) compares two segmentations, not two methods.
  const FusedEvidence& map_evidence = map.fusedEvidence();
  if (map_evidence.recorded && !map_evidence.empty()) {
    const FusedEvidence baselines = evidenceOf(sequence, first_frame, end, segmenter);
    if (!baselines.empty() && baselines != map_evidence) {
      std::string fix;
      if (map_evidence.models.size() == 1)
        fix = "give --segmenter " + map_evidence.models.front() +
              (map_evidence.own_probabilities ? "" : " as the map was fused") + ", or ";
      report.warnings.push_back(map_file + " was fused with " + describeEvidence(map_evidence) +
                                ", but the projection baselines and the 2D metrics read " +
                                describeEvidence(baselines) + ": the comparison is not matched; " +
                                fix + "score without --map");
    }
  }
  if (fused > 0 && fused == scored &&
      !sameCameraViews(map.cameraViews(), cameraViewsOf(sequence, first_frame, end)))
    report.warnings.push_back(
        map_file + " was fused from " + std::to_string(fused) +
        (fused == 1 ? " frame" : " frames") + ", as many as are scored, but not from " +
        frames_text +
        ": the directions its cameras looked in differ from theirs, so the baselines project "
        "other views than the map fused; fuse and score the same frames (--frames), or score "
        "without --map");
  else if (fused > 0 && fused != scored)
    report.warnings.push_back(
        map_file + " was fused from " + std::to_string(fused) +
        (fused == 1 ? " frame" : " frames") + ", the baselines project the " +
        std::to_string(scored) + (scored == 1 ? " frame" : " frames") + " scored (" + frames_text +
        "): the comparison is not matched; fuse and score the same frames (--frames), or score "
        "without --map");
}

EvaluationReport scoreSequence(const ScoreInputs& inputs, const EvaluationOptions& options,
                               const EvaluationProgressFn& progress) {
  const Sequence sequence = loadSequence(inputs.sequence);
  const Annotations annotations =
      loadAnnotationsFor(inputs.annotations, sequence.labels, sequence.frame_id);
  EvaluationOptions named = options;
  named.annotations_file = inputs.annotations.string();
  // Reject unusable annotations before the long fusion.
  checkAnnotationsForSequence(sequence, annotations, named.annotations_file);

  if (inputs.map) {
    named.map_file = inputs.map->string();
    LabelMap map = LabelMap::load(*inputs.map);
    if (inputs.occupancy_threshold) map.setOccupancyThreshold(*inputs.occupancy_threshold);
    const FusedCandidates& fused = map.fusedCandidates();
    if (options.candidates_from_map && fused.recorded) named.fusion.candidates = fused.labels;
    EvaluationReport report = evaluate(sequence, annotations, map, named, progress);
    describeMapFile(report, map, sequence, named.map_file, options.candidates_from_map,
                    options.fusion.first_frame, options.fusion.last_frame,
                    options.fusion.segmenter.get());
    return report;
  }
  named.map_file = (sequence.root / "sequence.json").string() + " (fused)";
  FrameStats totals;
  std::vector<size_t> frames_outside_map;
  LabelMap map = fuseSequence(sequence, options.fusion, [&](const FusionProgress& fused) {
    totals = fused.totals;
    if (fused.stats.outside_map_pixels > 0) frames_outside_map.push_back(fused.frame_index);
    return !progress || progress(EvaluationProgress{"fusing", fused.done, fused.total});
  });
  if (progress && !progress(EvaluationProgress{"fusing", 1, 1})) throw EvaluationCancelled();
  EvaluationReport report = evaluate(sequence, annotations, map, named, progress);
  const size_t first = std::min(options.fusion.first_frame, sequence.frames.size());
  const size_t last = std::min(options.fusion.last_frame, sequence.frames.size());
  if (last > first) report.fused_frames = std::make_pair(first, last - 1);
  // Named only when it ran: frames with a proba image of their own are fused
  // as they are (one an import made from the label image is replaced).
  for (size_t i = first; i < last && options.fusion.segmenter; ++i)
    if (segmenterRunsOn(sequence, i, options.fusion.segmenter.get())) {
      report.segmenter = options.fusion.segmenter->modelPath().string();
      break;
    }
  report.fusion_totals = totals;
  report.frames_outside_map = std::move(frames_outside_map);
  return report;
}

std::vector<BatchEntry> readBatchList(const fs::path& list) {
  if (const std::string why = notARegularFile(list); !why.empty())
    throw Error(list.string(), "", "an existing batch list file", why);
  std::ifstream in(list);
  if (!in) throw Error(list.string(), "", "a readable batch list file", "cannot open it");
  const fs::path base = list.has_parent_path() ? list.parent_path() : fs::path(".");
  auto resolve = [&](const std::string& text) {
    const fs::path path(text);
    return path.is_absolute() ? path : base / path;
  };

  std::vector<BatchEntry> entries;
  std::map<std::string, size_t> line_of_name;
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    // A byte-order mark some editors put at the start of a UTF-8 file is not
    // part of the first path.
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    const std::string text = trimmed(line);
    if (text.empty() || text[0] == '#') continue;
    const std::string where = "line " + std::to_string(number);
    bool unterminated = false;
    const std::vector<std::string> fields = splitFields(text, unterminated);
    if (unterminated) throw Error(list.string(), where, "a closing double quote", text);
    if (fields.size() < 2 || fields.size() > 3)
      throw Error(list.string(), where, "SEQ_PATH ANNOTATIONS_PATH [MAP.ot]", text);
    BatchEntry entry;
    entry.line = number;
    entry.inputs.sequence = resolve(fields[0]);
    entry.inputs.annotations = resolve(fields[1]);
    if (fields.size() == 3) entry.inputs.map = resolve(fields[2]);
    const fs::path json = entry.inputs.sequence.extension() == ".json"
                              ? entry.inputs.sequence
                              : entry.inputs.sequence / "sequence.json";
    if (const std::string why = notARegularFile(json); !why.empty())
      throw Error(list.string(), where + " (SEQ_PATH)", "a sequence folder holding sequence.json",
                  json.string() + ": " + why);
    if (const std::string why = notARegularFile(entry.inputs.annotations); !why.empty())
      throw Error(list.string(), where + " (ANNOTATIONS_PATH)", "an existing annotations file",
                  entry.inputs.annotations.string() + ": " + why);
    if (entry.inputs.map)
      if (const std::string why = notARegularFile(*entry.inputs.map); !why.empty())
        throw Error(list.string(), where + " (MAP)", "an existing .ot map file",
                    entry.inputs.map->string() + ": " + why);
    entry.name = sequenceName(entry.inputs.sequence);
    const auto [previous, inserted] = line_of_name.emplace(entry.name, number);
    if (!inserted)
      throw Error(list.string(), where,
                  "sequence folders with distinct names (reports go to DIR/<name>/)",
                  "\"" + entry.name + "\" again (also on line " + std::to_string(previous->second) + ")");
    entries.push_back(std::move(entry));
  }
  if (entries.empty()) throw Error(list.string(), "", "at least one line SEQ_PATH ANNOTATIONS_PATH", "none");
  return entries;
}

}  // namespace lom
