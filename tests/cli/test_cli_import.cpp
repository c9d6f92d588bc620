// labeloctomap import: conversions, detection, usage errors and data errors.
#include <gtest/gtest.h>

#include <fstream>
#include <iomanip>

#include "lom/images.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

#ifdef LOM_WITH_ROSBAG
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>
#endif

namespace lom {
namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

DepthImage plane(int width, int height, float z) {
  DepthImage depth;
  depth.width = width;
  depth.height = height;
  depth.metres.assign(static_cast<size_t>(width) * height, z);
  return depth;
}

// Two posed frames and one without a pose, in the frames layout.
void writeFrames(const fs::path& dir) {
  writeText(dir / "camera-intrinsics.txt", "20 0 7.5\n0 20 5.5\n0 0 1\n");
  for (int n = 0; n < 3; ++n) {
    char base[32];
    std::snprintf(base, sizeof base, "frame-%06d", n);
    writeDepthPng(dir / (std::string(base) + ".depth.png"), plane(16, 12, 1.0f + 0.1f * n), 0.001);
    if (n < 2)
      writeText(dir / (std::string(base) + ".pose.txt"),
                "1 0 0 " + std::to_string(0.1 * n) + "\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  }
}

void writeQuaternion(const fs::path& dir) {
  fs::create_directories(dir / "depth");
  for (int n = 1; n <= 2; ++n) writeDepthPng(dir / "depth" / (std::to_string(n) + ".png"), plane(16, 12, 2.0f), 0.001);
  writeText(dir / "pose.txt", "0 0 0 0 0 0 1\n0.2 0 0 0 0 0 1\n");
}

TEST(CliImport, FramesFolderToAValidSequence) {
  test::TempDir dir;
  writeFrames(dir / "frames");
  const auto result = test::runCli("import frames " + quoted(dir / "frames") + " --out " + quoted(dir / "seq"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("imported 2 of 3 frames (frames)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("frame-000002: no pose file"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("depth filter:"), std::string::npos) << result.out;
  const auto validate = test::runCli("validate " + quoted(dir / "seq"));
  EXPECT_EQ(validate.exit_code, 0) << validate.out << validate.err;
  EXPECT_EQ(loadSequence(dir / "seq").frames.size(), 2u);

  // Again into the same folder: refused, then replaced with --overwrite.
  const auto again = test::runCli("import auto " + quoted(dir / "frames") + " --out " + quoted(dir / "seq"));
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("already holds sequence.json"), std::string::npos) << again.err;
  const auto overwrite = test::runCli("import auto " + quoted(dir / "frames") + " --out " +
                                      quoted(dir / "seq") + " --overwrite --every 2");
  EXPECT_EQ(overwrite.exit_code, 0) << overwrite.err;
  EXPECT_EQ(loadSequence(dir / "seq").frames.size(), 1u);
  EXPECT_EQ(overwrite.err.find("warning"), std::string::npos) << overwrite.err;

  // A depth scale no depth camera measures: the import says so, as info does.
  const auto metres = test::runCli("import auto " + quoted(dir / "frames") + " --out " +
                                   quoted(dir / "seq") + " --overwrite --depth-scale 1");
  EXPECT_EQ(metres.exit_code, 0) << metres.err;
  EXPECT_NE(metres.err.find("warning: "), std::string::npos) << metres.err;
  EXPECT_NE(metres.err.find("depth_scale"), std::string::npos) << metres.err;
  // Intrinsics of images of another size: the principal point is far off the centre.
  const auto camera = test::runCli("import auto " + quoted(dir / "frames") + " --out " +
                                   quoted(dir / "seq") + " --overwrite --intrinsics 20,20,2,1.5");
  EXPECT_EQ(camera.exit_code, 0) << camera.err;
  EXPECT_NE(camera.err.find("sequence.json: camera: the principal point cx = 2, cy = 1.5 lies at "
                            "12 % and 12 % of the 16 x 12 pixels'"),
            std::string::npos)
      << camera.err;
}

// --overwrite that fails at its very end (the new sequence.json does not
// fit: a full disk) leaves the old sequence whole: its file and its frames
// (the old frames were deleted before the new file was written).
TEST(CliImport, AnOverwriteThatFailsAtTheEndKeepsTheOldSequence) {
  test::TempDir dir;
  writeText(dir / "frames" / "camera-intrinsics.txt", "20 0 7.5\n0 20 5.5\n0 0 1\n");
  for (int n = 0; n < 60; ++n) {  // many frames: a sequence.json of well over 4 KiB
    char base[32];
    std::snprintf(base, sizeof base, "frame-%06d", n);
    writeDepthPng(dir / "frames" / (std::string(base) + ".depth.png"), plane(4, 3, 1.0f), 0.001);
    writeText(dir / "frames" / (std::string(base) + ".pose.txt"),
              "1 0 0 " + std::to_string(0.01 * n) + "\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  }
  const std::string import =
      "import frames " + quoted(dir / "frames") + " --out " + quoted(dir / "seq");
  ASSERT_EQ(test::runCli(import + " --every 30 --quiet").exit_code, 0);
  const std::string before = test::slurp(dir / "seq" / "sequence.json");
  ASSERT_EQ(loadSequence(dir / "seq").frames.size(), 2u);
  test::CliLimits limits;
  limits.file_kib = 4;
  const auto failed = test::runCli(import + " --overwrite --quiet", limits);
  EXPECT_EQ(failed.exit_code, 1) << failed.err;
  EXPECT_NE(failed.err.find((dir / "seq" / "sequence.json").string() + ": output"),
            std::string::npos)
      << failed.err;
  EXPECT_NE(failed.err.find("the sequence there is left as it was"), std::string::npos)
      << failed.err;
  EXPECT_EQ(test::slurp(dir / "seq" / "sequence.json"), before);
  const Sequence kept = loadSequence(dir / "seq");
  EXPECT_EQ(kept.frames.size(), 2u);
  EXPECT_TRUE(validateSequence(kept).empty());
  for (const auto& entry : fs::directory_iterator(dir / "seq"))
    EXPECT_NE(entry.path().filename().string()[0], '.') << "no staging left: " << entry.path();
  // Without the limit it goes through.
  ASSERT_EQ(test::runCli(import + " --overwrite --quiet").exit_code, 0);
  EXPECT_EQ(loadSequence(dir / "seq").frames.size(), 60u);
}

// A recording kept in OUT/color (or depth, proba, label) would be deleted by
// the import that replaces those folders: a mistake in the call, refused.
TEST(CliImport, ASourceAmongTheFoldersTheImportReplacesIsAUsageError) {
  test::TempDir dir;
  writeFrames(dir / "proj" / "color");
  for (const char* overwrite : {"", " --overwrite"}) {
    const auto result = test::runCli("import frames " + quoted(dir / "proj" / "color") + " --out " +
                                     quoted(dir / "proj") + overwrite);
    EXPECT_EQ(result.exit_code, 2) << result.err;
    EXPECT_NE(result.err.find("which the import into --out"), std::string::npos) << result.err;
  }
  EXPECT_TRUE(fs::exists(dir / "proj" / "color" / "frame-000000.depth.png"));
  EXPECT_FALSE(fs::exists(dir / "proj" / "sequence.json"));
}

TEST(CliImport, QuaternionLayoutNeedsIntrinsics) {
  test::TempDir dir;
  writeQuaternion(dir / "room");
  const auto missing = test::runCli("import auto " + quoted(dir / "room") + " --out " + quoted(dir / "seq"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("--intrinsics fx,fy,cx,cy"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir / "seq"));
  const auto ok = test::runCli("import quaternion " + quoted(dir / "room") + " --out " +
                               quoted(dir / "seq") + " --intrinsics 20,20,7.5,5.5 --max-depth 3");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("imported 2 of 2 frames (quaternion)"), std::string::npos) << ok.out;
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_EQ(sequence.camera.fx, 20.0);
  EXPECT_NEAR(sequence.frames[1].T_world_camera.translation().x(), 0.2, 1e-12);
  // Depths beyond --max-depth are dropped.
  const auto near = test::runCli("import quaternion " + quoted(dir / "room") + " --out " +
                                 quoted(dir / "seq2") + " --intrinsics 20,20,7.5,5.5 --max-depth 1.5");
  EXPECT_EQ(near.exit_code, 1);
  EXPECT_NE(near.err.find("no valid depth"), std::string::npos) << near.err;
}

TEST(CliImport, UsageErrors) {
  test::TempDir dir;
  writeFrames(dir / "frames");
  const std::string src = quoted(dir / "frames");
  const std::string out = " --out " + quoted(dir / "seq");
  auto expectUsage = [](const test::CliResult& r, const std::string& text) {
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("usage: labeloctomap import"), std::string::npos) << r.err;
  };
  expectUsage(test::runCli("import kitti " + src + out), "unknown KIND 'kitti'");
  expectUsage(test::runCli("import frames " + src), "missing option --out");
  expectUsage(test::runCli("import frames"), "missing argument: SRC");
  expectUsage(test::runCli("import frames " + src + out + " --label-confidence 1.5"),
              "option --label-confidence expects a probability strictly between 0 and 1");
  expectUsage(test::runCli("import frames " + src + out + " --flying-ratio -1"), "--flying-ratio");
  expectUsage(test::runCli("import frames " + src + out + " --intrinsics 1,2"), "--intrinsics");
  expectUsage(test::runCli("import frames " + src + out + " --every 0"), "--every");
  expectUsage(test::runCli("import frames " + src + out + " --colour-topic x"), "unknown option --colour-topic");
  EXPECT_FALSE(fs::exists(dir / "seq"));
  const auto help = test::runCli("import --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--flying-ratio"), std::string::npos) << help.out;
}

TEST(CliImport, DataErrors) {
  test::TempDir dir;
  writeText(dir / "broken.bag", "not a bag\n");
  const auto bag = test::runCli("import rosbag " + quoted(dir / "broken.bag") + " --out " + quoted(dir / "a"));
  EXPECT_EQ(bag.exit_code, 1);
  EXPECT_NE(bag.err.find("ROS"), std::string::npos) << bag.err;
  writeText(dir / "unknown" / "readme.txt", "hello");
  const auto unknown = test::runCli("import auto " + quoted(dir / "unknown") + " --out " + quoted(dir / "b"));
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.err.find("readme.txt"), std::string::npos) << unknown.err;
  const auto missing = test::runCli("import tum " + quoted(dir / "nothing") + " --out " + quoted(dir / "c"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("no such file or folder"), std::string::npos) << missing.err;
}

// Topic and tf frame options are read from ROS bags only: for another source they
// would be ignored, so the call is refused as it stands.
TEST(CliImport, RosbagOptionsForAnotherSourceAreUsageErrors) {
  test::TempDir dir;
  writeFrames(dir / "frames");
  writeQuaternion(dir / "room");
  for (const std::string option : {"depth-topic", "color-topic", "camera-info-topic", "proba-topic",
                                   "label-topic", "fixed-frame", "camera-frame", "max-pose-gap"}) {
    SCOPED_TRACE(option);
    const auto given = test::runCli("import frames " + quoted(dir / "frames") + " --out " +
                                    quoted(dir / "seq") + " --" + option + " x");
    EXPECT_EQ(given.exit_code, 2) << given.err;
    EXPECT_NE(given.err.find("option --" + option + " applies to ROS bags only; " +
                             (dir / "frames").string() + " is read as frames (the KIND given)"),
              std::string::npos)
        << given.err;
  }
  const auto detected =
      test::runCli("import auto " + quoted(dir / "room") + " --out " + quoted(dir / "seq") +
                   " --intrinsics 20,20,7.5,5.5 --depth-topic /camera/depth --fixed-frame map");
  EXPECT_EQ(detected.exit_code, 2) << detected.err;
  EXPECT_NE(detected.err.find("option --depth-topic applies to ROS bags only; " +
                              (dir / "room").string() + " is read as quaternion (detected)"),
            std::string::npos)
      << detected.err;
  EXPECT_NE(detected.err.find("usage: labeloctomap import"), std::string::npos) << detected.err;
  EXPECT_FALSE(fs::exists(dir / "seq"));
}

// --max-pose-gap takes a positive number of seconds; 0, a negative value, a
// word or an infinity is a mistake in the call, refused before the bag is read.
TEST(CliImport, MaxPoseGapMustBeAPositiveNumber) {
  test::TempDir dir;
  writeText(dir / "rec.bag", "not a bag\n");
  for (const std::string value : {"0", "-1", "abc", "inf"}) {
    SCOPED_TRACE(value);
    const auto r = test::runCli("import rosbag " + quoted(dir / "rec.bag") + " --out " +
                                quoted(dir / "seq") + " --max-pose-gap " + value);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("option --max-pose-gap expects a "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("'" + value + "'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("usage: labeloctomap import"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "seq"));
  const auto help = test::runCli("import --help");
  EXPECT_NE(help.out.find("--max-pose-gap S"), std::string::npos) << help.out;
}

// A label list is checked whether or not the source has label images to name.
TEST(CliImport, LabelListIsCheckedEvenForASourceWithoutLabels) {
  test::TempDir dir;
  writeQuaternion(dir / "room");
  const std::string call = "import quaternion " + quoted(dir / "room") + " --out " +
                           quoted(dir / "seq") + " --intrinsics 20,20,7.5,5.5 --labels ";
  writeText(dir / "twice.txt", "__background__\nfoo\n# a comment\n  foo  \n");
  auto r = test::runCli(call + quoted(dir / "twice.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find((dir / "twice.txt").string() +
                       ": --labels, line 4: expected each label name once, found \"foo\" again "
                       "(also line 2)"),
            std::string::npos)
      << r.err;
  writeText(dir / "tab.txt", "__background__\nfo\to\n");
  r = test::runCli(call + quoted(dir / "tab.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("tab.txt: --labels, line 2: expected a label name"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("a tab (0x09) at byte 2"), std::string::npos) << r.err;
  writeText(dir / "empty.txt", "# nothing\n\n");
  r = test::runCli(call + quoted(dir / "empty.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("empty.txt: --labels: expected a list of 1 to 256 label names"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "seq"));

  // A source without labels keeps the list for a segmenter's channels; its
  // frames' label images are placeholders, which scoring does not use.
  writeText(dir / "good.txt", "__background__\nfoo\n");
  r = test::runCli(call + quoted(dir / "good.txt"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("the source has no label or probability images: the given labels are "
                       "the sequence's, for a segmenter's probabilities"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("single label __background__"), std::string::npos)
      << "no note contradicting it\n"
      << r.out;
  const Sequence sequence = loadSequence(dir / "seq");
  ASSERT_EQ(sequence.labels.size(), 2);
  EXPECT_EQ(sequence.labels.at(1).name, "foo");
  for (const FrameRecord& frame : sequence.frames) {
    EXPECT_FALSE(frame.label.empty());
    EXPECT_TRUE(frame.label_placeholder);
  }
  r = test::runCli("info " + quoted(dir / "seq"));
  EXPECT_NE(r.out.find("placeholders (all background, no ground truth)"), std::string::npos)
      << r.out;
}

#ifdef LOM_WITH_ROSBAG
// A bag with two depth topics, a camera info and tf in "odom" under "map".
void writeBag(const fs::path& path) {
  rosbag::Bag bag(path.string(), rosbag::bagmode::Write);
  for (int k = 0; k <= 4; ++k) {
    const double t = 5.0 + 0.1 * k;
    tf2_msgs::TFMessage tf;
    geometry_msgs::TransformStamped odom;
    odom.header.stamp = ros::Time(t);
    odom.header.frame_id = "map";
    odom.child_frame_id = "odom";
    odom.transform.rotation.w = 1.0;
    geometry_msgs::TransformStamped camera = odom;
    camera.header.frame_id = "odom";
    camera.child_frame_id = "cam_optical";
    camera.transform.translation.x = 0.1 * k;
    tf.transforms = {odom, camera};
    bag.write("/tf", ros::Time(t), tf);
  }
  for (int f = 0; f < 3; ++f) {
    const ros::Time stamp(5.0 + 0.1 * f);
    sensor_msgs::Image depth;
    depth.header.stamp = stamp;
    depth.header.frame_id = "cam_optical";
    depth.width = 8;
    depth.height = 6;
    depth.encoding = "16UC1";
    depth.step = 16;
    depth.data.assign(96, 0);
    for (size_t i = 0; i < 48; ++i) depth.data[2 * i + 1] = 0x04;  // 1024 mm
    bag.write("/cam/depth/image_raw", stamp, depth);
    bag.write("/cam/ir_depth/image_raw", stamp, depth);
    sensor_msgs::CameraInfo info;
    info.header = depth.header;
    info.width = 8;
    info.height = 6;
    info.K = {10, 0, 3.5, 0, 10, 2.5, 0, 0, 1};
    bag.write("/cam/depth/camera_info", stamp, info);
  }
}

TEST(CliImport, RosbagTopicsAndFramesAsOptions) {
  test::TempDir dir;
  writeBag(dir / "rec.bag");
  const auto ambiguous = test::runCli("import auto " + quoted(dir / "rec.bag") + " --out " + quoted(dir / "a"));
  EXPECT_EQ(ambiguous.exit_code, 1);
  EXPECT_NE(ambiguous.err.find("several"), std::string::npos) << ambiguous.err;
  const auto ok = test::runCli("import rosbag " + quoted(dir / "rec.bag") + " --out " + quoted(dir / "a") +
                               " --depth-topic /cam/depth/image_raw --fixed-frame odom --quiet");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("imported 3 of 3 frames (rosbag)"), std::string::npos) << ok.out;
  const Sequence sequence = loadSequence(dir / "a");
  EXPECT_EQ(sequence.frame_id, "odom");
  EXPECT_NEAR(sequence.frames[2].T_world_camera.translation().x(), 0.2, 1e-9);
  EXPECT_NEAR(loadFrame(sequence, 0).depth.at(3, 3), 1.024, 1e-6);
}
#endif

}  // namespace
}  // namespace lom
