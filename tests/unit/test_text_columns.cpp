// Plain-text tables line up in terminal columns: names in other scripts than
// Latin take fewer (or, East Asian, more) columns than they have bytes.
#include <gtest/gtest.h>

#include <sstream>

#include "lom/evaluation.hpp"
#include "lom/report.hpp"
#include "lom/text_columns.hpp"

namespace {

const std::string kUmlaut =
    "K\xc3\xbc"
    "chenrolle";                                      // "Küchenrolle": 11 columns, 12 bytes
const std::string kCup = "\xe6\xb0\xb4\xe6\x9d\xaf";  // two wide characters: 4 columns, 6 bytes
const std::string kAccent = "e\xcc\x81";              // e and a combining acute: 1 column

TEST(TextColumns, CountCharactersWideOnesTwiceAndMarksNotAtAll) {
  EXPECT_EQ(lom::textColumns("bowl"), 4u);
  EXPECT_EQ(lom::textColumns(kUmlaut), 11u);
  EXPECT_EQ(lom::textColumns(kCup), 4u);
  EXPECT_EQ(lom::textColumns(kAccent), 1u);
  EXPECT_EQ(lom::textColumns("a\xff"
                             "b"),
            3u);  // an invalid byte counts as the one replacement it is printed as
}

TEST(TextColumns, PaddingFillsColumnsNotBytes) {
  EXPECT_EQ(lom::padRight(kUmlaut, 14), kUmlaut + "   ");
  EXPECT_EQ(lom::padLeft(kCup, 6), "  " + kCup);
  EXPECT_EQ(lom::padRight("long name", 4), "long name");
}

TEST(TextColumns, CutsEndOnACharacterBoundary) {
  // "Kü" + "~" would be 3 columns; the cut never splits the two bytes of ü.
  EXPECT_EQ(lom::cutToColumns(kUmlaut, 3), "K\xc3\xbc~");
  EXPECT_EQ(lom::cutToColumns(kUmlaut, 2), "K~");
  // A wide character that does not fit is left out whole.
  EXPECT_EQ(lom::cutToColumns(kCup, 4), kCup);
  EXPECT_EQ(lom::cutToColumns(kCup, 3), "\xe6\xb0\xb4~");
  EXPECT_EQ(lom::cutToColumns(kCup, 2), "~");
  EXPECT_EQ(lom::textColumns(lom::cutToColumns(kUmlaut + kCup, 12)), 12u);
}

// Column where `needle` starts in the line of `text` that contains `row`.
size_t columnInRow(const std::string& text, const std::string& row, const std::string& needle) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.find(row) != std::string::npos) {
      const size_t at = line.find(needle, line.find(row) + row.size());
      return at == std::string::npos ? std::string::npos : lom::textColumns(line.substr(0, at));
    }
  return std::string::npos;
}

TEST(TextColumns, ScoreTableColumnsLineUpForNamesInOtherScripts) {
  lom::EvaluationReport report;
  report.sequence = "bin";
  report.resolution = 0.01;
  const std::vector<std::string> names = {"dasani_water_bottle", kUmlaut, kCup};
  const std::vector<size_t> voxels = {111111, 222222, 333333};
  for (size_t k = 0; k < names.size(); ++k) {
    lom::ObjectScore object;
    object.label = static_cast<int>(k + 1);
    object.name = names[k];
    object.voxels = voxels[k];
    report.objects.push_back(object);
  }
  const std::string table = lom::reportTable(report);
  const size_t ascii = columnInRow(table, names[0], "111111");
  ASSERT_NE(ascii, std::string::npos) << table;
  EXPECT_EQ(columnInRow(table, kUmlaut, "222222"), ascii) << table;
  EXPECT_EQ(columnInRow(table, kCup, "333333"), ascii) << table;
}

}  // namespace
