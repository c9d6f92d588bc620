// Writing synthetic scenes to disk: layout, determinism, readability.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>

#include "lom/annotations.hpp"
#include "lom/error.hpp"
#include "lom/sequence.hpp"
#include "lom/synth.hpp"
#include "test_support.hpp"

namespace lom {
namespace {

namespace fs = std::filesystem;

SynthOptions tinyScene(std::uint64_t seed) {
  SynthOptions options;
  options.seed = seed;
  options.objects = 4;
  options.frames = 4;
  options.views = 3;
  options.width = 160;
  options.height = 120;
  return options;
}

// Every regular file below `root`, by relative path, with its bytes.
std::map<std::string, std::string> filesBelow(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    files[fs::relative(entry.path(), root).string()] =
        std::string(std::istreambuf_iterator<char>(in), {});
  }
  return files;
}

TEST(SynthWriteTest, WritesTheDocumentedFiles) {
  test::TempDir dir;
  const fs::path out = dir / "scene";
  const SynthScene scene = writeSyntheticScene(tinyScene(1), out);
  for (const char* name : {"sequence.json", "annotations.json", "synth.json", "depth/000000.png",
                           "color/000003.png", "label/000002.png", "proba/000001.npy"})
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
  EXPECT_FALSE(fs::exists(out / "depth/000004.png"));
  EXPECT_EQ(filesBelow(out).size(), 3u + 4u * 4u) << "unexpected extra files";

  ASSERT_EQ(scene.sequence.frames.size(), 4u);
  EXPECT_EQ(scene.sequence.labels.size(), 40);
  EXPECT_TRUE(scene.sequence.labels == apc2016Labels());
  EXPECT_EQ(scene.sequence.camera.width, 160);
  int views = 0;
  for (const auto& frame : scene.sequence.frames) {
    views += frame.view;
    EXPECT_FALSE(frame.proba_labels.empty());
    EXPECT_EQ(frame.proba_labels.front(), 0);
  }
  EXPECT_EQ(views, 3);
  EXPECT_EQ(scene.sequence.frames[2].depth, "depth/000002.png");
  EXPECT_EQ(scene.annotations.boxes.size(), 4u);
}

TEST(SynthWriteTest, SameSeedGivesByteIdenticalFilesOtherSeedDifferentOnes) {
  test::TempDir dir;
  writeSyntheticScene(tinyScene(11), dir / "a");
  writeSyntheticScene(tinyScene(11), dir / "b");
  writeSyntheticScene(tinyScene(12), dir / "c");
  const auto a = filesBelow(dir / "a"), b = filesBelow(dir / "b"), c = filesBelow(dir / "c");
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, bytes] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_TRUE(b.at(name) == bytes) << name << " differs for the same seed";
  }
  ASSERT_EQ(a.size(), c.size());
  for (const char* name : {"annotations.json", "depth/000000.png", "color/000001.png",
                           "label/000002.png", "proba/000003.npy"})
    EXPECT_FALSE(a.at(name) == c.at(name)) << name << " equal for different seeds";
}

TEST(SynthWriteTest, SequenceLoadsValidatesAndMatchesTheRenderedFrames) {
  test::TempDir dir;
  const SynthOptions options = tinyScene(5);
  const SynthScene scene = writeSyntheticScene(options, dir.path());
  const Sequence sequence = loadSequence(dir.path());
  const std::vector<Problem> problems = validateSequence(sequence);
  for (const auto& problem : problems) ADD_FAILURE() << problem.message();
  ASSERT_EQ(sequence.frames.size(), 4u);
  EXPECT_TRUE(sequence.camera == scene.sequence.camera);
  EXPECT_EQ(sequence.labels.size(), 40);

  const SynthLayout layout = makeSynthLayout(options);
  for (size_t f = 0; f < sequence.frames.size(); ++f) {
    EXPECT_TRUE(sequence.frames[f].T_world_camera.isApprox(layout.T_world_camera[f], 1e-9));
    EXPECT_EQ(sequence.frames[f].view, layout.view[f]);
    const FrameData loaded = loadFrame(sequence, f);
    const SynthFrame rendered = renderSynthFrame(layout, options, f);
    ASSERT_EQ(loaded.depth.metres.size(), rendered.depth.metres.size());
    for (size_t i = 0; i < rendered.depth.metres.size(); ++i)
      ASSERT_NEAR(loaded.depth.metres[i], rendered.depth.metres[i], 1e-6) << "depth pixel " << i;
    ASSERT_TRUE(loaded.label.has_value());
    EXPECT_EQ(loaded.label->ids, rendered.label.ids);
    ASSERT_TRUE(loaded.color.has_value());
    EXPECT_EQ(loaded.color->rgb, rendered.color.rgb);
    ASSERT_TRUE(loaded.proba.has_value());
    ASSERT_EQ(loaded.proba->height, 120);
    ASSERT_EQ(loaded.proba->width, 160);
    // Channels of the file or expanded to all labels: compare label by label.
    for (int c = 0; c < rendered.proba.channels; ++c) {
      const int label = rendered.proba.channel_labels[static_cast<size_t>(c)];
      const auto& loaded_labels = loaded.proba->channel_labels;
      const auto it = std::find(loaded_labels.begin(), loaded_labels.end(), label);
      ASSERT_NE(it, loaded_labels.end()) << "no channel for label " << label;
      const int lc = static_cast<int>(it - loaded_labels.begin());
      for (int v = 0; v < 120; v += 7)
        for (int u = 0; u < 160; u += 5)
          ASSERT_NEAR(loaded.proba->pixel(u, v)[lc], rendered.proba.pixel(u, v)[c], 1e-6);
    }
  }
}

TEST(SynthWriteTest, AnnotationsHoldTheExactObjectBoxes) {
  test::TempDir dir;
  const SynthOptions options = tinyScene(6);
  writeSyntheticScene(options, dir.path());
  const Annotations annotations = loadAnnotations(dir / "annotations.json");
  const SynthLayout layout = makeSynthLayout(options);
  ASSERT_EQ(annotations.boxes.size(), layout.objects.size());
  for (const auto& object : layout.objects) {
    const GroundTruthBox* box = annotations.find(object.label);
    ASSERT_NE(box, nullptr) << object.name;
    EXPECT_EQ(box->name, object.name);
    EXPECT_TRUE(box->box.center.isApprox(object.box.center, 1e-9));
    EXPECT_TRUE(box->box.size.isApprox(object.box.size, 1e-9));
    EXPECT_NEAR(std::abs(box->box.rotation.dot(object.box.rotation)), 1.0, 1e-9);
  }
}

TEST(SynthWriteTest, FullResolutionScene) {
  test::TempDir dir;
  SynthOptions options;  // 640 x 480
  options.seed = 2;
  options.frames = 3;
  const SynthScene scene = writeSyntheticScene(options, dir.path());
  EXPECT_EQ(scene.sequence.camera.width, 640);
  EXPECT_DOUBLE_EQ(scene.sequence.camera.fx, 615.2);
  const Sequence sequence = loadSequence(dir.path());
  EXPECT_TRUE(validateSequence(sequence).empty());
  const FrameData frame = loadFrame(sequence, 1);
  EXPECT_EQ(frame.depth.width, 640);
  EXPECT_EQ(frame.depth.height, 480);
  size_t valid = 0;
  for (const float z : frame.depth.metres) valid += z > 0;
  EXPECT_GT(valid, 640u * 480u * 8 / 10);
}

TEST(SynthWriteTest, OverwritesAnEarlierOutputWithoutStaleFrames) {
  test::TempDir dir;
  SynthOptions options = tinyScene(3);
  options.frames = 6;
  writeSyntheticScene(options, dir.path());
  ASSERT_TRUE(fs::exists(dir / "depth/000005.png"));
  options.frames = 4;
  writeSyntheticScene(options, dir.path());
  EXPECT_FALSE(fs::exists(dir / "depth/000005.png"));
  EXPECT_FALSE(fs::exists(dir / "proba/000004.npy"));
  EXPECT_EQ(loadSequence(dir.path()).frames.size(), 4u);
  test::TempDir fresh;
  writeSyntheticScene(options, fresh.path());
  EXPECT_EQ(filesBelow(dir.path()), filesBelow(fresh.path()));
}

TEST(SynthWriteTest, RefusesAFolderThatIsNotAnEarlierOutput) {
  test::TempDir dir;
  {
    std::ofstream notes(dir / "notes.txt");
    notes << "keep me";
  }
  try {
    writeSyntheticScene(tinyScene(1), dir.path());
    FAIL() << "wrote into a foreign folder";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir.path().string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "sequence.json"));
  EXPECT_EQ(filesBelow(dir.path()).size(), 1u);

  const fs::path file = dir / "notes.txt";
  EXPECT_THROW(writeSyntheticScene(tinyScene(1), file), Error);
}

}  // namespace
}  // namespace lom
