// labeloctomap score: per-object IU_3d of LabelOctoMap against the projection
// baselines, for one sequence or a batch list (docs/evaluation.md).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "args.hpp"
#include "commands.hpp"
#include "lom/annotations.hpp"
#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/label_map.hpp"
#include "lom/report.hpp"
#include "output_paths.hpp"
#include "segmenter_option.hpp"

namespace lom::cli {

namespace {

// The batch summary files written into DIR beside the report folders.
constexpr const char* kAggregateFiles[] = {"aggregate.json", "aggregate.csv", "aggregate.md",
                                           "aggregate.svg"};

namespace fs = std::filesystem;

EvaluationProgressFn progressPrinter(bool enabled, const std::string& prefix) {
  if (!enabled) return {};
  return [prefix](const EvaluationProgress& p) {
    std::fprintf(stderr, "\r%s%-10s %zu/%zu   ", prefix.c_str(), p.stage.c_str(), p.done, p.total);
    std::fflush(stderr);
    return true;
  };
}

// Options that only make sense against a given sequence; the sequence's files
// become inputs. A map fused here must hold every camera (`fused`: no map given).
void checkOptionsForSequence(const fs::path& sequence_path, const EvaluationOptions& options,
                             bool fused, CommandInputs& inputs) {
  const Sequence sequence = loadSequence(sequence_path);
  checkFusionOptionsForSequence(options.fusion, sequence);
  if (fused)
    checkCamerasInsideMap(sequence, options.fusion.map.resolution, options.fusion.first_frame,
                          options.fusion.last_frame);
  inputs.addSequence(sequence);
}

// The frame files scoring reads (depth, proba, label; the colour image when a
// segmenter runs on the frame) exist and are files: a batch checks every
// line's before its first fusion, so that a missing file on its last line
// does not wait for the sequences before it to be fused and scored.
void checkFrameFilesExist(const fs::path& sequence_path, const EvaluationOptions& options,
                          bool with_segmenter) {
  const Sequence sequence = loadSequence(sequence_path);
  const std::string json = (sequence.root / "sequence.json").string();
  const size_t end = std::min(options.fusion.last_frame, sequence.frames.size());
  for (size_t i = options.fusion.first_frame; i < end; ++i) {
    const FrameRecord& frame = sequence.frames[i];
    const auto check = [&](const std::string& relative, const char* field) {
      if (relative.empty()) return;
      const fs::path file = sequence.root / relative;
      std::error_code ec;
      const fs::file_status status = fs::status(file, ec);
      if (fs::is_regular_file(status)) return;
      throw Error(json, "frames[" + std::to_string(i) + "]." + field,
                  "an existing image file (" + file.string() + ")",
                  fs::exists(status) ? "not a regular file" : "no such file");
    };
    check(frame.depth, "depth");
    check(frame.proba, "proba");
    check(frame.label, "label");
    if (with_segmenter && (frame.proba.empty() || frame.proba_from_label))
      check(frame.color, "color");
  }
}

// Report folders in DIR that this batch did not write (an earlier run's, of
// sequences not on this list) sit beside its aggregate: said, since a script
// collecting DIR/*/report.json would mix them in. They are not removed: they
// may be someone's results.
// A warning, so said with --quiet too.
void warnReportsOfOtherRuns(const fs::path& out, const std::vector<BatchEntry>& entries) {
  std::set<std::string> listed;
  for (const auto& entry : entries) listed.insert(entry.name);
  std::vector<std::string> others;
  std::error_code ec;
  for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code file_ec;
    if (listed.count(name) == 0 && it->is_directory(file_ec) &&
        fs::is_regular_file(it->path() / "report.json", file_ec))
      others.push_back(name);
  }
  if (others.empty()) return;
  std::sort(others.begin(), others.end());
  std::string names;
  for (const std::string& name : others) names += (names.empty() ? "" : ", ") + name;
  std::cerr << "warning: " << out.string() << " also holds reports of sequences not in this batch ("
            << names << "), from an earlier run; aggregate.json covers only the " << entries.size()
            << " listed\n";
}

// What the command line adds to a report's warnings: when scoreSequence fused
// the map, the depth points it left out (outside the map's extent, or most
// beyond max range). A note for a fifth or more beyond max range.
void addFusionWarnings(const ScoreInputs& inputs, EvaluationReport& report, const Args& args) {
  if (inputs.map) return;
  const fs::path file =
      inputs.sequence.extension() == ".json" ? inputs.sequence : inputs.sequence / "sequence.json";
  if (!report.frames_outside_map.empty()) {
    const std::string warning = outsideMapWarning(file.string(), report.fusion_totals,
                                                  report.frames_outside_map, report.resolution);
    if (!warning.empty()) report.warnings.push_back(warning);
  }
  if (report.fused_frames) {
    const std::string warning =
        nearDepthWarning(loadSequence(file), report.fused_frames->first,
                         report.fused_frames->second + 1, report.fusion_totals);
    if (!warning.empty()) report.warnings.push_back(warning);
  }
  const RangeMessage range =
      maxRangeMessage(report.fusion_totals, report.max_range, report.resolution, file.string());
  if (range.warning)
    report.warnings.push_back(range.text);
  else if (!range.text.empty() && !args.flag("quiet"))
    std::cerr << "note: " << range.text << "\n";
}

// What the report found worth saying (it is in the report files too), and a
// note when the baselines took the map's candidates.
void sayReportWarnings(const EvaluationReport& report, const Args& args) {
  for (const std::string& warning : report.warnings) std::cerr << "warning: " << warning << "\n";
  if (!report.map_candidates_note.empty() && !args.flag("quiet"))
    std::cerr << "note: " << report.map_candidates_note << "\n";
}

// --threshold against the clamping of the map it applies to: the given map, or the
// map fused with the options.
void checkThresholdFor(const std::optional<double>& threshold, const std::optional<fs::path>& map,
                       const EvaluationOptions& options) {
  if (!threshold) return;
  if (!map) return checkOccupancyThreshold(*threshold, options.fusion.map, "");
  checkOccupancyThreshold(*threshold, LabelMap::load(*map).parameters(), map->string());
}

void addScoreInputs(const ScoreInputs& score, CommandInputs& inputs) {
  inputs.addSequencePath(score.sequence);
  inputs.addFile(score.annotations, "the annotations file");
  if (score.map) inputs.addFile(*score.map, "the input map");
}

// Everything a report folder receives.
void checkReportFolder(const fs::path& dir, const CommandInputs& inputs) {
  for (const char* name : {"report.json", "report.csv", "report.md", "report.svg"})
    checkOutputInFolder(dir / name, "out", inputs);
}

// YAML boxes are read in the sequence's frame: said once per file, unless quiet.
void noteYamlBoxes(const fs::path& annotations, const Args& args) {
  if (!isYamlBoxesPath(annotations) || args.flag("quiet")) return;
  std::cerr << "note: " << annotations.string()
            << ": YAML boxes of the original experiments; label N from each name object_N, "
               "positions read in the sequence's frame\n";
}

// A map keeps the parameters it was fused with: options that would have
// fused it otherwise are overridden, said once each (unless quiet).
void noteResolution(const Args& args, const EvaluationReport& report, const fs::path& map) {
  if (args.flag("quiet")) return;
  const struct {
    const char* option;
    double map_value;
    const char* what;
  } parameters[] = {{"resolution", report.resolution, "resolution"},
                    {"max-range", report.max_range, "max range"},
                    {"p-miss", report.p_miss, "p_miss"}};
  for (const auto& parameter : parameters) {
    if (!args.option(parameter.option)) continue;
    const double given = args.number(parameter.option, 0.0);
    if (given == parameter.map_value) continue;
    std::cerr << "note: " << map.string() << " has " << parameter.what << " " << parameter.map_value
              << (std::string(parameter.option) == "p-miss" ? "" : " m") << "; it overrides --"
              << parameter.option << " " << given
              << " (a map keeps the settings it was fused with)\n";
  }
}

}  // namespace

int runScore(const Words& words) {
  const Args args(words, {"quiet"});
  args.expectOnly({"annotations", "out", "map", "batch", "iou", "resolution", "max-range", "p-miss",
                   "threshold", "candidates", "frames", "frame-memory", "quiet", kSegmenterOption},
                  1);
  const fs::path out = args.required("out");
  EvaluationOptions options;
  options.fusion = fusionOptionsFromArgs(args);
  // A map fused earlier is compared with baselines of its own candidates
  // unless --candidates says otherwise.
  options.candidates_from_map = !args.option("candidates");
  if (const auto mode = args.option("iou")) {
    const auto parsed = parseIouMode(*mode);
    if (!parsed) throw UsageError("option --iou expects exact or center, got '" + *mode + "'");
    options.iou_mode = *parsed;
  }
  std::optional<double> threshold;
  if (args.option("threshold")) threshold = options.fusion.map.occupancy_threshold;
  const bool show_progress = !args.flag("quiet") && ::isatty(STDERR_FILENO);
  const std::string what = "the reports";
  // --frames chooses the frames that are fused and projected; a map given
  // with --map was fused from frames this command cannot know: say so, since
  // its column is only comparable when it was fused from the same frames.
  const auto noteFramesWithMap = [&](const std::string& where) {
    if (!args.option("frames") || args.flag("quiet")) return;
    std::cerr << "note: " << where << " is scored as it was fused; --frames "
              << *args.option("frames")
              << " chooses the frames projected for the baselines and the 2D metrics, so the "
                 "comparison is matched only if the map was fused with the same --frames\n";
  };

  if (const auto batch = args.option("batch")) {
    if (args.positionalCount() > 0 || args.option("annotations") || args.option("map"))
      throw UsageError("--batch takes the sequences, annotations and maps from the list; "
                       "give no SEQ, --annotations or --map with it");
    CommandInputs read;
    read.addFile(*batch, "the batch list");
    checkOutputFolder(out, "out", what, read);
    const std::vector<BatchEntry> entries = readBatchList(*batch);
    for (const auto& entry : entries)
      if (entry.inputs.map)
        noteFramesWithMap("the map " + entry.inputs.map->string() + " (" + *batch + " line " +
                          std::to_string(entry.line) + ")");
    for (const auto& entry : entries) {
      addScoreInputs(entry.inputs, read);
      noteYamlBoxes(entry.inputs.annotations, args);
    }
    checkOutputFolder(out, "out", what, read);
    for (const auto& entry : entries) {
      checkOptionsForSequence(entry.inputs.sequence, options, !entry.inputs.map, read);
      // Every line's map, boxes and frame files before the first fusion: a bad
      // file on the last line must not wait for the sequences before it to
      // be fused.
      try {
        if (const auto& map_file = entry.inputs.map) {
          const LabelMap map = LabelMap::load(*map_file);
          checkMapMatchesSequence(map, loadSequence(entry.inputs.sequence), map_file->string());
          if (threshold) checkOccupancyThreshold(*threshold, map.parameters(), map_file->string());
        } else {
          checkThresholdFor(threshold, std::nullopt, options);
        }
        checkAnnotationsFor(entry.inputs);
        checkFrameFilesExist(entry.inputs.sequence, options, args.option("segmenter").has_value());
      } catch (const std::exception&) {
        std::cerr << "labeloctomap score: " << *batch << " line " << entry.line << " ("
                  << entry.name << ") failed\n";
        throw;
      }
    }
    checkOutputFolder(out, "out", what, read);
    for (const auto& entry : entries) {
      // A sequence named like a summary file would have its report folder
      // where the summary goes, found only after everything else is written.
      for (const char* name : kAggregateFiles)
        if (entry.name == name)
          throw Error(*batch, "line " + std::to_string(entry.line),
                      "a sequence folder not named aggregate.json, aggregate.csv, aggregate.md or "
                      "aggregate.svg "
                      "(its report folder would take the place of the batch's summary file)",
                      entry.name);
      checkOutputSubfolder(out / entry.name, "out",
                           "the report of " + entry.name + " (" + *batch + " line " +
                               std::to_string(entry.line) + ")",
                           read);
      checkReportFolder(out / entry.name, read);
    }
    for (const char* name : kAggregateFiles) checkOutputInFolder(out / name, "out", read);
    options.fusion.segmenter = segmenterFromArgs(args);
    // Every sequence is scored before anything is written, so a failure leaves DIR as it was.
    std::vector<EvaluationReport> reports;
    for (size_t i = 0; i < entries.size(); ++i) {
      ScoreInputs inputs = entries[i].inputs;
      inputs.occupancy_threshold = threshold;
      const std::string prefix =
          "[" + std::to_string(i + 1) + "/" + std::to_string(entries.size()) + "] " + entries[i].name + " ";
      try {
        reports.push_back(scoreSequence(inputs, options, progressPrinter(show_progress, prefix)));
      } catch (const std::exception&) {
        if (show_progress) std::fprintf(stderr, "\n");
        std::cerr << "labeloctomap score: " << *batch << " line " << entries[i].line << " ("
                  << entries[i].name << ") failed; nothing was written to " << out.string()
                  << " (the reports are written once every sequence is scored)\n";
        throw;
      }
      if (show_progress) std::fprintf(stderr, "\n");
      addFusionWarnings(inputs, reports.back(), args);
      sayReportWarnings(reports.back(), args);
      if (inputs.map) noteResolution(args, reports.back(), *inputs.map);
      std::cout << reportTable(reports.back()) << "\n";
    }
    writeBatchReports(reports, out);
    for (const std::string& warning : mixedSettingsWarnings(reports))
      std::cerr << "warning: " << warning << "\n";
    warnReportsOfOtherRuns(out, entries);
    std::cout << aggregateTable(reports) << "wrote " << reports.size()
              << (reports.size() == 1 ? " report and " : " reports and ")
              << (out / "aggregate.{json,csv,md,svg}").string() << "\n";
    return 0;
  }

  ScoreInputs inputs;
  inputs.sequence = args.positional(0, "SEQ (a sequence folder)");
  inputs.annotations = args.required("annotations");
  noteYamlBoxes(inputs.annotations, args);
  if (const auto map = args.option("map")) {
    noteFramesWithMap(*map);
    inputs.map = *map;
  }
  inputs.occupancy_threshold = threshold;
  CommandInputs read;
  addScoreInputs(inputs, read);
  checkOutputFolder(out, "out", what, read);
  checkOptionsForSequence(inputs.sequence, options, !inputs.map, read);
  checkThresholdFor(threshold, inputs.map, options);
  checkOutputFolder(out, "out", what, read);
  checkReportFolder(out, read);
  options.fusion.segmenter = segmenterFromArgs(args);
  EvaluationReport report;
  try {
    report = scoreSequence(inputs, options, progressPrinter(show_progress, ""));
  } catch (...) {
    if (show_progress) std::fprintf(stderr, "\n");
    throw;
  }
  if (show_progress) std::fprintf(stderr, "\n");
  addFusionWarnings(inputs, report, args);
  sayReportWarnings(report, args);
  if (inputs.map) noteResolution(args, report, *inputs.map);
  writeReport(report, out);
  std::cout << reportTable(report) << "wrote " << (out / "report.{json,csv,md,svg}").string() << "\n";
  return 0;
}

}  // namespace lom::cli
