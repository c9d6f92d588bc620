// labeloctomap score: per-object IU_3d of LabelOctoMap against the projection
// baselines, for one sequence or a batch list (docs/evaluation.md).
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "args.hpp"
#include "commands.hpp"
#include "segmenter_option.hpp"
#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/report.hpp"

namespace lom::cli {

namespace {

namespace fs = std::filesystem;

EvaluationProgressFn progressPrinter(bool enabled, const std::string& prefix) {
  if (!enabled) return {};
  return [prefix](const EvaluationProgress& p) {
    std::fprintf(stderr, "\r%s%-10s %zu/%zu   ", prefix.c_str(), p.stage.c_str(), p.done, p.total);
    std::fflush(stderr);
    return true;
  };
}

// Options that only make sense against a given sequence.
void checkOptionsForSequence(const fs::path& sequence_path, const EvaluationOptions& options) {
  const Sequence sequence = loadSequence(sequence_path);
  if (options.fusion.candidates)
    for (int id : *options.fusion.candidates)
      if (!sequence.labels.contains(id))
        throw UsageError("option --candidates: label " + std::to_string(id) + " is not in " +
                         (sequence.root / "sequence.json").string() + " (labels 0.." +
                         std::to_string(sequence.labels.size() - 1) + ")");
  if (options.fusion.first_frame >= sequence.frames.size())
    throw UsageError("option --frames: " + (sequence.root / "sequence.json").string() + " has only " +
                     std::to_string(sequence.frames.size()) + " frames");
}

void checkOutFolder(const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    throw Error(out.string(), "--out", "a folder for the reports (created when missing)", "an existing file");
}

void noteResolution(const Args& args, const EvaluationReport& report, const fs::path& map) {
  if (!args.option("resolution") || args.number("resolution", 0.0) == report.resolution) return;
  std::cerr << "note: " << map.string() << " has resolution " << report.resolution
            << " m; it overrides --resolution " << args.number("resolution", 0.0) << "\n";
}

}  // namespace

int runScore(const Words& words) {
  const Args args(words, {"quiet"});
  args.expectOnly({"annotations", "out", "map", "batch", "iou", "resolution", "max-range", "p-miss",
                   "threshold", "candidates", "frames", "quiet", kSegmenterOption},
                  1);
  const fs::path out = args.required("out");
  EvaluationOptions options;
  options.fusion = fusionOptionsFromArgs(args);
  if (const auto mode = args.option("iou")) {
    const auto parsed = parseIouMode(*mode);
    if (!parsed) throw UsageError("option --iou expects exact or center, got '" + *mode + "'");
    options.iou_mode = *parsed;
  }
  std::optional<double> threshold;
  if (args.option("threshold")) threshold = options.fusion.map.occupancy_threshold;
  const bool show_progress = !args.flag("quiet") && ::isatty(STDERR_FILENO);
  checkOutFolder(out);

  if (const auto batch = args.option("batch")) {
    if (args.positionalCount() > 0 || args.option("annotations") || args.option("map"))
      throw UsageError("--batch takes the sequences, annotations and maps from the list; "
                       "give no SEQ, --annotations or --map with it");
    const std::vector<BatchEntry> entries = readBatchList(*batch);
    for (const auto& entry : entries) checkOptionsForSequence(entry.inputs.sequence, options);
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
                  << entries[i].name << ") failed\n";
        throw;
      }
      if (show_progress) std::fprintf(stderr, "\n");
      if (inputs.map) noteResolution(args, reports.back(), *inputs.map);
      std::cout << reportTable(reports.back()) << "\n";
    }
    for (const auto& report : reports) writeReport(report, out / report.sequence);
    writeAggregate(reports, out);
    std::cout << aggregateTable(reports) << "wrote " << reports.size() << " reports and "
              << (out / "aggregate.{json,md,svg}").string() << "\n";
    return 0;
  }

  ScoreInputs inputs;
  inputs.sequence = args.positional(0, "SEQ (a sequence folder)");
  inputs.annotations = args.required("annotations");
  if (const auto map = args.option("map")) inputs.map = *map;
  inputs.occupancy_threshold = threshold;
  checkOptionsForSequence(inputs.sequence, options);
  EvaluationReport report;
  try {
    report = scoreSequence(inputs, options, progressPrinter(show_progress, ""));
  } catch (...) {
    if (show_progress) std::fprintf(stderr, "\n");
    throw;
  }
  if (show_progress) std::fprintf(stderr, "\n");
  if (inputs.map) noteResolution(args, report, *inputs.map);
  writeReport(report, out);
  std::cout << reportTable(report) << "wrote " << (out / "report.{json,csv,md,svg}").string() << "\n";
  return 0;
}

}  // namespace lom::cli
