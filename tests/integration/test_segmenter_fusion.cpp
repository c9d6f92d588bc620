// A sequence with colour and depth but no probability images is fused through
// a tiny ONNX network: load, pre-process, infer, softmax, resize, fuse, with
// the map's voxels holding exactly the network's probabilities.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <type_traits>

#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/segmenter.hpp"
#include "onnx_model_builder.hpp"
#include "test_support.hpp"

namespace {

using lom::Segmenter;
using lom::test::TempDir;

constexpr double kTolerance = 2e-5;

lom::FusionOptions fusionOptions() {
  lom::FusionOptions options;
  options.map.resolution = 0.05;  // pixels are 0.125 m apart on the wall: one voxel each
  options.map.max_range = 5.0;
  options.integration.path = lom::IntegrationPath::Reference;
  return options;
}

std::shared_ptr<Segmenter> loadModel(const TempDir& dir, lom::SegmenterOptions options = {}) {
  const auto path = dir / "colour.onnx";
  if (!std::filesystem::exists(path))
    lom::test::writeModel(path, lom::test::buildConvModel(lom::test::colourChannelModel()));
  return Segmenter::load(path, std::move(options));
}

std::vector<double> expectedAt(int frame, int u) {
  return lom::test::expectedProbabilities(lom::test::colourChannelModel(),
                                          lom::test::colourWallPixel(frame, u));
}

// Integrates frames [0, n) loaded through the segmenter.
lom::LabelMap fuseWithSegmenter(const lom::Sequence& sequence, const Segmenter& segmenter, size_t n) {
  const lom::FusionOptions options = fusionOptions();
  lom::LabelMap map(sequence.labels, options.map);
  for (size_t i = 0; i < n; ++i) {
    const lom::FrameData frame = lom::loadFrameWithSegmenter(sequence, i, &segmenter);
    const lom::FrameEvidence evidence = lom::makeEvidence(sequence, i, frame, options);
    (void)lom::integrateFrame(map, sequence.cameraOf(i), sequence.frames[i].T_world_camera,
                              frame.depth, evidence, options.integration);
  }
  return map;
}

Eigen::Vector3d wallPoint(const lom::Sequence& sequence, int u, int v) {
  return sequence.camera.backProject(u, v, 1.0);
}

// An 8 x 6 probability image of labels 0, 1, 2 with the same three values at
// every pixel, written as `name` into the sequence folder.
lom::ProbabilityImage writeUniformProba(const lom::Sequence& sequence, const std::string& name,
                                        const std::array<float, 3>& pixel) {
  lom::ProbabilityImage proba;
  proba.width = 8;
  proba.height = 6;
  proba.channels = 3;
  proba.channel_labels = {0, 1, 2};
  for (int i = 0; i < 48; ++i) proba.values.insert(proba.values.end(), pixel.begin(), pixel.end());
  lom::writeProbabilityNpy(sequence.root / name, proba, lom::NpyType::Float32);
  return proba;
}

TEST(SegmenterFusion, FramesWithoutProbaAreFusedWithTheNetworksProbabilities) {
  TempDir dir;
  const lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 1);
  const auto segmenter = loadModel(dir);

  const lom::FrameData frame = lom::loadFrameWithSegmenter(sequence, 0, segmenter.get());
  ASSERT_TRUE(frame.proba);
  EXPECT_EQ(frame.proba->width, 8);
  EXPECT_EQ(frame.proba->height, 6);
  EXPECT_EQ(frame.proba->channel_labels, (std::vector<int>{0, 1, 2}));
  for (int v = 0; v < 6; ++v)
    for (int u = 0; u < 8; ++u)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(frame.proba->pixel(u, v)[k], expectedAt(0, u)[k], 2e-6);

  // One frame: each wall voxel holds exactly one pixel's probabilities (all
  // inside the clamping range), so the map reproduces the network's output.
  const lom::LabelMap map = fuseWithSegmenter(sequence, *segmenter, 1);
  for (int v = 0; v < 6; ++v)
    for (int u = 0; u < 8; ++u) {
      const lom::VoxelState voxel = map.voxelAt(wallPoint(sequence, u, v));
      ASSERT_TRUE(voxel.known);
      ASSERT_EQ(voxel.probabilities.size(), 3u);
      const auto expected = expectedAt(0, u);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(voxel.probabilities[static_cast<size_t>(k)], expected[k], kTolerance)
            << "u=" << u << " v=" << v << " label " << k;
      EXPECT_TRUE(voxel.occupied);
      EXPECT_EQ(voxel.label, u < 4 ? 1 : 2);  // red block on the left, green on the right
    }
}

TEST(SegmenterFusion, SecondFrameAddsItsLogOdds) {
  TempDir dir;
  const lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 2);
  const auto segmenter = loadModel(dir);
  const lom::LabelMap map = fuseWithSegmenter(sequence, *segmenter, 2);
  auto logit = [](double p) { return std::log(p / (1.0 - p)); };
  auto sigmoid = [](double l) { return 1.0 / (1.0 + std::exp(-l)); };
  const double lo = logit(0.12), hi = logit(0.97);
  for (int u = 0; u < 8; ++u) {
    const lom::VoxelState voxel = map.voxelAt(wallPoint(sequence, u, 3));
    const auto a = expectedAt(0, u), b = expectedAt(1, u);
    for (int k = 0; k < 3; ++k) {
      const double expected = sigmoid(std::clamp(std::clamp(logit(a[k]), lo, hi) + logit(b[k]), lo, hi));
      EXPECT_NEAR(voxel.probabilities[static_cast<size_t>(k)], expected, kTolerance) << "u=" << u;
    }
  }
}

TEST(SegmenterFusion, RefusingDoesNotRunTheNetworkAgain) {
  TempDir dir;
  const lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 3);
  const auto segmenter = loadModel(dir);
  const lom::LabelMap first = fuseWithSegmenter(sequence, *segmenter, 3);
  // Frames 0 and 2 have the same colour image: the network ran for two images.
  EXPECT_EQ(segmenter->stats().inferences, 2u);
  const lom::LabelMap second = fuseWithSegmenter(sequence, *segmenter, 3);
  EXPECT_EQ(segmenter->stats().inferences, 2u);
  EXPECT_EQ(segmenter->stats().memory_hits, 4u);
  EXPECT_TRUE(std::filesystem::is_directory(dir / "seq" / ".segmenter-cache"));

  // A new program run (a new segmenter) reads the outputs from the sequence's cache.
  const auto fresh = loadModel(dir);
  const lom::LabelMap third = fuseWithSegmenter(sequence, *fresh, 3);
  EXPECT_EQ(fresh->stats().inferences, 0u);
  EXPECT_EQ(fresh->stats().disk_hits, 2u);
  for (int u = 0; u < 8; ++u) {
    const auto a = first.voxelAt(wallPoint(sequence, u, 2));
    EXPECT_EQ(a.probabilities, second.voxelAt(wallPoint(sequence, u, 2)).probabilities);
    EXPECT_EQ(a.probabilities, third.voxelAt(wallPoint(sequence, u, 2)).probabilities);
  }
}

TEST(SegmenterFusion, FramesWithProbaKeepTheirOwn) {
  TempDir dir;
  lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 2);
  const lom::ProbabilityImage own = writeUniformProba(sequence, "own.npy", {0.2f, 0.3f, 0.5f});
  sequence.frames[1].proba = "own.npy";
  sequence.frames[0].label = "label.png";  // a label image alone is ground truth, not evidence
  lom::LabelImage truth{8, 6, std::vector<std::uint16_t>(48, 2)};
  lom::writeLabelPng(dir / "seq" / "label.png", truth);
  lom::saveSequence(sequence, sequence.root);

  const auto segmenter = loadModel(dir);
  const lom::FrameData with_label = lom::loadFrameWithSegmenter(sequence, 0, segmenter.get());
  ASSERT_TRUE(with_label.label);
  ASSERT_TRUE(with_label.proba);
  EXPECT_NEAR(with_label.proba->pixel(0, 0)[1], expectedAt(0, 0)[1], 2e-6);
  const lom::FrameData with_proba = lom::loadFrameWithSegmenter(sequence, 1, segmenter.get());
  EXPECT_EQ(with_proba.proba->values, own.values);
  EXPECT_EQ(segmenter->stats().inferences, 1u);
  // Without a segmenter it is loadFrame.
  EXPECT_FALSE(lom::loadFrameWithSegmenter(sequence, 0, nullptr).proba);

  // Fusion reads the colour image for the network and its own proba
  // otherwise, and nothing it does not fuse (the label image is ground truth).
  const lom::FrameData fused_0 = lom::loadFusionFrame(sequence, 0, segmenter.get());
  ASSERT_TRUE(fused_0.proba);
  EXPECT_EQ(fused_0.proba->values, with_label.proba->values);
  EXPECT_FALSE(fused_0.label);
  const lom::FrameData fused_1 = lom::loadFusionFrame(sequence, 1, segmenter.get());
  ASSERT_TRUE(fused_1.proba);
  EXPECT_EQ(fused_1.proba->values, own.values);
  EXPECT_FALSE(fused_1.color);
  EXPECT_FALSE(fused_1.label);
  // Frame 0's network output came from the disk cache: still one inference.
  EXPECT_EQ(segmenter->stats().inferences, 1u);
}

TEST(SegmenterFusion, ProbaMadeFromTheLabelImageIsReplacedByTheNetworks) {
  TempDir dir;
  lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 1);
  const lom::ProbabilityImage one_hot =
      writeUniformProba(sequence, "one_hot.npy", {0.05f, 0.05f, 0.9f});
  sequence.frames[0].proba = "one_hot.npy";
  sequence.frames[0].proba_from_label = true;  // as an import of label images writes it
  lom::saveSequence(sequence, sequence.root);

  const auto segmenter = loadModel(dir);
  const lom::FrameData frame = lom::loadFrameWithSegmenter(sequence, 0, segmenter.get());
  ASSERT_TRUE(frame.proba);
  EXPECT_NEAR(frame.proba->pixel(0, 0)[1], expectedAt(0, 0)[1], 2e-6);
  EXPECT_EQ(segmenter->stats().inferences, 1u);
  // Without a segmenter the frame keeps the proba it has.
  const lom::FrameData own = lom::loadFrameWithSegmenter(sequence, 0, nullptr);
  ASSERT_TRUE(own.proba);
  EXPECT_EQ(own.proba->values, one_hot.values);

  // Fusion with the network reads the colour image and not the one-hot proba
  // it replaces: that file may even be gone.
  const lom::FrameParts parts = lom::fusionPartsOf(sequence, 0, segmenter.get());
  EXPECT_TRUE(parts.color);
  EXPECT_FALSE(parts.proba);
  std::filesystem::remove(dir / "seq" / "one_hot.npy");
  const lom::FrameData fused = lom::loadFusionFrame(sequence, 0, segmenter.get());
  ASSERT_TRUE(fused.proba);
  EXPECT_EQ(fused.proba->values, frame.proba->values);
  EXPECT_THROW((void)lom::loadFusionFrame(sequence, 0, nullptr), lom::Error);
}

// The one-frame colour wall in `dir`/seq with a label image of label 2 made
// into probabilities, as an import does (proba_from_label), and a view.
lom::Sequence writeWallWithLabelProba(const TempDir& dir) {
  lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 1);
  lom::LabelImage truth{8, 6, std::vector<std::uint16_t>(48, 2)};
  lom::writeLabelPng(dir / "seq" / "label.png", truth);
  (void)writeUniformProba(sequence, "one_hot.npy", {0.05f, 0.05f, 0.9f});
  sequence.frames[0].label = "label.png";
  sequence.frames[0].proba = "one_hot.npy";
  sequence.frames[0].proba_from_label = true;
  sequence.frames[0].view = true;
  lom::saveSequence(sequence, sequence.root);
  return sequence;
}

TEST(SegmenterFusion, ProbaMadeFromTheLabelImageIsScoredIn2dOnlyWithASegmenter) {
  TempDir dir;
  const lom::Sequence sequence = writeWallWithLabelProba(dir);

  const auto segmenter = loadModel(dir);
  const lom::LabelMap map = fuseWithSegmenter(sequence, *segmenter, 1);
  lom::EvaluationOptions options;
  options.fusion = fusionOptions();
  lom::Annotations boxes;  // one box (any) so that there is something to score
  lom::GroundTruthBox box;
  box.label = 2;
  box.box.center = wallPoint(sequence, 4, 3);
  boxes.boxes.push_back(box);
  const lom::EvaluationReport own = lom::evaluate(sequence, boxes, map, options);
  EXPECT_FALSE(own.metrics_2d) << "the one-hot proba would score 100 % against its own labels";
  EXPECT_EQ(own.metrics_2d_excluded_frames, (std::vector<size_t>{0}));

  options.fusion.segmenter = segmenter;
  const lom::EvaluationReport network = lom::evaluate(sequence, boxes, map, options);
  ASSERT_TRUE(network.metrics_2d);
  EXPECT_EQ(network.metrics_2d->pixels, 48u);
  EXPECT_TRUE(network.metrics_2d_excluded_frames.empty());
  EXPECT_TRUE(network.metrics_2d_not_scored.empty());

  // Scored by fusing the sequence (score --segmenter): the report names the
  // network that replaced the proba made from the label image.
  boxes.boxes.front().box.size = Eigen::Vector3d::Constant(0.2);
  lom::saveAnnotations(boxes, dir / "boxes.json");
  lom::ScoreInputs inputs;
  inputs.sequence = dir / "seq";
  inputs.annotations = dir / "boxes.json";
  const lom::EvaluationReport scored = lom::scoreSequence(inputs, options);
  EXPECT_EQ(scored.segmenter, segmenter->modelPath().string());
}

// A map records where its probabilities came from: scored with --map
// against baselines that read other ones (the frames' own, not the
// segmenter's it was fused with), the report says the comparison is not
// matched and how to match it.
TEST(SegmenterFusion, AMapFusedWithASegmenterSaysSoWhenTheBaselinesReadOtherProbabilities) {
  TempDir dir;
  const lom::Sequence sequence = writeWallWithLabelProba(dir);  // the segmenter replaces its proba
  const auto segmenter = loadModel(dir);
  lom::FusionOptions fusion = fusionOptions();
  fusion.segmenter = segmenter;
  lom::fuseSequence(sequence, fusion).save(dir / "network.ot");
  fusion.segmenter.reset();
  lom::fuseSequence(sequence, fusion).save(dir / "own.ot");

  const lom::FusedEvidence network = lom::LabelMap::load(dir / "network.ot").fusedEvidence();
  EXPECT_TRUE(network.recorded);
  EXPECT_FALSE(network.own_probabilities);
  EXPECT_EQ(network.models, (std::vector<std::string>{"colour.onnx"}));
  const lom::FusedEvidence own = lom::LabelMap::load(dir / "own.ot").fusedEvidence();
  EXPECT_TRUE(own.own_probabilities);
  EXPECT_TRUE(own.models.empty());

  lom::Annotations boxes;
  lom::GroundTruthBox box;
  box.label = 2;
  box.box.center = wallPoint(sequence, 4, 3);
  box.box.size = Eigen::Vector3d::Constant(0.2);
  boxes.boxes.push_back(box);
  lom::saveAnnotations(boxes, dir / "boxes.json");
  auto scoreWith = [&](const char* map, std::shared_ptr<Segmenter> model) {
    lom::ScoreInputs inputs;
    inputs.sequence = dir / "seq";
    inputs.annotations = dir / "boxes.json";
    inputs.map = dir / map;
    lom::EvaluationOptions options;
    options.fusion = fusionOptions();
    options.fusion.segmenter = std::move(model);
    return lom::scoreSequence(inputs, options).warnings;
  };
  auto unmatched = [](const std::vector<std::string>& warnings) {
    for (const std::string& warning : warnings)
      if (warning.find("the projection baselines and the 2D metrics read") != std::string::npos)
        return warning;
    return std::string();
  };
  EXPECT_EQ(unmatched(scoreWith("network.ot", segmenter)), "");
  EXPECT_EQ(unmatched(scoreWith("own.ot", nullptr)), "");
  EXPECT_EQ(unmatched(scoreWith("network.ot", nullptr)),
            (dir / "network.ot").string() +
                " was fused with segmenter colour.onnx, but the projection baselines and the 2D "
                "metrics read the frames' own probabilities: the comparison is not matched; give "
                "--segmenter colour.onnx as the map was fused, or score without --map");
  EXPECT_NE(unmatched(scoreWith("own.ot", segmenter))
                .find("own.ot was fused with the frames' own probabilities, but the projection "
                      "baselines and the 2D metrics read segmenter colour.onnx"),
            std::string::npos);
}

TEST(SegmenterFusion, FrameWithoutColourIsAClearError) {
  TempDir dir;
  const lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 1, 0, false);
  const auto segmenter = loadModel(dir);
  try {
    (void)lom::loadFrameWithSegmenter(sequence, 0, segmenter.get());
    FAIL() << "expected lom::Error";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "frames[0].color");
    EXPECT_NE(std::string(e.what()).find("sequence.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("colour.onnx"), std::string::npos) << e.what();
  }
}

TEST(SegmenterFusion, NetworkWithTooFewChannelsForTheLabelsIsAClearError) {
  TempDir dir;
  const lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 1, 2);  // 5 labels
  const auto segmenter = loadModel(dir);
  try {
    (void)lom::loadFrameWithSegmenter(sequence, 0, segmenter.get());
    FAIL() << "expected lom::Error";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "output channels");
    EXPECT_NE(std::string(e.what()).find("expected 5 channels"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("found 3 channels"), std::string::npos) << e.what();
  }
}

// fuseSequence runs the segmenter of its options, once per frame.
TEST(SegmenterFusion, FuseSequenceUsesTheSegmenterOfTheOptions) {
  TempDir dir;
  const lom::Sequence sequence = lom::test::writeColourWallSequence(dir / "seq", 2);
  const auto segmenter = loadModel(dir);
  lom::FusionOptions options = fusionOptions();
  options.segmenter = segmenter;
  const lom::LabelMap map = lom::fuseSequence(sequence, options);
  const lom::LabelMap expected = fuseWithSegmenter(sequence, *segmenter, 2);
  EXPECT_EQ(segmenter->stats().inferences, 2u);
  for (int v = 0; v < 6; ++v)
    for (int u = 0; u < 8; ++u)
      EXPECT_EQ(map.voxelAt(wallPoint(sequence, u, v)).probabilities,
                expected.voxelAt(wallPoint(sequence, u, v)).probabilities);
  (void)lom::fuseSequence(sequence, options);  // re-fusing
  EXPECT_EQ(segmenter->stats().inferences, 2u);
}

}  // namespace
