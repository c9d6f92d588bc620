#include <memory>
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

using Files = std::vector<std::pair<const char*, std::string>>;

// The text formats take names from the file system (the sequence folder, the
// map file) as they are; bytes that are not UTF-8 become U+FFFD, so that each
// file stays what it says it is (report.json is made valid as it is written).
std::string utf8(const std::string& text) { return validUtf8(text, "\xEF\xBF\xBD"); }

Files reportFiles(const EvaluationReport& report) {
  return {{"report.json", reportJson(report)},
          {"report.csv", utf8(reportCsv(report))},
          {"report.md", utf8(reportMarkdown(report))},
          {"report.svg", utf8(reportSvg(report))}};
}

Files aggregateFiles(const std::vector<EvaluationReport>& reports) {
  return {{"aggregate.json", aggregateJson(reports)},
          {"aggregate.csv", utf8(aggregateCsv(reports))},
          {"aggregate.md", utf8(aggregateMarkdown(reports))},
          {"aggregate.svg", utf8(aggregateSvg(reports))}};
}

// Files of several folders that replace the old ones together (a failure on
// the way, such as a full disk, leaves every old file whole), in folders that
// are taken away again if they were created for them. Everything is rendered
// before the first file is touched.
void writeFolders(const std::vector<std::pair<fs::path, Files>>& folders) {
  // Made outer folder first; taken away (when not kept) innermost first.
  std::vector<std::unique_ptr<NewFolders>> created;
  struct TakeAway {
    std::vector<std::unique_ptr<NewFolders>>& created;
    ~TakeAway() {
      while (!created.empty()) created.pop_back();
    }
  } take_away{created};
  for (const auto& [dir, files] : folders) {
    created.push_back(std::make_unique<NewFolders>(dir));
    makeFolder(dir);
  }
  StagedFiles staged;
  for (const auto& [dir, files] : folders)
    for (const auto& [name, text] : files)
      staged.add(
          dir / name, [&text = text](std::ostream& out) { out << text; }, false);
  staged.commit();
  for (auto& folder : created) folder->keep();
}

}  // namespace

void writeReport(const EvaluationReport& report, const fs::path& dir) {
  writeFolders({{dir, reportFiles(report)}});
}

void writeAggregate(const std::vector<EvaluationReport>& reports, const fs::path& dir) {
  writeFolders({{dir, aggregateFiles(reports)}});
}

void writeBatchReports(const std::vector<EvaluationReport>& reports, const fs::path& dir) {
  std::vector<std::pair<fs::path, Files>> folders;
  folders.emplace_back(dir, aggregateFiles(reports));
  for (const auto& report : reports)
    folders.emplace_back(dir / report.sequence, reportFiles(report));
  writeFolders(folders);
}

}  // namespace lom
