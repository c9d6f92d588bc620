// The text of reports: the batch aggregate's rows link to each sequence's
// report, whatever its name holds; the settings line counts views in words.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "lom/evaluation.hpp"
#include "lom/report.hpp"

namespace {

TEST(ReportText, AggregateLinksWorkForNamesWithSpacesAndBrackets) {
  std::vector<lom::EvaluationReport> reports(3);
  reports[0].sequence = "bin_a";
  reports[1].sequence = "scene two (2)";
  reports[2].sequence = "caf\xc3\xa9|100%";
  const std::string text = lom::aggregateMarkdown(reports);
  EXPECT_NE(text.find("](bin_a/report.md)"), std::string::npos) << text;
  EXPECT_NE(text.find("[scene two (2)](scene%20two%20%282%29/report.md)"), std::string::npos)
      << text;
  EXPECT_NE(text.find("](caf%C3%A9%7C100%25/report.md)"), std::string::npos) << text;
}

// A sequence's warnings make its row doubtful: the aggregate keeps them.
TEST(ReportText, AggregateKeepsEachSequencesWarnings) {
  std::vector<lom::EvaluationReport> reports(2);
  reports[0].sequence = "bin_a";
  reports[1].sequence = "bin_b";
  EXPECT_EQ(lom::aggregateMarkdown(reports).find("Warnings"), std::string::npos);
  reports[1].warnings = {"m.ot was fused from 3 frames, the baselines project the 5 frames"};
  const std::string text = lom::aggregateMarkdown(reports);
  EXPECT_NE(text.find("**Warnings**\n\nbin\\_b:\n\n- m.ot was fused from 3 frames"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("bin\\_a:"), std::string::npos) << text;
  const std::string json = lom::aggregateJson(reports);
  EXPECT_NE(json.find("m.ot was fused from 3 frames"), std::string::npos) << json;
  EXPECT_NE(json.find("\"warnings\": []"), std::string::npos) << json;
}

// Sequences scored at other settings (maps of other resolutions in a batch
// list) make the "all" row an average of scores that do not compare: said in
// both aggregate files, which also keep each sequence's settings.
TEST(ReportText, AggregateSaysWhenTheSequencesWereScoredAtOtherSettings) {
  std::vector<lom::EvaluationReport> reports(4);
  for (size_t i = 0; i < reports.size(); ++i) {
    reports[i].sequence = "bin_" + std::string(1, static_cast<char>('a' + i));
    reports[i].resolution = 0.01;
    reports[i].max_range = 1.0;
    reports[i].occupancy_threshold = 0.5;
    reports[i].p_miss = 0.3;
  }
  EXPECT_TRUE(lom::mixedSettingsWarnings(reports).empty());
  std::string text = lom::aggregateMarkdown(reports);
  EXPECT_EQ(text.find("Warnings"), std::string::npos) << text;
  EXPECT_NE(text.find("Settings of every sequence: 1 cm voxels, max range 1 m, threshold 0.5"),
            std::string::npos)
      << text;

  reports[2].resolution = 0.02;
  reports[3].occupancy_threshold = 0.7;
  const std::vector<std::string> warnings = lom::mixedSettingsWarnings(reports);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0],
            "the sequences were scored at different resolutions: 0.01 m (bin_a, bin_b, bin_d); "
            "0.02 m (bin_c); the \"all\" row averages scores that are not comparable (score "
            "them at one setting)");
  EXPECT_NE(warnings[1].find("different occupancy thresholds: 0.5 (bin_a, bin_b, bin_c); 0.7 "
                             "(bin_d)"),
            std::string::npos)
      << warnings[1];
  text = lom::aggregateMarkdown(reports);
  EXPECT_NE(text.find("**Warnings**\n\nall:\n\n- the sequences were scored at different "
                      "resolutions"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("cm voxels"), std::string::npos) << "not every sequence's: " << text;
  EXPECT_NE(text.find("Settings of every sequence: max range 1 m, p_miss 0.3"), std::string::npos)
      << text;
  const std::string json = lom::aggregateJson(reports);
  EXPECT_NE(json.find("different resolutions"), std::string::npos) << json;
  EXPECT_NE(json.find("\"resolution\": 0.02"), std::string::npos) << json;
  EXPECT_NE(json.find("\"occupancy_threshold\": 0.7"), std::string::npos) << json;
}

// aggregate.csv: every object of every sequence on a row that names its sequence.
TEST(ReportText, AggregateCsvHasOneRowPerObjectOfEverySequence) {
  std::vector<lom::EvaluationReport> reports(2);
  reports[0].sequence = "bin_a";
  reports[1].sequence = "scene, two";
  lom::ObjectScore cup;
  cup.label = 3;
  cup.name = "blue_cup";
  cup.voxels = 120;
  cup.iou_3d = {0.25, 0.5, 0.75};
  cup.box_iou = {0.125, 0.375, 0.625};
  cup.per_view = {0.1, 0.2};
  reports[0].objects = {cup};
  lom::ObjectScore box = cup;
  box.label = 7;
  box.name = "square_box";
  box.voxels = 44;
  box.iou_3d.labeloctomap = 0.5;
  reports[1].objects = {cup, box};
  const std::string csv = lom::aggregateCsv(reports);
  const std::string header =
      "sequence,label,name,voxels,iou3d_projection_mean,iou3d_projection_max,iou3d_labeloctomap,"
      "box_iou_projection_mean,box_iou_projection_max,box_iou_labeloctomap\n";
  ASSERT_EQ(csv.substr(0, header.size()), header) << csv;
  EXPECT_NE(csv.find("\nbin_a,3,blue_cup,120,0.25"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n\"scene, two\",3,blue_cup,120,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n\"scene, two\",7,square_box,44,0.25"), std::string::npos) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4) << csv;
  // Every row has the header's ten columns (no per-view ones).
  std::istringstream rows(csv);
  std::string row;
  std::getline(rows, row);
  while (std::getline(rows, row)) {
    EXPECT_EQ(std::count(row.begin(), row.end(), ','), row[0] == '"' ? 10 : 9) << row;
  }
}

TEST(ReportText, TheSettingsCountOneViewInTheSingular) {
  lom::EvaluationReport report;
  report.sequence = "bin_a";
  report.resolution = 0.01;
  report.views = {4};
  EXPECT_NE(lom::reportTable(report).find(", 1 view (frame 4)"), std::string::npos)
      << lom::reportTable(report);
  report.views = {0, 4};
  EXPECT_NE(lom::reportMarkdown(report).find(", 2 views (frames 0, 4)"), std::string::npos)
      << lom::reportMarkdown(report);
  report.views = {0, 10, 20, 30, 40, 50};
  EXPECT_NE(lom::reportTable(report).find(", 6 views (frames 0, 10, 20, 30, 40, 50)"),
            std::string::npos)
      << lom::reportTable(report);
  // A view every ten frames of a long recording: the settings stay one line.
  report.views.clear();
  for (size_t frame = 0; frame < 1500; frame += 10) report.views.push_back(frame);
  const std::string table = lom::reportTable(report);
  EXPECT_NE(table.find(", 150 views (frames 0, 10, 20, ... 1490)"), std::string::npos) << table;
  EXPECT_EQ(table.find("750"), std::string::npos) << table;
}

}  // namespace

namespace {

// A slanted object name reaches left of its group: a long first name stays
// inside the picture (it was cut off at the left edge), and short names
// leave the layout as it was.
TEST(BarChartSvg, LongFirstNamesStayInsideThePicture) {
  lom::BarChart chart;
  chart.series = {"a", "b", "c"};
  const std::string longest = "elmers_washable_no_run_school_glue";
  chart.groups = {{"13", longest, {0.2, 0.3, 0.4}}, {"4", "cup", {0.1, 0.1, 0.1}}};
  const std::string svg = lom::barChartSvg(chart);
  const std::string marker = "translate(";
  const size_t slanted = svg.find("rotate(-40)");  // the first object name
  ASSERT_NE(slanted, std::string::npos) << svg;
  const size_t at = svg.rfind(marker, slanted);
  const double anchor_x = std::stod(svg.substr(at + marker.size()));
  // At the chart's own 5.6 px per character, slanted by 40 degrees.
  EXPECT_GE(anchor_x - 5.6 * static_cast<double>(longest.size()) * std::cos(40.0 * M_PI / 180.0),
            0.0)
      << svg.substr(at, 120);
  chart.groups[0].sublabel = "cup";
  const std::string short_names = lom::barChartSvg(chart);
  EXPECT_NE(short_names.find("<line x1=\"64\""), std::string::npos) << "the usual left margin";
}

}  // namespace
