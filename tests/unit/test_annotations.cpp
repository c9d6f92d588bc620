// annotations.json reading and writing, and the YAML box importer.
#include <cmath>
#include <fstream>
#include <functional>

#include "lom/annotations.hpp"
#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "test_input_helpers.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

using lom::test::errorOf;
using lom::test::writeText;

std::string annotationsWithBoxes(const std::string& boxes) {
  return R"({"format": "labeloctomap-annotations", "version": 1, "frame_id": "base", "boxes": [)" +
         boxes + "]}";
}

class AnnotationsTest : public ::testing::Test {
 protected:
  lom::test::TempDir dir;
  fs::path file() const { return dir / "annotations.json"; }
  lom::Problem loadError(const std::string& text) {
    writeText(file(), text);
    return errorOf([&] { (void)lom::loadAnnotations(file()); });
  }
};

TEST_F(AnnotationsTest, RoundTripOfARotatedBoxIsExact) {
  lom::Annotations original;
  original.frame_id = "shelf";
  lom::GroundTruthBox book;
  book.label = 19;
  book.name = "i_am_a_bunny_book";
  book.box.center = {0.1234567890123, -0.5, 1.0 / 3.0};
  book.box.size = {0.2, 0.15, 0.025};
  book.box.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.5).normalized()));
  lom::GroundTruthBox cup;
  cup.label = 12;
  cup.name = "easter_turtle_sippy_cup";
  cup.box.center = {0.0, 0.0, 0.1};
  original.boxes = {book, cup};
  lom::saveAnnotations(original, file());

  const lom::Annotations loaded = lom::loadAnnotations(file());
  EXPECT_EQ(loaded.frame_id, "shelf");
  ASSERT_EQ(loaded.boxes.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(loaded.boxes[i].label, original.boxes[i].label);
    EXPECT_EQ(loaded.boxes[i].name, original.boxes[i].name);
    EXPECT_EQ(loaded.boxes[i].box.center, original.boxes[i].box.center);
    EXPECT_EQ(loaded.boxes[i].box.size, original.boxes[i].box.size);
    EXPECT_EQ(loaded.boxes[i].box.rotation.coeffs(), original.boxes[i].box.rotation.coeffs());
  }
  ASSERT_NE(loaded.find(19), nullptr);
  EXPECT_EQ(loaded.find(19)->name, "i_am_a_bunny_book");
  EXPECT_EQ(loaded.find(5), nullptr);
}

TEST_F(AnnotationsTest, NormalisesQuaternionsAndDefaultsRotationAndFrame) {
  writeText(file(), R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [
      {"label": 1, "center": [0, 0, 0], "size": [1, 2, 3], "rotation": [0, 0, 2, 2]},
      {"label": 2, "center": [1, 1, 1], "size": [1, 1, 1]}]})");
  const auto loaded = lom::loadAnnotations(file());
  EXPECT_EQ(loaded.frame_id, "world");
  EXPECT_NEAR(loaded.boxes[0].box.rotation.norm(), 1.0, 1e-15);
  EXPECT_NEAR(loaded.boxes[0].box.rotation.z(), std::sqrt(0.5), 1e-15);
  EXPECT_TRUE(
      loaded.boxes[1].box.rotation.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs()));
  EXPECT_EQ(loaded.boxes[1].name, "");
}

TEST_F(AnnotationsTest, RejectsZeroQuaternionNamingTheField) {
  const auto problem = loadError(annotationsWithBoxes(
      R"({"label": 1, "center": [0, 0, 0], "size": [1, 1, 1], "rotation": [0, 0, 0, 0]})"));
  EXPECT_EQ(problem.file, file().string());
  EXPECT_EQ(problem.field, "boxes[0].rotation");
  EXPECT_NE(problem.expected.find("non-zero quaternion"), std::string::npos);
}

TEST_F(AnnotationsTest, RejectsDuplicateLabels) {
  const auto problem = loadError(annotationsWithBoxes(
      R"({"label": 4, "center": [0, 0, 0], "size": [1, 1, 1]},
         {"label": 4, "center": [1, 0, 0], "size": [1, 1, 1]})"));
  EXPECT_EQ(problem.field, "boxes[1].label");
  EXPECT_NE(problem.found.find("also boxes[0].label"), std::string::npos) << problem.message();
}

TEST_F(AnnotationsTest, RejectsMalformedFields) {
  auto size =
      loadError(annotationsWithBoxes(R"({"label": 1, "center": [0, 0, 0], "size": [1, 0, 1]})"));
  EXPECT_EQ(size.field, "boxes[0].size");
  EXPECT_NE(size.expected.find("positive"), std::string::npos);

  auto center =
      loadError(annotationsWithBoxes(R"({"label": 1, "center": [0, "x", 0], "size": [1, 1, 1]})"));
  EXPECT_EQ(center.field, "boxes[0].center[1]");

  auto label =
      loadError(annotationsWithBoxes(R"({"label": -1, "center": [0, 0, 0], "size": [1, 1, 1]})"));
  EXPECT_EQ(label.field, "boxes[0].label");

  auto format = loadError(R"({"format": "labeloctomap-sequence", "version": 1, "boxes": []})");
  EXPECT_EQ(format.field, "format");
  EXPECT_EQ(format.file, file().string());
  // A whole sequence.json, keys and all, is named by its format too.
  auto sequence = loadError(
      R"({"format": "labeloctomap-sequence", "version": 1, "labels": [], "camera": {}, "frames": []})");
  EXPECT_EQ(sequence.field, "format");
  EXPECT_NE(sequence.found.find("labeloctomap-sequence"), std::string::npos) << sequence.message();

  auto json = loadError(R"({"format": "labeloctomap-annotations", "version": 1, "boxes": [}")");
  EXPECT_EQ(json.expected, "valid JSON");

  auto missing = errorOf([&] { (void)lom::loadAnnotations(dir / "absent.json"); });
  EXPECT_EQ(missing.found, "no such file");
}

class AnnotationsYamlTest : public AnnotationsTest {
 protected:
  fs::path yaml() const { return dir / "boxes.yaml"; }
};

TEST_F(AnnotationsYamlTest, ImportsBoxesWithNamesFromTheLabelSet) {
  writeText(yaml(), R"(boxes:
  - dimensions: [0.2, 0.15, 0.03]
    position: [0.5, -0.1, 0.8]
    orientation: [0.0, 0.0, 0.7071067811865476, 0.7071067811865476]
    name: object_19
    frame_id: base
  - dimensions: [0.1, 0.1, 0.1]
    position: [0.4, 0.1, 0.8]
    orientation: [0, 0, 0, 1]
    name: object_77
    frame_id: base
)");
  const auto annotations = lom::importYamlBoxes(yaml(), lom::apc2016Labels());
  EXPECT_EQ(annotations.frame_id, "base");
  ASSERT_EQ(annotations.boxes.size(), 2u);
  EXPECT_EQ(annotations.boxes[0].label, 19);
  EXPECT_EQ(annotations.boxes[0].name, "i_am_a_bunny_book");
  EXPECT_EQ(annotations.boxes[0].box.size, Eigen::Vector3d(0.2, 0.15, 0.03));
  EXPECT_EQ(annotations.boxes[0].box.center, Eigen::Vector3d(0.5, -0.1, 0.8));
  EXPECT_NEAR(annotations.boxes[0].box.rotation.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(annotations.boxes[0].box.rotation.z(), std::sqrt(0.5), 1e-15);
  EXPECT_EQ(annotations.boxes[1].label, 77);
  EXPECT_EQ(annotations.boxes[1].name, "object_77");  // not in the label set

  EXPECT_EQ(lom::importYamlBoxes(yaml()).boxes[0].name, "object_19");
}

TEST_F(AnnotationsYamlTest, TheSequencesFrameReplacesTheFrameTheFileNames) {
  writeText(yaml(),
            "boxes: [{dimensions: [0.2, 0.15, 0.03], position: [0.5, -0.1, 0.8], "
            "orientation: [0, 0, 0, 1], name: object_19, frame_id: base}]\n");
  const auto in_world = lom::importYamlBoxes(yaml(), lom::apc2016Labels(), "world");
  EXPECT_EQ(in_world.frame_id, "world");
  ASSERT_EQ(in_world.boxes.size(), 1u);
  EXPECT_EQ(in_world.boxes[0].name, "i_am_a_bunny_book");
  EXPECT_EQ(lom::importYamlBoxes(yaml(), lom::apc2016Labels()).frame_id, "base");

  // loadAnnotationsFor reads a YAML box file the same way, annotations.json as it is.
  const auto loaded = lom::loadAnnotationsFor(yaml(), lom::apc2016Labels(), "shelf");
  EXPECT_EQ(loaded.frame_id, "shelf");
  ASSERT_EQ(loaded.boxes.size(), 1u);
  EXPECT_EQ(loaded.boxes[0].name, "i_am_a_bunny_book");
  writeText(file(), annotationsWithBoxes(""));
  EXPECT_EQ(lom::loadAnnotationsFor(file(), lom::apc2016Labels(), "shelf").frame_id, "base");

  // Boxes of disagreeing frames are refused all the same.
  const std::string box =
      "{dimensions: [0.1, 0.1, 0.1], position: [0, 0, 0], orientation: [0, 0, 0, 1]";
  writeText(yaml(), "boxes: [" + box + ", name: object_1, frame_id: base}, " + box +
                        ", name: object_2, frame_id: camera}]\n");
  EXPECT_EQ(errorOf([&] { (void)lom::importYamlBoxes(yaml(), {}, "world"); }).field,
            "boxes[1].frame_id");
}

TEST_F(AnnotationsYamlTest, AMissingKeyIsNamedWithItsBox) {
  for (const char* missing : {"dimensions", "position", "orientation"}) {
    std::string box;
    for (const char* key : {"dimensions", "position", "orientation"})
      if (std::string(key) != missing)
        box += std::string("    ") + key +
               (std::string(key) == "orientation" ? ": [0, 0, 0, 1]\n" : ": [0.1, 0.1, 0.1]\n");
    writeText(yaml(), "boxes:\n  - name: object_4\n" + box);
    const lom::Problem error = errorOf([&] { (void)lom::importYamlBoxes(yaml()); });
    EXPECT_EQ(error.file, yaml().string()) << missing;
    EXPECT_EQ(error.field, std::string("boxes[0].") + missing);
    EXPECT_EQ(error.found, "nothing") << missing;
  }
}

// A misspelt key (frameid) would otherwise be ignored, and a key given twice
// keep one of its values: both are refused, naming the field.
TEST_F(AnnotationsYamlTest, UnknownAndRepeatedKeysAreRefused) {
  const std::string box =
      "    dimensions: [0.1, 0.1, 0.1]\n    position: [0, 0, 0]\n"
      "    orientation: [0, 0, 0, 1]\n    name: object_4\n";
  writeText(yaml(),
            "boxes:\n  - " + box.substr(4) + "  - " + box.substr(4) + "    frameid: base\n");
  const lom::Problem unknown = errorOf([&] { (void)lom::importYamlBoxes(yaml()); });
  EXPECT_EQ(unknown.file, yaml().string());
  EXPECT_EQ(unknown.field, "boxes[1].frameid");
  EXPECT_EQ(unknown.expected, "only the keys dimensions, position, orientation, name, frame_id");
  EXPECT_EQ(unknown.found, "an unknown key");
  writeText(yaml(), "boxes:\n  - " + box.substr(4) + "    position: [1, 0, 0]\n");
  const lom::Problem twice = errorOf([&] { (void)lom::importYamlBoxes(yaml()); });
  EXPECT_EQ(twice.field, "boxes[0].position");
  EXPECT_EQ(twice.found, "the key 'position' a second time");
  writeText(yaml(), "boxs: []\nboxes:\n  - " + box.substr(4));
  EXPECT_EQ(errorOf([&] { (void)lom::importYamlBoxes(yaml()); }).field, "boxs");
  writeText(yaml(), "boxes:\n  - " + box.substr(4));
  EXPECT_EQ(lom::importYamlBoxes(yaml()).boxes.size(), 1u);
}

TEST_F(AnnotationsYamlTest, RejectsBadDimensionsNamesAndDisagreeingFrames) {
  const std::string box = R"(
  - dimensions: [0.1, 0.1, 0.1]
    position: [0, 0, 0]
    orientation: [0, 0, 0, 1]
    name: object_1
    frame_id: base)";
  writeText(yaml(), "boxes:" + box + R"(
  - dimensions: [0.1, 0.1]
    position: [0, 0, 0]
    orientation: [0, 0, 0, 1]
    name: object_2
)");
  auto dimensions = errorOf([&] { (void)lom::importYamlBoxes(yaml()); });
  EXPECT_EQ(dimensions.file, yaml().string());
  EXPECT_EQ(dimensions.field, "boxes[1].dimensions");

  writeText(yaml(), "boxes:" + box + R"(
  - dimensions: [0.1, 0.1, 0.1]
    position: [0, 0, 0]
    orientation: [0, 0, 0, 1]
    name: bunny_book
)");
  EXPECT_EQ(errorOf([&] { (void)lom::importYamlBoxes(yaml()); }).field, "boxes[1].name");

  writeText(yaml(), "boxes:" + box + R"(
  - dimensions: [0.1, 0.1, 0.1]
    position: [0, 0, 0]
    orientation: [0, 0, 0, 1]
    name: object_3
    frame_id: camera
)");
  auto frame = errorOf([&] { (void)lom::importYamlBoxes(yaml()); });
  EXPECT_EQ(frame.field, "boxes[1].frame_id");
  EXPECT_NE(frame.expected.find("boxes[0].frame_id"), std::string::npos) << frame.expected;

  writeText(yaml(), "boxes:" + box + box);
  EXPECT_EQ(errorOf([&] { (void)lom::importYamlBoxes(yaml()); }).field, "boxes[1].name");

  writeText(yaml(), "boxes: [ {dimensions: [1, 1, 1]");
  EXPECT_EQ(errorOf([&] { (void)lom::importYamlBoxes(yaml()); }).expected, "valid YAML");
}

// Every box score would refuse is listed (score throws the first), and a
// refused box is never said to be "scored" under another name.
TEST(BoxLabelProblemsTest, ListsEveryRefusedBoxAndWarnsOnlyOfScoredOnes) {
  const lom::LabelSet labels(
      {{0, "background", {0, 0, 0}}, {1, "cup", {1, 1, 1}}, {2, "book", {2, 2, 2}}});
  lom::Annotations annotations;
  annotations.boxes = {{1, "mug", {}}, {1, "jar", {}}, {7, "lamp", {}}, {2, "book", {}}};
  const std::vector<lom::Problem> problems =
      lom::boxLabelProblems(annotations, labels.size(), "boxes.json", "the sequence");
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].field, "boxes[1].label");
  EXPECT_EQ(problems[0].expected, "each label in at most one box");
  EXPECT_EQ(problems[0].found, "label 1 again (also boxes[0])");
  EXPECT_EQ(problems[1].field, "boxes[2].label");
  EXPECT_EQ(problems[1].expected, "an object label of the sequence (1..2; 0 is the background)");
  EXPECT_EQ(problems[1].found, "7");
  const lom::Problem first = errorOf(
      [&] { lom::checkBoxLabels(annotations, labels.size(), "boxes.json", "the sequence"); });
  EXPECT_EQ(first.field, problems[0].field);

  const std::vector<std::string> warnings =
      lom::boxNameWarnings(annotations, labels, "boxes.json", "sequence.json");
  ASSERT_EQ(warnings.size(), 1u);  // boxes[0] only: boxes[1] and [2] are not scored
  EXPECT_NE(warnings[0].find("boxes[0].name is 'mug'"), std::string::npos) << warnings[0];

  annotations.boxes.resize(1);
  EXPECT_TRUE(
      lom::boxLabelProblems(annotations, labels.size(), "boxes.json", "the sequence").empty());
  annotations.boxes.clear();
  EXPECT_EQ(errorOf([&] {
              lom::checkBoxLabels(annotations, labels.size(), "boxes.json", "the sequence");
            }).field,
            "boxes");
}

}  // namespace
