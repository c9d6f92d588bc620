// sequence.json parsing, writing and validation, and the frame image files.
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>

#include "lom/fusion.hpp"
#include "lom/npy.hpp"
#include "lom/sequence.hpp"
#include "test_input_helpers.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr int kWidth = 8;
constexpr int kHeight = 6;

lom::LabelSet threeLabels() {
  return lom::LabelSet({{0, "__background__", {0, 0, 0}},
                        {1, "red_mug", {200, 10, 10}},
                        {2, "blue_book", {10, 10, 200}}});
}

lom::CameraIntrinsics smallCamera() {
  lom::CameraIntrinsics camera;
  camera.width = kWidth;
  camera.height = kHeight;
  camera.fx = 10.5;
  camera.fy = 11.25;
  camera.cx = 3.5;
  camera.cy = 2.5;
  camera.depth_scale = 0.001;
  return camera;
}

Eigen::Isometry3d poseOf(size_t i) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.3 * static_cast<double>(i) + 0.1, Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.1 * static_cast<double>(i), -0.2, 1.0 / 3.0);
  return pose;
}

// Two frames of 8 x 6 pixels: depth PNG, 2-channel proba for labels {0, 2},
// label PNG and colour PNG, all consistent with smallCamera().
lom::Sequence writeSmallSequence(const fs::path& root, size_t frames = 2) {
  for (const char* folder : {"depth", "proba", "label", "color"})
    fs::create_directories(root / folder);
  lom::Sequence sequence;
  sequence.root = root;
  sequence.labels = threeLabels();
  sequence.camera = smallCamera();
  for (size_t i = 0; i < frames; ++i) {
    const std::string stem = std::to_string(i);
    lom::FrameRecord frame;
    frame.stamp = 0.5 * static_cast<double>(i);
    frame.T_world_camera = poseOf(i);
    frame.depth = "depth/" + stem + ".png";
    frame.proba = "proba/" + stem + ".npy";
    frame.proba_labels = {0, 2};
    frame.label = "label/" + stem + ".png";
    frame.color = "color/" + stem + ".png";

    lom::DepthImage depth{kWidth, kHeight, {}};
    lom::LabelImage label{kWidth, kHeight, {}};
    lom::ColorImage color{kWidth, kHeight, {}};
    std::vector<float> proba;
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u) {
        depth.metres.push_back(0.5f + 0.001f * static_cast<float>(u + v));
        label.ids.push_back(static_cast<std::uint16_t>((u + v) % 3));
        color.rgb.insert(color.rgb.end(), {static_cast<std::uint8_t>(u * 10),
                                           static_cast<std::uint8_t>(v * 10), 200});
        const float p = static_cast<float>(u) / (kWidth - 1);
        proba.insert(proba.end(), {1.0f - p, p});
      }
    lom::writeDepthPng(root / frame.depth, depth, 0.001);
    lom::writeLabelPng(root / frame.label, label);
    lom::writeColorPng(root / frame.color, color);
    lom::writeNpyFloat32(root / frame.proba, {kHeight, kWidth, 2}, proba);
    sequence.frames.push_back(frame);
  }
  lom::saveSequence(sequence, root);
  return sequence;
}

Json readJson(const fs::path& path) {
  std::ifstream in(path);
  return Json::parse(in);
}

void writeJson(const fs::path& path, const Json& json) {
  std::ofstream out(path);
  out << json.dump(2);
}

using lom::test::slurp;

lom::Problem loadError(const fs::path& folder) {
  try {
    (void)lom::loadSequence(folder);
  } catch (const lom::Error& e) {
    return e.problem();
  }
  ADD_FAILURE() << "loadSequence accepted " << folder;
  return {};
}

// Applies `edit` to the sequence.json of a fresh small sequence and returns
// the error loadSequence reports.
class SequenceTest : public ::testing::Test {
 protected:
  lom::test::TempDir dir;
  fs::path json() const { return dir.path() / "sequence.json"; }
  lom::Problem errorAfterEdit(const std::function<void(Json&)>& edit) {
    writeSmallSequence(dir.path());
    Json j = readJson(json());
    edit(j);
    writeJson(json(), j);
    return loadError(dir.path());
  }
};

TEST_F(SequenceTest, RoundTripKeepsEveryFieldAndPosesExactly) {
  lom::Sequence original = writeSmallSequence(dir.path(), 3);
  original.frame_id = "shelf";
  original.frames[1].view = false;
  original.frames[0].proba_from_label = true;
  original.frames[2].stamp.reset();
  original.frames[2].proba_labels.clear();
  original.frames[2].proba.clear();
  lom::CameraIntrinsics other = smallCamera();
  other.fx = 612.3456789012345;
  other.depth_scale = 0.0001;
  original.frames[1].camera = other;
  lom::saveSequence(original, dir.path());

  const lom::Sequence loaded = lom::loadSequence(dir.path());
  EXPECT_EQ(loaded.root, fs::absolute(dir.path()).lexically_normal());
  EXPECT_EQ(loaded.frame_id, "shelf");
  EXPECT_TRUE(loaded.labels == threeLabels());
  EXPECT_EQ(loaded.camera, smallCamera());
  ASSERT_EQ(loaded.frames.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const auto& a = original.frames[i];
    const auto& b = loaded.frames[i];
    EXPECT_EQ(b.stamp, a.stamp);
    EXPECT_LE((b.T_world_camera.matrix() - a.T_world_camera.matrix()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(b.depth, a.depth);
    EXPECT_EQ(b.color, a.color);
    EXPECT_EQ(b.proba, a.proba);
    EXPECT_EQ(b.proba_labels, a.proba_labels);
    EXPECT_EQ(b.proba_from_label, a.proba_from_label);
    EXPECT_EQ(b.label, a.label);
    EXPECT_EQ(b.view, a.view);
    EXPECT_EQ(b.camera.has_value(), a.camera.has_value());
  }
  ASSERT_TRUE(loaded.frames[1].camera);
  EXPECT_EQ(*loaded.frames[1].camera, other);
  EXPECT_EQ(loaded.cameraOf(1).fx, 612.3456789012345);
  EXPECT_EQ(loaded.cameraOf(0), smallCamera());

  // Saving what was loaded reproduces the file byte for byte.
  const std::string first = slurp(json());
  lom::saveSequence(loaded, dir.path());
  EXPECT_EQ(slurp(json()), first);
}

TEST(CameraJumps, NamesEachStepLongerThanTheLimit) {
  lom::Sequence sequence;
  for (const double x : {0.0, 0.05, 300.05, 300.1, 9.0}) {
    lom::FrameRecord frame;
    frame.T_world_camera.translation() = Eigen::Vector3d(x, 0.0, 1.0);
    sequence.frames.push_back(frame);
  }
  const auto jumps = lom::cameraJumps(sequence);
  ASSERT_EQ(jumps.size(), 2u);
  EXPECT_EQ(jumps[0],
            "frames[2].pose: the camera is 300 m from where it was in frames[1] (a wrong "
            "pose?)");
  EXPECT_NE(jumps[1].find("frames[4]"), std::string::npos) << jumps[1];
  EXPECT_NE(jumps[1].find("291.1 m"), std::string::npos) << jumps[1];
  EXPECT_EQ(lom::cameraJumps(sequence, 1000.0).size(), 0u);
  EXPECT_EQ(lom::cameraJumps(sequence, 0.01).size(), 4u);
  // Only the frames fused count (fuse --frames): 0:2 has no jump, 2:4 none
  // either (frames[2] starts it), 3:5 the step from frames[3] to frames[4].
  EXPECT_TRUE(lom::cameraJumps(sequence, 10.0, 0, 2).empty());
  EXPECT_TRUE(lom::cameraJumps(sequence, 10.0, 2, 4).empty());
  const auto last_two = lom::cameraJumps(sequence, 10.0, 3, 5);
  ASSERT_EQ(last_two.size(), 1u);
  EXPECT_NE(last_two[0].find("frames[4]"), std::string::npos) << last_two[0];
}

// A camera outside every map fusion can make is a wrong pose of its own
// (checkCameraExtents names it): its neighbours are not reported as jumps.
TEST(CameraJumps, LeaveOutCamerasOutsideEveryMap) {
  lom::Sequence sequence;
  for (const double x : {1e20, 0.0, 0.05, 1e20, 0.1, 300.1}) {
    lom::FrameRecord frame;
    frame.T_world_camera.translation() = Eigen::Vector3d(x, 0.0, 1.0);
    sequence.frames.push_back(frame);
  }
  const auto jumps = lom::cameraJumps(sequence);
  ASSERT_EQ(jumps.size(), 1u);
  EXPECT_EQ(jumps[0],
            "frames[5].pose: the camera is 300 m from where it was in frames[4] (a wrong "
            "pose?)");
}

TEST(ImplausibleIntrinsics, NameCamerasNoDepthCameraHas) {
  lom::Sequence sequence;
  sequence.frames.resize(5);
  // A depth camera's own: 55 x 42 degrees.
  EXPECT_TRUE(lom::implausibleIntrinsics(sequence).empty());
  // Focal lengths in millimetres: nearly 180 degrees either way.
  sequence.camera.fx = sequence.camera.fy = 1.93;
  auto warnings = lom::implausibleIntrinsics(sequence);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("camera: fx = 1.93, fy = 1.93, cx = 298.4, cy = 247.5 give a field of "
                              "view of 179.",
                              0),
            0u)
      << warnings[0];
  EXPECT_NE(warnings[0].find("at 640 x 480 pixels"), std::string::npos) << warnings[0];
  // Narrow views are not flagged (small images with a real camera's focal lengths).
  sequence.camera.fx = sequence.camera.fy = 1e6;
  EXPECT_TRUE(lom::implausibleIntrinsics(sequence).empty());
  // The camera matrix of quarter-size images: a plausible field of view, but
  // the principal point far from the centre of these.
  sequence.camera = lom::CameraIntrinsics();
  sequence.camera.fx = sequence.camera.fy = 153.8;
  sequence.camera.cx = 74.6;
  sequence.camera.cy = 61.9;
  warnings = lom::implausibleIntrinsics(sequence);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "camera: the principal point cx = 74.6, cy = 61.9 lies at 12 % and 13 % of the 640 x "
            "480 pixels' width and height; a camera's lies near the centre (are these the "
            "intrinsics of 149 x 124 pixel images? scale fx, fy, cx and cy by the ratio of the "
            "sizes)");
  // Half-size images' (a field of view of 92 degrees): off-centre on both axes.
  sequence.camera.fx = sequence.camera.fy = 307.6;
  sequence.camera.cx = 149.2;
  sequence.camera.cy = 123.8;
  EXPECT_EQ(lom::implausibleIntrinsics(sequence).size(), 1u);
  // One axis is enough; a point a little off the centre is a real camera's.
  sequence.camera.cx = 298.4;
  sequence.camera.cy = 61.9;
  EXPECT_EQ(lom::implausibleIntrinsics(sequence).size(), 1u);
  sequence.camera.cy = 247.5;
  EXPECT_TRUE(lom::implausibleIntrinsics(sequence).empty());
  // 150 degrees is the widest taken.
  sequence.camera = lom::CameraIntrinsics();
  sequence.camera.cx = 320.0;
  sequence.camera.fx = 320.0 / std::tan(75.0 / 57.29577951308232) * 1.0001;
  EXPECT_TRUE(lom::implausibleIntrinsics(sequence).empty());
  sequence.camera.fx *= 0.999;
  EXPECT_EQ(lom::implausibleIntrinsics(sequence).size(), 1u);
  // One axis is enough.
  sequence.camera = lom::CameraIntrinsics();
  sequence.camera.fy = 20.0;
  EXPECT_EQ(lom::implausibleIntrinsics(sequence).size(), 1u);

  // Frames with cameras of their own: the first implausible one, and how many more.
  sequence.camera = lom::CameraIntrinsics();
  lom::CameraIntrinsics millimetres;
  millimetres.fx = millimetres.fy = 1.93;
  sequence.frames[2].camera = millimetres;
  sequence.frames[4].camera = millimetres;
  sequence.frames[3].camera = lom::CameraIntrinsics();
  warnings = lom::implausibleIntrinsics(sequence);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("frames[2].camera: fx = 1.93", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find("(and 1 more frames)"), std::string::npos) << warnings[0];
  // A shared camera no frame uses is not checked.
  sequence.camera.fx = 1.0;
  EXPECT_EQ(lom::implausibleIntrinsics(sequence).size(), 2u);
  for (auto& frame : sequence.frames)
    if (!frame.camera) frame.camera = lom::CameraIntrinsics();
  EXPECT_EQ(lom::implausibleIntrinsics(sequence).size(), 1u);

  // Only the frames fused count (fuse --frames 0:2 warned about frame 2's).
  EXPECT_TRUE(lom::implausibleIntrinsics(sequence, 0, 2).empty());
  warnings = lom::implausibleIntrinsics(sequence, 3, 5);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("frames[4].camera: fx = 1.93", 0), 0u) << warnings[0];
  sequence.frames[1].camera.reset();  // frame 1 uses the shared camera, fx = 1
  EXPECT_EQ(lom::implausibleIntrinsics(sequence, 0, 2).size(), 1u);
  EXPECT_TRUE(lom::implausibleIntrinsics(sequence, 3, 4).empty());
}

TEST_F(SequenceTest, AcceptsTheJsonPathAndAppliesDefaults) {
  writeSmallSequence(dir.path());
  Json j = readJson(json());
  j.erase("labels");
  j.erase("frame_id");
  j["camera"].erase("depth_scale");
  j["frames"][0].erase("stamp");
  j["frames"][1].erase("stamp");
  j["frames"][1].erase("view");
  j["frames"][1]["camera"] = {{"fx", 500.0}};
  j["frames"][0].erase("proba_labels");
  writeJson(json(), j);

  const lom::Sequence loaded = lom::loadSequence(json());
  EXPECT_EQ(loaded.labels.size(), 40);
  EXPECT_EQ(loaded.labels.at(19).name, "i_am_a_bunny_book");
  EXPECT_EQ(loaded.frame_id, "world");
  EXPECT_EQ(loaded.camera.depth_scale, 0.001);
  EXPECT_FALSE(loaded.frames[0].stamp.has_value());
  EXPECT_FALSE(loaded.frames[1].stamp.has_value());
  EXPECT_FALSE(loaded.frames[0].proba_from_label);
  EXPECT_TRUE(loaded.frames[1].view);
  EXPECT_TRUE(loaded.frames[0].proba_labels.empty());
  ASSERT_TRUE(loaded.frames[1].camera);
  EXPECT_EQ(loaded.frames[1].camera->fx, 500.0);
  EXPECT_EQ(loaded.frames[1].camera->width, kWidth);
  EXPECT_EQ(loaded.frames[1].camera->cy, smallCamera().cy);
}

// "link/../seq" is the folder beside the link's target, as the kernel (and
// the command that wrote it there) resolves it, not the one beside the link.
TEST_F(SequenceTest, APathWithDotDotAfterALinkIsTheOneTheKernelResolves) {
  fs::create_directories(dir.path() / "a" / "b");
  fs::create_directories(dir.path() / "work" / "seq");  // another folder of the user's
  fs::create_directory_symlink(dir.path() / "a" / "b", dir.path() / "work" / "link");
  writeSmallSequence(dir.path() / "a" / "seq");
  const lom::Sequence loaded = lom::loadSequence(dir.path() / "work" / "link" / ".." / "seq");
  EXPECT_EQ(loaded.root, fs::canonical(dir.path() / "a" / "seq"));
  EXPECT_EQ(loaded.frames.size(), lom::loadSequence(dir.path() / "a" / "seq").frames.size());
  // A sequence.json that is itself a link keeps its folder: the frames are there.
  fs::create_directories(dir.path() / "shared");
  fs::rename(dir.path() / "a" / "seq" / "sequence.json", dir.path() / "shared" / "sequence.json");
  fs::create_symlink(dir.path() / "shared" / "sequence.json",
                     dir.path() / "a" / "seq" / "sequence.json");
  const lom::Sequence linked = lom::loadSequence(dir.path() / "work" / "link" / ".." / "seq");
  EXPECT_EQ(linked.root, fs::canonical(dir.path() / "a" / "seq"));
  EXPECT_TRUE(lom::validateSequence(linked).empty());
}

// A depth scale whose depths single-precision metres cannot hold (a 16-bit
// depth times 1e300 is infinite, times 1e-320 zero) is refused naming the
// field; a frame name with a line break in it too (info prints it on one line).
TEST_F(SequenceTest, RefusesDepthScalesAndFrameNamesItCannotUse) {
  writeSmallSequence(dir.path());
  const Json original = readJson(json());
  for (const double scale : {1e300, 1e-320, 1e7, 1e-13}) {
    SCOPED_TRACE(scale);
    Json j = original;
    j["camera"]["depth_scale"] = scale;
    writeJson(json(), j);
    const lom::Problem problem = lom::test::errorOf([&] { (void)lom::loadSequence(json()); });
    EXPECT_EQ(problem.field, "camera.depth_scale");
    EXPECT_NE(problem.expected.find("from 1e-12 to 1e6"), std::string::npos) << problem.expected;
  }
  for (const double scale : {1e-12, 0.0002, 1e6}) {
    Json j = original;
    j["camera"]["depth_scale"] = scale;
    writeJson(json(), j);
    EXPECT_EQ(lom::loadSequence(json()).camera.depth_scale, scale);
  }
  Json j = original;
  j["frame_id"] = "base\nlink";
  writeJson(json(), j);
  const lom::Problem problem = lom::test::errorOf([&] { (void)lom::loadSequence(json()); });
  EXPECT_EQ(problem.field, "frame_id");
  EXPECT_NE(problem.found.find("a line feed"), std::string::npos) << problem.found;
}

// A sequence without a single depth measurement cannot be fused (fuse
// refuses it): validate says so instead of OK. One frame with depths is enough.
TEST_F(SequenceTest, ValidateRefusesASequenceWithoutAnyDepth) {
  writeSmallSequence(dir.path(), 2);
  const lom::DepthImage empty{kWidth, kHeight, std::vector<float>(kWidth * kHeight, 0.f)};
  lom::writeDepthPng(dir / "depth" / "0.png", empty, 0.001);
  EXPECT_TRUE(lom::validateSequence(lom::loadSequence(dir.path())).empty())
      << "frame 1 still has depths";
  lom::writeDepthPng(dir / "depth" / "1.png", empty, 0.001);
  const std::vector<lom::Problem> problems = lom::validateSequence(lom::loadSequence(dir.path()));
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].field, "frames[].depth");
  EXPECT_NE(problems[0].found.find("none in the 2 frames"), std::string::npos)
      << problems[0].message();
}

TEST_F(SequenceTest, AFrameWithoutAStampHasNoneAndIsSavedWithout) {
  lom::Sequence sequence = writeSmallSequence(dir.path(), 3);
  sequence.frames[0].stamp.reset();
  sequence.frames[2].stamp.reset();
  lom::saveSequence(sequence, dir.path());
  const Json j = readJson(json());
  EXPECT_FALSE(j["frames"][0].contains("stamp"));
  EXPECT_EQ(j["frames"][1]["stamp"], 0.5);
  EXPECT_FALSE(j["frames"][2].contains("stamp"));

  const lom::Sequence loaded = lom::loadSequence(dir.path());
  EXPECT_FALSE(loaded.frames[0].stamp.has_value()) << "not the frame index";
  ASSERT_TRUE(loaded.frames[1].stamp.has_value());
  EXPECT_EQ(*loaded.frames[1].stamp, 0.5);
  EXPECT_FALSE(loaded.frames[2].stamp.has_value());
}

TEST_F(SequenceTest, ProbaFromLabelRoundTripsAndNeedsAProba) {
  lom::Sequence sequence = writeSmallSequence(dir.path(), 2);
  sequence.frames[1].proba_from_label = true;
  lom::saveSequence(sequence, dir.path());
  const Json j = readJson(json());
  EXPECT_FALSE(j["frames"][0].contains("proba_from_label")) << "written only when true";
  EXPECT_EQ(j["frames"][1]["proba_from_label"], true);
  const lom::Sequence loaded = lom::loadSequence(dir.path());
  EXPECT_FALSE(loaded.frames[0].proba_from_label);
  EXPECT_TRUE(loaded.frames[1].proba_from_label);

  auto type = errorAfterEdit([](Json& j) { j["frames"][1]["proba_from_label"] = "yes"; });
  EXPECT_EQ(type.file, json().string());
  EXPECT_EQ(type.field, "frames[1].proba_from_label");
  EXPECT_EQ(type.expected, "true or false");

  auto alone = errorAfterEdit([](Json& j) {
    j["frames"][0].erase("proba");
    j["frames"][0].erase("proba_labels");
    j["frames"][0]["proba_from_label"] = true;
  });
  EXPECT_EQ(alone.field, "frames[0].proba_from_label");
  EXPECT_NE(alone.expected.find("frames[0].proba"), std::string::npos) << alone.message();

  sequence.frames[0].proba.clear();
  sequence.frames[0].proba_labels.clear();
  sequence.frames[0].proba_from_label = true;
  try {
    lom::saveSequence(sequence, dir.path());
    ADD_FAILURE() << "saveSequence wrote proba_from_label without a proba";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "frames[0].proba_from_label");
  }
}

TEST_F(SequenceTest, LabelPlaceholderRoundTripsAndNeedsALabel) {
  lom::Sequence sequence = writeSmallSequence(dir.path(), 2);
  sequence.frames[1].label_placeholder = true;
  lom::saveSequence(sequence, dir.path());
  const Json j = readJson(json());
  EXPECT_FALSE(j["frames"][0].contains("label_placeholder")) << "written only when true";
  EXPECT_EQ(j["frames"][1]["label_placeholder"], true);
  const lom::Sequence loaded = lom::loadSequence(dir.path());
  EXPECT_FALSE(loaded.frames[0].label_placeholder);
  EXPECT_TRUE(loaded.frames[1].label_placeholder);

  auto type = errorAfterEdit([](Json& j) { j["frames"][1]["label_placeholder"] = 1; });
  EXPECT_EQ(type.field, "frames[1].label_placeholder");
  EXPECT_EQ(type.expected, "true or false");
  auto alone = errorAfterEdit([](Json& j) {
    j["frames"][0].erase("label");
    j["frames"][0]["label_placeholder"] = true;
  });
  EXPECT_EQ(alone.field, "frames[0].label_placeholder");
  EXPECT_NE(alone.expected.find("frames[0].label"), std::string::npos) << alone.message();

  sequence.frames[0].label.clear();
  sequence.frames[0].label_placeholder = true;
  EXPECT_THROW(lom::saveSequence(sequence, dir.path()), lom::Error);
}

TEST_F(SequenceTest, SortsLabelsListedOutOfOrder) {
  writeSmallSequence(dir.path());
  Json j = readJson(json());
  std::swap(j["labels"][0], j["labels"][2]);
  j["labels"][1].erase("color");
  writeJson(json(), j);
  const lom::Sequence loaded = lom::loadSequence(dir.path());
  ASSERT_EQ(loaded.labels.size(), 3);
  EXPECT_EQ(loaded.labels.at(0).name, "__background__");
  EXPECT_EQ(loaded.labels.at(2).name, "blue_book");
  EXPECT_EQ(loaded.labels.at(1).color, lom::vocColor(1));
}

TEST_F(SequenceTest, RejectsDuplicateAndMissingLabelIds) {
  auto duplicate = errorAfterEdit([](Json& j) { j["labels"][2]["id"] = 1; });
  EXPECT_EQ(duplicate.file, json().string());
  EXPECT_EQ(duplicate.field, "labels[2].id");
  EXPECT_NE(duplicate.found.find("also labels[1].id"), std::string::npos) << duplicate.message();

  auto gap = errorAfterEdit([](Json& j) { j["labels"][2]["id"] = 5; });
  EXPECT_EQ(gap.field, "labels[2].id");
  EXPECT_NE(gap.expected.find("0 to 2"), std::string::npos) << gap.message();
}

TEST_F(SequenceTest, RejectsBadJsonNamingTheFile) {
  writeSmallSequence(dir.path());
  std::ofstream(json()) << "{\"format\": \"labeloctomap-sequence\",\n \"version\": 1,, }";
  const auto problem = loadError(dir.path());
  EXPECT_EQ(problem.file, json().string());
  EXPECT_EQ(problem.expected, "valid JSON");
  EXPECT_NE(problem.found.find("line 2"), std::string::npos) << problem.message();
}

TEST_F(SequenceTest, RejectsUnknownFormatAndVersion) {
  auto format = errorAfterEdit([](Json& j) { j["format"] = "something-else"; });
  EXPECT_EQ(format.file, json().string());
  EXPECT_EQ(format.field, "format");
  EXPECT_NE(format.found.find("something-else"), std::string::npos);
  EXPECT_NE(format.expected.find("labeloctomap-sequence"), std::string::npos);

  // Another kind of file is named by its format, not by a key a sequence lacks.
  auto boxes = errorAfterEdit([](Json& j) {
    j = Json{{"format", "labeloctomap-annotations"}, {"version", 1}, {"boxes", Json::array()}};
  });
  EXPECT_EQ(boxes.field, "format");
  EXPECT_NE(boxes.found.find("labeloctomap-annotations"), std::string::npos) << boxes.message();

  auto version = errorAfterEdit([](Json& j) { j["version"] = 2; });
  EXPECT_EQ(version.field, "version");
  EXPECT_NE(version.found.find("2"), std::string::npos);
}

TEST_F(SequenceTest, RejectsNonRigidPoseNamingTheFrame) {
  auto scaled = errorAfterEdit([](Json& j) { j["frames"][1]["pose"][0] = 2.0; });
  EXPECT_EQ(scaled.file, json().string());
  EXPECT_EQ(scaled.field, "frames[1].pose");
  EXPECT_EQ(scaled.expected, "a rigid transform (orthonormal rotation, det +1, last row 0 0 0 1)");
  EXPECT_NE(scaled.found.find("det(R)"), std::string::npos) << scaled.message();

  auto mirrored = errorAfterEdit(
      [](Json& j) { j["frames"][0]["pose"] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; });
  EXPECT_EQ(mirrored.field, "frames[0].pose");
  EXPECT_NE(mirrored.found.find("det(R) = -1"), std::string::npos) << mirrored.message();

  auto last_row = errorAfterEdit([](Json& j) { j["frames"][0]["pose"][12] = 0.5; });
  EXPECT_NE(last_row.found.find("last row [0.5 0 0 1]"), std::string::npos) << last_row.message();

  auto short_pose = errorAfterEdit([](Json& j) { j["frames"][0]["pose"].erase(3); });
  EXPECT_EQ(short_pose.field, "frames[0].pose");
  EXPECT_NE(short_pose.found.find("15 elements"), std::string::npos);
}

// A pose that fails by a little names the failing condition, its tolerance
// and the deviation with the digits that show it: rounded to 6 digits, the
// last row 0 0 0 1.000003 read "last row [0 0 0 1]", the values expected.
TEST_F(SequenceTest, ANonRigidPoseNamesWhatFailsByHowMuchAndTheTolerance) {
  auto last_row = errorAfterEdit([](Json& j) { j["frames"][1]["pose"][15] = 1.000003; });
  EXPECT_EQ(last_row.field, "frames[1].pose");
  EXPECT_EQ(last_row.found, "last row [0 0 0 1.000003] differs from [0 0 0 1] by 3e-06 > 1e-06")
      << last_row.message();

  auto scaled = errorAfterEdit([](Json& j) {
    j["frames"][0]["pose"] = {1.000102, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  });
  EXPECT_EQ(scaled.found,
            "det(R) = 1.000102: |det(R) - 1| = 0.000102 > 0.0001; "
            "max |R^T R - I| = 0.000204 > 0.0001")
      << scaled.message();

  // Just past the tolerance: the deviation gets the digits that tell it from the tolerance.
  auto barely = errorAfterEdit([](Json& j) {
    j["frames"][0]["pose"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1.0000011e-6, 1};
  });
  EXPECT_EQ(barely.found,
            "last row [0 0 1.0000011e-06 1] differs from [0 0 0 1] by 1.000001e-06 > 1e-06")
      << barely.message();
}

TEST_F(SequenceTest, ReorthonormalisesSlightlyNoisyRotations) {
  writeSmallSequence(dir.path());
  Json j = readJson(json());
  j["frames"][0]["pose"] = {1.00002, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  writeJson(json(), j);
  // A copy: the sequence is gone after this line.
  const Eigen::Matrix3d rotation = lom::loadSequence(dir.path()).frames[0].T_world_camera.linear();
  EXPECT_LE((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(),
            1e-12);
  EXPECT_NEAR(rotation.determinant(), 1.0, 1e-12);
}

TEST_F(SequenceTest, RejectsUnknownLabelIdInProbaLabels) {
  auto problem = errorAfterEdit([](Json& j) { j["frames"][1]["proba_labels"] = {0, 2, 7}; });
  EXPECT_EQ(problem.file, json().string());
  EXPECT_EQ(problem.field, "frames[1].proba_labels[2]");
  EXPECT_NE(problem.found.find("7"), std::string::npos);
  EXPECT_NE(problem.expected.find("0 to 2"), std::string::npos) << problem.message();
}

TEST_F(SequenceTest, RejectsMissingDepthAndWrongFieldTypes) {
  auto depth = errorAfterEdit([](Json& j) { j["frames"][0].erase("depth"); });
  EXPECT_EQ(depth.file, json().string());
  EXPECT_EQ(depth.field, "frames[0].depth");
  EXPECT_NE(depth.found.find("missing"), std::string::npos);

  auto fx = errorAfterEdit([](Json& j) { j["camera"]["fx"] = "615"; });
  EXPECT_EQ(fx.field, "camera.fx");
  EXPECT_EQ(fx.expected, "a number");
  EXPECT_NE(fx.found.find("string"), std::string::npos);

  auto width = errorAfterEdit([](Json& j) { j["frames"][1]["camera"] = {{"width", 6.5}}; });
  EXPECT_EQ(width.field, "frames[1].camera.width");

  auto view = errorAfterEdit([](Json& j) { j["frames"][0]["view"] = "yes"; });
  EXPECT_EQ(view.field, "frames[0].view");

  auto typo = errorAfterEdit([](Json& j) { j["frames"][0]["veiw"] = false; });
  EXPECT_EQ(typo.field, "frames[0].veiw");
  EXPECT_NE(typo.expected.find("view"), std::string::npos);
}

TEST_F(SequenceTest, ReportsAMissingSequenceJson) {
  const auto problem = loadError(dir.path());
  EXPECT_EQ(problem.file, (fs::absolute(dir.path()) / "sequence.json").lexically_normal().string());
  EXPECT_EQ(problem.found, "no such file");
}

class SequenceValidationTest : public SequenceTest {
 protected:
  lom::Sequence sequence;
  void SetUp() override { sequence = lom::loadSequence(writeSmallSequence(dir.path()).root); }
  std::vector<lom::Problem> problems() const { return lom::validateSequence(sequence); }
  static const lom::Problem* findField(const std::vector<lom::Problem>& list,
                                       const std::string& field) {
    for (const auto& p : list)
      if (p.field.rfind(field, 0) == 0) return &p;
    return nullptr;
  }
};

TEST_F(SequenceValidationTest, AcceptsAConsistentSequence) {
  const auto list = problems();
  EXPECT_TRUE(list.empty()) << list.front().message();
}

TEST_F(SequenceValidationTest, ReportsAMissingFile) {
  fs::remove(dir / "depth/1.png");
  const auto list = problems();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].file, (sequence.root / "depth/1.png").string());
  EXPECT_EQ(list[0].field, "frames[1].depth");
  EXPECT_EQ(list[0].found, "no such file");
}

TEST_F(SequenceValidationTest, ReportsAWrongImageSize) {
  lom::LabelImage small{4, 3, std::vector<std::uint16_t>(12, 1)};
  lom::writeLabelPng(dir / "label/0.png", small);
  const auto list = problems();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].file, (sequence.root / "label/0.png").string());
  EXPECT_EQ(list[0].field, "frames[0].label (image size)");
  EXPECT_NE(list[0].expected.find("8 x 6"), std::string::npos);
  EXPECT_EQ(list[0].found, "4 x 3");
}

TEST_F(SequenceValidationTest, ReportsAWrongBitDepth) {
  // An 8-bit PNG where a 16-bit depth PNG belongs, and a 16-bit one as colour.
  lom::writeLabelPng(dir / "depth/0.png", {kWidth, kHeight, std::vector<std::uint16_t>(48, 3)});
  lom::writeDepthPng(dir / "color/1.png", {kWidth, kHeight, std::vector<float>(48, 1.0f)}, 0.001);
  const auto list = problems();
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].file, (sequence.root / "depth/0.png").string());
  EXPECT_EQ(list[0].field, "frames[0].depth (bit depth)");
  EXPECT_NE(list[0].expected.find("16-bit"), std::string::npos);
  EXPECT_NE(list[0].found.find("8-bit"), std::string::npos);
  EXPECT_EQ(list[1].file, (sequence.root / "color/1.png").string());
  EXPECT_EQ(list[1].field, "frames[1].color (bit depth)");
  EXPECT_NE(list[1].found.find("16-bit"), std::string::npos);
}

TEST_F(SequenceValidationTest, ReportsAWrongChannelCount) {
  lom::writeNpyFloat32(dir / "proba/1.npy", {kHeight, kWidth, 3}, std::vector<float>(144, 0.25f));
  const auto list = problems();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].file, (sequence.root / "proba/1.npy").string());
  EXPECT_EQ(list[0].field, "frames[1].proba (channels)");
  EXPECT_NE(list[0].expected.find("2 channels"), std::string::npos);
  EXPECT_NE(list[0].found.find("3 channels"), std::string::npos);
}

TEST_F(SequenceValidationTest, ReportsAnUnsupportedProbaDtype) {
  std::string bytes = slurp(dir / "proba/0.npy");
  bytes.replace(bytes.find("'<f4'"), 5, "'<i8'");
  std::ofstream(dir / "proba/0.npy", std::ios::binary) << bytes;
  const auto list = problems();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].field, "frames[0].proba (dtype)");
  EXPECT_NE(list[0].found.find("int64"), std::string::npos) << list[0].message();
}

TEST_F(SequenceValidationTest, ReportsUnknownLabelIdsInALabelPng) {
  std::vector<std::uint16_t> ids(48, 1);
  ids[2 * kWidth + 5] = 9;
  lom::writeLabelPng(dir / "label/1.png", {kWidth, kHeight, ids});
  const auto list = problems();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].file, (sequence.root / "label/1.png").string());
  EXPECT_EQ(list[0].field, "frames[1].label (label ids)");
  EXPECT_NE(list[0].found.find("id 9 at pixel (u=5, v=2)"), std::string::npos) << list[0].message();
}

TEST_F(SequenceValidationTest, ReportsAFrameWithoutLabelsAndEveryOtherProblemAtOnce) {
  sequence.frames[0].proba.clear();
  sequence.frames[0].proba_labels.clear();
  sequence.frames[0].label.clear();
  fs::remove(dir / "color/1.png");
  fs::remove(dir / "proba/1.npy");
  const auto list = problems();
  ASSERT_EQ(list.size(), 3u);
  const auto* neither = findField(list, "frames[0]");
  ASSERT_NE(neither, nullptr);
  EXPECT_EQ(neither->file, (sequence.root / "sequence.json").string());
  EXPECT_EQ(neither->found, "neither");
  EXPECT_NE(findField(list, "frames[1].color"), nullptr);
  EXPECT_NE(findField(list, "frames[1].proba"), nullptr);
}

// "No valid depth" is the one problem fixing the others leaves: it is
// reported beside them, and depths count whatever the frame's other images.
TEST_F(SequenceValidationTest, ReportsNoDepthAnywhereBesideOtherProblems) {
  const lom::DepthImage empty{kWidth, kHeight, std::vector<float>(kWidth * kHeight, 0.f)};
  lom::writeDepthPng(dir / "depth/1.png", empty, 0.001);
  fs::remove(dir / "label/0.png");
  auto list = problems();
  EXPECT_EQ(findField(list, "frames[].depth"), nullptr)
      << "frame 0 has depths, whatever its label image";
  ASSERT_NE(findField(list, "frames[0].label"), nullptr);

  lom::writeDepthPng(dir / "depth/0.png", empty, 0.001);
  list = problems();
  ASSERT_EQ(list.size(), 2u);
  EXPECT_NE(findField(list, "frames[0].label"), nullptr);
  const lom::Problem* none = findField(list, "frames[].depth");
  ASSERT_NE(none, nullptr);
  EXPECT_EQ(none->file, (sequence.root / "sequence.json").string());
  EXPECT_EQ(none->found,
            "none in the 2 frames: every depth pixel is 0 (no measurement) or invalid");

  // A depth image that cannot be read holds no depth either.
  fs::remove(dir / "depth/0.png");
  list = problems();
  none = findField(list, "frames[].depth");
  ASSERT_NE(none, nullptr);
  EXPECT_EQ(none->found,
            "none in the 2 frames: 1 of the 2 depth images could not be read (see the "
            "frames[i].depth problems), and every pixel of the other is 0 (no measurement) or "
            "invalid");
  EXPECT_NE(findField(list, "frames[0].depth"), nullptr);
}

// A wrong depth_scale gives valid numbers that decode: only the depths'
// median shows it (0.05 m: the map would come out 10 times too small).
TEST_F(SequenceValidationTest, WarnsAboutDepthsNoDepthCameraMeasures) {
  lom::SequenceCheck check = lom::checkSequence(sequence);
  EXPECT_TRUE(check.warnings.empty()) << check.warnings.front();
  ASSERT_EQ(check.frame_depths.size(), 2u);
  ASSERT_TRUE(check.frame_depths[1].has_value());
  EXPECT_EQ(check.frame_depths[1]->pixels, 48u);
  EXPECT_EQ(check.frame_depths[1]->valid, 48u);
  EXPECT_DOUBLE_EQ(check.frame_depths[1]->validFraction(), 1.0);
  // 0.5 + 0.001 (u + v): the lower middle of the 48 is u + v = 6.
  EXPECT_NEAR(check.frame_depths[1]->median, 0.506, 1e-6);
  EXPECT_EQ(check.depths.valid, 96u);
  EXPECT_NEAR(check.depths.min, 0.5, 1e-6);
  EXPECT_NEAR(check.depths.max, 0.512, 1e-6);
  EXPECT_NEAR(check.depths.median, 0.506, 0.506 * 1e-3);

  const std::string prefix = (sequence.root / "sequence.json").string() + ": camera.depth_scale: ";
  sequence.camera.depth_scale = 0.0001;
  check = lom::checkSequence(sequence);
  EXPECT_TRUE(check.problems.empty()) << check.problems.front().message();
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_EQ(check.warnings[0],
            prefix +
                "the median valid depth of the 2 frames is 0.0506 m (0.05 .. 0.0512 m), nearer "
                "than depth cameras measure (a median of 0.1 to 20 m expected): depth_scale "
                "0.0001 metres per unit is likely wrong; 0.001 would give a median of 0.506 m "
                "(fused as it is, the map comes out 10 times too small)");

  sequence.camera.depth_scale = 1.0;
  check = lom::checkSequence(sequence);
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_EQ(check.warnings[0].rfind(prefix, 0), 0u) << check.warnings[0];
  EXPECT_NE(check.warnings[0].find("is 506 m (500 .. 512 m), farther than depth cameras measure"),
            std::string::npos)
      << check.warnings[0];
  EXPECT_NE(check.warnings[0].find("depth_scale 1 metres per unit is likely wrong; 0.001 would "
                                   "give a median of 0.506 m (fused as it is, the map comes out "
                                   "1000 times too large)"),
            std::string::npos)
      << check.warnings[0];
}

// .npy depths are metres: millimetres written as they are name the .npy files.
TEST_F(SequenceValidationTest, WarnsAboutNpyDepthsNotInMetres) {
  for (size_t i = 0; i < 2; ++i) {
    sequence.frames[i].depth = "depth/" + std::to_string(i) + ".npy";
    lom::writeNpyFloat32(dir / sequence.frames[i].depth, {kHeight, kWidth},
                         std::vector<float>(kWidth * kHeight, 800.0f));
  }
  const lom::SequenceCheck check = lom::checkSequence(sequence);
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_EQ(check.warnings[0],
            (sequence.root / "sequence.json").string() +
                ": frames[].depth (.npy, in metres): the median valid depth of the 2 frames is "
                "800 m (800 .. 800 m), farther than depth cameras measure (a median of 0.1 to 20 "
                "m expected): .npy depths are metres (depth_scale does not apply); scaled by "
                "0.001 they would have a median of 0.8 m (fused as they are, the map comes out "
                "1000 times too large)");
}

// Valid files listed so that a fusion counts one image twice, or puts it in
// two places, or frames out of recording order: warnings naming the frames.
TEST_F(SequenceValidationTest, WarnsAboutRepeatedFramesSharedDepthFilesAndStampsGoingBack) {
  const std::string json_file = (sequence.root / "sequence.json").string();
  lom::Sequence repeated = sequence;
  repeated.frames.push_back(sequence.frames[0]);
  repeated.frames.back().depth = "./depth/../depth/0.png";  // the same file, spelt otherwise
  repeated.frames.back().stamp = 2.0;
  lom::SequenceCheck check = lom::checkSequence(repeated);
  EXPECT_TRUE(check.problems.empty()) << check.problems.front().message();
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_EQ(check.warnings[0],
            json_file +
                ": frames: frames[2] repeats frames[0] (the same depth file and the same pose): "
                "fused, its evidence counts twice (a frame listed again by mistake?)");

  lom::Sequence shared = sequence;
  shared.frames[1].depth = sequence.frames[0].depth;
  check = lom::checkSequence(shared);
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_EQ(check.warnings[0].rfind(json_file +
                                        ": frames[].depth: a depth file is named by "
                                        "frames with different poses: " +
                                        (sequence.root / "depth/0.png").string() +
                                        " (frames[0].depth and frames[1].depth, 2 poses)",
                                    0),
            0u)
      << check.warnings[0];

  lom::Sequence back = sequence;
  back.frames[1].stamp = -0.25;
  check = lom::checkSequence(back);
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_EQ(check.warnings[0],
            json_file +
                ": frames[].stamp: the stamps go back once, frames[1].stamp -0.25 after "
                "frames[0].stamp 0, but frames are listed in recording order (frames out of "
                "order?)");
  // Frames without a stamp are passed over; equal stamps do not go back.
  back.frames.push_back(sequence.frames[1]);
  back.frames.back().stamp.reset();
  back.frames.back().depth = "depth/1.png";
  back.frames.back().T_world_camera.translation().x() += 0.5;
  EXPECT_EQ(lom::checkSequence(back).warnings.size(), 2u) << "depth/1.png now has two poses";
}

TEST_F(SequenceValidationTest, LoadFrameReturnsTheImagesAndThrowsOnProblems) {
  const lom::FrameData frame = lom::loadFrame(sequence, 1);
  EXPECT_EQ(frame.depth.width, kWidth);
  EXPECT_FLOAT_EQ(frame.depth.at(3, 2), 0.505f);
  ASSERT_TRUE(frame.proba && frame.label && frame.color);
  EXPECT_EQ(frame.proba->channel_labels, (std::vector<int>{0, 2}));
  EXPECT_FLOAT_EQ(frame.proba->pixel(kWidth - 1, 4)[1], 1.0f);
  EXPECT_EQ(frame.label->at(4, 1), 2);
  EXPECT_EQ(frame.color->rgb[3 * (2 * kWidth + 3) + 0], 30);
  EXPECT_EQ(frame.color->rgb[3 * (2 * kWidth + 3) + 1], 20);
  EXPECT_EQ(frame.color->rgb[3 * (2 * kWidth + 3) + 2], 200);

  fs::remove(dir / "proba/1.npy");
  try {
    (void)lom::loadFrame(sequence, 1);
    ADD_FAILURE() << "loadFrame accepted a missing proba file";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "frames[1].proba");
    EXPECT_EQ(e.problem().file, (sequence.root / "proba/1.npy").string());
  }
  EXPECT_THROW((void)lom::loadFrame(sequence, 2), lom::Error);
}

// Fusion reads a frame's depth and the images it fuses, nothing else: a
// broken colour or label image does not stop it (validate reports them),
// and an 8-bit proba image comes as its codes only.
TEST_F(SequenceValidationTest, FusionReadsOnlyTheImagesItFuses) {
  std::ofstream(dir / "color/1.png", std::ios::binary) << "not a PNG";
  std::ofstream(dir / "label/1.png", std::ios::binary) << "not a PNG";
  EXPECT_THROW((void)lom::loadFrame(sequence, 1), lom::Error);
  const lom::FrameParts parts = lom::fusionPartsOf(sequence, 1, nullptr);
  EXPECT_TRUE(parts.proba);
  EXPECT_FALSE(parts.proba_floats);
  EXPECT_FALSE(parts.color);
  EXPECT_FALSE(parts.label);
  const lom::FrameData frame = lom::loadFusionFrame(sequence, 1, nullptr);
  EXPECT_FALSE(frame.color);
  EXPECT_FALSE(frame.label);
  ASSERT_TRUE(frame.proba);
  // A float image has no codes: its values are read as they are.
  EXPECT_TRUE(frame.proba->codes.empty());
  EXPECT_FLOAT_EQ(frame.proba->pixel(kWidth - 1, 4)[1], 1.0f);

  // An 8-bit image: codes only for fusion, codes and floats for everyone else.
  lom::NpyArray coded;
  coded.type = lom::NpyType::UInt8;
  coded.shape = {kHeight, kWidth, 2};
  for (size_t i = 0; i < 2 * kWidth * kHeight; ++i)
    coded.bytes.push_back(static_cast<std::uint8_t>(i * 5));
  lom::writeNpy(dir / "proba/0.npy", coded);
  const lom::FrameData codes_only = lom::loadFusionFrame(sequence, 0, nullptr);
  ASSERT_TRUE(codes_only.proba);
  EXPECT_TRUE(codes_only.proba->values.empty());
  EXPECT_FALSE(codes_only.proba->hasValues());
  EXPECT_EQ(codes_only.proba->codes, coded.bytes);
  const lom::FrameData full = lom::loadFrame(sequence, 0);
  ASSERT_EQ(full.proba->values.size(), coded.bytes.size());
  for (size_t i = 0; i < coded.bytes.size(); ++i) {
    EXPECT_EQ(codes_only.proba->probability(i), full.proba->values[i]) << i;
    EXPECT_EQ(full.proba->probability(i), full.proba->values[i]) << i;
  }

  // Without a proba, fusion reads the label image; a missing depth still fails.
  sequence.frames[1].proba.clear();
  sequence.frames[1].proba_labels.clear();
  EXPECT_THROW((void)lom::loadFusionFrame(sequence, 1, nullptr), lom::Error);  // the broken label
  lom::writeLabelPng(dir / "label/1.png", {kWidth, kHeight, std::vector<std::uint16_t>(48, 2)});
  const lom::FrameData labelled = lom::loadFusionFrame(sequence, 1, nullptr);
  ASSERT_TRUE(labelled.label);
  EXPECT_FALSE(labelled.proba);
  EXPECT_EQ(labelled.label->at(3, 3), 2);
  fs::remove(dir / "depth/1.png");
  try {
    (void)lom::loadFusionFrame(sequence, 1, nullptr);
    ADD_FAILURE() << "fusion read a frame without its depth image";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "frames[1].depth");
  }
}

// A minimal PNG encoder (stored, uncompressed deflate blocks) so that the
// image readers are checked against files not written by OpenCV.
std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t crc = 0xffffffffu;
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

std::string bigEndian32(std::uint32_t value) {
  return {static_cast<char>(value >> 24), static_cast<char>(value >> 16),
          static_cast<char>(value >> 8), static_cast<char>(value)};
}

std::string pngChunk(const std::string& type, const std::string& data) {
  return bigEndian32(static_cast<std::uint32_t>(data.size())) + type + data +
         bigEndian32(crc32(type + data));
}

// `rows` holds the raw samples of each row (big-endian for 16-bit).
void writeRawPng(const fs::path& path, int width, int height, int bit_depth, int color_type,
                 const std::vector<std::string>& rows) {
  std::string scanlines;
  for (const auto& row : rows) scanlines += '\0' + row;  // filter type 0 per row
  std::string zlib = "\x78\x01";
  for (size_t start = 0; start < scanlines.size() || start == 0; start += 65535) {
    const std::string block = scanlines.substr(start, 65535);
    const bool last = start + 65535 >= scanlines.size();
    const auto length = static_cast<std::uint16_t>(block.size());
    zlib += static_cast<char>(last ? 1 : 0);
    zlib += {static_cast<char>(length & 0xff), static_cast<char>(length >> 8),
             static_cast<char>(~length & 0xff), static_cast<char>((~length >> 8) & 0xff)};
    zlib += block;
  }
  std::uint32_t a = 1, b = 0;
  for (unsigned char byte : scanlines) {
    a = (a + byte) % 65521;
    b = (b + a) % 65521;
  }
  zlib += bigEndian32((b << 16) | a);
  const std::string header =
      bigEndian32(static_cast<std::uint32_t>(width)) +
      bigEndian32(static_cast<std::uint32_t>(height)) +
      std::string{static_cast<char>(bit_depth), static_cast<char>(color_type), 0, 0, 0};
  std::ofstream out(path, std::ios::binary);
  out << "\x89PNG\r\n\x1a\n"
      << pngChunk("IHDR", header) << pngChunk("IDAT", zlib) << pngChunk("IEND", "");
}

TEST(SequenceImagesTest, ReadsIndependentlyEncodedPngs) {
  lom::test::TempDir dir;
  // Two RGB pixels, red-ish then blue-ish: the reader must not swap to BGR.
  writeRawPng(dir / "color.png", 2, 1, 8, 2, {std::string("\xff\x0a\x00\x01\x02\xfe", 6)});
  const auto color = lom::readColorImage(dir / "color.png");
  EXPECT_EQ(color.rgb, (std::vector<std::uint8_t>{255, 10, 0, 1, 2, 254}));

  // 16-bit grey, big-endian samples 1234 and 65535 in millimetres.
  writeRawPng(dir / "depth.png", 2, 1, 16, 0, {std::string("\x04\xd2\xff\xff", 4)});
  const auto depth = lom::readDepthImage(dir / "depth.png", 0.001);
  ASSERT_EQ(depth.metres.size(), 2u);
  EXPECT_EQ(depth.metres[0], static_cast<float>(1234 * 0.001));
  EXPECT_EQ(depth.metres[1], static_cast<float>(65535 * 0.001));

  writeRawPng(dir / "label.png", 3, 1, 16, 0, {std::string("\x00\x00\x01\x2c\x00\x13", 6)});
  EXPECT_EQ(lom::readLabelImage(dir / "label.png").ids, (std::vector<std::uint16_t>{0, 300, 19}));
}

TEST(SequenceImagesTest, DepthPngRoundTripIsExactInDepthScaleUnits) {
  lom::test::TempDir dir;
  for (double scale : {0.001, 0.0001, 0.005}) {
    lom::DepthImage depth{7, 5, {}};
    std::vector<int> units;
    for (int i = 0; i < 35; ++i) {
      units.push_back(i == 3 ? 0 : 1 + i * 1871);
      depth.metres.push_back(static_cast<float>(units.back() * scale));
    }
    depth.metres[4] = std::nanf("");  // no measurement
    units[4] = 0;
    lom::writeDepthPng(dir / "depth.png", depth, scale);
    const auto read = lom::readDepthImage(dir / "depth.png", scale);
    ASSERT_EQ(read.width, 7);
    ASSERT_EQ(read.height, 5);
    for (int i = 0; i < 35; ++i)
      EXPECT_EQ(read.metres[static_cast<size_t>(i)],
                static_cast<float>(units[static_cast<size_t>(i)] * scale))
          << "pixel " << i << " scale " << scale;
  }
}

TEST(SequenceImagesTest, DepthPngWriterRejectsDepthsBeyondSixteenBits) {
  lom::test::TempDir dir;
  lom::DepthImage depth{1, 1, {70.0f}};
  EXPECT_THROW(lom::writeDepthPng(dir / "depth.png", depth, 0.001), lom::Error);
  EXPECT_FALSE(fs::exists(dir / "depth.png"));
}

TEST(SequenceImagesTest, DepthNpyInMetresTurnsInvalidValuesIntoZero) {
  lom::test::TempDir dir;
  lom::writeNpyFloat32(dir / "depth.npy", {2, 2},
                       {1.25f, std::nanf(""), -3.0f, std::numeric_limits<float>::infinity()});
  const auto depth = lom::readDepthImage(dir / "depth.npy", 0.001);
  EXPECT_EQ(depth.width, 2);
  EXPECT_EQ(depth.metres, (std::vector<float>{1.25f, 0.0f, 0.0f, 0.0f}));
}

// readNpy reads uint8 and uint16 too, but a depth refuses them: the message
// lists only the dtypes a depth takes.
TEST(SequenceImagesTest, ADepthNpyOfAnotherDtypeListsOnlyTheDepthDtypes) {
  lom::test::TempDir dir;
  lom::writeNpyFloat32(dir / "depth.npy", {2, 2}, {1.f, 1.f, 1.f, 1.f});
  std::string bytes = slurp(dir / "depth.npy");
  bytes.replace(bytes.find("'<f4'"), 5, "'<i4'");
  std::ofstream(dir / "depth.npy", std::ios::binary) << bytes;
  try {
    (void)lom::readDepthImage(dir / "depth.npy", 0.001);
    ADD_FAILURE() << "an int32 depth was read";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().file, (dir / "depth.npy").string());
    EXPECT_EQ(e.problem().field, "dtype");
    EXPECT_EQ(e.problem().expected,
              "float32 depths in metres ('<f4'/'>f4'; float16 and float64 also accepted)");
    EXPECT_EQ(e.problem().found, "'<i4' (int32)");
  }
}

TEST(SequenceImagesTest, ReadsRecordedRealSenseDepth) {
  LOM_REQUIRE_SHARED_DATA("apc-box-realsense");
  const auto depth = lom::readDepthImage(
      lom::test::sharedDataDir() / "apc-box-realsense/frame-000015.depth.png", 0.001);
  EXPECT_EQ(depth.width, 640);
  EXPECT_EQ(depth.height, 480);
  size_t valid = 0, plausible = 0;
  for (float z : depth.metres) {
    if (z <= 0.0f) continue;
    ++valid;
    if (z >= 0.1f && z <= 5.0f) ++plausible;
  }
  EXPECT_GT(valid, depth.metres.size() / 10);
  // A few flying pixels at object edges are tolerated.
  EXPECT_GE(static_cast<double>(plausible), 0.99 * static_cast<double>(valid));
}

}  // namespace
