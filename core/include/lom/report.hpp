#pragma once
// Evaluation reports: report.json (a public contract, docs/evaluation.md),
// report.csv, report.md, report.svg, and the aggregate of a batch.
#include <filesystem>
#include <string>
#include <vector>

#include "lom/evaluation.hpp"

namespace lom {

[[nodiscard]] std::string reportJson(const EvaluationReport& report);
[[nodiscard]] std::string reportCsv(const EvaluationReport& report);
[[nodiscard]] std::string reportMarkdown(const EvaluationReport& report);
[[nodiscard]] std::string reportSvg(const EvaluationReport& report);
// The paper-style table for a terminal (values x100).
[[nodiscard]] std::string reportTable(const EvaluationReport& report);

// Writes report.json, report.csv, report.md and report.svg into `dir` (created
// with its parents when missing), each file atomically.
void writeReport(const EvaluationReport& report, const std::filesystem::path& dir);

// The settings a batch's sequences were scored at differently (the map's
// resolution, max range, threshold and p_miss, the IU_3d mode, the segmenter):
// one sentence each, naming the values and their sequences, since the "all"
// row then averages scores that are not comparable. Empty when they agree.
[[nodiscard]] std::vector<std::string> mixedSettingsWarnings(
    const std::vector<EvaluationReport>& reports);
// A batch: the mean over all objects of all sequences, and one row per sequence.
[[nodiscard]] std::string aggregateJson(const std::vector<EvaluationReport>& reports);
[[nodiscard]] std::string aggregateMarkdown(const std::vector<EvaluationReport>& reports);
// One row per object of every sequence (its sequence first), the columns of
// report.csv without the per-view ones, which differ between sequences.
[[nodiscard]] std::string aggregateCsv(const std::vector<EvaluationReport>& reports);
[[nodiscard]] std::string aggregateTable(const std::vector<EvaluationReport>& reports);
[[nodiscard]] std::string aggregateSvg(const std::vector<EvaluationReport>& reports);
// Writes aggregate.json, aggregate.csv, aggregate.md and aggregate.svg into `dir`, each
// atomically.
void writeAggregate(const std::vector<EvaluationReport>& reports, const std::filesystem::path& dir);
// A batch's files: the aggregate into `dir` and each report into
// `dir`/<sequence>/, all rendered first and put in place together, so that a
// failure on the way leaves every earlier file as it was.
void writeBatchReports(const std::vector<EvaluationReport>& reports,
                       const std::filesystem::path& dir);

// A grouped bar chart as a standalone SVG document (no display needed).
struct BarChart {
  std::string title;
  std::string y_label;
  double y_unit = 100.0;  // values are multiplied by this for the axis (fractions -> percent)
  std::vector<std::string> series;  // one colour per series
  struct Group {
    std::string label;     // under the group
    std::string sublabel;  // smaller, slanted, below the label (e.g. an object name)
    std::vector<double> values;  // one per series
  };
  std::vector<Group> groups;
};
[[nodiscard]] std::string barChartSvg(const BarChart& chart);

}  // namespace lom
