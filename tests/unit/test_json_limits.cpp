// JSON files as a hostile or careless hand may write them: nesting deep
// enough to exhaust a recursive walk, numbers beyond a double, huge values in
// error messages. Every one gives lom::Error naming the file, never a crash.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "lom/annotations.hpp"
#include "lom/segmenter.hpp"
#include "test_input_helpers.hpp"

namespace {

using Json = nlohmann::json;
using lom::test::errorOf;
using lom::test::writeSequence;
using lom::test::writeText;

std::string nested(size_t depth) {
  return "{\"format\": " + std::string(depth, '[') + std::string(depth, ']') + "}";
}

TEST(JsonInputTest, DeeplyNestedSequenceIsRefusedNamingTheFile) {
  lom::test::TempDir dir;
  writeText(dir / "sequence.json", nested(100000));
  const lom::Problem problem = errorOf([&] { (void)lom::loadSequence(dir.path()); });
  EXPECT_EQ(problem.file, (dir / "sequence.json").string());
  EXPECT_NE(problem.expected.find("nested at most 256 levels"), std::string::npos)
      << problem.message();
  EXPECT_NE(problem.found.find("line 1, column 267"), std::string::npos) << problem.message();
}

TEST(JsonInputTest, NestingUpToTheLimitIsDescribedWithoutRecursion) {
  lom::test::TempDir dir;
  // 255 levels inside "format" (256 with the top-level object) are accepted
  // as JSON; the wrong value is then described by its start.
  writeText(dir / "sequence.json", nested(255));
  const lom::Problem problem = errorOf([&] { (void)lom::loadSequence(dir.path()); });
  EXPECT_EQ(problem.field, "format");
  EXPECT_EQ(problem.found.rfind("an array [[[[", 0), 0u) << problem.message();
  EXPECT_LE(problem.found.size(), 80u) << problem.message();
}

TEST(JsonInputTest, LargeValuesAreDescribedByTheirStart) {
  lom::test::TempDir dir;
  std::string big = "[";
  for (int i = 0; i < 200000; ++i) big += (i ? ",\"" : "\"") + std::string(100, 'x') + "\"";
  big += "]";
  writeText(dir / "sequence.json", "{\"format\": " + big + "}");
  const lom::Problem problem = errorOf([&] { (void)lom::loadSequence(dir.path()); });
  EXPECT_EQ(problem.field, "format");
  EXPECT_EQ(problem.found, "an array [\"" + std::string(55, 'x') + "...") << problem.message();
}

TEST(JsonInputTest, DeeplyNestedAnnotationBoxesAreRefused) {
  lom::test::TempDir dir;
  const size_t depth = 400000;
  writeText(dir / "boxes.json",
            R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [)" +
                std::string(depth, '[') + std::string(depth, ']') + "]}");
  const lom::Problem problem = errorOf([&] { (void)lom::loadAnnotations(dir / "boxes.json"); });
  EXPECT_EQ(problem.file, (dir / "boxes.json").string());
  EXPECT_NE(problem.expected.find("nested at most"), std::string::npos) << problem.message();
}

TEST(JsonInputTest, DeeplyNestedSegmenterConfigurationIsRefused) {
  const lom::Problem problem =
      errorOf([&] { (void)lom::parseSegmenterConfig(nested(100000), "model.json"); });
  EXPECT_EQ(problem.file, "model.json");
  EXPECT_NE(problem.expected.find("nested at most"), std::string::npos) << problem.message();
}

// A key given twice would keep only its last value (a box moved by an edit
// that left the old centre above it): refused, naming the field.
TEST(JsonInputTest, AKeyGivenTwiceIsRefusedNamingTheField) {
  lom::test::TempDir dir;
  writeText(dir / "boxes.json",
            R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [)"
            R"({"label": 3, "center": [0, 0, 0], "size": [0.1, 0.1, 0.1]},)"
            R"({"label": 4, "center": [1, 0, 0], "size": [0.1, 0.1, 0.1], "center": [2, 0, 0]}]})");
  const lom::Problem problem = errorOf([&] { (void)lom::loadAnnotations(dir / "boxes.json"); });
  EXPECT_EQ(problem.file, (dir / "boxes.json").string());
  EXPECT_EQ(problem.field, "boxes[1].center");
  EXPECT_EQ(problem.expected, "each key once in its object");
  EXPECT_EQ(problem.found, "the key \"center\" a second time");
  // The same key in two objects is no repetition.
  writeText(dir / "fine.json", R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [)"
                               R"({"label": 3, "center": [0, 0, 0], "size": [0.1, 0.1, 0.1]},)"
                               R"({"label": 4, "center": [1, 0, 0], "size": [0.1, 0.1, 0.1]}]})");
  EXPECT_EQ(lom::loadAnnotations(dir / "fine.json").boxes.size(), 2u);
  // Nor at the top level of a sequence.
  writeSequence(dir.path());
  std::string text;
  {
    std::ifstream in(dir / "sequence.json");
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  writeText(dir / "sequence.json", "{\"frames\": [], " + text.substr(text.find('{') + 1));
  const lom::Problem top = errorOf([&] { (void)lom::loadSequence(dir.path()); });
  EXPECT_EQ(top.field, "frames");
  EXPECT_EQ(top.found, "the key \"frames\" a second time");
}

TEST(JsonInputTest, NumberBeyondADoubleNamesFieldAndPosition) {
  lom::test::TempDir dir;
  writeSequence(dir.path());
  Json json = Json::parse(std::ifstream(dir / "sequence.json"));
  json["frames"][0]["pose"][3] = 12345.0;
  std::string text = json.dump(1);
  const size_t at = text.find("12345.0");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 7, "1e999");
  writeText(dir / "sequence.json", text);
  const lom::Problem problem = errorOf([&] { (void)lom::loadSequence(dir.path()); });
  EXPECT_EQ(problem.file, (dir / "sequence.json").string());
  EXPECT_EQ(problem.field, "frames[0].pose[3]");
  EXPECT_NE(problem.expected.find("a finite number"), std::string::npos) << problem.message();
  EXPECT_NE(problem.found.find("'1e999' at line "), std::string::npos) << problem.message();
  EXPECT_EQ(problem.message().find("json.exception"), std::string::npos) << problem.message();
}

TEST(JsonInputTest, NumberBeyondADoubleInAnnotationsNamesTheField) {
  lom::test::TempDir dir;
  writeText(dir / "boxes.json", R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [)"
                                R"({"label": 1, "center": [0, 0, 0], "size": [1, -1e999, 1]}]})");
  const lom::Problem problem = errorOf([&] { (void)lom::loadAnnotations(dir / "boxes.json"); });
  EXPECT_EQ(problem.file, (dir / "boxes.json").string());
  EXPECT_EQ(problem.field, "boxes[0].size[1]");
  EXPECT_NE(problem.found.find("'-1e999' at line 1, column "), std::string::npos)
      << problem.message();
}

// Python's json.dump writes NaN and Infinity, which JSON has not: the
// message names the field and the fix.
TEST(JsonInputTest, NaNAndInfinityNameTheFieldAndTheFix) {
  for (const std::string word : {"NaN", "Infinity", "-Infinity", "nan"}) {
    lom::test::TempDir dir;
    writeText(dir / "boxes.json",
              R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [)"
              R"({"label": 1, "center": [0, 0, 0], "size": [1, 1, 1]},)"
              "\n {\"label\": 2, \"center\": [0, " +
                  word + R"(, 0], "size": [1, 1, 1]}]})");
    const lom::Problem problem = errorOf([&] { (void)lom::loadAnnotations(dir / "boxes.json"); });
    EXPECT_EQ(problem.file, (dir / "boxes.json").string()) << word;
    EXPECT_EQ(problem.field, "boxes[1].center[1]") << word << ": " << problem.message();
    EXPECT_NE(problem.expected.find("JSON has no NaN or Infinity"), std::string::npos)
        << problem.message();
    EXPECT_NE(problem.expected.find("allow_nan=False"), std::string::npos) << problem.message();
    EXPECT_NE(problem.found.find("'" + word + "' at line 2, column 29"), std::string::npos)
        << problem.message();
  }
  // Other lexer errors stay what they were.
  lom::test::TempDir dir;
  writeText(dir / "boxes.json", R"({"boxes": [Nope]})");
  const lom::Problem other = errorOf([&] { (void)lom::loadAnnotations(dir / "boxes.json"); });
  EXPECT_EQ(other.expected, "valid JSON");
}

TEST(JsonInputTest, HugeIntegerLiteralIsReportedLikeAnOverflowingNumber) {
  lom::test::TempDir dir;
  writeText(dir / "sequence.json", "{\"version\": 1" + std::string(400, '0') + "}");
  const lom::Problem problem = errorOf([&] { (void)lom::loadSequence(dir.path()); });
  EXPECT_EQ(problem.field, "version");
  EXPECT_NE(problem.expected.find("a finite number"), std::string::npos) << problem.message();
}

// The parser stops at a NUL byte as if the text ended there; a binary or damaged
// file is named as such instead of "unexpected end of input".
TEST(JsonInputTest, NulByteIsReportedAsSuchWithItsPosition) {
  lom::test::TempDir dir;
  writeText(dir / "sequence.json",
            std::string("{\"format\": \"lom-sequence\",\n  \0\"x\": 1}", 37));
  lom::Problem problem = errorOf([&] { (void)lom::loadSequence(dir.path()); });
  EXPECT_EQ(problem.file, (dir / "sequence.json").string());
  EXPECT_EQ(problem.expected, "a JSON text file");
  EXPECT_EQ(problem.found, "a NUL byte at line 2, column 3 (a binary or damaged file?)");
  writeText(dir / "boxes.json", std::string("[\0]", 3));
  problem = errorOf([&] { (void)lom::loadAnnotations(dir / "boxes.json"); });
  EXPECT_EQ(problem.found, "a NUL byte at line 1, column 2 (a binary or damaged file?)");
}

}  // namespace
