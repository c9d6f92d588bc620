// labeloctomap info / validate, run as a separate process.
#include <fstream>

#include "lom/npy.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 6;
constexpr int kHeight = 4;

// Three frames with depth PNG, label PNG and (for frame 0) a proba .npy.
void writeSequence(const fs::path& root) {
  fs::create_directories(root / "frames");
  lom::Sequence sequence;
  sequence.labels = lom::LabelSet(
      {{0, "__background__", {0, 0, 0}}, {1, "mug", {128, 0, 0}}, {2, "book", {0, 128, 0}}});
  sequence.camera.width = kWidth;
  sequence.camera.height = kHeight;
  sequence.camera.cx = 0.5 * (kWidth - 1);  // a real camera's focal lengths, centred
  sequence.camera.cy = 0.5 * (kHeight - 1);
  for (int i = 0; i < 3; ++i) {
    const std::string stem = "frames/" + std::to_string(i);
    lom::FrameRecord frame;
    frame.stamp = 10.0 + i;
    frame.T_world_camera.translation() = Eigen::Vector3d(0.25 * i, 0.0, -1.0);
    frame.depth = stem + ".depth.png";
    frame.label = stem + ".label.png";
    frame.view = i != 1;
    lom::writeDepthPng(root / frame.depth, {kWidth, kHeight, std::vector<float>(24, 0.8f)}, 0.001);
    lom::writeLabelPng(root / frame.label, {kWidth, kHeight, std::vector<std::uint16_t>(24, 2)});
    if (i == 0) {
      frame.proba = stem + ".proba.npy";
      frame.proba_labels = {0, 2};
      lom::writeNpyFloat32(root / frame.proba, {kHeight, kWidth, 2}, std::vector<float>(48, 0.5f));
    }
    sequence.frames.push_back(frame);
  }
  lom::saveSequence(sequence, root);
}

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

class CliInfoTest : public ::testing::Test {
 protected:
  lom::test::TempDir dir;
  fs::path seq() const { return dir / "seq"; }
  void SetUp() override { writeSequence(seq()); }
};

TEST_F(CliInfoTest, InfoSummarisesTheSequence) {
  const auto result = lom::test::runCli("info " + quoted(seq()));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("frames:           3"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("views:            2"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("labels:           3"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("book"), std::string::npos) << result.out;
  EXPECT_EQ(result.out.find("mug"), std::string::npos) << "mug has no proba channel\n"
                                                       << result.out;
  EXPECT_NE(result.out.find("time span:        10 .. 12"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("proba:            1/3"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("x 0 .. 0.5"), std::string::npos) << result.out;
}

TEST_F(CliInfoTest, InfoSaysWhenTheFramesHaveNoTimeStamps) {
  lom::Sequence sequence = lom::loadSequence(seq());
  for (auto& frame : sequence.frames) frame.stamp.reset();
  sequence.frames[0].proba_from_label = true;
  lom::saveSequence(sequence, seq());
  const auto result = lom::test::runCli("info " + quoted(seq()));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("time span:        none (the frames have no time stamps)\n"),
            std::string::npos)
      << result.out;
  EXPECT_EQ(result.out.find(" s)"), std::string::npos) << "no span in seconds\n" << result.out;
  EXPECT_NE(result.out.find("proba:            1/3 (1 .npy), 1 made from the label images"),
            std::string::npos)
      << result.out;

  sequence.frames[2].stamp = 4.5;
  sequence.frames[1].stamp = 2.0;
  lom::saveSequence(sequence, seq());
  const auto some = lom::test::runCli("info " + quoted(seq()));
  EXPECT_NE(some.out.find("time span:        2 .. 4.5 (2.5 s; 2 of 3 frames have a time stamp)"),
            std::string::npos)
      << some.out;
}

// A sequence is its folder's sequence.json: a copy under another name was
// read, but every message (and every file written back) named sequence.json.
TEST_F(CliInfoTest, ASequenceFileOfAnotherNameIsRefusedNamingIt) {
  fs::copy_file(seq() / "sequence.json", seq() / "other.json");
  const auto result = lom::test::runCli("info " + quoted(seq() / "other.json"));
  EXPECT_EQ(result.exit_code, 1) << result.out;
  EXPECT_NE(result.err.find((seq() / "other.json").string() + ": expected a sequence folder"),
            std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("a sequence's file is named sequence.json"), std::string::npos)
      << result.err;
  EXPECT_EQ(lom::test::runCli("info " + quoted(seq() / "sequence.json")).exit_code, 0);
}

// Stamps of real recordings (seconds since 1970) and site coordinates keep
// their digits: "1.7e+09 .. 1.7e+09" told nothing.
TEST_F(CliInfoTest, InfoShowsEpochStampsAndFarCoordinatesInFull) {
  lom::Sequence sequence = lom::loadSequence(seq());
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    sequence.frames[i].stamp = 1700000000.125 + 0.25 * static_cast<double>(i);
    sequence.frames[i].T_world_camera.translation().x() += 654321.0;
  }
  lom::saveSequence(sequence, seq());
  const auto result = lom::test::runCli("info " + quoted(seq()));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("time span:        1700000000.125 .. 1700000000.625 (0.5 s)"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("x 654321 .. 654321.5"), std::string::npos) << result.out;
}

// sequence.json may name files that are gone: info counts the files that are there.
TEST_F(CliInfoTest, InfoCountsOnlyFrameFilesThatExist) {
  fs::remove(seq() / "frames" / "0.depth.png");
  fs::remove(seq() / "frames" / "1.label.png");
  fs::remove(seq() / "frames" / "2.label.png");
  fs::create_directories(seq() / "frames" / "2.label.png");  // a folder under a file's name
  const auto result = lom::test::runCli("info " + quoted(seq()));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("depth:            2/3 (2 .png); 1 file named in sequence.json "
                            "missing or not a regular file"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("label:            1/3 (1 .png); 2 files named in sequence.json "
                            "missing or not a regular file"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("proba:            1/3 (1 .npy)\n"), std::string::npos) << result.out;
}

TEST_F(CliInfoTest, InfoAcceptsThePathOfSequenceJson) {
  const auto result = lom::test::runCli("info " + quoted(seq() / "sequence.json"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("frames:           3"), std::string::npos) << result.out;
}

TEST_F(CliInfoTest, InfoOnAMissingSequenceFailsNamingThePath) {
  const auto result = lom::test::runCli("info " + quoted(dir / "nowhere"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("nowhere"), std::string::npos) << result.err;
}

// A mistyped map name is a missing map, as export, plan and render say, not
// a missing sequence.
TEST_F(CliInfoTest, InfoOnAMissingMapFileSaysAMapFileIsMissing) {
  for (const char* name : {"missing.ot", "missing.BT"}) {
    const auto result = lom::test::runCli("info " + quoted(dir / name));
    EXPECT_EQ(result.exit_code, 1) << name;
    EXPECT_NE(result.err.find(std::string(name) + ": map file: expected a readable"),
              std::string::npos)
        << result.err;
    EXPECT_EQ(result.err.find("sequence"), std::string::npos) << result.err;
  }
}

TEST_F(CliInfoTest, UnknownOptionOrMissingArgumentExitsTwo) {
  EXPECT_EQ(lom::test::runCli("info " + quoted(seq()) + " --bogus 1").exit_code, 2);
  EXPECT_EQ(lom::test::runCli("validate " + quoted(seq()) + " --strict=yes").exit_code, 2);
  const auto missing = lom::test::runCli("validate");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("SEQ"), std::string::npos) << missing.err;
}

TEST_F(CliInfoTest, ValidateAcceptsAGoodSequence) {
  const auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_NE(result.out.find("OK: 3 frames valid"), std::string::npos) << result.out;
}

// A camera 300 m away from the frame before: valid numbers, so not a failure,
// but a warning naming the frame and the distance (validate and fuse).
TEST_F(CliInfoTest, CameraJumpsAreWarnedAbout) {
  lom::Sequence sequence = lom::loadSequence(seq());
  sequence.frames[2].T_world_camera.translation() += Eigen::Vector3d(300.0, 0.0, 0.0);
  lom::saveSequence(sequence, seq());
  const auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  // Named with sequence.json, whose field it is, as validate's problems are.
  const std::string json_file = (seq() / "sequence.json").string();
  EXPECT_NE(result.out.find("warning: " + json_file +
                            ": frames[2].pose: the camera is 300.2 m from where "
                            "it was in frames[1]"),
            std::string::npos)
      << result.out;
  // 300 m out, the camera also needs voxels coarser than the finest (2 mm: 65.536 m).
  EXPECT_NE(result.out.find("warning: " + json_file +
                            ": frames[2].pose: the camera lies outside the extent"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("OK: 3 frames valid (2 warnings)"), std::string::npos) << result.out;
  const auto fused = lom::test::runCli("fuse " + quoted(seq()) + " --out " + quoted(dir / "m.ot"));
  EXPECT_NE(fused.err.find("warning: frames[2].pose"), std::string::npos) << fused.err;
}

// A focal length in metres instead of pixels: valid numbers, so not a
// failure, but a warning with the field of view (validate and fuse).
TEST_F(CliInfoTest, ImplausibleIntrinsicsAreWarnedAbout) {
  lom::Sequence sequence = lom::loadSequence(seq());
  // 6 x 4 pixels: 172 x 168 degrees.
  sequence.camera.fx = sequence.camera.fy = 0.2;
  sequence.camera.cx = 2.5;
  sequence.camera.cy = 1.5;
  for (auto& frame : sequence.frames) frame.camera.reset();
  lom::saveSequence(sequence, seq());
  const auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_NE(result.out.find("warning: " + (seq() / "sequence.json").string() +
                            ": camera: fx = 0.2, fy = 0.2, cx = 2.5, cy = 1.5 give a field of "
                            "view of 172.2 x 167.8 degrees at 6 x 4 pixels"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("depth cameras see about 40 to 120 degrees"), std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("OK: 3 frames valid (1 warning)"), std::string::npos) << result.out;
  const auto fused = lom::test::runCli("fuse " + quoted(seq()) + " --out " + quoted(dir / "m.ot"));
  EXPECT_NE(fused.err.find("warning: " + (seq() / "sequence.json").string() + ": camera: fx = 0.2"),
            std::string::npos)
      << fused.err;
}

// validate has no voxel size: a camera that no voxel size fusion takes can
// hold is a problem naming its pose; one that only coarser voxels than the
// finest hold is a warning with the voxel size it needs.
TEST_F(CliInfoTest, ValidateFlagsCamerasOutsideTheMapsExtent) {
  lom::Sequence sequence = lom::loadSequence(seq());
  sequence.frames[1].T_world_camera.translation().x() = 100.0;
  lom::saveSequence(sequence, seq());
  auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_NE(result.out.find("warning: " + (seq() / "sequence.json").string() +
                            ": frames[1].pose: the camera lies outside the extent of a map with "
                            "the finest voxels fusion takes, 65.536 m either side of the origin "
                            "on each axis at 0.002 m voxels"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("fusing needs voxels of 0.004 m or more"), std::string::npos)
      << result.out;

  sequence.frames[1].T_world_camera.translation().x() = 1e20;
  lom::saveSequence(sequence, seq());
  result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 1) << result.out << result.err;
  EXPECT_NE(result.out.find((seq() / "sequence.json").string() +
                            ": frames[1].pose: expected a camera position inside the map's "
                            "extent, 32768 m either side of the origin on each axis at 1 m voxels"),
            std::string::npos)
      << result.out;
  // Its neighbours did not jump: the far camera is the wrong pose.
  EXPECT_EQ(result.out.find("frames[2].pose: the camera is"), std::string::npos) << result.out;
}

// Depths of 8 cm (a depth_scale of 0.0001 for millimetres): every command
// that reads depths says so, naming the field; validate and info give the figures.
TEST_F(CliInfoTest, ADepthScaleNoDepthCameraHasIsWarnedAbout) {
  auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_NE(result.out.find("depth: 100.0% of the pixels of 3 frames read valid (100.0% .. "
                            "100.0% per frame), 0.8 .. 0.8 m, median 0.8 m (frame medians 0.8 "
                            ".. 0.8 m)\n"),
            std::string::npos)
      << result.out;
  EXPECT_EQ(result.out.find("warning:"), std::string::npos) << result.out;
  result = lom::test::runCli("info " + quoted(seq()));
  EXPECT_NE(result.out.find("depth (sampled):  frames 0, 1, 2: 100.0% of pixels valid, 0.8 .. "
                            "0.8 m, median 0.8 m\n"),
            std::string::npos)
      << result.out;
  EXPECT_EQ(result.err, "");

  lom::Sequence sequence = lom::loadSequence(seq());
  sequence.camera.depth_scale = 0.0001;
  lom::saveSequence(sequence, seq());
  const std::string json_file = (seq() / "sequence.json").string();
  result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_NE(result.out.find("warning: " + json_file +
                            ": camera.depth_scale: the median valid depth of the 3 frames is "
                            "0.08 m (0.08 .. 0.08 m), nearer than depth cameras measure (a "
                            "median of 0.1 to 20 m expected): depth_scale 0.0001 metres per unit "
                            "is likely wrong; 0.001 would give a median of 0.8 m (fused as it "
                            "is, the map comes out 10 times too small)\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("OK: 3 frames valid (1 warning)"), std::string::npos) << result.out;

  result = lom::test::runCli("info " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("depth (sampled):  frames 0, 1, 2: 100.0% of pixels valid, 0.08 .. "
                            "0.08 m, median 0.08 m\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.err.find("warning: " + json_file +
                            ": camera.depth_scale: the median valid depth of the 3 frames "
                            "sampled is 0.08 m"),
            std::string::npos)
      << result.err;

  result = lom::test::runCli("fuse " + quoted(seq()) + " --out " + quoted(dir / "m.ot"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("warning: " + json_file +
                            ": camera.depth_scale: the farthest measured point of the 3 frames "
                            "fused lies 0.0"),
            std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("nearer than depth cameras measure (0.1 to 20 m): depth_scale 0.0001 "
                            "(metres per unit of the depth images) is likely too small, which "
                            "shrinks the map by the same factor"),
            std::string::npos)
      << result.err;

  // A scale 1000 times too large: validate warns, fuse's max range message names the scale.
  sequence.camera.depth_scale = 1.0;
  lom::saveSequence(sequence, seq());
  result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_NE(result.out.find("is 800 m (800 .. 800 m), farther than depth cameras measure"),
            std::string::npos)
      << result.out;
}

// Problems anywhere (here a label image) leave "no valid depth" said.
TEST_F(CliInfoTest, ValidateSaysThereIsNoDepthBesideOtherProblems) {
  for (int i = 0; i < 3; ++i)
    lom::writeDepthPng(seq() / ("frames/" + std::to_string(i) + ".depth.png"),
                       {kWidth, kHeight, std::vector<float>(24, 0.f)}, 0.001);
  fs::remove(seq() / "frames/2.label.png");
  const auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.out.find("frames[2].label: expected"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find((seq() / "sequence.json").string() +
                            ": frames[].depth: expected depth images with valid measurements"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.err.find("2 problems"), std::string::npos) << result.err;
}

// A copy of a frame, a depth file of two frames with different poses, a
// stamp going back: valid files, so warnings naming the frames.
TEST_F(CliInfoTest, ValidateWarnsAboutRepeatedFramesAndStampsGoingBack) {
  lom::Sequence sequence = lom::loadSequence(seq());
  sequence.frames.push_back(sequence.frames[1]);
  sequence.frames[2].depth = sequence.frames[0].depth;
  sequence.frames[2].stamp = 9.0;
  lom::saveSequence(sequence, seq());
  const auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  const std::string json_file = (seq() / "sequence.json").string();
  for (const std::string& expected : std::vector<std::string>{
           "warning: " + json_file + ": frames: frames[3] repeats frames[1]",
           "warning: " + json_file + ": frames[].depth: a depth file is named by frames with " +
               "different poses: " + (seq() / "frames/0.depth.png").string() +
               " (frames[0].depth and frames[2].depth, 2 poses)",
           "warning: " + json_file + ": frames[].stamp: the stamps go back once, frames[2].stamp " +
               "9 after frames[1].stamp 11,",
           std::string("OK: 4 frames valid (3 warnings)")})
    EXPECT_NE(result.out.find(expected), std::string::npos) << expected << "\nin\n" << result.out;
}

// The boxes beside sequence.json are read as score reads them: whatever
// score would refuse is a problem, every box with a label the sequence
// lacks at once.
TEST_F(CliInfoTest, ValidateChecksTheSequencesBoxes) {
  const fs::path boxes = seq() / "annotations.json";
  const auto validate = [&](const std::string& text) {
    std::ofstream(boxes) << text;
    return lom::test::runCli("validate " + quoted(seq()));
  };
  const std::string head =
      R"({"format": "labeloctomap-annotations", "version": 1, "frame_id": "world", "boxes": [)";
  const std::string good = R"({"label": 1, "center": [0, 0, 1], "size": [0.1, 0.1, 0.1]})";
  auto result = validate(head + good + "]}");
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_NE(result.out.find("OK: 3 frames valid\n"), std::string::npos) << result.out;

  // Labels the sequence lacks (it has 0..2): every box named.
  result = validate(head + good +
                    R"(, {"label": 77, "center": [0, 0, 1], "size": [0.1, 0.1, 0.1]},
                         {"label": 0, "center": [0, 0, 1], "size": [0.1, 0.1, 0.1]}]})");
  EXPECT_EQ(result.exit_code, 1) << result.out << result.err;
  EXPECT_NE(result.out.find(
                boxes.string() + ": boxes[1].label: expected an object label of the sequence " +
                (seq() / "sequence.json").string() + " (1..2; 0 is the background), found 77"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find(boxes.string() + ": boxes[2].label: expected an object label"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.err.find("2 problems"), std::string::npos) << result.err;
  // A refused box named as another label is not also said to be "scored".
  result = validate(
      head + good +
      R"(, {"label": 0, "name": "thing_two", "center": [0, 0, 1], "size": [0.1, 0.1, 0.1]}]})");
  EXPECT_EQ(result.exit_code, 1) << result.out << result.err;
  EXPECT_NE(result.out.find("boxes[1].label: expected an object label"), std::string::npos)
      << result.out;
  EXPECT_EQ(result.out.find("is scored"), std::string::npos) << result.out;
  // Nor is a second box of a label (the loader refuses it), whichever name it bears.
  result = validate(
      head + good +
      R"(, {"label": 1, "name": "thing_two", "center": [0, 0, 1], "size": [0.1, 0.1, 0.1]}]})");
  EXPECT_EQ(result.exit_code, 1) << result.out << result.err;
  EXPECT_NE(result.out.find("boxes[1].label: expected each label in at most one box, found label "
                            "1 again (also boxes[0]"),
            std::string::npos)
      << result.out;
  EXPECT_EQ(result.out.find("is scored"), std::string::npos) << result.out;

  // What the loader refuses, named as score names it.
  const std::vector<std::pair<std::string, std::string>> broken = {
      {head + R"({"label": 1, "center": [0, 0, 1], "size": [0.1, -0.1, 0.1]}]})",
       ": boxes[0].size"},
      {head + R"({"label": 1, "center": [0, 0], "size": [0.1, 0.1, 0.1]}]})",
       ": boxes[0].center: expected 3 numbers"},
      {head + good.substr(0, good.size() - 1) + R"(, "rotation": [0, 0, 0, 0]}]})",
       ": boxes[0].rotation"},
      {head + good, ": expected"},  // cut short
      {R"({"format": "labeloctomap-annotations", "version": 1, "frame_id": "base", "boxes": [)" +
           good + "]}",
       ": frame_id: expected the sequence's frame \"world\""}};
  for (const auto& [text, expected] : broken) {
    result = validate(text);
    EXPECT_EQ(result.exit_code, 1) << text + "\n" + result.out + result.err;
    EXPECT_NE(result.out.find(boxes.string() + expected), std::string::npos)
        << text + "\n" + result.out;
  }

  // The YAML box files of the original experiments, beside sequence.json.
  fs::remove(boxes);
  std::ofstream(seq() / "annotations.yaml")
      << "boxes:\n  - {dimensions: [0.1, 0.1, 0.1], position: [0, 0, 1], orientation: [0, 0, "
         "0, 1], name: object_9}\n";
  result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 1) << result.out << result.err;
  EXPECT_NE(result.out.find((seq() / "annotations.yaml").string() +
                            ": boxes[0].name: expected an object label of the sequence"),
            std::string::npos)
      << result.out;
}

TEST_F(CliInfoTest, ValidateListsEveryProblemOfABrokenSequence) {
  fs::remove(seq() / "frames/1.depth.png");
  lom::writeLabelPng(seq() / "frames/2.label.png",
                     {kWidth, kHeight, std::vector<std::uint16_t>(24, 7)});
  lom::writeNpyFloat32(seq() / "frames/0.proba.npy", {kHeight, kWidth, 3},
                       std::vector<float>(72, 0.1f));
  const auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 1);
  const std::string all = result.out + result.err;
  for (const std::string expected :
       {"frames/1.depth.png: frames[1].depth: expected",
        "frames/2.label.png: frames[2].label (label ids)",
        "frames/0.proba.npy: frames[0].proba (channels)", "3 problems"})
    EXPECT_NE(all.find(expected), std::string::npos) << expected << " missing in\n" << all;
}

TEST_F(CliInfoTest, ValidateReportsJsonLevelProblems) {
  std::ofstream(seq() / "sequence.json") << R"({"format": "labeloctomap-sequence", "version": 7})";
  const auto result = lom::test::runCli("validate " + quoted(seq()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.out.find("sequence.json: version: expected 1"), std::string::npos) << result.out;
}

}  // namespace
