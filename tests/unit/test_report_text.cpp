// The text of the batch aggregate: every sequence's row links to its report,
// whatever its name holds.
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

}  // namespace
