// The text of reports: the batch aggregate's rows link to each sequence's
// report, whatever its name holds; the settings line counts views in words.
#include <gtest/gtest.h>

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
}

}  // namespace
