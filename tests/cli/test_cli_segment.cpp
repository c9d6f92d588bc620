// labeloctomap segment (and --segmenter on fuse) end to end with a tiny ONNX model.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "lom/label_map.hpp"
#include "lom/npy.hpp"
#include "lom/sequence.hpp"
#include "onnx_model_builder.hpp"
#include "test_support.hpp"

namespace {

using lom::test::runCli;
using lom::test::TempDir;

std::string quoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

using lom::test::slurp;

class CliSegmentTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sequence_ = lom::test::writeColourWallSequence(dir_ / "seq", 2);
    model_ = dir_ / "colour.onnx";
    lom::test::writeModel(model_, lom::test::buildConvModel(lom::test::colourChannelModel()));
  }
  [[nodiscard]] std::vector<double> expected(int frame, int u) const {
    return lom::test::expectedProbabilities(lom::test::colourChannelModel(),
                                            lom::test::colourWallPixel(frame, u));
  }
  TempDir dir_;
  lom::Sequence sequence_;
  std::filesystem::path model_;
};

TEST_F(CliSegmentTest, WritesProbabilityImagesAndUpdatesTheSequence) {
  const auto r = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("segmented 2 frames"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 network runs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("float32 probability images"), std::string::npos) << r.out;

  const lom::Sequence updated = lom::loadSequence(dir_ / "seq");
  ASSERT_EQ(updated.frames.size(), 2u);
  for (int f = 0; f < 2; ++f) {
    const lom::FrameRecord& record = updated.frames[static_cast<size_t>(f)];
    EXPECT_EQ(record.proba, "proba-colour/00000" + std::to_string(f) + ".npy");
    EXPECT_TRUE(record.proba_labels.empty());  // one channel per label, in order
    EXPECT_EQ(record.color, sequence_.frames[static_cast<size_t>(f)].color);
    const lom::NpyArray array = lom::readNpy(updated.pathOf(record.proba));
    EXPECT_EQ(array.type, lom::NpyType::Float32);
    ASSERT_EQ(array.shape, (std::vector<size_t>{6, 8, 3}));
    const std::vector<float> values = array.toFloat(false);
    for (int v = 0; v < 6; ++v)
      for (int u = 0; u < 8; ++u)
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(values[(static_cast<size_t>(v) * 8 + u) * 3 + k], expected(f, u)[k], 2e-6);
  }
  const auto validate = runCli("validate " + quoted(dir_ / "seq"));
  EXPECT_EQ(validate.exit_code, 0) << validate.out << validate.err;

  // The written sequence fuses like any other: red on the left, green on the right.
  const auto fused = runCli("fuse " + quoted(dir_ / "seq") + " --out " + quoted(dir_ / "m.ot") +
                            " --resolution 0.05 --max-range 5 --frames 0:1");
  ASSERT_EQ(fused.exit_code, 0) << fused.err;
  const lom::LabelMap map = lom::LabelMap::load(dir_ / "m.ot");
  const auto counts = map.occupiedCountPerLabel();
  EXPECT_EQ(counts.count(0), 0u);
  ASSERT_EQ(counts.count(1), 1u);
  EXPECT_EQ(counts.at(1), counts.at(2));

  // Nothing left to do; --all segments again, from the cache.
  const auto again = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_));
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("nothing to do"), std::string::npos) << again.out;
  const auto all = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_) +
                          " --all --dtype uint8 --out-dir net8");
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_NE(all.out.find("0 network runs, 2 outputs from the cache"), std::string::npos) << all.out;
  const lom::Sequence quantised = lom::loadSequence(dir_ / "seq");
  EXPECT_EQ(quantised.frames[1].proba, "net8/000001.npy");
  const lom::NpyArray bytes = lom::readNpy(quantised.pathOf(quantised.frames[1].proba));
  EXPECT_EQ(bytes.type, lom::NpyType::UInt8);
  ASSERT_EQ(bytes.bytes.size(), 6u * 8 * 3);
  EXPECT_EQ(bytes.bytes[1], static_cast<std::uint8_t>(std::lround(expected(1, 0)[1] * 255)));
}

TEST_F(CliSegmentTest, ReplacingOneHotProbabilitiesClearsProbaFromLabel) {
  ASSERT_EQ(runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_)).exit_code,
            0);
  // As an import leaves label images turned into probabilities.
  lom::Sequence marked = lom::loadSequence(dir_ / "seq");
  for (auto& frame : marked.frames) frame.proba_from_label = true;
  lom::saveSequence(marked, dir_ / "seq");

  // Such frames have no network output yet: they are segmented without --all.
  const auto marked_only = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " +
                                  quoted(model_) + " --out-dir net");
  ASSERT_EQ(marked_only.exit_code, 0) << marked_only.err;
  for (const auto& frame : lom::loadSequence(dir_ / "seq").frames) {
    EXPECT_EQ(frame.proba.rfind("net/", 0), 0u) << frame.proba;
    EXPECT_FALSE(frame.proba_from_label) << "the network's output is independent of the labels";
  }
  const auto again = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("nothing to do"), std::string::npos) << again.out;

  marked = lom::loadSequence(dir_ / "seq");
  for (auto& frame : marked.frames) frame.proba_from_label = true;
  lom::saveSequence(marked, dir_ / "seq");
  const auto all = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_) +
                          " --all --out-dir net2");
  ASSERT_EQ(all.exit_code, 0) << all.err;
  for (const auto& frame : lom::loadSequence(dir_ / "seq").frames) {
    EXPECT_EQ(frame.proba.rfind("net2/", 0), 0u) << frame.proba;
    EXPECT_FALSE(frame.proba_from_label);
  }
}

TEST_F(CliSegmentTest, Float16AndLabelMapping) {
  // The network's three channels hold labels 3, 1 and 2 of a 4-label sequence.
  sequence_ = lom::test::writeColourWallSequence(dir_ / "seq", 1, 1);
  std::ofstream(dir_ / "colour.json") << R"({"labels": ["extra_0", "red_block", 2]})";
  const auto r = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_) +
                        " --dtype float16");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const lom::Sequence updated = lom::loadSequence(dir_ / "seq");
  EXPECT_EQ(updated.frames[0].proba_labels, (std::vector<int>{3, 1, 2}));
  const lom::FrameData frame = lom::loadFrame(updated, 0);
  ASSERT_TRUE(frame.proba);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(frame.proba->pixel(1, 1)[k], expected(0, 1)[k], 1e-3);  // half precision
}

TEST_F(CliSegmentTest, ErrorsAreClearAndLeaveTheSequenceAlone) {
  const std::string before = slurp(dir_ / "seq" / "sequence.json");
  auto segment = [&](const std::string& rest) {
    return runCli("segment " + quoted(dir_ / "seq") + " " + rest);
  };

  auto r = segment("--segmenter " + quoted(dir_ / "missing.onnx"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing.onnx: model: expected a readable ONNX model file"), std::string::npos)
      << r.err;

  std::ofstream(dir_ / "junk.onnx") << "not a model";
  r = segment("--segmenter " + quoted(dir_ / "junk.onnx"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("junk.onnx: model"), std::string::npos) << r.err;

  r = segment("");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing option --segmenter"), std::string::npos) << r.err;
  r = segment("--segmenter " + quoted(model_) + " --dtype float64");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--dtype expects float32, float16 or uint8"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "seq" / "sequence.json"), before);

  // A network whose output does not match the label set (3 channels, 5 labels).
  TempDir other;
  (void)lom::test::writeColourWallSequence(other / "seq", 1, 2);
  const std::string five = slurp(other / "seq" / "sequence.json");
  r = runCli("segment " + quoted(other / "seq") + " --segmenter " + quoted(model_));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("colour.onnx: output channels: expected 5 channels"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("found 3 channels"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(other / "seq" / "sequence.json"), five);
  // Nor is such an output kept in the sequence's cache.
  EXPECT_FALSE(std::filesystem::exists(other / "seq" / ".segmenter-cache"));

  // A sequence without colour images.
  TempDir grey;
  (void)lom::test::writeColourWallSequence(grey / "seq", 2, 0, false);
  r = runCli("segment " + quoted(grey / "seq") + " --segmenter " + quoted(model_));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("frames[0].color: expected a colour image in every frame to segment"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("a sequence without colour images"), std::string::npos) << r.err;
}

// --start-from a map fused from other probabilities: the map mixes both, and
// its record widens to both; fuse says so. The same source says nothing.
TEST_F(CliSegmentTest, FusingAnotherSegmentersFramesIntoAMapIsAWarning) {
  const std::string first = "fuse " + quoted(dir_ / "seq") + " --frames 0:1 --out " +
                            quoted(dir_ / "first.ot") +
                            " --resolution 0.05 --max-range 5 --segmenter " + quoted(model_);
  ASSERT_EQ(runCli(first).exit_code, 0);
  const std::string more = "fuse " + quoted(dir_ / "seq") + " --frames 1:2 --start-from " +
                           quoted(dir_ / "first.ot") + " --out " + quoted(dir_ / "more.ot") +
                           " --segmenter ";
  const auto same = runCli(more + quoted(model_));
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(same.err.find("other probabilities"), std::string::npos) << same.err;

  std::filesystem::copy_file(model_, dir_ / "other.onnx");
  const auto other = runCli(more + quoted(dir_ / "other.onnx"));
  ASSERT_EQ(other.exit_code, 0) << other.err;
  EXPECT_NE(other.err.find("warning: " + (dir_ / "first.ot").string() +
                           " was fused from other probabilities (segmenter colour.onnx) than "
                           "these frames give (segmenter other.onnx)"),
            std::string::npos)
      << other.err;
  const auto info = runCli("info " + quoted(dir_ / "more.ot"));
  EXPECT_NE(info.out.find("colour.onnx"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("other.onnx"), std::string::npos) << info.out;
}

// A model that ends with a Softmax gives probabilities: without MODEL.json
// they are used as they are (a second softmax over 40 labels would leave every
// label about 1/40 and the map empty); declared "scores", fuse warns about the
// empty map.
TEST_F(CliSegmentTest, FuseWithAModelEndingWithASoftmax) {
  const auto forty = dir_ / "forty";
  (void)lom::test::writeColourWallSequence(forty, 2, 37);
  lom::test::ConvModelSpec spec = lom::test::colourChannelModel();
  spec.weights = {0.f, 0.f, 0.f, 10.f, 0.f, 0.f, 0.f, 10.f, 0.f};  // confident
  spec.outputs = 40;
  spec.weights.resize(40 * 3, 0.f);
  spec.bias.resize(40, -10.f);  // the extra labels never win
  spec.softmax = true;
  const auto model = dir_ / "softmax.onnx";
  lom::test::writeModel(model, lom::test::buildConvModel(spec));
  const std::string fuse = "fuse " + quoted(forty) + " --out " + quoted(dir_ / "m.ot") +
                           " --resolution 0.05 --max-range 5 --segmenter " + quoted(model);
  const auto r = runCli(fuse);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto counts = lom::LabelMap::load(dir_ / "m.ot").occupiedCountPerLabel();
  EXPECT_EQ(counts.count(1), 1u) << r.out;
  EXPECT_EQ(counts.count(2), 1u) << r.out;
  EXPECT_EQ(r.err.find("no voxel is occupied"), std::string::npos) << r.err;
  // The map says where its probabilities came from.
  const auto info = runCli("info " + quoted(dir_ / "m.ot"));
  EXPECT_NE(info.out.find("probabilities:    segmenter softmax.onnx\n"), std::string::npos)
      << info.out;

  std::ofstream(dir_ / "softmax.json") << R"({"output": "scores"})";
  const auto twice = runCli(fuse);
  ASSERT_EQ(twice.exit_code, 0) << twice.err;
  EXPECT_NE(twice.out.find("occupied voxels: 0"), std::string::npos) << twice.out;
  EXPECT_NE(twice.err.find("warning: no voxel is occupied: the probabilities of the segmenter "
                           "softmax.onnx"),
            std::string::npos)
      << twice.err;
  EXPECT_NE(twice.err.find("\"output\": \"probabilities\" in softmax.json"), std::string::npos)
      << twice.err;

  // Read as probabilities, an output that never reaches the threshold (every
  // label 1/40) gets the other advice: MODEL.json is not the fix there.
  spec.weights.assign(40 * 3, 0.f);
  spec.bias.assign(40, 0.f);
  const auto flat = dir_ / "flat.onnx";
  lom::test::writeModel(flat, lom::test::buildConvModel(spec));
  std::ofstream(dir_ / "flat.json") << R"({"output": "probabilities"})";
  const auto uniform = runCli("fuse " + quoted(forty) + " --out " + quoted(dir_ / "flat.ot") +
                              " --resolution 0.05 --max-range 5 --segmenter " + quoted(flat));
  ASSERT_EQ(uniform.exit_code, 0) << uniform.err;
  EXPECT_NE(uniform.err.find("warning: no voxel is occupied: the probabilities of the segmenter "
                             "flat.onnx"),
            std::string::npos)
      << uniform.err;
  EXPECT_NE(uniform.err.find("its output was read as probabilities, and no label's reached the "
                             "occupancy threshold"),
            std::string::npos)
      << uniform.err;
  EXPECT_EQ(uniform.err.find("went through a softmax"), std::string::npos) << uniform.err;
}

TEST_F(CliSegmentTest, AColourImageOfAnotherSizeOrAnUnwritableFolderIsRefusedFirst) {
  const std::string before = slurp(dir_ / "seq" / "sequence.json");
  // A colour image wider than the camera: refused as fuse --segmenter refuses it.
  const std::filesystem::path color = dir_ / "seq" / sequence_.frames[1].color;
  lom::ColorImage wide;
  wide.width = 2 * sequence_.camera.width;
  wide.height = sequence_.camera.height;
  wide.rgb.assign(static_cast<size_t>(wide.width * wide.height) * 3, 128);
  const std::string original_color = slurp(color);
  lom::writeColorPng(color, wide);
  auto r = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.err.find("frames[1].color (image size): expected " +
                       std::to_string(sequence_.camera.width) + " x " +
                       std::to_string(sequence_.camera.height)),
            std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(dir_ / "seq" / "sequence.json"), before);
  std::ofstream(color, std::ios::binary) << original_color;

  // The network needs only the colour images: a depth image it cannot read
  // (fuse would name it) does not stop segmenting.
  const std::filesystem::path depth = dir_ / "seq" / sequence_.frames[0].depth;
  const std::string original_depth = slurp(depth);
  std::ofstream(depth, std::ios::binary) << "not a PNG";
  r = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_) +
             " --out-dir colour-only");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::ofstream(depth, std::ios::binary) << original_depth;
  std::ofstream(dir_ / "seq" / "sequence.json") << before;

  // An --out-dir where nothing can be written is refused before any frame is
  // segmented (a real network takes hours). /proc/sys takes no new file.
  if (::access("/proc/sys", W_OK) == 0) GTEST_SKIP() << "/proc/sys is writable here";
  r = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_) +
             " --out-dir /proc/sys/proba");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.err.find("--out-dir: expected a folder where files can be written"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("segmented"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "seq" / "sequence.json"), before);
}

TEST_F(CliSegmentTest, NeverWritesOverAnotherFileOfTheSequence) {
  const std::string segment =
      "segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_) + " --out-dir ";
  ASSERT_EQ(runCli(segment + "net").exit_code, 0);
  // Frame 0 now reads the image that frame 1 would get; frame 1 has none, so it is segmented.
  lom::Sequence sequence = lom::loadSequence(dir_ / "seq");
  sequence.frames[0].proba = "net/000001.npy";
  sequence.frames[1].proba.clear();
  lom::saveSequence(sequence, dir_ / "seq");
  const std::string json = slurp(dir_ / "seq" / "sequence.json");
  const std::string image = slurp(dir_ / "seq" / "net" / "000001.npy");
  auto r = runCli(segment + "net");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("would overwrite frames[0].proba"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "seq" / "net" / "000001.npy"), image);
  EXPECT_EQ(slurp(dir_ / "seq" / "sequence.json"), json);

  // A file where the folder should be.
  std::ofstream(dir_ / "seq" / "notes") << "keep";
  r = runCli(segment + "notes");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("is an existing file; expected a folder"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "seq" / "notes"), "keep");
  EXPECT_EQ(slurp(dir_ / "seq" / "sequence.json"), json);
  // A folder to create under a file: refused before any frame is segmented.
  std::filesystem::remove_all(dir_ / "seq" / ".segmenter-cache");
  r = runCli(segment + "sequence.json/sub");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("an existing file; expected a folder"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "seq" / ".segmenter-cache")) << "no work was done";
  EXPECT_EQ(slurp(dir_ / "seq" / "sequence.json"), json);
}

// Another sequence's frame files are not this run's to replace: an --out-dir
// pointing into it is refused, and its images stay as they were.
TEST_F(CliSegmentTest, NeverWritesOverTheFramesOfAnotherSequence) {
  std::filesystem::copy(dir_ / "seq", dir_ / "other", std::filesystem::copy_options::recursive);
  ASSERT_EQ(runCli("segment " + quoted(dir_ / "other") + " --segmenter " + quoted(model_) +
                   " --out-dir net")
                .exit_code,
            0);
  const std::string image = slurp(dir_ / "other" / "net" / "000000.npy");
  const auto r = runCli("segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_) +
                        " --out-dir ../other/net");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("would overwrite a frame file"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((dir_ / "other").string()), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "other" / "net" / "000000.npy"), image);
  EXPECT_TRUE(lom::loadSequence(dir_ / "seq").frames[0].proba.empty());
}

// A run that fails half-way (here frame 1's colour image is damaged) changes
// nothing: the images --all would replace stay as they were, and a new output
// folder is removed again.
TEST_F(CliSegmentTest, AFailedRunLeavesTheImagesItWouldReplace) {
  const std::string segment = "segment " + quoted(dir_ / "seq") + " --segmenter " + quoted(model_);
  ASSERT_EQ(runCli(segment + " --out-dir net").exit_code, 0);
  const std::string json = slurp(dir_ / "seq" / "sequence.json");
  const std::string image = slurp(dir_ / "seq" / "net" / "000000.npy");
  const std::filesystem::path colour = sequence_.pathOf(sequence_.frames[1].color);
  const std::string png = slurp(colour);
  std::ofstream(colour, std::ios::binary | std::ios::trunc) << png.substr(0, 60);

  auto r = runCli(segment + " --all --out-dir net --dtype float16");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("frames[1].color"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "seq" / "net" / "000000.npy"), image);
  EXPECT_EQ(slurp(dir_ / "seq" / "sequence.json"), json);
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(dir_ / "seq" / "net"))
    left.push_back(entry.path().filename().string());
  EXPECT_EQ(left.size(), 2u) << "temporary files left: " << ::testing::PrintToString(left);

  r = runCli(segment + " --all --out-dir fresh");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "seq" / "fresh"));
  EXPECT_EQ(slurp(dir_ / "seq" / "sequence.json"), json);
}

TEST_F(CliSegmentTest, FuseRunsTheSegmenterOnFramesWithoutProba) {
  const auto r = runCli("fuse " + quoted(dir_ / "seq") + " --out " + quoted(dir_ / "m.ot") +
                        " --resolution 0.05 --max-range 5 --frames 0:1 --segmenter " + quoted(model_));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const lom::LabelMap map = lom::LabelMap::load(dir_ / "m.ot");
  const auto counts = map.occupiedCountPerLabel();
  EXPECT_EQ(counts.count(0), 0u);
  ASSERT_EQ(counts.count(1), 1u);
  EXPECT_EQ(counts.at(1), counts.at(2));
  EXPECT_TRUE(std::filesystem::is_directory(dir_ / "seq" / ".segmenter-cache"));
  // The sequence itself is not changed by fuse.
  EXPECT_TRUE(lom::loadSequence(dir_ / "seq").frames[0].proba.empty());
}

}  // namespace
