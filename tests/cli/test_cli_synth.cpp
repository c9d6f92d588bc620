// labeloctomap synth, run as a separate process.
#include <fstream>
#include <iterator>

#include "lom/annotations.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

const char* const kSmall = " --seed 3 --objects 4 --frames 5 --views 3 --width 160 --height 120";

TEST(CliSynthTest, WritesSequenceAndAnnotations) {
  lom::test::TempDir dir;
  const fs::path out = dir / "scene";
  const auto result = lom::test::runCli("synth --out " + quoted(out) + kSmall);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(fs::is_regular_file(out / "sequence.json"));
  EXPECT_TRUE(fs::is_regular_file(out / "annotations.json"));
  EXPECT_TRUE(fs::is_regular_file(out / "proba/000004.npy"));
  EXPECT_NE(result.out.find("5 frames (3 views)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("4 objects"), std::string::npos) << result.out;

  const lom::Sequence sequence = lom::loadSequence(out);
  EXPECT_EQ(sequence.frames.size(), 5u);
  EXPECT_EQ(sequence.camera.width, 160);
  const lom::Annotations annotations = lom::loadAnnotations(out / "annotations.json");
  ASSERT_EQ(annotations.boxes.size(), 4u);
  for (const auto& box : annotations.boxes)
    EXPECT_NE(result.out.find(box.name), std::string::npos) << "output does not list " << box.name;
}

TEST(CliSynthTest, SameSeedTwiceGivesTheSameSequence) {
  lom::test::TempDir dir;
  ASSERT_EQ(lom::test::runCli("synth --out " + quoted(dir / "a") + kSmall).exit_code, 0);
  ASSERT_EQ(lom::test::runCli("synth --out " + quoted(dir / "b") + kSmall).exit_code, 0);
  auto slurp = [](const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(slurp(dir / "a/annotations.json"), slurp(dir / "b/annotations.json"));
  EXPECT_EQ(slurp(dir / "a/depth/000002.png"), slurp(dir / "b/depth/000002.png"));
}

TEST(CliSynthTest, BadOptionValuesExitWithUsageErrorNamingTheOption) {
  lom::test::TempDir dir;
  const std::string out = " --out " + quoted(dir / "scene");
  const std::pair<const char*, const char*> cases[] = {
      {"--objects 0", "--objects"},
      {"--objects 40", "--objects"},
      {"--views 2", "--views"},
      {"--frames 2", "--frames"},
      {"--frames 4 --views 5", "--views"},
      {"--width 8", "--width"},
      {"--height 2049", "--height"},
      {"--seed -1", "--seed"},
      {"--seed ' -1'", "--seed"},
      {"--seed +5", "--seed"},
      {"--seed abc", "--seed"},
      {"--objects two", "--objects"},
      {"--colour red", "--colour"},
  };
  for (const auto& [arguments, option] : cases) {
    const auto result = lom::test::runCli(std::string("synth") + out + " " + arguments);
    EXPECT_EQ(result.exit_code, 2) << arguments << "\n" << result.err;
    EXPECT_NE(result.err.find(option), std::string::npos) << arguments << "\n" << result.err;
  }
  EXPECT_FALSE(fs::exists(dir / "scene"));
}

TEST(CliSynthTest, MissingOutIsAUsageError) {
  const auto result = lom::test::runCli("synth --seed 3");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--out"), std::string::npos) << result.err;
}

TEST(CliSynthTest, RefusesAForeignNonEmptyFolder) {
  lom::test::TempDir dir;
  { std::ofstream(dir / "notes.txt") << "keep me"; }
  const auto result = lom::test::runCli("synth --out " + quoted(dir.path()) + kSmall);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find(dir.path().string()), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("synth.json"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(dir / "sequence.json"));
}

// A sequence above the output folder whose frame files lie in it: synth would
// replace them (its own earlier output or not), so the folder is refused.
TEST(CliSynthTest, RefusesAFolderHoldingFramesOfASequenceAboveIt) {
  lom::test::TempDir dir;
  ASSERT_EQ(lom::test::runCli("synth --out " + quoted(dir / "P" / "s") + kSmall).exit_code, 0);
  lom::Sequence outer = lom::loadSequence(dir / "P" / "s");
  for (auto& frame : outer.frames)
    for (std::string* file : {&frame.depth, &frame.color, &frame.label, &frame.proba})
      if (!file->empty()) *file = "s/" + *file;
  lom::saveSequence(outer, dir / "P");
  ASSERT_NO_THROW((void)lom::loadFrame(lom::loadSequence(dir / "P"), 0));
  const std::string before = lom::test::slurp(dir / "P" / "s" / "depth" / "000000.png");
  const auto result = lom::test::runCli("synth --out " + quoted(dir / "P" / "s") +
                                        " --frames 3 --width 32 --height 24");
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_NE(result.err.find("holds frame files of the sequence in " + (dir / "P").string()),
            std::string::npos)
      << result.err;
  EXPECT_EQ(lom::test::slurp(dir / "P" / "s" / "depth" / "000000.png"), before);
}

// A scene written again into its folder replaces the boxes it wrote, not the
// boxes a user edited since (the studio saves them to annotations.json).
TEST(CliSynthTest, BoxesEditedSinceTheLastRunAreKept) {
  lom::test::TempDir dir;
  const fs::path out = dir / "scene";
  const std::string small = " --objects 4 --frames 5 --views 3 --width 160 --height 120";
  ASSERT_EQ(lom::test::runCli("synth --out " + quoted(out) + small).exit_code, 0);
  const auto again = lom::test::runCli("synth --out " + quoted(out) + small + " --seed 4");
  ASSERT_EQ(again.exit_code, 0) << again.err;  // its own boxes, unedited: replaced
  lom::Annotations boxes = lom::loadAnnotations(out / "annotations.json");
  ASSERT_FALSE(boxes.boxes.empty());
  boxes.boxes.front().box.size.x() += 0.01;
  lom::saveAnnotations(boxes, out / "annotations.json");
  const std::string edited = lom::test::slurp(out / "annotations.json");
  const std::string sequence = lom::test::slurp(out / "sequence.json");

  const auto refused = lom::test::runCli("synth --out " + quoted(out) + small + " --seed 5");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("annotations.json with other boxes"), std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find(out.string()), std::string::npos) << refused.err;
  EXPECT_EQ(lom::test::slurp(out / "annotations.json"), edited);
  EXPECT_EQ(lom::test::slurp(out / "sequence.json"), sequence);  // nothing removed

  // Moved away, the boxes are kept and the scene is written.
  fs::rename(out / "annotations.json", dir / "mine.json");
  EXPECT_EQ(lom::test::runCli("synth --out " + quoted(out) + small + " --seed 5").exit_code, 0);
  EXPECT_EQ(lom::test::slurp(dir / "mine.json"), edited);
}

}  // namespace

namespace {

// A full disk (here: a limit on the size of any file written) stops synth with
// the product's message, not libpng's, and leaves no half-written scene.
TEST(CliSynthTest, AFullDiskLeavesNoHalfWrittenScene) {
  lom::test::TempDir dir;
  const char* const kScene = " --frames 3 --width 320 --height 240";
  lom::test::CliLimits full_disk;
  full_disk.file_kib = 20;  // less than one frame's depth PNG

  const fs::path fresh = dir / "fresh";
  const auto r = lom::test::runCli("synth --out " + quoted(fresh) + kScene, full_disk);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(
                (fresh / "depth/000000.png").string() +
                ": output: expected a complete write, found write failed (the file-size limit of "),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("libpng"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(fresh)) << "the new folder is taken away again";

  const fs::path empty = dir / "empty";
  fs::create_directories(empty);
  EXPECT_EQ(lom::test::runCli("synth --out " + quoted(empty) + kScene, full_disk).exit_code, 1);
  EXPECT_TRUE(fs::is_directory(empty));
  EXPECT_TRUE(fs::is_empty(empty)) << "an empty folder given is left empty";

  // An earlier scene being replaced stays marked as synth output, without a
  // sequence.json that would mix old and new frames; the next run replaces it.
  const fs::path earlier = dir / "earlier";
  ASSERT_EQ(lom::test::runCli("synth --out " + quoted(earlier) + kScene).exit_code, 0);
  EXPECT_EQ(lom::test::runCli("synth --out " + quoted(earlier) + kScene + " --seed 9", full_disk)
                .exit_code,
            1);
  EXPECT_TRUE(fs::exists(earlier / "synth.json"));
  EXPECT_FALSE(fs::exists(earlier / "sequence.json"));
  EXPECT_EQ(lom::test::runCli("synth --out " + quoted(earlier) + kScene).exit_code, 0);
  EXPECT_TRUE(fs::exists(earlier / "sequence.json"));
}

}  // namespace
