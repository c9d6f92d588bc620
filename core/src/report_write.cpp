#include <ostream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

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

// All of a report's files replace the old ones together (a failure on the way,
// such as a full disk, leaves the old report whole), in a folder that is taken
// away again if it was created for them.
void writeFiles(const fs::path& dir, const std::vector<std::pair<const char*, std::string>>& files) {
  NewFolders created(dir);
  makeFolder(dir);
  StagedFiles staged;
  for (const auto& [name, text] : files)
    staged.add(dir / name, [&text = text](std::ostream& out) { out << text; }, false);
  staged.commit();
  created.keep();
}

}  // namespace

void writeReport(const EvaluationReport& report, const fs::path& dir) {
  // Everything is rendered before the first file is touched.
  writeFiles(dir, {{"report.json", reportJson(report)},
                   {"report.csv", reportCsv(report)},
                   {"report.md", reportMarkdown(report)},
                   {"report.svg", reportSvg(report)}});
}

void writeAggregate(const std::vector<EvaluationReport>& reports, const fs::path& dir) {
  writeFiles(dir, {{"aggregate.json", aggregateJson(reports)},
                   {"aggregate.md", aggregateMarkdown(reports)},
                   {"aggregate.svg", aggregateSvg(reports)}});
}

}  // namespace lom
