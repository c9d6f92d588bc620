// The fast integration path gives the same map as the reference path.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "lom/fusion.hpp"
#include "lom/octree/label_octree.hpp"
#include "lom/synth.hpp"
#include "test_support.hpp"

namespace {

using lom::IntegrationPath;
using lom::LabelMap;

struct Comparison {
  size_t checked = 0;
  size_t mismatched_state = 0;   // known / occupied / label differ
  double max_probability_difference = 0.0;
};

// Checks every leaf of `a` against the voxel at the same key in `b`.
void compareLeaves(const LabelMap& a, const LabelMap& b, Comparison& result) {
  for (auto it = a.tree().begin_leafs(), end = a.tree().end_leafs(); it != end; ++it) {
    const octomap::OcTreeKey key = it.getIndexKey();
    const lom::VoxelKey voxel{key[0], key[1], key[2]};
    const lom::VoxelState sa = a.voxelAt(voxel);
    const lom::VoxelState sb = b.voxelAt(voxel);
    ++result.checked;
    if (sa.known != sb.known || sa.occupied != sb.occupied ||
        (sa.occupied && sa.label != sb.label)) {
      ++result.mismatched_state;
      continue;
    }
    for (size_t k = 0; k < sa.probabilities.size(); ++k)
      result.max_probability_difference =
          std::max(result.max_probability_difference,
                   static_cast<double>(std::fabs(sa.probabilities[k] - sb.probabilities[k])));
  }
}

void expectSameMaps(const LabelMap& reference, const LabelMap& fast) {
  Comparison result;
  compareLeaves(reference, fast, result);
  compareLeaves(fast, reference, result);
  EXPECT_GT(result.checked, 1000u);
  EXPECT_EQ(result.mismatched_state, 0u);
  EXPECT_LE(result.max_probability_difference, 1e-4);
  EXPECT_EQ(reference.occupiedCountPerLabel(), fast.occupiedCountPerLabel());
  EXPECT_EQ(reference.tree().size(), reference.tree().calcNumNodes());
  EXPECT_EQ(fast.tree().size(), fast.tree().calcNumNodes());
}

// A generated 320x240 shelf-bin scene (8-bit probability images) in `dir`.
lom::Sequence generatedScene(const lom::test::TempDir& dir, std::uint64_t seed, int objects, int frames,
                             int width = 320, int height = 240) {
  lom::SynthOptions options;
  options.seed = seed;
  options.objects = objects;
  options.frames = frames;
  options.views = 3;
  options.width = width;
  options.height = height;
  lom::writeSyntheticScene(options, dir.path());
  return lom::loadSequence(dir.path());
}

// Fuses frame `i` of `sequence` (its camera and pose) into `map`.
lom::FrameStats integrate(LabelMap& map, const lom::Sequence& sequence, size_t i,
                          const lom::DepthImage& depth, const lom::FrameEvidence& evidence,
                          const lom::IntegrationOptions& options = {}) {
  return lom::integrateFrame(map, sequence.cameraOf(i), sequence.frames[i].T_world_camera, depth,
                             evidence, options);
}

lom::IntegrationOptions referencePath() {
  lom::IntegrationOptions options;
  options.path = IntegrationPath::Reference;
  return options;
}

TEST(FastPathTest, SameMapAsReferenceOnASyntheticScene) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = generatedScene(dir, 21, 5, 4);

  lom::FusionOptions fusion;
  fusion.integration.path = IntegrationPath::Reference;
  const LabelMap reference = lom::fuseSequence(sequence, fusion);
  fusion.integration.path = IntegrationPath::Fast;
  const LabelMap fast = lom::fuseSequence(sequence, fusion);
  expectSameMaps(reference, fast);
  // Candidates go through the general (dense) per-pixel evidence.
  fusion.candidates = std::vector<int>{0, sequence.labels.size() - 1};
  fusion.first_frame = 1;
  fusion.last_frame = 3;
  fusion.integration.path = IntegrationPath::Reference;
  const LabelMap reference_candidates = lom::fuseSequence(sequence, fusion);
  fusion.integration.path = IntegrationPath::Fast;
  expectSameMaps(reference_candidates, lom::fuseSequence(sequence, fusion));
}

// With several threads the rows' groups are merged while rays are cast from
// every part's groups, and the hit and miss streams are merged in halves:
// one, two and three threads all give the reference path's map.
TEST(FastPathTest, EveryThreadCountGivesTheReferenceMap) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = generatedScene(dir, 34, 6, 3);
  const int n = sequence.labels.size();
  auto fuse = [&](IntegrationPath path, int threads) {
    LabelMap map(sequence.labels, lom::MapParameters{});
    lom::IntegrationOptions integration;
    integration.path = path;
    integration.threads = threads;
    size_t most_misses = 0;
    for (size_t i = 0; i < sequence.frames.size(); ++i) {
      const lom::FrameData frame = lom::loadFrame(sequence, i);
      const lom::FrameEvidence evidence(n, &*frame.proba, nullptr, std::nullopt, 0.9);
      const lom::FrameStats stats = integrate(map, sequence, i, frame.depth, evidence, integration);
      most_misses = std::max(most_misses, stats.miss_voxels);
    }
    // Enough misses for the streams to be merged in two halves (4096 or more).
    EXPECT_GT(most_misses, 8192u);
    return map;
  };
  const LabelMap reference = fuse(IntegrationPath::Reference, 1);
  for (const int threads : {1, 2, 3}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    expectSameMaps(reference, fuse(IntegrationPath::Fast, threads));
  }
}

// 8-bit probability images go through a log-odds table, other images through
// the vectorised logit: both give the reference path's map.
TEST(FastPathTest, EightBitAndFloatProbabilityImagesGiveTheSameMap) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = generatedScene(dir, 5, 4, 3);
  lom::MapParameters parameters;
  LabelMap reference(sequence.labels, parameters);
  LabelMap coded(sequence.labels, parameters);
  LabelMap floats(sequence.labels, parameters);
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    const lom::FrameData frame = lom::loadFrame(sequence, i);
    ASSERT_TRUE(frame.proba.has_value());
    ASSERT_EQ(frame.proba->codes.size(), frame.proba->values.size()) << "generated scenes store 8-bit probabilities";
    lom::ProbabilityImage without_codes = *frame.proba;
    without_codes.codes.clear();
    const int n = sequence.labels.size();
    const lom::FrameEvidence with(n, &*frame.proba, nullptr, std::nullopt, 0.9);
    const lom::FrameEvidence without(n, &without_codes, nullptr, std::nullopt, 0.9);
    integrate(reference, sequence, i, frame.depth, with, referencePath());
    integrate(coded, sequence, i, frame.depth, with);
    integrate(floats, sequence, i, frame.depth, without);
  }
  expectSameMaps(reference, coded);
  expectSameMaps(reference, floats);
}

// Fusion reads 8-bit probability images as their codes only (no float copy):
// both paths, with and without class candidates, give the same bits as from
// the image with its floats.
TEST(FastPathTest, ProbabilityCodesWithoutFloatsGiveTheSameBits) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = generatedScene(dir, 9, 4, 3);
  const int n = sequence.labels.size();
  const std::vector<int> candidates{0, 4, 6, 10, 12, 28, 32, n - 1};
  for (const bool restricted : {false, true}) {
    for (const IntegrationPath path : {IntegrationPath::Fast, IntegrationPath::Reference}) {
      SCOPED_TRACE(std::string(path == IntegrationPath::Fast ? "fast" : "reference") +
                   (restricted ? ", candidates" : ""));
      LabelMap with_floats(sequence.labels, lom::MapParameters{});
      LabelMap codes_only(sequence.labels, lom::MapParameters{});
      lom::IntegrationOptions options;
      options.path = path;
      const auto given = restricted ? std::optional<std::vector<int>>(candidates) : std::nullopt;
      for (size_t i = 0; i < sequence.frames.size(); ++i) {
        const lom::FrameData full = lom::loadFrame(sequence, i);
        const lom::FrameData fused = lom::loadFusionFrame(sequence, i, nullptr);
        ASSERT_TRUE(full.proba && fused.proba);
        ASSERT_FALSE(full.proba->values.empty());
        ASSERT_TRUE(fused.proba->values.empty());
        ASSERT_EQ(fused.proba->codes.size(), full.proba->values.size());
        integrate(with_floats, sequence, i, full.depth,
                  lom::FrameEvidence(n, &*full.proba, nullptr, given, 0.9), options);
        integrate(codes_only, sequence, i, fused.depth,
                  lom::FrameEvidence(n, &*fused.proba, nullptr, given, 0.9), options);
      }
      Comparison result;
      compareLeaves(with_floats, codes_only, result);
      compareLeaves(codes_only, with_floats, result);
      EXPECT_GT(result.checked, 1000u);
      EXPECT_EQ(result.mismatched_state, 0u);
      EXPECT_EQ(result.max_probability_difference, 0.0);
    }
  }
}

// A single float channel (a single-label map, or one label of many) sums each
// run of pixels in a register: random probabilities per pixel, so that every
// pixel of a voxel counts, give the reference path's map.
TEST(FastPathTest, OneChannelFloatImagesGiveTheReferenceMap) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = generatedScene(dir, 17, 4, 3);
  const int n = sequence.labels.size();
  std::mt19937 random(17);
  std::uniform_real_distribution<float> probability(0.05f, 0.95f);
  LabelMap reference(sequence.labels, lom::MapParameters{});
  LabelMap fast(sequence.labels, lom::MapParameters{});
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    const lom::FrameData frame = lom::loadFrame(sequence, i);
    lom::ProbabilityImage proba;
    proba.width = frame.depth.width;
    proba.height = frame.depth.height;
    proba.channels = 1;
    proba.channel_labels = {2};
    proba.values.resize(static_cast<size_t>(proba.width) * proba.height);
    for (float& value : proba.values) value = probability(random);
    const lom::FrameEvidence evidence(n, &proba, nullptr, std::nullopt, 0.9);
    integrate(reference, sequence, i, frame.depth, evidence, referencePath());
    integrate(fast, sequence, i, frame.depth, evidence);
  }
  expectSameMaps(reference, fast);
  EXPECT_GT(fast.occupiedCountPerLabel()[2], 100u);
}

// The vector kernels (AVX-512, AVX2) and the baseline instructions add the
// same values in the same order: the maps agree to the last bit.
TEST(FastPathTest, EveryKernelChoiceGivesTheSameBits) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = generatedScene(dir, 13, 6, 3);
  lom::FusionOptions fusion;
  fusion.integration.threads = 2;
  fusion.integration.kernels = lom::VectorKernels::Baseline;
  const LabelMap baseline = lom::fuseSequence(sequence, fusion);
  fusion.integration.kernels = lom::VectorKernels::UpToAvx2;
  const LabelMap avx2 = lom::fuseSequence(sequence, fusion);
  fusion.integration.kernels = lom::VectorKernels::UpToAvx512F;
  const LabelMap avx512 = lom::fuseSequence(sequence, fusion);
  fusion.integration.kernels = lom::VectorKernels::Best;
  const LabelMap best = lom::fuseSequence(sequence, fusion);
  for (const LabelMap* other : {&avx2, &avx512, &best}) {
    Comparison result;
    compareLeaves(baseline, *other, result);
    compareLeaves(*other, baseline, result);
    EXPECT_GT(result.checked, 1000u);
    EXPECT_EQ(result.mismatched_state, 0u);
    EXPECT_EQ(result.max_probability_difference, 0.0);
    EXPECT_EQ(baseline.tree().size(), other->tree().size());
  }
}

// The 8-bit kernels read a pixel's codes a whole register at a time (up to
// four pixels at once): every channel count up to 16, an image width that is
// not a multiple of four and the image's last pixel give the same bits with
// every kernel choice.
TEST(FastPathTest, EveryKernelChoiceGivesTheSameBitsAtEveryChannelCount) {
  lom::test::TempDir dir;
  const lom::Sequence sequence = generatedScene(dir, 8, 4, 3, 163, 122);  // odd width: rows end inside a four-pixel load
  const int n = sequence.labels.size();
  std::vector<lom::FrameData> frames;
  for (size_t i = 0; i < sequence.frames.size(); ++i) frames.push_back(lom::loadFrame(sequence, i));
  for (const int channels : {1, 3, 7, 12, 15, 16}) {
    // Codes drawn at random for the listed labels (a spread of labels).
    std::vector<lom::ProbabilityImage> images;
    std::mt19937 random(static_cast<unsigned>(channels));
    std::uniform_int_distribution<int> code(0, 255);
    for (const lom::FrameData& frame : frames) {
      lom::ProbabilityImage proba;
      proba.width = frame.depth.width;
      proba.height = frame.depth.height;
      proba.channels = channels;
      for (int c = 0; c < channels; ++c) proba.channel_labels.push_back((c * 5) % n);
      proba.codes.resize(static_cast<size_t>(proba.width) * proba.height * channels);
      proba.values.resize(proba.codes.size());
      for (size_t i = 0; i < proba.codes.size(); ++i) {
        proba.codes[i] = static_cast<std::uint8_t>(code(random));
        proba.values[i] = lom::probabilityOfCode(proba.codes[i]);
      }
      images.push_back(std::move(proba));
    }
    auto fuse = [&](lom::VectorKernels kernels) {
      LabelMap map(sequence.labels, lom::MapParameters{});
      lom::IntegrationOptions integration;
      integration.threads = 2;
      integration.kernels = kernels;
      for (size_t i = 0; i < frames.size(); ++i) {
        const lom::FrameEvidence evidence(n, &images[i], nullptr, std::nullopt, 0.9);
        integrate(map, sequence, i, frames[i].depth, evidence, integration);
      }
      return map;
    };
    const LabelMap baseline = fuse(lom::VectorKernels::Baseline);
    for (const auto kernels : {lom::VectorKernels::UpToAvx2, lom::VectorKernels::UpToAvx512F, lom::VectorKernels::Best}) {
      const LabelMap other = fuse(kernels);
      Comparison result;
      compareLeaves(baseline, other, result);
      compareLeaves(other, baseline, result);
      EXPECT_GT(result.checked, 500u) << channels << " channels";
      EXPECT_EQ(result.mismatched_state, 0u) << channels << " channels";
      EXPECT_EQ(result.max_probability_difference, 0.0) << channels << " channels";
    }
  }
}

// Real recorded depth and poses, with probability images made up from colour.
lom::ProbabilityImage madeUpProbabilities(const lom::ColorImage& color, int num_labels) {
  lom::ProbabilityImage proba;
  proba.width = color.width;
  proba.height = color.height;
  proba.channels = 4;
  proba.channel_labels = {0, 3, 17, num_labels - 1};
  proba.values.resize(static_cast<size_t>(color.width) * color.height * 4);
  for (size_t i = 0; i < static_cast<size_t>(color.width) * color.height; ++i) {
    const float r = color.rgb[3 * i] / 255.f, gch = color.rgb[3 * i + 1] / 255.f,
                b = color.rgb[3 * i + 2] / 255.f;
    const float scores[4] = {1.f, 4.f * r, 4.f * gch, 4.f * b};
    float total = 0.f;
    for (float s : scores) total += std::exp(s);
    for (int c = 0; c < 4; ++c) proba.values[4 * i + static_cast<size_t>(c)] = std::exp(scores[c]) / total;
  }
  return proba;
}

Eigen::Isometry3d readPose(const std::filesystem::path& path) {
  std::ifstream in(path);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) in >> m(r, c);
  Eigen::Isometry3d pose;
  pose.matrix() = m;
  return pose;
}

TEST(FastPathTest, SameMapAsReferenceOnRecordedFrames) {
  LOM_REQUIRE_SHARED_DATA("apc-box-realsense");
  const auto folder = lom::test::sharedDataDir() / "apc-box-realsense";
  lom::CameraIntrinsics camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = camera.fy = 615.195;
  camera.cx = 298.443;
  camera.cy = 247.519;
  const lom::LabelSet labels = lom::apc2016Labels();
  lom::MapParameters parameters;
  LabelMap reference(labels, parameters);
  LabelMap fast(labels, parameters);
  for (const char* frame : {"000015", "000031", "000061"}) {
    const auto stem = folder / (std::string("frame-") + frame);
    const lom::DepthImage depth = lom::readDepthImage(stem.string() + ".depth.png", 0.001);
    const lom::ColorImage color = lom::readColorImage(stem.string() + ".color.png");
    const lom::ProbabilityImage proba = madeUpProbabilities(color, labels.size());
    const Eigen::Isometry3d pose = readPose(stem.string() + ".pose.txt");
    const lom::FrameEvidence evidence(labels.size(), &proba, nullptr, std::nullopt, 0.9);
    lom::IntegrationOptions options;
    options.path = IntegrationPath::Reference;
    const auto stats_reference = lom::integrateFrame(reference, camera, pose, depth, evidence, options);
    options.path = IntegrationPath::Fast;
    const auto stats_fast = lom::integrateFrame(fast, camera, pose, depth, evidence, options);
    EXPECT_EQ(stats_reference.hit_voxels, stats_fast.hit_voxels);
    EXPECT_EQ(stats_reference.miss_voxels, stats_fast.miss_voxels);
    EXPECT_GT(stats_fast.hit_voxels, 1000u);
  }
  expectSameMaps(reference, fast);
}

}  // namespace
