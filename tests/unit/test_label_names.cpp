// Label names go on one line of text headers and into the map file: names
// too long for either or holding control characters are refused where they
// enter, and never written where they could not be read back.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "lom/label_map.hpp"
#include "test_input_helpers.hpp"

namespace {

using Json = nlohmann::json;
using lom::test::errorOf;
using lom::test::writeSequence;

TEST(LabelNameTest, SequencesRefuseLongNamesAndControlCharacters) {
  lom::test::TempDir dir;
  writeSequence(dir.path());
  const auto errorForName = [&](const std::string& name) {
    Json json = Json::parse(std::ifstream(dir / "sequence.json"));
    json["labels"][1]["name"] = name;
    std::ofstream(dir / "sequence.json") << json.dump();
    return errorOf([&] { (void)lom::loadSequence(dir.path()); });
  };
  const lom::Problem long_name = errorForName(std::string(65536 + 3, 'a'));
  EXPECT_EQ(long_name.field, "labels[1].name");
  EXPECT_NE(long_name.expected.find("1 to 255 bytes"), std::string::npos) << long_name.message();
  EXPECT_EQ(long_name.found, "a name of 65539 bytes");
  EXPECT_EQ(errorForName(std::string(256, 'b')).found, "a name of 256 bytes");
  EXPECT_EQ(errorForName("mug\nend_header").found, "a line feed (0x0a) at byte 3");
  EXPECT_EQ(errorForName(std::string("m\0g", 3)).found, "a NUL character (0x00) at byte 1");

  // 255 bytes of UTF-8 and other printable characters are fine.
  Json json = Json::parse(std::ifstream(dir / "sequence.json"));
  std::string accented;
  for (int i = 0; i < 85; ++i) accented += "\xc3\xa9";  // U+00E9, 2 bytes each
  json["labels"][1]["name"] = accented + std::string(85, 'e');
  std::ofstream(dir / "sequence.json") << json.dump();
  EXPECT_EQ(lom::loadSequence(dir.path()).labels.at(1).name.size(), 255u);
}

TEST(LabelNameTest, MapsAndSequencesAreNeverWrittenWithNamesTheyCannotReadBack) {
  lom::test::TempDir dir;
  const lom::LabelSet long_names(
      {{0, "__background__", {0, 0, 0}}, {1, std::string(65536 + 10, 'n'), {1, 2, 3}}});
  const lom::Problem map_problem = errorOf([&] { lom::LabelMap map(long_names); });
  EXPECT_EQ(map_problem.field, "labels[1].name");
  EXPECT_EQ(map_problem.found, "a name of 65546 bytes");

  lom::Sequence sequence = writeSequence(dir / "seq");
  sequence.labels = long_names;
  const lom::Problem save_problem = errorOf([&] { lom::saveSequence(sequence, dir / "seq"); });
  EXPECT_EQ(save_problem.field, "labels[1].name");
  // The old sequence.json is untouched.
  EXPECT_EQ(lom::loadSequence(dir / "seq").labels.at(1).name, "mug");
}

}  // namespace

namespace {

// A label list saved in Latin-1 or UTF-16 is refused where it is read, naming
// the line and the byte: its names would otherwise come out changed
// ("caf\uFFFD cup") and no longer be found by name.
TEST(LabelNameTest, LabelListsInAnotherEncodingThanUtf8AreRefused) {
  lom::test::TempDir dir;
  std::ofstream(dir / "latin1.txt") << "__background__\nmug\ncaf\xe9 cup\n";
  lom::Problem problem = errorOf([&] { (void)lom::readLabelList(dir / "latin1.txt"); });
  EXPECT_EQ(problem.field, "line 3");
  EXPECT_EQ(problem.found, "a byte that is not UTF-8 at byte 3 (save the file as UTF-8)");
  std::ofstream(dir / "utf16.txt") << std::string("\xFF\xFE_\0_\0b\0g\0\n\0", 12);
  problem = errorOf([&] { (void)lom::readLabelList(dir / "utf16.txt"); });
  EXPECT_EQ(problem.expected, "a label list in UTF-8 (or ASCII)");
  EXPECT_NE(problem.found.find("a UTF-16 file"), std::string::npos) << problem.found;
  // UTF-8 names of every length of character are kept.
  std::ofstream(dir / "utf8.txt")
      << "__background__\ncaf\xc3\xa9 cup\n\xe6\x9d\xaf\n\xf0\x9f\x8d\xb5\n";
  const lom::LabelSet labels = lom::readLabelList(dir / "utf8.txt");
  EXPECT_EQ(labels.at(1).name, "caf\xc3\xa9 cup");
  EXPECT_EQ(labels.at(3).name, "\xf0\x9f\x8d\xb5");
  for (const std::string bad : {"\xc0\xaf", "\xed\xa0\x80", "\xe6\x9d", "\xf5\x80\x80\x80"})
    EXPECT_NE(lom::labelNameProblem("x" + bad).find("not UTF-8 at byte 1"), std::string::npos)
        << bad;
}

}  // namespace
