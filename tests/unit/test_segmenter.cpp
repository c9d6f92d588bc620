// The segmenter on tiny ONNX models built in the test: configuration,
// pre-processing, inference, softmax, label mapping, resizing and caches, all
// against probabilities computed here from the model's weights.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <thread>

#include "lom/error.hpp"
#include "lom/segmenter.hpp"
#include "onnx_model_builder.hpp"
#include "test_support.hpp"

namespace {

using lom::ColorImage;
using lom::LabelSet;
using lom::ProbabilityImage;
using lom::Segmenter;
using lom::SegmenterConfig;
using lom::test::ConvModelSpec;
using lom::test::TempDir;
using Rgb = std::array<std::uint8_t, 3>;

constexpr double kTolerance = 2e-6;

LabelSet labelsOf(int n) {
  std::vector<lom::LabelInfo> labels;
  const char* names[] = {"__background__", "red_block", "green_block", "cup", "box", "can"};
  for (int i = 0; i < n; ++i) labels.push_back({i, names[i], {0, 0, 0}});
  return LabelSet(labels);
}

// A model with mixed weights so that every input channel and the bias matter.
ConvModelSpec mixedModel() {
  ConvModelSpec spec;
  spec.outputs = 3;
  spec.weights = {2.0f, -1.0f, 0.5f,  //
                  -0.5f, 1.5f, 1.0f,  //
                  0.25f, 0.75f, -2.0f};
  spec.bias = {0.1f, -0.2f, 0.4f};
  return spec;
}

Rgb varied(int u, int v) {
  return {static_cast<std::uint8_t>(30 * u + 7 * v), static_cast<std::uint8_t>(250 - 40 * v),
          static_cast<std::uint8_t>((u * 53 + v * 31) % 256)};
}

std::filesystem::path writeModelFile(const TempDir& dir, const std::string& name,
                                     const ConvModelSpec& spec) {
  const auto path = dir / name;
  lom::test::writeModel(path, lom::test::buildConvModel(spec));
  return path;
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

lom::SegmenterOptions memoryOnly() {
  lom::SegmenterOptions options;
  options.disk_cache = false;
  return options;
}

void expectPixel(const ProbabilityImage& proba, int u, int v, const std::vector<double>& expected) {
  ASSERT_EQ(proba.channels, static_cast<int>(expected.size()));
  const float* p = proba.pixel(u, v);
  for (int c = 0; c < proba.channels; ++c)
    EXPECT_NEAR(p[c], expected[static_cast<size_t>(c)], kTolerance)
        << "pixel (" << u << ", " << v << ") channel " << c;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const lom::Error& e) {
    return e.what();
  }
  return "(no lom::Error)";
}

// ---------------------------------------------------------------------------
// Configuration

TEST(SegmenterConfig, DefaultsAndEveryKey) {
  const SegmenterConfig defaults = lom::parseSegmenterConfig("{}", "m.json");
  EXPECT_FALSE(defaults.input_width);
  EXPECT_DOUBLE_EQ(defaults.scale, 1.0 / 255.0);
  EXPECT_EQ(defaults.mean, (std::array<double, 3>{0, 0, 0}));
  EXPECT_EQ(defaults.stddev, (std::array<double, 3>{1, 1, 1}));
  EXPECT_EQ(defaults.channel_order, lom::SegmenterChannelOrder::Rgb);
  EXPECT_FALSE(defaults.output);  // the model tells (a final Softmax: probabilities)
  EXPECT_EQ(defaults.resize, lom::SegmenterResize::Linear);
  EXPECT_FALSE(defaults.labels);

  const SegmenterConfig c = lom::parseSegmenterConfig(
      R"({"input_width": 320, "input_height": 240, "scale": 1, "mean": [104, 117, 123],
          "std": [58.4, 57.1, 57.4], "channel_order": "bgr", "output": "probabilities",
          "labels": [0, "cup", null, 7], "resize": "nearest"})",
      "m.json");
  EXPECT_EQ(*c.input_width, 320);
  EXPECT_EQ(*c.input_height, 240);
  EXPECT_DOUBLE_EQ(c.scale, 1.0);
  EXPECT_EQ(c.mean, (std::array<double, 3>{104, 117, 123}));
  EXPECT_EQ(c.stddev, (std::array<double, 3>{58.4, 57.1, 57.4}));
  EXPECT_EQ(c.channel_order, lom::SegmenterChannelOrder::Bgr);
  EXPECT_EQ(*c.output, lom::SegmenterOutput::Probabilities);
  EXPECT_EQ(c.resize, lom::SegmenterResize::Nearest);
  ASSERT_TRUE(c.labels);
  ASSERT_EQ(c.labels->size(), 4u);
  EXPECT_EQ((*c.labels)[0].id, 0);
  EXPECT_EQ((*c.labels)[1].name, "cup");
  EXPECT_TRUE((*c.labels)[2].dropped());
  EXPECT_EQ((*c.labels)[3].id, 7);
  // Whole numbers written with a fraction part read as integers, as in
  // sequence.json; other fractions are refused.
  const SegmenterConfig floats = lom::parseSegmenterConfig(
      R"({"input_width": 320.0, "input_height": 2.4e2, "labels": [0, 6.0]})", "m.json");
  EXPECT_EQ(*floats.input_width, 320);
  EXPECT_EQ(*floats.input_height, 240);
  EXPECT_EQ((*floats.labels)[1].id, 6);
  EXPECT_THROW((void)lom::parseSegmenterConfig(R"({"labels": [0, 6.5]})", "m.json"), lom::Error);
  EXPECT_THROW(
      (void)lom::parseSegmenterConfig(R"({"input_width": 320.5, "input_height": 240})", "m.json"),
      lom::Error);
}

TEST(SegmenterConfig, ErrorsNameTheFileAndKey) {
  auto error = [](const std::string& json) {
    return errorOf([&] { (void)lom::parseSegmenterConfig(json, "/models/net.json"); });
  };
  EXPECT_NE(error(R"({"chanel_order": "rgb"})").find("/models/net.json: chanel_order"),
            std::string::npos);
  EXPECT_NE(error(R"({"channel_order": "rbg"})").find("channel_order: expected \"rgb\" or \"bgr\""),
            std::string::npos);
  EXPECT_NE(error(R"({"mean": [1, 2]})").find("mean: expected 3 numbers"), std::string::npos);
  EXPECT_NE(error(R"({"std": [1, 0, 1]})").find("std[1]: expected a positive number"),
            std::string::npos);
  EXPECT_NE(error(R"({"input_width": 320})").find("input_height"), std::string::npos);
  EXPECT_NE(error(R"({"input_width": 0, "input_height": 2})").find("input_width"),
            std::string::npos);
  EXPECT_NE(error(R"({"output": "logits"})").find("\"scores\" or \"probabilities\""),
            std::string::npos);
  EXPECT_NE(error(R"({"labels": [0, -3]})").find("labels[1]"), std::string::npos);
  EXPECT_NE(error(R"({"labels": [null]})").find("at least one channel"), std::string::npos);
  EXPECT_NE(error(R"({"scale": 0})").find("scale: expected a positive number"), std::string::npos);
  EXPECT_NE(error("[1, 2]").find("a JSON object"), std::string::npos);
  EXPECT_NE(error("{ not json").find("valid JSON"), std::string::npos);
}

TEST(SegmenterConfig, LivesBesideTheModel) {
  EXPECT_EQ(lom::segmenterConfigPath("/m/deeplab.onnx"), std::filesystem::path("/m/deeplab.json"));
  TempDir dir;
  const auto model = writeModelFile(dir, "net.onnx", mixedModel());
  EXPECT_TRUE(Segmenter::load(model)->configPath().empty());  // defaults
  writeText(dir / "net.json", R"({"channel_order": "bgr"})");
  const auto segmenter = Segmenter::load(model);
  EXPECT_EQ(segmenter->configPath(), dir / "net.json");
  EXPECT_EQ(segmenter->config().channel_order, lom::SegmenterChannelOrder::Bgr);
  writeText(dir / "net.json", R"({"channel_order": 3})");
  EXPECT_NE(errorOf([&] { (void)Segmenter::load(model); }).find("net.json: channel_order"),
            std::string::npos);
}

// ---------------------------------------------------------------------------
// Inference

TEST(Segmenter, ScoresGetAPixelwiseSoftmax) {
  TempDir dir;
  const ConvModelSpec spec = mixedModel();
  const auto segmenter = Segmenter::load(writeModelFile(dir, "net.onnx", spec), memoryOnly());
  const ColorImage image = lom::test::makeColorImage(7, 5, varied);
  EXPECT_EQ(segmenter->inputSize(7, 5), std::make_pair(7, 5));  // any-size model: the image's

  const ProbabilityImage proba = segmenter->segment(image, 7, 5, labelsOf(3));
  EXPECT_EQ(proba.width, 7);
  EXPECT_EQ(proba.height, 5);
  EXPECT_EQ(proba.channel_labels, (std::vector<int>{0, 1, 2}));
  for (int v = 0; v < 5; ++v)
    for (int u = 0; u < 7; ++u) expectPixel(proba, u, v, lom::test::expectedProbabilities(spec, varied(u, v)));
  EXPECT_EQ(segmenter->stats().inferences, 1u);
}

TEST(Segmenter, PreprocessingAppliesScaleMeanStdAndChannelOrder) {
  TempDir dir;
  const ConvModelSpec spec = mixedModel();
  const auto model = writeModelFile(dir, "net.onnx", spec);
  SegmenterConfig config;
  config.scale = 1.0 / 128.0;
  config.mean = {0.5, 1.0, 0.25};
  config.stddev = {0.5, 2.0, 0.75};
  config.channel_order = lom::SegmenterChannelOrder::Bgr;
  const auto segmenter = Segmenter::load(model, config, memoryOnly());
  const ColorImage image = lom::test::makeColorImage(4, 3, varied);
  const ProbabilityImage proba = segmenter->segment(image, 4, 3, labelsOf(3));
  // Independent check of one pixel by hand: BGR order, (value / 128 - mean) / std.
  const Rgb pixel = varied(2, 1);
  const std::array<double, 3> x = {(pixel[2] / 128.0 - 0.5) / 0.5, (pixel[1] / 128.0 - 1.0) / 2.0,
                                   (pixel[0] / 128.0 - 0.25) / 0.75};
  expectPixel(proba, 2, 1, lom::test::expectedProbabilities(spec, x));
  for (int v = 0; v < 3; ++v)
    for (int u = 0; u < 4; ++u)
      expectPixel(proba, u, v, lom::test::expectedProbabilities(spec, varied(u, v), config));
  // The same model with the default pre-processing gives other probabilities.
  const auto plain = Segmenter::load(model, SegmenterConfig{}, memoryOnly());
  const ProbabilityImage other = plain->segment(image, 4, 3, labelsOf(3));
  EXPECT_GT(std::fabs(other.pixel(2, 1)[0] - proba.pixel(2, 1)[0]), 1e-3);
}

TEST(Segmenter, ProbabilitiesFromTheModelAreUsedAsIs) {
  TempDir dir;
  ConvModelSpec spec = mixedModel();
  spec.softmax = true;
  const auto model = writeModelFile(dir, "net.onnx", spec);
  writeText(dir / "net.json", R"({"output": "probabilities"})");
  const auto segmenter = Segmenter::load(model, memoryOnly());
  const ColorImage image = lom::test::makeColorImage(5, 4, varied);
  const ProbabilityImage proba = segmenter->segment(image, 5, 4, labelsOf(3));
  for (int v = 0; v < 4; ++v)
    for (int u = 0; u < 5; ++u)
      expectPixel(proba, u, v, lom::test::expectedProbabilities(spec, varied(u, v)));

  // Declared as scores, the softmax would be applied a second time.
  writeText(dir / "net.json", R"({"output": "scores"})");
  const ProbabilityImage twice = Segmenter::load(model, memoryOnly())->segment(image, 5, 4, labelsOf(3));
  const auto once = lom::test::expectedProbabilities(spec, varied(1, 1));
  double sum = 0.0;
  for (double p : once) sum += std::exp(p);
  EXPECT_NEAR(twice.pixel(1, 1)[0], std::exp(once[0]) / sum, kTolerance);
}

TEST(Segmenter, AModelEndingWithASoftmaxGivesProbabilitiesWithoutAConfig) {
  // Without MODEL.json, a second softmax over 3 channels would have flattened
  // the probabilities towards 1/3 (with 40 labels: nothing ever occupied).
  TempDir dir;
  ConvModelSpec spec = mixedModel();
  spec.bias = {4.f, -2.f, 0.f};  // far from uniform
  spec.softmax = true;
  const auto segmenter = Segmenter::load(writeModelFile(dir, "net.onnx", spec), memoryOnly());
  EXPECT_EQ(segmenter->config().output, lom::SegmenterOutput::Probabilities);
  const ColorImage image = lom::test::makeColorImage(5, 4, varied);
  const ProbabilityImage proba = segmenter->segment(image, 5, 4, labelsOf(3));
  for (int v = 0; v < 4; ++v)
    for (int u = 0; u < 5; ++u)
      expectPixel(proba, u, v, lom::test::expectedProbabilities(spec, varied(u, v)));
  // A model without a Softmax still gets one.
  const auto plain = Segmenter::load(writeModelFile(dir, "plain.onnx", mixedModel()), memoryOnly());
  EXPECT_EQ(plain->config().output, lom::SegmenterOutput::Scores);
}

// net.onnx in `dir`: scores well above 1, declared as probabilities in net.json.
std::filesystem::path writeScoresDeclaredAsProbabilities(const TempDir& dir) {
  ConvModelSpec spec = mixedModel();
  spec.bias = {5.f, 0.f, 0.f};
  const auto model = writeModelFile(dir, "net.onnx", spec);
  writeText(dir / "net.json", R"({"output": "probabilities"})");
  return model;
}

TEST(Segmenter, ScoresDeclaredAsProbabilitiesAreRejected) {
  TempDir dir;
  const auto model = writeScoresDeclaredAsProbabilities(dir);
  const auto segmenter = Segmenter::load(model, memoryOnly());
  const std::string message = errorOf([&] {
    (void)segmenter->segment(lom::test::makeColorImage(3, 2, varied), 3, 2, labelsOf(3));
  });
  EXPECT_NE(message.find("net.onnx: output"), std::string::npos) << message;
  EXPECT_NE(message.find("probabilities in [0, 1]"), std::string::npos) << message;
  EXPECT_NE(message.find("\"scores\""), std::string::npos) << message;
}

// Its output is refused on any image: checkFits (the studio's Choose…) says so
// before a fusion would drop the map to fail on the first frame.
TEST(Segmenter, CheckFitsRefusesAModelWhoseOutputIsNeverValid) {
  TempDir dir;
  const auto model = writeScoresDeclaredAsProbabilities(dir);
  const auto segmenter = Segmenter::load(model, memoryOnly());
  const std::string message = errorOf([&] { segmenter->checkFits(labelsOf(3)); });
  EXPECT_NE(message.find("net.onnx: output: expected probabilities in [0, 1]"), std::string::npos)
      << message;
  EXPECT_NE(message.find("on a uniform grey test image"), std::string::npos) << message;
  // Read as scores (the default), the same network fits.
  std::filesystem::remove(dir / "net.json");
  EXPECT_NO_THROW(Segmenter::load(model, memoryOnly())->checkFits(labelsOf(3)));
}

// ---------------------------------------------------------------------------
// Sizes

// 2 x 2 blocks of one colour each, so that shrinking by 2 is exact.
Rgb blockColour(int u, int v) { return varied(u / 2, v / 2); }

// OpenCV's bilinear sampling with pixel centres aligned and borders clamped.
double bilinear(const std::vector<std::vector<double>>& grid, int out_width, int out_height, int u,
                int v) {
  const int h = static_cast<int>(grid.size()), w = static_cast<int>(grid[0].size());
  auto axis = [](int i, int out, int in, int& i0, int& i1, double& t) {
    double s = (i + 0.5) * in / out - 0.5;
    if (s < 0) s = 0;
    i0 = std::min(static_cast<int>(std::floor(s)), in - 1);
    i1 = std::min(i0 + 1, in - 1);
    t = s - i0;
    if (i0 == in - 1) t = 0;
  };
  int x0, x1, y0, y1;
  double tx, ty;
  axis(u, out_width, w, x0, x1, tx);
  axis(v, out_height, h, y0, y1, ty);
  return (1 - ty) * ((1 - tx) * grid[y0][x0] + tx * grid[y0][x1]) +
         ty * ((1 - tx) * grid[y1][x0] + tx * grid[y1][x1]);
}

TEST(Segmenter, OutputIsResizedToTheRequestedSize) {
  TempDir dir;
  const ConvModelSpec spec = mixedModel();
  const auto model = writeModelFile(dir, "net.onnx", spec);
  const ColorImage image = lom::test::makeColorImage(8, 6, blockColour);
  // Expected network output on the 4 x 3 input: one value per block.
  std::vector<std::vector<std::vector<double>>> block(3, std::vector<std::vector<double>>(3, std::vector<double>(4)));
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      const auto p = lom::test::expectedProbabilities(spec, varied(x, y));
      for (int k = 0; k < 3; ++k) block[k][y][x] = p[k];
    }

  SegmenterConfig config;
  config.input_width = 4;
  config.input_height = 3;
  config.resize = lom::SegmenterResize::Nearest;
  const auto nearest = Segmenter::load(model, config, memoryOnly());
  EXPECT_EQ(nearest->inputSize(8, 6), std::make_pair(4, 3));
  const ProbabilityImage n = nearest->segment(image, 8, 6, labelsOf(3));
  ASSERT_EQ(n.width, 8);
  ASSERT_EQ(n.height, 6);
  for (int v = 0; v < 6; ++v)
    for (int u = 0; u < 8; ++u)
      expectPixel(n, u, v, {block[0][v / 2][u / 2], block[1][v / 2][u / 2], block[2][v / 2][u / 2]});

  config.resize = lom::SegmenterResize::Linear;
  const ProbabilityImage l = Segmenter::load(model, config, memoryOnly())->segment(image, 8, 6, labelsOf(3));
  for (int v = 0; v < 6; ++v)
    for (int u = 0; u < 8; ++u)
      expectPixel(l, u, v,
                  {bilinear(block[0], 8, 6, u, v), bilinear(block[1], 8, 6, u, v),
                   bilinear(block[2], 8, 6, u, v)});
  // An interior pixel mixes neighbouring blocks (0.75 / 0.25 horizontally).
  EXPECT_NEAR(l.pixel(1, 0)[0], 0.75 * block[0][0][0] + 0.25 * block[0][0][1], kTolerance);

  // A depth image smaller than the network output: pixel areas are averaged,
  // which is exact on 2 x 2 blocks.
  const ProbabilityImage small = Segmenter::load(model, memoryOnly())->segment(image, 4, 3, labelsOf(3));
  for (int v = 0; v < 3; ++v)
    for (int u = 0; u < 4; ++u) expectPixel(small, u, v, {block[0][v][u], block[1][v][u], block[2][v][u]});
}

TEST(Segmenter, FixedInputSizeOfTheModelIsTheDefault) {
  TempDir dir;
  ConvModelSpec spec = mixedModel();
  spec.input_width = 4;
  spec.input_height = 3;
  const auto model = writeModelFile(dir, "fixed.onnx", spec);
  const auto segmenter = Segmenter::load(model, memoryOnly());
  EXPECT_EQ(segmenter->inputSize(8, 6), std::make_pair(4, 3));
  const ProbabilityImage proba =
      segmenter->segment(lom::test::makeColorImage(8, 6, blockColour), 4, 3, labelsOf(3));
  for (int v = 0; v < 3; ++v)
    for (int u = 0; u < 4; ++u) expectPixel(proba, u, v, lom::test::expectedProbabilities(spec, varied(u, v)));

  writeText(dir / "fixed.json", R"({"input_width": 8, "input_height": 6})");
  const std::string message = errorOf([&] { (void)Segmenter::load(model); });
  EXPECT_NE(message.find("fixed.json: input_width"), std::string::npos) << message;
  EXPECT_NE(message.find("4 x 3"), std::string::npos) << message;
}

// ---------------------------------------------------------------------------
// Labels

TEST(Segmenter, LabelsMapChannelsAndNullDropsOne) {
  TempDir dir;
  const ConvModelSpec spec = mixedModel();
  const auto model = writeModelFile(dir, "net.onnx", spec);
  writeText(dir / "net.json", R"({"labels": [4, null, "cup"]})");
  const auto segmenter = Segmenter::load(model, memoryOnly());
  const ProbabilityImage proba =
      segmenter->segment(lom::test::makeColorImage(3, 2, varied), 3, 2, labelsOf(6));
  EXPECT_EQ(proba.channel_labels, (std::vector<int>{4, 3}));
  for (int v = 0; v < 2; ++v)
    for (int u = 0; u < 3; ++u) {
      const auto p = lom::test::expectedProbabilities(spec, varied(u, v));
      expectPixel(proba, u, v, {p[0], p[2]});
    }
}

TEST(Segmenter, OutputThatDoesNotMatchTheLabelsIsAnError) {
  TempDir dir;
  const auto model = writeModelFile(dir, "net.onnx", mixedModel());
  const ColorImage image = lom::test::makeColorImage(3, 2, varied);
  auto error = [&](const std::string& json, int labels) {
    if (json.empty())
      std::filesystem::remove(dir / "net.json");
    else
      writeText(dir / "net.json", json);
    return errorOf([&] { (void)Segmenter::load(model, memoryOnly())->segment(image, 3, 2, labelsOf(labels)); });
  };
  std::string m = error("", 4);  // 3 channels, 4 labels, no "labels"
  EXPECT_NE(m.find("net.onnx: output channels: expected 4 channels, one per label"), std::string::npos) << m;
  EXPECT_NE(m.find("found 3 channels"), std::string::npos) << m;
  m = error(R"({"labels": [0, 1]})", 4);
  EXPECT_NE(m.find("expected 2 channels (one per entry of \"labels\""), std::string::npos) << m;
  m = error(R"({"labels": [0, 1, 7]})", 4);
  EXPECT_NE(m.find("net.json: labels[2]: expected a label id from 0 to 3"), std::string::npos) << m;
  m = error(R"({"labels": [0, 1, 1]})", 4);
  EXPECT_NE(m.find("labels[2]: expected each label once"), std::string::npos) << m;
  m = error(R"({"labels": [0, 1, "spoon"]})", 4);
  EXPECT_NE(m.find("labels[2]: expected the name of a label of the sequence"), std::string::npos) << m;
  EXPECT_EQ(error("", 3), "(no lom::Error)");
}

TEST(Segmenter, UnreadableModelsAreClearErrors) {
  TempDir dir;
  auto error = [&](const std::filesystem::path& path) {
    return errorOf([&] { (void)Segmenter::load(path); });
  };
  std::string m = error(dir / "missing.onnx");
  EXPECT_NE(m.find("missing.onnx: model: expected a readable ONNX model file"), std::string::npos) << m;
  EXPECT_NE(m.find("no such file"), std::string::npos) << m;
  writeText(dir / "empty.onnx", "");
  EXPECT_NE(error(dir / "empty.onnx").find("an empty file"), std::string::npos);
  writeText(dir / "text.onnx", "this is not a network, just some text\n");
  m = error(dir / "text.onnx");
  EXPECT_NE(m.find("text.onnx: model: expected an ONNX model file"), std::string::npos) << m;
  EXPECT_NE(error(dir.path()).find("a folder"), std::string::npos);

  ConvModelSpec four = mixedModel();  // an RGBA-input network
  four.input_channels = 4;
  four.weights = std::vector<float>(12, 1.f);
  four.input_width = 4;
  four.input_height = 3;
  m = error(writeModelFile(dir, "rgba.onnx", four));
  EXPECT_NE(m.find("expected 3 input channels"), std::string::npos) << m;
  EXPECT_NE(m.find("1 x 4 x 3 x 4"), std::string::npos) << m;
}

// ---------------------------------------------------------------------------
// Caches

TEST(Segmenter, MemoryCacheRunsTheNetworkOncePerImage) {
  TempDir dir;
  const auto segmenter = Segmenter::load(writeModelFile(dir, "net.onnx", mixedModel()), memoryOnly());
  const ColorImage a = lom::test::makeColorImage(6, 4, varied);
  const ColorImage b = lom::test::makeColorImage(6, 4, blockColour);
  const ProbabilityImage first = segmenter->segment(a, 6, 4, labelsOf(3));
  const ProbabilityImage again = segmenter->segment(a, 6, 4, labelsOf(3));
  EXPECT_EQ(first.values, again.values);
  EXPECT_EQ(segmenter->stats().inferences, 1u);
  EXPECT_EQ(segmenter->stats().memory_hits, 1u);
  // Another size of the same image reuses the network output too.
  (void)segmenter->segment(a, 3, 2, labelsOf(3));
  EXPECT_EQ(segmenter->stats().inferences, 1u);
  (void)segmenter->segment(b, 6, 4, labelsOf(3));
  EXPECT_EQ(segmenter->stats().inferences, 2u);
  // Nothing was written to disk.
  size_t entries = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir.path()))
    entries += entry.path().filename() != "net.onnx";
  EXPECT_EQ(entries, 0u);
}

TEST(Segmenter, DiskCacheIsSharedAcrossLoadsAndKeyedByModelConfigAndImage) {
  TempDir dir;
  const auto model = writeModelFile(dir, "net.onnx", mixedModel());
  const auto cache = dir / "cache";
  const ColorImage image = lom::test::makeColorImage(6, 4, varied);

  const auto first = Segmenter::load(model);
  const ProbabilityImage computed = first->segment(image, 6, 4, labelsOf(3), cache);
  EXPECT_EQ(first->stats().inferences, 1u);
  size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(cache)) files += entry.path().extension() == ".npy";
  EXPECT_EQ(files, 1u);

  const auto second = Segmenter::load(model);  // e.g. the next run of the program
  const ProbabilityImage cached = second->segment(image, 6, 4, labelsOf(3), cache);
  EXPECT_EQ(second->stats().inferences, 0u);
  EXPECT_EQ(second->stats().disk_hits, 1u);
  EXPECT_EQ(cached.values, computed.values);  // bit for bit

  // Another image, another pre-processing or another model runs the network.
  (void)second->segment(lom::test::makeColorImage(6, 4, blockColour), 6, 4, labelsOf(3), cache);
  EXPECT_EQ(second->stats().inferences, 1u);
  SegmenterConfig shifted;
  shifted.mean = {0.1, 0.0, 0.0};
  const auto other_config = Segmenter::load(model, shifted);
  (void)other_config->segment(image, 6, 4, labelsOf(3), cache);
  EXPECT_EQ(other_config->stats().inferences, 1u);
  ConvModelSpec changed = mixedModel();
  changed.bias[0] = 0.0f;
  const auto other_model = Segmenter::load(writeModelFile(dir, "net2.onnx", changed));
  (void)other_model->segment(image, 6, 4, labelsOf(3), cache);
  EXPECT_EQ(other_model->stats().inferences, 1u);

  // A damaged cache file is recomputed and replaced.
  for (const auto& entry : std::filesystem::directory_iterator(cache)) writeText(entry.path(), "garbage");
  const auto third = Segmenter::load(model);
  const ProbabilityImage recomputed = third->segment(image, 6, 4, labelsOf(3), cache);
  EXPECT_EQ(third->stats().inferences, 1u);
  EXPECT_EQ(recomputed.values, computed.values);
  const auto fourth = Segmenter::load(model);
  (void)fourth->segment(image, 6, 4, labelsOf(3), cache);
  EXPECT_EQ(fourth->stats().inferences, 0u);
}

TEST(Segmenter, CacheEntriesOfAnotherShapeOrNotProbabilitiesAreRecomputed) {
  // Entries that read as .npy files but cannot be this model's output: the
  // wrong channel count, a NaN, a value above 1. Each is a miss, recomputed
  // and replaced, never an error blaming the model.
  TempDir dir;
  const auto model = writeModelFile(dir, "net.onnx", mixedModel());
  const auto cache = dir / "cache";
  const ColorImage image = lom::test::makeColorImage(6, 4, varied);
  const ProbabilityImage computed =
      Segmenter::load(model)->segment(image, 6, 4, labelsOf(3), cache);
  std::filesystem::path entry;
  for (const auto& file : std::filesystem::directory_iterator(cache)) entry = file.path();
  ASSERT_FALSE(entry.empty());

  const std::vector<float> good_values = [&] {
    const lom::NpyArray array = lom::readNpy(entry);
    std::vector<float> values(array.size());
    std::memcpy(values.data(), array.bytes.data(), array.bytes.size());
    return values;
  }();
  std::vector<float> with_nan = good_values;
  with_nan[5] = std::nanf("");
  std::vector<float> above_one = good_values;
  above_one[7] = 3.0f;
  const std::vector<std::pair<std::vector<size_t>, std::vector<float>>> damaged = {
      {{2, 4, 6}, std::vector<float>(good_values.begin(), good_values.begin() + 48)},
      {{3, 4, 6}, with_nan},
      {{3, 4, 6}, above_one}};
  for (const auto& [shape, values] : damaged) {
    SCOPED_TRACE(shape[0]);
    lom::writeNpyFloat32(entry, shape, values);
    const auto segmenter = Segmenter::load(model);
    ProbabilityImage recomputed;
    EXPECT_NO_THROW(recomputed = segmenter->segment(image, 6, 4, labelsOf(3), cache));
    EXPECT_EQ(segmenter->stats().inferences, 1u);
    EXPECT_EQ(segmenter->stats().disk_hits, 0u);
    EXPECT_EQ(recomputed.values, computed.values);
    // Replaced: the next run reads it.
    const auto next = Segmenter::load(model);
    (void)next->segment(image, 6, 4, labelsOf(3), cache);
    EXPECT_EQ(next->stats().disk_hits, 1u);
  }

  // An entry that fits the labels but not the channel count this model gives.
  ConvModelSpec four = mixedModel();
  four.outputs = 4;
  four.weights.insert(four.weights.end(), {0.5f, 0.5f, 0.5f});
  four.bias.push_back(0.f);
  const auto four_model = writeModelFile(dir, "four.onnx", four);
  const auto segmenter = Segmenter::load(four_model);
  const ColorImage other = lom::test::makeColorImage(6, 4, blockColour);
  (void)segmenter->segment(other, 6, 4, labelsOf(4), cache);  // learns: 4 channels
  std::filesystem::path four_entry;
  for (const auto& file : std::filesystem::directory_iterator(cache))
    if (file.path() != entry) four_entry = file.path();
  ASSERT_FALSE(four_entry.empty());
  lom::writeNpyFloat32(four_entry, {3, 4, 6}, good_values);
  const auto memoryless = [&] {
    lom::SegmenterOptions options;
    options.memory_cache_bytes = 0;
    return options;
  }();
  const auto fresh = Segmenter::load(four_model, memoryless);
  (void)fresh->outputChannels();
  const std::string message =
      errorOf([&] { (void)fresh->segment(other, 6, 4, labelsOf(3), cache); });
  EXPECT_NE(message.find("four.onnx: output channels: expected 3 channels"), std::string::npos)
      << message;  // the model's 4 channels, not the entry's 3
}

TEST(Segmenter, CheckFitsProbesTheChannelCountBeforeAnyWork) {
  TempDir dir;
  const auto segmenter =
      Segmenter::load(writeModelFile(dir, "net.onnx", mixedModel()), memoryOnly());
  EXPECT_EQ(segmenter->outputChannels(), 3);
  EXPECT_NO_THROW(segmenter->checkFits(labelsOf(3)));
  const std::string message = errorOf([&] { segmenter->checkFits(labelsOf(5)); });
  EXPECT_NE(message.find("net.onnx: output channels: expected 5 channels, one per label of the "
                         "sequence"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("found 3 channels (output 1 x 3 x 64 x 64"), std::string::npos) << message;
  EXPECT_EQ(segmenter->stats().inferences, 0u);  // a probe is no frame's run

  // A model of fixed input size is probed at that size; "labels" in MODEL.json
  // must have one entry per channel.
  ConvModelSpec fixed = mixedModel();
  fixed.input_width = 10;
  fixed.input_height = 6;
  const auto model = writeModelFile(dir, "fixed.onnx", fixed);
  writeText(dir / "fixed.json", R"({"labels": [0, 1]})");
  const auto configured = Segmenter::load(model, memoryOnly());
  const std::string labelled = errorOf([&] { configured->checkFits(labelsOf(3)); });
  EXPECT_NE(labelled.find("fixed.onnx: output channels: expected 2 channels (one per entry of "
                          "\"labels\""),
            std::string::npos)
      << labelled;
  EXPECT_NE(labelled.find("1 x 3 x 6 x 10"), std::string::npos) << labelled;
}

// The studio asks for the channels and the statistics from its GUI thread
// (on a sequence switch) while a fusion worker segments a frame: those calls
// must not wait for the network to finish.
TEST(Segmenter, ChannelsAndStatsDoNotWaitForARunningInference) {
  using Clock = std::chrono::steady_clock;
  TempDir dir;
  const auto segmenter =
      Segmenter::load(writeModelFile(dir, "net.onnx", mixedModel()), memoryOnly());
  EXPECT_EQ(segmenter->outputChannels(), 3);  // probed before any frame, as the studio does
  std::atomic<bool> done{false};
  Clock::duration shortest_run = Clock::duration::max();
  std::thread worker([&] {
    // Large images, each new (no cache hit): every call runs the network.
    for (int i = 0; i < 3; ++i) {
      const ColorImage image = lom::test::makeColorImage(1280, 960, [i](int u, int v) {
        return Rgb{static_cast<std::uint8_t>(u + i), static_cast<std::uint8_t>(v),
                   static_cast<std::uint8_t>(i)};
      });
      const auto start = Clock::now();
      (void)segmenter->segment(image, 64, 48, labelsOf(3));
      shortest_run = std::min(shortest_run, Clock::now() - start);
    }
    done = true;
  });
  // Asked again and again meanwhile: each answer comes at once, not after a run.
  Clock::duration longest_answer{0};
  size_t seen_running = 0;
  while (!done) {
    const auto start = Clock::now();
    seen_running += segmenter->stats().running;
    EXPECT_EQ(segmenter->outputChannels(), 3);
    EXPECT_NO_THROW(segmenter->checkFits(labelsOf(3)));
    longest_answer = std::max(longest_answer, Clock::now() - start);
  }
  worker.join();
  EXPECT_GT(seen_running, 0u) << "the statistics never showed a run in progress";
  EXPECT_LT(longest_answer * 4, shortest_run)
      << "an answer took " << std::chrono::duration<double, std::milli>(longest_answer).count()
      << " ms; one network run " << std::chrono::duration<double, std::milli>(shortest_run).count()
      << " ms";
  EXPECT_EQ(segmenter->stats().running, 0u);
  EXPECT_EQ(segmenter->stats().inferences, 3u);
}

TEST(Segmenter, UnwritableCacheWarnsOnceAndKeepsGoing) {
  TempDir dir;
  writeText(dir / "not-a-folder", "x");
  std::vector<std::string> warnings;
  lom::SegmenterOptions options;
  options.cache_dir = dir / "not-a-folder" / "cache";
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  const ConvModelSpec spec = mixedModel();
  const auto segmenter = Segmenter::load(writeModelFile(dir, "net.onnx", spec), options);
  const ProbabilityImage a = segmenter->segment(lom::test::makeColorImage(3, 2, varied), 3, 2, labelsOf(3));
  (void)segmenter->segment(lom::test::makeColorImage(3, 2, blockColour), 3, 2, labelsOf(3));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("segmenter cache"), std::string::npos);
  expectPixel(a, 1, 1, lom::test::expectedProbabilities(spec, varied(1, 1)));
  EXPECT_EQ(segmenter->stats().inferences, 2u);
}

}  // namespace
