#include <system_error>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/report.hpp"

namespace lom {

namespace fs = std::filesystem;

namespace {

void makeFolder(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw Error(dir.string(), "--out", "a folder for the reports", "an existing file");
  fs::create_directories(dir, ec);
  if (ec) throw Error(dir.string(), "--out", "a folder that can be created", ec.message());
}

}  // namespace

void writeReport(const EvaluationReport& report, const fs::path& dir) {
  // Everything is rendered before the first file is touched.
  const std::string json = reportJson(report);
  const std::string csv = reportCsv(report);
  const std::string markdown = reportMarkdown(report);
  const std::string svg = reportSvg(report);
  makeFolder(dir);
  writeTextFileAtomically(dir / "report.json", json);
  writeTextFileAtomically(dir / "report.csv", csv);
  writeTextFileAtomically(dir / "report.md", markdown);
  writeTextFileAtomically(dir / "report.svg", svg);
}

void writeAggregate(const std::vector<EvaluationReport>& reports, const fs::path& dir) {
  const std::string json = aggregateJson(reports);
  const std::string markdown = aggregateMarkdown(reports);
  const std::string svg = aggregateSvg(reports);
  makeFolder(dir);
  writeTextFileAtomically(dir / "aggregate.json", json);
  writeTextFileAtomically(dir / "aggregate.md", markdown);
  writeTextFileAtomically(dir / "aggregate.svg", svg);
}

}  // namespace lom
