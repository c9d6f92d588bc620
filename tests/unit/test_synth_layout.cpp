// Synthetic scene layout: objects in the bin, camera path, options.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>

#include "lom/synth.hpp"

namespace lom {
namespace {

SynthOptions optionsWith(std::uint64_t seed, int objects) {
  SynthOptions options;
  options.seed = seed;
  options.objects = objects;
  options.width = 160;
  options.height = 120;
  return options;
}

std::vector<Eigen::Vector3d> corners(const OrientedBox& box) {
  std::vector<Eigen::Vector3d> result;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d sign(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
    result.push_back(box.center + box.rotation * box.size.cwiseProduct(sign));
  }
  return result;
}

// Points filling the box, its corners included.
std::vector<Eigen::Vector3d> samplesInside(const OrientedBox& box) {
  std::vector<Eigen::Vector3d> points;
  constexpr int kSteps = 9;
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j)
      for (int k = 0; k < kSteps; ++k) {
        const Eigen::Vector3d fraction(i, j, k);
        const Eigen::Vector3d local = (fraction / (kSteps - 1) - Eigen::Vector3d::Constant(0.5));
        points.push_back(box.center + box.rotation * box.size.cwiseProduct(local));
      }
  return points;
}

TEST(SynthLayoutTest, ObjectsHaveDistinctCatalogueLabels) {
  for (const int count : {1, 6, 12, 39}) {
    const SynthLayout layout = makeSynthLayout(optionsWith(7, count));
    ASSERT_EQ(static_cast<int>(layout.objects.size()), count);
    std::set<int> labels;
    const LabelSet catalogue = apc2016Labels();
    for (const auto& object : layout.objects) {
      EXPECT_GE(object.label, 1);
      EXPECT_LE(object.label, 39);
      EXPECT_EQ(object.name, catalogue.at(object.label).name);
      labels.insert(object.label);
    }
    EXPECT_EQ(static_cast<int>(labels.size()), count) << "labels repeat";
  }
}

TEST(SynthLayoutTest, ObjectsRestOnTheFloorInsideTheBin) {
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const SynthLayout layout = makeSynthLayout(optionsWith(seed, seed == 12 ? 39 : 8));
    for (const auto& object : layout.objects) {
      double lowest = 1e9;
      for (const auto& corner : corners(object.box)) {
        lowest = std::min(lowest, corner.z());
        EXPECT_TRUE(layout.bin_interior.contains(corner, 1e-9))
            << object.name << " sticks out of the bin, seed " << seed;
      }
      EXPECT_NEAR(lowest, 0.0, 1e-9) << object.name << " does not rest on the floor";
      EXPECT_NEAR(object.box.rotation.norm(), 1.0, 1e-12);
    }
  }
}

TEST(SynthLayoutTest, ObjectSizesArePlausibleWhenTheBinIsNotCrowded) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const SynthLayout layout = makeSynthLayout(optionsWith(seed, 6));
    for (const auto& object : layout.objects) {
      EXPECT_GE(object.box.size.maxCoeff(), 0.03) << object.name;
      EXPECT_LE(object.box.size.maxCoeff(), 0.25) << object.name;
      if (object.shape == SynthShape::Cylinder) {
        EXPECT_DOUBLE_EQ(object.box.size.x(), object.box.size.y()) << object.name;
      }
    }
  }
}

TEST(SynthLayoutTest, ObjectsDoNotInterpenetrate) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const SynthLayout layout = makeSynthLayout(optionsWith(seed, seed == 8 ? 39 : 10));
    for (size_t a = 0; a < layout.objects.size(); ++a)
      for (size_t b = 0; b < layout.objects.size(); ++b) {
        if (a == b) continue;
        for (const auto& point : samplesInside(layout.objects[a].box))
          ASSERT_FALSE(layout.objects[b].box.contains(point))
              << layout.objects[a].name << " overlaps " << layout.objects[b].name << ", seed "
              << seed;
      }
  }
}

TEST(SynthLayoutTest, SameSeedSameLayoutOtherSeedOtherLayout) {
  const SynthLayout first = makeSynthLayout(optionsWith(42, 6));
  const SynthLayout again = makeSynthLayout(optionsWith(42, 6));
  const SynthLayout other = makeSynthLayout(optionsWith(43, 6));
  ASSERT_EQ(first.objects.size(), again.objects.size());
  bool differs = false;
  for (size_t i = 0; i < first.objects.size(); ++i) {
    EXPECT_EQ(first.objects[i].label, again.objects[i].label);
    EXPECT_EQ(first.objects[i].box.center, again.objects[i].box.center);
    EXPECT_EQ(first.objects[i].box.size, again.objects[i].box.size);
    differs = differs || first.objects[i].label != other.objects[i].label ||
              first.objects[i].box.center != other.objects[i].box.center;
  }
  EXPECT_TRUE(differs);
  for (size_t i = 0; i < first.T_world_camera.size(); ++i)
    EXPECT_TRUE(first.T_world_camera[i].isApprox(again.T_world_camera[i], 0.0));
}

TEST(SynthLayoutTest, ObjectsDoNotDependOnFramesOrImageSize) {
  SynthOptions small = optionsWith(9, 5);
  SynthOptions large = small;
  large.frames = 30;
  large.views = 5;
  large.width = 640;
  large.height = 480;
  const SynthLayout a = makeSynthLayout(small), b = makeSynthLayout(large);
  for (size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].label, b.objects[i].label);
    EXPECT_EQ(a.objects[i].box.center, b.objects[i].box.center);
  }
  EXPECT_EQ(a.proba_labels, b.proba_labels);
}

TEST(SynthLayoutTest, CamerasLookIntoTheBinWithinFusionRange) {
  SynthOptions options = optionsWith(3, 8);
  options.frames = 15;
  const SynthLayout layout = makeSynthLayout(options);
  ASSERT_EQ(layout.T_world_camera.size(), 15u);
  for (size_t f = 0; f < layout.T_world_camera.size(); ++f) {
    const Eigen::Isometry3d& pose = layout.T_world_camera[f];
    EXPECT_TRUE(pose.linear().isUnitary(1e-9));
    EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-9);
    EXPECT_LT(pose.translation().x(), -0.2) << "camera " << f << " is not in front of the opening";
    const Eigen::Isometry3d to_camera = pose.inverse();
    for (const auto& object : layout.objects)
      for (const auto& corner : corners(object.box)) {
        const Eigen::Vector3d p = to_camera * corner;
        EXPECT_GT(p.z(), 0.3) << "frame " << f << " " << object.name;
        EXPECT_LT(p.norm(), 0.95) << "frame " << f << " " << object.name << " beyond 1 m";
      }
    for (const auto& object : layout.objects) {
      const Eigen::Vector2d uv = layout.camera.project(to_camera * object.box.center);
      EXPECT_GT(uv.x(), 0);
      EXPECT_LT(uv.x(), layout.camera.width);
      EXPECT_GT(uv.y(), 0);
      EXPECT_LT(uv.y(), layout.camera.height);
    }
  }
}

TEST(SynthLayoutTest, PathSweepsSmoothlyAndMarksEvenlySpacedViews) {
  SynthOptions options = optionsWith(4, 3);
  options.frames = 15;
  options.views = 4;
  const SynthLayout layout = makeSynthLayout(options);
  const std::vector<size_t> expected_views = {0, 5, 9, 14};
  std::vector<size_t> views;
  for (size_t f = 0; f < layout.view.size(); ++f)
    if (layout.view[f]) views.push_back(f);
  EXPECT_EQ(views, expected_views);
  double total = 0.0;
  for (size_t f = 1; f < layout.T_world_camera.size(); ++f) {
    const double step =
        (layout.T_world_camera[f].translation() - layout.T_world_camera[f - 1].translation())
            .norm();
    EXPECT_GT(step, 0.005);
    EXPECT_LT(step, 0.08);
    total += step;
  }
  // Left to right: the first and last views are far apart.
  EXPECT_GT(
      (layout.T_world_camera.front().translation() - layout.T_world_camera.back().translation())
          .norm(),
      0.4);
  EXPECT_GT(total, 0.4);
}

TEST(SynthLayoutTest, IntrinsicsScaleWithImageSize) {
  const SynthLayout full = makeSynthLayout(SynthOptions{});  // 640 x 480
  EXPECT_EQ(full.camera.width, 640);
  EXPECT_DOUBLE_EQ(full.camera.fx, 615.2);
  EXPECT_DOUBLE_EQ(full.camera.fy, 615.2);
  EXPECT_DOUBLE_EQ(full.camera.cx, 319.5);
  EXPECT_DOUBLE_EQ(full.camera.cy, 239.5);
  EXPECT_DOUBLE_EQ(full.camera.depth_scale, 0.001);
  const SynthLayout quarter = makeSynthLayout(optionsWith(1, 2));
  EXPECT_EQ(quarter.camera.width, 160);
  EXPECT_EQ(quarter.camera.height, 120);
  EXPECT_DOUBLE_EQ(quarter.camera.fx, 153.8);
  EXPECT_DOUBLE_EQ(quarter.camera.cx, 79.5);
  EXPECT_DOUBLE_EQ(quarter.camera.cy, 59.5);
}

TEST(SynthLayoutTest, ProbaChannelsCoverBackgroundObjectsAndLookAlikes) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const SynthLayout layout = makeSynthLayout(optionsWith(seed, 6));
    const auto& channels = layout.proba_labels;
    EXPECT_TRUE(std::is_sorted(channels.begin(), channels.end()));
    EXPECT_EQ(std::adjacent_find(channels.begin(), channels.end()), channels.end());
    ASSERT_FALSE(channels.empty());
    EXPECT_EQ(channels.front(), 0);
    EXPECT_LE(channels.back(), 39);
    for (const auto& object : layout.objects)
      EXPECT_TRUE(std::binary_search(channels.begin(), channels.end(), object.label));
    // Background, objects, and at least the distractors on top.
    EXPECT_GE(channels.size(), layout.objects.size() + 3);
  }
  // The toothbrushes are look-alikes: one in the scene brings the other's channel.
  for (std::uint64_t seed = 1; seed <= 400; ++seed) {
    const SynthLayout layout = makeSynthLayout(optionsWith(seed, 4));
    const bool green = std::any_of(layout.objects.begin(), layout.objects.end(),
                                   [](const SynthObject& o) { return o.label == 25; });
    if (!green) continue;
    EXPECT_TRUE(std::binary_search(layout.proba_labels.begin(), layout.proba_labels.end(), 26));
    return;
  }
  FAIL() << "no seed in 1..400 puts oral_b_toothbrush_green into a 4-object scene";
}

TEST(SynthLayoutTest, RejectsOptionsOutOfRange) {
  auto rejects = [](auto change, const std::string& field) {
    SynthOptions options;
    change(options);
    try {
      checkSynthOptions(options);
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  rejects([](SynthOptions& o) { o.objects = 0; }, "objects");
  rejects([](SynthOptions& o) { o.objects = 40; }, "objects");
  rejects([](SynthOptions& o) { o.views = 2; }, "views");
  rejects([](SynthOptions& o) { o.frames = 2, o.views = 3; }, "frames");
  rejects([](SynthOptions& o) { o.frames = 4, o.views = 5; }, "frames");
  rejects([](SynthOptions& o) { o.width = 8; }, "width");
  rejects([](SynthOptions& o) { o.height = 5000; }, "height");
  EXPECT_NO_THROW(checkSynthOptions(SynthOptions{}));
  EXPECT_THROW((void)makeSynthLayout(optionsWith(1, 40)), std::invalid_argument);
}

}  // namespace
}  // namespace lom
