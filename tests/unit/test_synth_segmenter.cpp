// The simulated segmenter's probability images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "lom/synth.hpp"

namespace lom {
namespace {

SynthOptions sceneOptions(std::uint64_t seed, bool mistakes = true) {
  SynthOptions options;
  options.seed = seed;
  options.objects = 7;
  options.frames = 4;
  options.views = 3;
  options.width = 320;
  options.height = 240;
  options.segmenter_mistakes = mistakes;
  return options;
}

int channelOf(const ProbabilityImage& proba, int label) {
  const auto& labels = proba.channel_labels;
  const auto it = std::find(labels.begin(), labels.end(), label);
  return it == labels.end() ? -1 : static_cast<int>(it - labels.begin());
}

int argmaxLabel(const ProbabilityImage& proba, int u, int v) {
  const float* p = proba.pixel(u, v);
  return proba.channel_labels[static_cast<size_t>(std::max_element(p, p + proba.channels) - p)];
}

// A pixel whose 4-neighbours all carry its label.
bool interior(const LabelImage& label, int u, int v, int radius) {
  for (int dv = -radius; dv <= radius; ++dv)
    for (int du = -radius; du <= radius; ++du) {
      const int nu = u + du, nv = v + dv;
      if (nu < 0 || nv < 0 || nu >= label.width || nv >= label.height) continue;
      if (label.at(nu, nv) != label.at(u, v)) return false;
    }
  return true;
}

TEST(SynthSegmenterTest, ProbabilitiesSumToOneAndAreStoredAsBytes) {
  const SynthOptions options = sceneOptions(1);
  const SynthLayout layout = makeSynthLayout(options);
  const SynthFrame frame = renderSynthFrame(layout, options, 1);
  const ProbabilityImage& proba = frame.proba;
  EXPECT_EQ(proba.channel_labels, layout.proba_labels);
  ASSERT_EQ(proba.channels, static_cast<int>(layout.proba_labels.size()));
  ASSERT_EQ(proba.values.size(), static_cast<size_t>(320 * 240 * proba.channels));
  const double rounding = 0.5 / 255.0 * proba.channels + 1e-6;
  for (int v = 0; v < proba.height; ++v)
    for (int u = 0; u < proba.width; ++u) {
      const float* p = proba.pixel(u, v);
      double sum = 0.0;
      for (int c = 0; c < proba.channels; ++c) {
        ASSERT_GE(p[c], 0.0f);
        ASSERT_NEAR(p[c] * 255.0, std::round(p[c] * 255.0), 1e-3) << "not a byte value";
        sum += p[c];
      }
      ASSERT_NEAR(sum, 1.0, rounding) << "pixel " << u << "," << v;
    }
}

TEST(SynthSegmenterTest, ArgmaxAgreesWithTruthOnMostButNotAllObjectPixels) {
  size_t object_pixels = 0, agreeing = 0;
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    const SynthOptions options = sceneOptions(seed);
    const SynthLayout layout = makeSynthLayout(options);
    for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
      const SynthFrame frame = renderSynthFrame(layout, options, f);
      for (int v = 0; v < frame.label.height; ++v)
        for (int u = 0; u < frame.label.width; ++u) {
          const int truth = frame.label.at(u, v);
          if (truth == 0) continue;
          ++object_pixels;
          agreeing += argmaxLabel(frame.proba, u, v) == truth;
        }
    }
  }
  ASSERT_GT(object_pixels, 10000u);
  const double accuracy = static_cast<double>(agreeing) / object_pixels;
  EXPECT_GT(accuracy, 0.8);
  EXPECT_LT(accuracy, 0.995);
}

TEST(SynthSegmenterTest, ConfidentInsideObjectsUnsureAtTheirBoundaries) {
  const SynthOptions options = sceneOptions(2);
  const SynthLayout layout = makeSynthLayout(options);
  const SynthFrame frame = renderSynthFrame(layout, options, 1);
  double inside_sum = 0, edge_sum = 0;
  size_t inside_count = 0, edge_count = 0;
  for (int v = 0; v < frame.label.height; ++v)
    for (int u = 0; u < frame.label.width; ++u) {
      const int truth = frame.label.at(u, v);
      if (truth == 0) continue;
      const double p = frame.proba.pixel(u, v)[channelOf(frame.proba, truth)];
      if (interior(frame.label, u, v, 4)) {
        inside_sum += p, ++inside_count;
      } else if (!interior(frame.label, u, v, 1)) {
        edge_sum += p, ++edge_count;
      }
    }
  ASSERT_GT(inside_count, 500u);
  ASSERT_GT(edge_count, 200u);
  EXPECT_GT(inside_sum / inside_count, 0.75);
  EXPECT_LT(inside_sum / inside_count, 0.98);
  EXPECT_LT(edge_sum / edge_count, inside_sum / inside_count - 0.15);
}

TEST(SynthSegmenterTest, LookAlikeClassesGetSomeProbability) {
  // oral_b_toothbrush_green (25) and _red (26) are look-alikes.
  for (std::uint64_t seed = 1; seed < 500; ++seed) {
    SynthOptions options = sceneOptions(seed);
    const SynthLayout layout = makeSynthLayout(options);
    const bool has_green = std::any_of(layout.objects.begin(), layout.objects.end(),
                                       [](const SynthObject& o) { return o.label == 25; });
    if (!has_green) continue;
    double look_alike = 0, unrelated = 0;
    size_t pixels = 0;
    for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
      const SynthFrame frame = renderSynthFrame(layout, options, f);
      const int similar = channelOf(frame.proba, 26);
      ASSERT_GE(similar, 0);
      for (int v = 0; v < frame.label.height; ++v)
        for (int u = 0; u < frame.label.width; ++u) {
          if (frame.label.at(u, v) != 25 || !interior(frame.label, u, v, 2)) continue;
          const float* p = frame.proba.pixel(u, v);
          look_alike += p[similar];
          const int own = channelOf(frame.proba, 25);
          for (int c = 1; c < frame.proba.channels; ++c)  // mean of the other object channels
            if (c != own && c != similar) unrelated += p[c] / (frame.proba.channels - 3);
          ++pixels;
        }
    }
    ASSERT_GT(pixels, 50u);
    EXPECT_GT(look_alike / pixels, 0.03);
    EXPECT_GT(look_alike, 5 * unrelated);
    return;
  }
  FAIL() << "no seed puts oral_b_toothbrush_green into a scene";
}

TEST(SynthSegmenterTest, FalsePositivesAppearAwayFromObjects) {
  size_t wrong_background = 0;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const SynthOptions options = sceneOptions(seed);
    const SynthLayout layout = makeSynthLayout(options);
    for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
      const SynthFrame frame = renderSynthFrame(layout, options, f);
      for (int v = 0; v < frame.label.height; ++v)
        for (int u = 0; u < frame.label.width; ++u)
          if (frame.label.at(u, v) == 0 && interior(frame.label, u, v, 5) &&
              argmaxLabel(frame.proba, u, v) != 0)
            ++wrong_background;
    }
  }
  EXPECT_GT(wrong_background, 20u);
}

TEST(SynthSegmenterTest, WithoutMistakesTheTrueLabelAlwaysWins) {
  for (const std::uint64_t seed : {1u, 2u}) {
    const SynthOptions options = sceneOptions(seed, false);
    const SynthLayout layout = makeSynthLayout(options);
    for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
      const SynthFrame frame = renderSynthFrame(layout, options, f);
      for (int v = 0; v < frame.label.height; ++v)
        for (int u = 0; u < frame.label.width; ++u) {
          const float* p = frame.proba.pixel(u, v);
          const float truth = p[channelOf(frame.proba, frame.label.at(u, v))];
          ASSERT_EQ(truth, *std::max_element(p, p + frame.proba.channels))
              << "pixel " << u << "," << v << " frame " << f;
        }
    }
  }
}

}  // namespace
}  // namespace lom
