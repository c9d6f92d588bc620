// The report files as written: names from the file system that are not UTF-8
// cannot fail a report (a scored sequence's work would be lost at the very
// end), a batch is put in place all at once, and the settings line says how
// the map was fused.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/report.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::slurp;

const std::string kReplacement = "\xEF\xBF\xBD";

lom::EvaluationReport reportNamed(const std::string& sequence) {
  lom::EvaluationReport report;
  report.sequence = sequence;
  report.resolution = 0.01;
  report.max_range = 1.0;
  report.occupancy_threshold = 0.5;
  report.p_miss = 0.3;
  report.views = {0, 3};
  lom::ObjectScore object;
  object.label = 4;
  object.name = "cloud_b_plush_bear";
  object.per_view = {0.1, 0.2};
  object.per_view_box_iou = {0.3, 0.4};
  report.objects.push_back(object);
  return report;
}

TEST(ValidUtf8, ReplacesEveryByteOutsideAWellFormedCharacter) {
  const std::string good = "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80 \xF4\x8F\xBF\xBF";
  EXPECT_EQ(lom::validUtf8(good), good);
  EXPECT_EQ(lom::validUtf8("caf\xE9"), "caf?");
  EXPECT_EQ(lom::validUtf8("\xC0\xAF"), "??");            // overlong '/'
  EXPECT_EQ(lom::validUtf8("\xE0\x80\xAF"), "???");       // overlong, three bytes
  EXPECT_EQ(lom::validUtf8("\xED\xA0\x80"), "???");       // a UTF-16 surrogate
  EXPECT_EQ(lom::validUtf8("\xF4\x90\x80\x80"), "????");  // past U+10FFFF
  EXPECT_EQ(lom::validUtf8("\xF5\x80\x80\x80"), "????");
  EXPECT_EQ(lom::validUtf8("ab\xE2\x82"), "ab??");  // cut short
  EXPECT_EQ(lom::validUtf8("x\xE9y", kReplacement), "x" + kReplacement + "y");
}

TEST(ReportFiles, NamesThatAreNotUtf8AreWrittenWithReplacementCharacters) {
  const lom::test::TempDir dir;
  lom::EvaluationReport report = reportNamed("caf\xE9");
  report.map_file = "/maps/m\xE9.ot";
  report.warnings = {"/maps/m\xE9.ot: a warning"};
  ASSERT_NO_THROW(lom::writeReport(report, dir.path()));
  const nlohmann::json json = nlohmann::json::parse(slurp(dir / "report.json"));
  EXPECT_EQ(json.at("sequence"), "caf" + kReplacement);
  EXPECT_EQ(json.at("map"), "/maps/m" + kReplacement + ".ot");
  for (const char* name : {"report.md", "report.csv", "report.svg", "report.json"}) {
    const std::string text = slurp(dir / name);
    ASSERT_FALSE(text.empty()) << name;
    EXPECT_EQ(lom::validUtf8(text), text) << name << " is not UTF-8";
  }
  EXPECT_NE(slurp(dir / "report.md").find("m" + kReplacement + ".ot"), std::string::npos);
}

TEST(ReportFiles, ABatchIsWrittenWholeOrNotAtAll) {
  const lom::test::TempDir dir;
  const fs::path out = dir / "out";
  const std::vector<lom::EvaluationReport> reports = {reportNamed("bin_a"), reportNamed("bin_b")};
  // bin_b's report folder cannot be made: a file is in its place.
  fs::create_directories(out);
  { std::ofstream(out / "bin_b") << "in the way"; }
  EXPECT_THROW(lom::writeBatchReports(reports, out), lom::Error);
  EXPECT_FALSE(fs::exists(out / "bin_a")) << "the first report was written before the failure";
  EXPECT_FALSE(fs::exists(out / "aggregate.json"));
  EXPECT_TRUE(fs::is_regular_file(out / "bin_b"));

  fs::remove(out / "bin_b");
  ASSERT_NO_THROW(lom::writeBatchReports(reports, out));
  for (const char* name :
       {"aggregate.json", "aggregate.csv", "aggregate.md", "aggregate.svg", "bin_a/report.json",
        "bin_a/report.md", "bin_b/report.csv", "bin_b/report.svg"})
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
}

TEST(ReportFiles, ABatchIntoANewFolderLeavesNoFolderWhenItFails) {
  const lom::test::TempDir dir;
  const fs::path out = dir / "new" / "out";
  lom::EvaluationReport clash = reportNamed("aggregate.json");  // its folder clashes with a file
  EXPECT_THROW(lom::writeBatchReports({reportNamed("bin_a"), clash}, out), lom::Error);
  EXPECT_FALSE(fs::exists(dir / "new"));
}

TEST(ReportFiles, TheSettingsSayHowTheMapWasFused) {
  lom::EvaluationReport report = reportNamed("bin_a");
  report.p_miss = 0.45;
  report.fused_frames = std::make_pair(size_t{2}, size_t{6});
  report.segmenter = "/models/fcn.onnx";
  const nlohmann::json json = nlohmann::json::parse(lom::reportJson(report));
  EXPECT_DOUBLE_EQ(json.at("p_miss").get<double>(), 0.45);
  EXPECT_EQ(json.at("frames"), nlohmann::json::array({2, 6}));
  EXPECT_EQ(json.at("segmenter"), "/models/fcn.onnx");
  const std::string markdown = lom::reportMarkdown(report);
  EXPECT_NE(markdown.find("p\\_miss 0.45, frames 2-6 fused (segmenter /models/fcn.onnx)"),
            std::string::npos)
      << markdown;

  report.fused_frames.reset();
  report.segmenter.clear();
  const nlohmann::json plain = nlohmann::json::parse(lom::reportJson(report));
  EXPECT_TRUE(plain.at("frames").is_null());
  EXPECT_TRUE(plain.at("segmenter").is_null());
  EXPECT_EQ(lom::reportMarkdown(report).find("fused ("), std::string::npos);
}

}  // namespace
