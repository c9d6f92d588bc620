// Real recordings in ../shared/data imported and fused: the surfaces seen from
// two overlapping views must agree. Skipped with a message when the data is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/import.hpp"
#include "lom/label_map.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom {
namespace {

namespace fs = std::filesystem;

struct Agreement {
  size_t checked = 0;   // occupied voxels of A that view B saw (not occluded, valid depth)
  size_t agreeing = 0;  // ... of which B's map has an occupied voxel within one voxel
  [[nodiscard]] double fraction() const {
    return checked ? static_cast<double>(agreeing) / static_cast<double>(checked) : 0.0;
  }
};

LabelMap fuseOne(const Sequence& sequence, size_t frame, double resolution, double max_range) {
  FusionOptions options;
  options.map.resolution = resolution;
  options.map.max_range = max_range;
  options.first_frame = frame;
  options.last_frame = frame + 1;
  return fuseSequence(sequence, options);
}

// For every occupied voxel of map A: project it into view B; when B measured a
// depth there that does not hide the voxel (B's surface is not in front of it),
// B's own map should have an occupied voxel within one voxel of it.
Agreement agreement(const Sequence& sequence, const LabelMap& map_a, const LabelMap& map_b,
                    size_t frame_b, const Eigen::Isometry3d& pose_b, double max_range) {
  const FrameData data = loadFrame(sequence, frame_b);
  const CameraIntrinsics& camera = sequence.cameraOf(frame_b);
  const double resolution = map_a.parameters().resolution;
  const Eigen::Isometry3d world_to_b = pose_b.inverse();
  Agreement result;
  for (int label = 0; label < map_a.numLabels(); ++label)
    for (const VoxelKey& key : map_a.voxelsOfLabel(label)) {
      const Eigen::Vector3d centre = map_a.centerOf(key);
      const Eigen::Vector3d p = world_to_b * centre;
      if (p.z() <= 0.1 || p.norm() > max_range - 2 * resolution) continue;
      const Eigen::Vector2d uv = camera.project(p);
      const int u = static_cast<int>(std::lround(uv.x()));
      const int v = static_cast<int>(std::lround(uv.y()));
      if (u < 0 || v < 0 || u >= camera.width || v >= camera.height) continue;
      const float z = data.depth.at(u, v);
      if (!(z > 0.0f)) continue;                    // B has no measurement there
      if (z < p.z() - 2 * resolution) continue;     // occluded in B by a nearer surface
      ++result.checked;
      bool found = false;
      for (int dx = -1; dx <= 1 && !found; ++dx)
        for (int dy = -1; dy <= 1 && !found; ++dy)
          for (int dz = -1; dz <= 1 && !found; ++dz) {
            const VoxelState state =
                map_b.voxelAt(centre + resolution * Eigen::Vector3d(dx, dy, dz));
            found = state.known && state.occupied;
          }
      result.agreeing += found;
    }
  return result;
}

struct Case {
  const char* name;
  size_t frame_a, frame_b;
  double resolution, max_range;
};

void checkViews(const Sequence& sequence, const Case& c, double minimum) {
  const LabelMap a = fuseOne(sequence, c.frame_a, c.resolution, c.max_range);
  const LabelMap b = fuseOne(sequence, c.frame_b, c.resolution, c.max_range);
  const auto& pose_b = sequence.frames[c.frame_b].T_world_camera;
  const Agreement ab = agreement(sequence, a, b, c.frame_b, pose_b, c.max_range);
  const Agreement ba =
      agreement(sequence, b, a, c.frame_a, sequence.frames[c.frame_a].T_world_camera, c.max_range);
  // Negative control: with B's pose moved 10 cm along its image's vertical axis
  // (floors, tables and the box's top are horizontal) the measure must drop.
  Eigen::Isometry3d shifted = pose_b;
  shifted.translation() += pose_b.linear() * Eigen::Vector3d(0.0, 0.1, 0.0);
  Sequence moved = sequence;
  moved.frames[c.frame_b].T_world_camera = shifted;
  const LabelMap b_moved = fuseOne(moved, c.frame_b, c.resolution, c.max_range);
  const Agreement wrong = agreement(moved, a, b_moved, c.frame_b, shifted, c.max_range);

  std::cout << "[ agreement ] " << c.name << " frames " << c.frame_a << "/" << c.frame_b << " at "
            << c.resolution * 100 << " cm: A in B " << ab.agreeing << "/" << ab.checked << " = "
            << ab.fraction() << ", B in A " << ba.agreeing << "/" << ba.checked << " = "
            << ba.fraction() << "; B moved 10 cm: " << wrong.fraction() << "\n";
  EXPECT_GT(ab.checked, 1000u) << "the views should overlap";
  EXPECT_GT(ba.checked, 1000u) << "the views should overlap";
  EXPECT_GE(ab.fraction(), minimum);
  EXPECT_GE(ba.fraction(), minimum);
  EXPECT_LT(wrong.fraction(), ab.fraction() - 0.2) << "the measure must notice a wrong pose";
}

TEST(ImportRealData, ApcBoxRealsenseViewsAgree) {
  LOM_REQUIRE_SHARED_DATA("apc-box-realsense");
  test::TempDir dir;
  ImportOptions options;
  options.max_frames = 6;
  const ImportReport report =
      importSource(std::nullopt, test::sharedDataDir() / "apc-box-realsense", dir / "seq", options);
  EXPECT_EQ(report.kind, SourceKind::Frames);
  EXPECT_EQ(report.frames_found, 50u);
  ASSERT_EQ(report.frames_written, 6u);
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_NEAR(sequence.camera.fx, 615.195, 1e-3);
  EXPECT_NEAR(sequence.camera.cy, 247.519, 1e-3);
  EXPECT_TRUE(sequence.frames[0].T_world_camera.isApprox(Eigen::Isometry3d::Identity()));
  checkViews(sequence, {"apc-box-realsense", 0, 3, 0.01, 1.5}, 0.8);
}

// The first `count` frames of apc-box-realsense linked (not copied) into `out`,
// with its intrinsics file, and, when `labels`, a label image per frame: label 1
// over the measured pixels of the image centre, as a hand-drawn mask would be.
void linkApcBoxFrames(const fs::path& out, size_t count, bool labels) {
  const fs::path data = test::sharedDataDir() / "apc-box-realsense";
  fs::create_directories(out);
  fs::create_symlink(data / "intrinsics.K.txt", out / "intrinsics.K.txt");
  std::vector<fs::path> depths;
  for (const auto& entry : fs::directory_iterator(data)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 10 && name.compare(name.size() - 10, 10, ".depth.png") == 0)
      depths.push_back(entry.path());
  }
  std::sort(depths.begin(), depths.end());
  ASSERT_GE(depths.size(), count);
  for (size_t i = 0; i < count; ++i) {
    const std::string name = depths[i].filename().string();
    const std::string base = name.substr(0, name.size() - 10);
    for (const char* part : {".depth.png", ".color.png", ".pose.txt"})
      fs::create_symlink(data / (base + part), out / (base + part));
    if (!labels) continue;
    const DepthImage depth = readDepthImage(depths[i], 0.001);
    LabelImage label;
    label.width = depth.width;
    label.height = depth.height;
    label.ids.assign(depth.metres.size(), 0);
    for (int v = depth.height / 3; v < 2 * depth.height / 3; ++v)
      for (int u = depth.width / 3; u < 2 * depth.width / 3; ++u)
        if (depth.at(u, v) > 0.0f) label.ids[static_cast<size_t>(v * depth.width + u)] = 1;
    writeLabelPng(out / (base + ".label.png"), label);
  }
}

bool anyNote(const ImportReport& report, const std::string& part) {
  return std::any_of(report.notes.begin(), report.notes.end(),
                     [&](const std::string& note) { return note.find(part) != std::string::npos; });
}

TEST(ImportRealData, ApcBoxFramesHaveNoTimeStampsAndNoEmptyProbaFolder) {
  LOM_REQUIRE_SHARED_DATA("apc-box-realsense");
  test::TempDir dir;
  linkApcBoxFrames(dir / "src", 3, false);
  const ImportReport report = importSource(std::nullopt, dir / "src", dir / "seq");
  ASSERT_EQ(report.frames_written, 3u) << report.text();
  EXPECT_TRUE(anyNote(report, "intrinsics read from " +
                                  (dir / "src" / "intrinsics.K.txt").string() + ": fx 615.195"))
      << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  for (const auto& frame : sequence.frames)
    EXPECT_FALSE(frame.stamp.has_value()) << "frame numbers 15, 17, ... are not seconds";
  EXPECT_FALSE(fs::exists(dir / "seq" / "proba")) << "a geometry-only import has no proba";
  EXPECT_TRUE(validateSequence(sequence).empty());
}

TEST(ImportRealData, ApcBoxWithItsOwnLabelImagesIsNotScoredIn2d) {
  LOM_REQUIRE_SHARED_DATA("apc-box-realsense");
  test::TempDir dir;
  linkApcBoxFrames(dir / "src", 3, true);
  const ImportReport report = importSource(std::nullopt, dir / "src", dir / "seq");
  EXPECT_EQ(report.kind, SourceKind::Frames);
  ASSERT_EQ(report.frames_written, 3u) << report.text();
  EXPECT_TRUE(anyNote(report, "label images became one-hot probabilities")) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  for (const auto& frame : sequence.frames) EXPECT_TRUE(frame.proba_from_label);

  // A box around what label 1 covers in the first view (the world is its camera).
  const FrameData first = loadFrame(sequence, 0);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  size_t n = 0;
  for (int v = 0; v < first.depth.height; ++v)
    for (int u = 0; u < first.depth.width; ++u)
      if (first.label->at(u, v) == 1 && first.depth.at(u, v) > 0.0f) {
        sum += sequence.cameraOf(0).backProject(u, v, first.depth.at(u, v));
        ++n;
      }
  ASSERT_GT(n, 1000u);
  Annotations annotations;
  GroundTruthBox box;
  box.label = 1;
  box.box.center = sum / static_cast<double>(n);
  box.box.size = Eigen::Vector3d(0.2, 0.2, 0.2);
  annotations.boxes.push_back(box);

  EvaluationOptions options;
  options.fusion.map.max_range = 1.5;
  const LabelMap map = fuseSequence(sequence, options.fusion);
  const EvaluationReport scored = evaluate(sequence, annotations, map, options);
  EXPECT_FALSE(scored.metrics_2d) << "pixel accuracy " << scored.metrics_2d->pixel_accuracy
                                  << " against the images the probabilities were made from";
  EXPECT_EQ(scored.metrics_2d_excluded_frames, (std::vector<size_t>{0, 1, 2}));
  EXPECT_NE(scored.metrics_2d_not_scored.find("not an independent ground truth"),
            std::string::npos);
  ASSERT_EQ(scored.objects.size(), 1u);
  EXPECT_GT(scored.objects[0].voxels, 0u) << "the 3D scores are unaffected";
}

TEST(ImportRealData, KinectRoomViewsAgree) {
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  test::TempDir dir;
  ImportOptions options;
  options.intrinsics = parseIntrinsics("518,519,325.5,253.5");
  const ImportReport report = importSource(SourceKind::Quaternion,
                                           test::sharedDataDir() / "kinect-room-5", dir / "seq",
                                           options);
  ASSERT_EQ(report.frames_written, 5u);
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_EQ(sequence.camera.fx, 518.0);
  EXPECT_NEAR(sequence.frames[0].T_world_camera.translation().x(), -0.228993, 1e-9);
  checkViews(sequence, {"kinect-room-5", 0, 1, 0.02, 4.0}, 0.8);
}

// A map fits the depths of the recording it was fused from, not another
// recording's (with the same, background-only, label set) nor its own frames
// moved by a wrong pose: the warning of `score --map` and the studio.
TEST(ImportRealData, AMapFitsTheDepthsOfItsOwnRecordingOnly) {
  LOM_REQUIRE_SHARED_DATA("apc-box-realsense");
  LOM_REQUIRE_SHARED_DATA("kinect-room-5");
  test::TempDir dir;
  ImportOptions apc_options;
  apc_options.max_frames = 6;
  (void)importSource(std::nullopt, test::sharedDataDir() / "apc-box-realsense", dir / "apc",
                     apc_options);
  ImportOptions room_options;
  room_options.intrinsics = parseIntrinsics("518,519,325.5,253.5");
  (void)importSource(SourceKind::Quaternion, test::sharedDataDir() / "kinect-room-5", dir / "room",
                     room_options);
  const Sequence apc = loadSequence(dir / "apc");
  const Sequence room = loadSequence(dir / "room");
  FusionOptions at_1cm;
  at_1cm.map.resolution = 0.01;
  at_1cm.map.max_range = 1.5;
  const LabelMap apc_map = fuseSequence(apc, at_1cm);
  FusionOptions at_4cm;
  at_4cm.map.resolution = 0.04;
  at_4cm.map.max_range = 4.0;
  const LabelMap room_map = fuseSequence(room, at_4cm);

  const MapFit own = mapFitOf(apc_map, apc);
  const MapFit room_own = mapFitOf(room_map, room);
  const MapFit crossed = mapFitOf(apc_map, room);
  const MapFit crossed_back = mapFitOf(room_map, apc);
  Sequence moved = apc;
  for (FrameRecord& frame : moved.frames) frame.T_world_camera.translation().x() += 0.3;
  const MapFit wrong_pose = mapFitOf(apc_map, moved);
  std::cout << "[ map fit ] apc " << own.fraction() << " of " << own.depths << ", room "
            << room_own.fraction() << ", apc map on room " << crossed.fraction() << " of "
            << crossed.depths << ", room map on apc " << crossed_back.fraction()
            << ", apc moved 30 cm " << wrong_pose.fraction() << "\n";
  EXPECT_GT(own.depths, 1000u);
  EXPECT_GE(own.fraction(), 0.5);
  EXPECT_GE(room_own.fraction(), 0.5);
  EXPECT_GT(crossed.depths, 100u);  // the room's near depths, within the box map's range
  EXPECT_TRUE(poorMapFitWarning(own, "apc.ot").empty());
  for (const MapFit& poor : {crossed, crossed_back, wrong_pose}) {
    EXPECT_LT(poor.fraction(), kPoorMapFit);
    if (poor.depths > 0) {
      EXPECT_NE(poorMapFitWarning(poor, "apc.ot").find("apc.ot: only "), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace lom
