// Synthetic frames: depth geometry, sensor effects, occlusion, colour.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "lom/synth.hpp"

namespace lom {
namespace {

SynthOptions smallScene(std::uint64_t seed, int objects, bool noise) {
  SynthOptions options;
  options.seed = seed;
  options.objects = objects;
  options.frames = 5;
  options.views = 3;
  options.width = 320;
  options.height = 240;
  options.noise = noise;
  return options;
}

const SynthObject* objectWithLabel(const SynthLayout& layout, int label) {
  for (const auto& object : layout.objects)
    if (object.label == label) return &object;
  return nullptr;
}

// 0 on the surface of the object, positive off it (inside or outside).
double distanceToSurface(const SynthObject& object, const Eigen::Vector3d& p_world) {
  const Eigen::Vector3d p = object.box.rotation.conjugate() * (p_world - object.box.center);
  const Eigen::Vector3d half = 0.5 * object.box.size;
  if (object.shape == SynthShape::Cylinder) {
    const double radial = std::hypot(p.x(), p.y()) - half.x(), axial = std::abs(p.z()) - half.z();
    if (radial > 0 || axial > 0) return std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
    return std::min(-radial, -axial);
  }
  const Eigen::Vector3d beyond = p.cwiseAbs() - half;
  if ((beyond.array() > 0).any()) return beyond.cwiseMax(0.0).norm();
  return -beyond.maxCoeff();
}

Eigen::Vector3d worldPoint(const SynthLayout& layout, size_t frame, int u, int v, double z) {
  return layout.T_world_camera[frame] * layout.camera.backProject(u, v, z);
}

double median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

TEST(SynthRenderTest, NoiseFreeObjectPixelsLieOnTheirGroundTruthSurface) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const SynthOptions options = smallScene(seed, 8, false);
    const SynthLayout layout = makeSynthLayout(options);
    std::map<int, int> pixels_per_label;
    for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
      const SynthFrame frame = renderSynthFrame(layout, options, f);
      for (int v = 0; v < frame.depth.height; ++v)
        for (int u = 0; u < frame.depth.width; ++u) {
          const double z = frame.depth.at(u, v);
          const int label = frame.label.at(u, v);
          if (label > 0) ++pixels_per_label[label];
          if (z <= 0) continue;
          const Eigen::Vector3d p = worldPoint(layout, f, u, v, z);
          if (label > 0) {
            const SynthObject* object = objectWithLabel(layout, label);
            ASSERT_NE(object, nullptr) << "label " << label << " is not in the scene";
            // The 1 mm depth step moves a point by at most 0.5 mm in depth,
            // along its pixel's ray: 0.5 mm times the ray's length per metre
            // of depth (float storage adds well under a micrometre).
            const double ray_per_depth = layout.camera.backProject(u, v, 1.0).norm();
            ASSERT_LE(distanceToSurface(*object, p), 0.0005 * ray_per_depth + 1e-6)
                << object->name << " pixel " << u << "," << v << " frame " << f;
            ASSERT_TRUE(object->box.contains(p, 0.002));
          } else {
            for (const auto& object : layout.objects)
              ASSERT_FALSE(object.box.contains(p, -0.002))
                  << "background pixel " << u << "," << v << " inside " << object.name;
          }
        }
    }
    for (const auto& object : layout.objects)
      EXPECT_GT(pixels_per_label[object.label], 20) << object.name << " never seen";
  }
}

TEST(SynthRenderTest, NoisyDepthStaysWithinAFewMillimetres) {
  const SynthOptions options = smallScene(4, 8, true);
  const SynthLayout layout = makeSynthLayout(options);
  std::vector<double> errors;
  size_t object_pixels = 0;
  for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
    const SynthFrame frame = renderSynthFrame(layout, options, f);
    for (int v = 0; v < frame.depth.height; ++v)
      for (int u = 0; u < frame.depth.width; ++u) {
        const int label = frame.label.at(u, v);
        if (label == 0 || label == kSynthTransparentLabel) continue;
        ++object_pixels;
        const double z = frame.depth.at(u, v);
        if (z > 0)
          errors.push_back(
              distanceToSurface(*objectWithLabel(layout, label), worldPoint(layout, f, u, v, z)));
      }
  }
  ASSERT_GT(errors.size(), 1000u);
  EXPECT_LT(median(errors), 0.003);
  EXPECT_GT(median(errors), 0.0002) << "no noise at all";
  const double valid_fraction = static_cast<double>(errors.size()) / object_pixels;
  EXPECT_GT(valid_fraction, 0.6);
  EXPECT_LT(valid_fraction, 0.995) << "no missing pixels on objects";
}

TEST(SynthRenderTest, DepthIsQuantisedToTheMillimetreStep) {
  const SynthOptions options = smallScene(5, 4, true);
  const SynthFrame frame = renderSynthFrame(makeSynthLayout(options), options, 0);
  for (const float z : frame.depth.metres) {
    const double steps = z / 0.001;
    ASSERT_NEAR(steps, std::round(steps), 1e-3);
  }
}

TEST(SynthRenderTest, NoiseGrowsWithDepth) {
  const SynthOptions noisy = smallScene(6, 6, true);
  SynthOptions exact = noisy;
  exact.noise = false;
  const SynthLayout layout = makeSynthLayout(noisy);
  double near_squares = 0, far_squares = 0;
  size_t near_count = 0, far_count = 0;
  for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
    const SynthFrame a = renderSynthFrame(layout, noisy, f);
    const SynthFrame b = renderSynthFrame(layout, exact, f);
    for (size_t i = 0; i < a.depth.metres.size(); ++i) {
      const double z = b.depth.metres[i], error = a.depth.metres[i] - z;
      if (z <= 0 || a.depth.metres[i] <= 0) continue;
      if (z > 0.4 && z < 0.55) near_squares += error * error, ++near_count;
      if (z > 0.8 && z < 1.0) far_squares += error * error, ++far_count;
    }
  }
  ASSERT_GT(near_count, 1000u);
  ASSERT_GT(far_count, 1000u);
  // sigma(0.5 m) = 1.2 mm, sigma(0.9 m) = 1.7 mm, plus the 1 mm quantisation
  // of both depths (about 0.4 mm rms).
  const double near_rms = std::sqrt(near_squares / near_count);
  const double far_rms = std::sqrt(far_squares / far_count);
  EXPECT_GT(near_rms, 0.0009);
  EXPECT_LT(near_rms, 0.0016);
  EXPECT_GT(far_rms, 1.2 * near_rms);
}

TEST(SynthRenderTest, SensorLosesPixelsAtDepthEdges) {
  const SynthOptions noisy = smallScene(7, 8, true);
  SynthOptions exact = noisy;
  exact.noise = false;
  const SynthLayout layout = makeSynthLayout(noisy);
  const SynthFrame a = renderSynthFrame(layout, noisy, 2);
  const SynthFrame b = renderSynthFrame(layout, exact, 2);
  const int w = b.depth.width, h = b.depth.height;
  size_t edge_pixels = 0, edge_missing = 0, seen = 0, missing = 0;
  for (int v = 1; v + 1 < h; ++v)
    for (int u = 1; u + 1 < w; ++u) {
      const double z = b.depth.at(u, v);
      if (z <= 0) continue;
      ++seen;
      const bool lost = a.depth.at(u, v) <= 0;
      missing += lost;
      const double nearest_neighbour = std::min(
          {b.depth.at(u - 1, v), b.depth.at(u + 1, v), b.depth.at(u, v - 1), b.depth.at(u, v + 1)});
      if (nearest_neighbour > 0 && z - nearest_neighbour > 0.03) {
        ++edge_pixels;
        edge_missing += lost;
      }
    }
  ASSERT_GT(edge_pixels, 50u);
  EXPECT_GT(static_cast<double>(edge_missing) / edge_pixels, 0.6);
  EXPECT_GT(static_cast<double>(missing) / seen, 0.01);
  EXPECT_LT(static_cast<double>(missing) / seen, 0.3);
}

// The first seed whose `objects`-object scene holds `label`.
std::uint64_t seedWithLabel(int label, int objects) {
  for (std::uint64_t seed = 1; seed < 1000; ++seed) {
    SynthOptions options;
    options.seed = seed;
    options.objects = objects;
    if (objectWithLabel(makeSynthLayout(options), label)) return seed;
  }
  return 0;
}

TEST(SynthRenderTest, TransparentBottleHasNoDepth) {
  const std::uint64_t seed = seedWithLabel(kSynthTransparentLabel, 6);
  ASSERT_NE(seed, 0u);
  for (const bool noise : {true, false}) {
    const SynthOptions options = smallScene(seed, 6, noise);
    const SynthLayout layout = makeSynthLayout(options);
    size_t bottle_pixels = 0;
    for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
      const SynthFrame frame = renderSynthFrame(layout, options, f);
      for (size_t i = 0; i < frame.label.ids.size(); ++i) {
        if (frame.label.ids[i] != kSynthTransparentLabel) continue;
        ++bottle_pixels;
        ASSERT_EQ(frame.depth.metres[i], 0.0f) << "the bottle has depth, noise " << noise;
      }
    }
    EXPECT_GT(bottle_pixels, 100u);
  }
}

// Pixels of each label in one frame.
std::map<int, int> labelCounts(const SynthFrame& frame) {
  std::map<int, int> counts;
  for (const auto id : frame.label.ids) ++counts[id];
  return counts;
}

TEST(SynthRenderTest, SomeObjectIsPartlyHiddenInTheMiddleViewButSeenInAnother) {
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    SynthOptions options = smallScene(seed, 6, false);
    options.frames = 3;
    const SynthLayout layout = makeSynthLayout(options);
    std::vector<std::map<int, int>> with_others;
    for (size_t f = 0; f < 3; ++f)
      with_others.push_back(labelCounts(renderSynthFrame(layout, options, f)));
    bool found = false;
    for (const auto& object : layout.objects) {
      SynthLayout alone = layout;
      alone.objects = {object};
      std::vector<double> visible;  // fraction of the object not hidden by other objects
      for (size_t f = 0; f < 3; ++f) {
        const int unoccluded = labelCounts(renderSynthFrame(alone, options, f))[object.label];
        visible.push_back(unoccluded > 0 ? with_others[f][object.label] / double(unoccluded) : 1.0);
      }
      const double middle = visible[1], best_other = std::max(visible[0], visible[2]);
      if (middle < 0.85 && with_others[1][object.label] > 0 && best_other > middle + 0.1)
        found = true;
    }
    EXPECT_TRUE(found) << "no object partly hidden in the middle view, seed " << seed;
  }
}

TEST(SynthRenderTest, ColourImageShowsObjectsInTheirLabelColours) {
  const SynthOptions options = smallScene(8, 8, true);
  const SynthLayout layout = makeSynthLayout(options);
  const SynthFrame frame = renderSynthFrame(layout, options, 2);
  ASSERT_EQ(frame.color.rgb.size(), frame.label.ids.size() * 3);
  std::map<int, Eigen::Vector3d> sums;
  for (size_t i = 0; i < frame.label.ids.size(); ++i) {
    const int label = frame.label.ids[i];
    // Eigen vectors are not zero-initialised: start each sum explicitly.
    sums.try_emplace(label, Eigen::Vector3d::Zero());
    sums[label] += Eigen::Vector3d(frame.color.rgb[3 * i], frame.color.rgb[3 * i + 1],
                                   frame.color.rgb[3 * i + 2]);
  }
  int checked = 0;
  for (const auto& [label, sum] : sums) {
    if (label == 0 || label == kSynthTransparentLabel) continue;
    const Rgb expected = vocColor(label);
    const Eigen::Vector3d direction(expected[0], expected[1], expected[2]);
    EXPECT_GT(sum.normalized().dot(direction.normalized()), 0.97) << "label " << label;
    ++checked;
  }
  EXPECT_GE(checked, 4);
  // The bin is greyish brown, not an object colour.
  const Eigen::Vector3d bin = sums[0].normalized();
  EXPECT_GT(bin.x(), bin.z());
}

TEST(SynthRenderTest, FramesRenderTheSameInAnyOrder) {
  const SynthOptions options = smallScene(10, 5, true);
  const SynthLayout layout = makeSynthLayout(options);
  const SynthFrame late_first = renderSynthFrame(layout, options, 4);
  (void)renderSynthFrame(layout, options, 0);
  const SynthFrame late_again = renderSynthFrame(layout, options, 4);
  EXPECT_EQ(late_first.depth.metres, late_again.depth.metres);
  EXPECT_EQ(late_first.color.rgb, late_again.color.rgb);
  EXPECT_EQ(late_first.proba.values, late_again.proba.values);
  const SynthFrame other = renderSynthFrame(layout, options, 3);
  EXPECT_NE(late_first.depth.metres, other.depth.metres);
}

}  // namespace
}  // namespace lom
