// ROS 1 bags written with the rosbag API, imported, read back and compared;
// malformed bags. Without bag support in the build, the import must say so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "lom/import.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

#ifdef LOM_WITH_ROSBAG
#include <bzlib.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#endif

namespace lom {
namespace {

namespace fs = std::filesystem;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// A file that is no bag, an empty one and a folder are said to be so, not
// called truncated bags for `rosbag reindex` to recover.
TEST(ImportRosbag, NotABagFileIsReported) {
  test::TempDir dir;
  std::ofstream(dir / "broken.bag") << "this is not a bag\n";
  std::ofstream(dir / "empty.bag").flush();
  fs::create_directories(dir / "bags");
  std::ofstream(dir / "bags" / "rec.bag") << "#ROSBAG V2.0\n";
  const auto errorFor = [&](const char* name) {
    return errorOf([&] { importSource(SourceKind::RosBag, dir / name, dir / "seq"); });
  };
  const std::string broken = errorFor("broken.bag");
  const std::string empty = errorFor("empty.bag");
  const std::string folder = errorFor("bags");
  if (rosbagSupported()) {
    EXPECT_NE(broken.find("broken.bag: bag: expected a readable ROS 1 bag (format 2.0), found a "
                          "file that is not a ROS bag (it does not start with #ROSBAG V2.0)"),
              std::string::npos)
        << broken;
    EXPECT_NE(empty.find("empty.bag: bag: expected a readable ROS 1 bag (format 2.0), found a "
                         "file that is empty"),
              std::string::npos)
        << empty;
    EXPECT_NE(folder.find("bags: bag: expected a .bag file, found a folder (give one of its bags: "
                          "rec.bag)"),
              std::string::npos)
        << folder;
    for (const auto& error : {broken, empty, folder})
      EXPECT_EQ(error.find("reindex"), std::string::npos) << error;
    // A bag cut inside its first line is a bag cut short.
    std::ofstream(dir / "cut.bag") << "#ROSBAG V2";
    const std::string cut = errorFor("cut.bag");
    EXPECT_NE(cut.find("the file ending inside its first line"), std::string::npos) << cut;
  } else {
    EXPECT_NE(broken.find("no ROS bag support"), std::string::npos) << broken;
  }
  EXPECT_FALSE(fs::exists(dir / "seq"));
}

#ifdef LOM_WITH_ROSBAG

constexpr int kW = 32;
constexpr int kH = 24;
const char* const kOptical = "camera_depth_optical_frame";

float depthAt(int u, int v, int frame) {
  return static_cast<float>((900 + 3 * u + 2 * v + 7 * frame) / 1000.0);
}

// world -> base_link moves along x at 1 m/s and turns about z; base_link ->
// the optical frame is static.
Eigen::Isometry3d worldBase(double t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(t - 10.0, 0.5, 0.2);
  T.linear() = Eigen::AngleAxisd(0.3 * (t - 10.0), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}
Eigen::Isometry3d baseCamera() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.1, 0.0, 0.3);
  // Optical frame: z forward along base x, x right along -base y, y down along -base z.
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T.linear() = R;
  return T;
}

// Frame f of `sequence` is posed as the moving base at 10 + 0.1 f s, with the
// camera's mount on it; `why` is said for a frame that is not.
void expectPosesOfTheMovingBase(const Sequence& sequence, size_t frames, const char* why) {
  ASSERT_GE(sequence.frames.size(), frames);
  for (size_t f = 0; f < frames; ++f)
    EXPECT_TRUE(sequence.frames[f].T_world_camera.matrix().isApprox(
        (worldBase(10.0 + 0.1 * static_cast<double>(f)) * baseCamera()).matrix(), 1e-6))
        << "frame " << f << why << "\n"
        << sequence.frames[f].T_world_camera.matrix();
}

geometry_msgs::TransformStamped transformMsg(const Eigen::Isometry3d& T, const std::string& parent,
                                             const std::string& child, double stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time(stamp);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = T.translation().x();
  t.transform.translation.y = T.translation().y();
  t.transform.translation.z = T.translation().z();
  const Eigen::Quaterniond q(T.linear());
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  return t;
}

struct BagSpec {
  std::string depth_encoding = "16UC1";  // or 32FC1
  bool color = true;
  bool compressed_color = false;
  bool camera_info = true;
  int proba_channels = 3;  // 0: none
  std::string proba_encoding = "32FC";
  bool label = false;
  double image_clock_offset = 0.0;  // added to image stamps (not tf)
  bool second_depth_topic = false;
  bool bad_step_in_frame_2 = false;
  int frames = 5;
  rosbag::compression::CompressionType compression = rosbag::compression::Uncompressed;
  int proba_width = kW;  // probabilities of another resolution than depth
  int proba_height = kH;
  bool compressed_depth = false;         // compressedDepth: a 12-byte header, then a 16-bit PNG
  int flipped_depth_png_frame = -1;      // this frame's depth PNG has one byte flipped in IDAT
  int cut_color_png_frame = -1;          // this frame's colour PNG ends inside IDAT
  bool jpeg_color = false;               // compressed colour as JPEG instead of PNG
  int cut_color_jpeg_frame = -1;         // this frame's colour JPEG ends halfway
  bool info_projection = false;          // P differs from K (distorted raw images, rectified here)
  int info_size_factor = 1;              // the camera info names a size this many times the images'
  std::string info_frame;                // the camera info's frame_id (default: the depth frame)
  bool first_info_uncalibrated = false;  // the first camera info has K = 0
  bool tf_zero_stamps = false;           // dynamic tf stamped 0 (its record time is the stamp)
  bool tf_link_missing = false;          // /tf moves base_footprint, not the camera's base_link
  double stamp_scale = 1.0;              // header stamps of tf and depth: 10 + scale (t - 10)
  bool color_8uc3 = false;               // colour as 8UC3 instead of bgr8
  // Quaternions of /tf (world -> base_link) and /tf_static (base_link -> the
  // optical frame) multiplied by these: not unit, as some drivers write them.
  double tf_quaternion_scale = 1.0;
  double static_quaternion_scale = 1.0;
  bool tf_repeated = false;  // the first /tf message written twice (tf2 refuses the second)
  std::uint32_t chunk_threshold = 0;  // bytes of a chunk; 0: the library's (768 KiB)
  bool no_dynamic_tf = false;         // /tf_static only: /tf left out of the recording
  int restamped_frame = -1;           // this frame's depth header has the frame before's stamp
};

// `t` with its quaternion multiplied by `scale`.
geometry_msgs::TransformStamped scaledRotation(geometry_msgs::TransformStamped t, double scale) {
  t.transform.rotation.x *= scale;
  t.transform.rotation.y *= scale;
  t.transform.rotation.z *= scale;
  t.transform.rotation.w *= scale;
  return t;
}

// The offset and length of the first IDAT chunk's data in PNG bytes.
std::pair<size_t, size_t> firstImageData(const std::vector<std::uint8_t>& png) {
  for (size_t at = 8; at + 12 <= png.size();) {
    const size_t length = (size_t{png[at]} << 24) | (size_t{png[at + 1]} << 16) |
                          (size_t{png[at + 2]} << 8) | png[at + 3];
    if (std::memcmp(png.data() + at + 4, "IDAT", 4) == 0) return {at + 8, length};
    at += length + 12;
  }
  ADD_FAILURE() << "no IDAT chunk";
  return {0, 0};
}

void writeBag(const fs::path& path, const BagSpec& spec) {
  rosbag::Bag bag(path.string(), rosbag::bagmode::Write);
  bag.setCompression(spec.compression);
  if (spec.chunk_threshold > 0) bag.setChunkThreshold(spec.chunk_threshold);
  // tf at 20 Hz from 9.95 to 10.30; the frame at 10.4 has no pose.
  // Header stamps may run on another scale than the record times (a bag
  // replayed faster, or written without record times).
  const auto header = [&](double t) { return 10.0 + spec.stamp_scale * (t - 10.0); };
  for (int k = -1; k <= (spec.no_dynamic_tf ? -2 : 6); ++k) {
    const double t = 10.0 + 0.05 * k;
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(scaledRotation(
        transformMsg(worldBase(header(t)), "world",
                     spec.tf_link_missing ? "base_footprint" : "base_link", header(t)),
        spec.tf_quaternion_scale));
    if (spec.tf_zero_stamps) tf.transforms.back().header.stamp = ros::Time();
    bag.write("/tf", ros::Time(t), tf);
    if (spec.tf_repeated && k == -1) bag.write("/tf", ros::Time(t), tf);
  }
  tf2_msgs::TFMessage static_tf;
  static_tf.transforms.push_back(scaledRotation(
      transformMsg(baseCamera(), "base_link", kOptical, 9.9), spec.static_quaternion_scale));
  bag.write("/tf_static", ros::Time(9.9), static_tf);

  for (int f = 0; f < spec.frames; ++f) {
    const double t = 10.0 + 0.1 * f + spec.image_clock_offset;
    const ros::Time stamp(t);
    sensor_msgs::Image depth;
    depth.header.stamp = ros::Time(header(f == spec.restamped_frame ? t - 0.1 : t));
    depth.header.frame_id = kOptical;
    depth.width = kW;
    depth.height = kH;
    depth.encoding = spec.depth_encoding;
    const bool is_float = spec.depth_encoding == "32FC1";
    depth.step = kW * (is_float ? 4 : 2);
    depth.data.resize(depth.step * kH);
    for (int v = 0; v < kH; ++v)
      for (int u = 0; u < kW; ++u) {
        std::uint8_t* p = depth.data.data() + v * depth.step + u * (is_float ? 4 : 2);
        if (is_float) {
          const float z = (u == 3 && v == 3) ? NAN : depthAt(u, v, f);
          std::memcpy(p, &z, 4);
        } else {
          const std::uint16_t mm = static_cast<std::uint16_t>(std::lround(depthAt(u, v, f) * 1000));
          std::memcpy(p, &mm, 2);
        }
      }
    if (spec.bad_step_in_frame_2 && f == 2) depth.step = 7;
    if (spec.compressed_depth) {
      sensor_msgs::CompressedImage compressed;
      compressed.header = depth.header;
      compressed.format = "16UC1; compressedDepth png";
      const cv::Mat mm(kH, kW, CV_16UC1, depth.data.data());
      std::vector<std::uint8_t> png;
      cv::imencode(".png", mm, png);
      if (f == spec.flipped_depth_png_frame) {
        const auto [data, length] = firstImageData(png);
        png[data + length / 2] ^= 0x10;
      }
      compressed.data.assign(12, 0);  // format 0, quantisation parameters 0 (unused for mm)
      compressed.data.insert(compressed.data.end(), png.begin(), png.end());
      bag.write("/camera/depth/image_rect_raw/compressedDepth", stamp, compressed);
    } else {
      bag.write("/camera/depth/image_rect_raw", stamp, depth);
    }
    if (spec.second_depth_topic) bag.write("/camera/depth/image_raw", stamp, depth);

    if (spec.camera_info) {
      sensor_msgs::CameraInfo info;
      info.header = depth.header;
      if (!spec.info_frame.empty()) info.header.frame_id = spec.info_frame;
      info.width = kW * spec.info_size_factor;
      info.height = kH * spec.info_size_factor;
      info.K = {30, 0, 15.5, 0, 31, 11.5, 0, 0, 1};
      if (spec.info_projection) {
        info.D = {0.1, -0.05, 0, 0, 0};
        info.P = {26, 0, 16.2, 0, 0, 26, 12.1, 0, 0, 0, 1, 0};
      }
      if (spec.first_info_uncalibrated && f == 0) info.K = {};
      bag.write("/camera/depth/camera_info", stamp, info);
    }
    if (spec.color) {
      const ros::Time color_stamp(t + 0.004);
      if (spec.compressed_color) {
        sensor_msgs::CompressedImage image;
        image.header.stamp = color_stamp;
        image.header.frame_id = "camera_color_optical_frame";
        image.format = spec.jpeg_color ? "bgr8; jpeg compressed bgr8" : "bgr8; png compressed bgr8";
        cv::Mat bgr(kH, kW, CV_8UC3, cv::Scalar(10 * f, 100, 200));
        std::vector<std::uint8_t> png;
        cv::imencode(spec.jpeg_color ? ".jpg" : ".png", bgr, png);
        if (f == spec.cut_color_png_frame) {
          const auto [data, length] = firstImageData(png);
          png.resize(data + length / 2);
        }
        if (f == spec.cut_color_jpeg_frame) png.resize(png.size() / 2);
        image.data = png;
        bag.write("/camera/color/image_raw/compressed", color_stamp, image);
      } else {
        sensor_msgs::Image image;
        image.header.stamp = color_stamp;
        image.header.frame_id = "camera_color_optical_frame";
        image.width = kW;
        image.height = kH;
        image.encoding = spec.color_8uc3 ? "8UC3" : "bgr8";
        image.step = kW * 3 + 4;  // padded rows
        image.data.assign(image.step * kH, 0);
        for (int v = 0; v < kH; ++v)
          for (int u = 0; u < kW; ++u) {
            std::uint8_t* p = image.data.data() + v * image.step + 3 * u;
            p[0] = 200;                                    // B
            p[1] = 100;                                    // G
            p[2] = static_cast<std::uint8_t>(10 * f + u);  // R
          }
        bag.write("/camera/color/image_raw", color_stamp, image);
      }
    }
    if (spec.proba_channels > 0) {
      sensor_msgs::Image proba;
      proba.header.stamp = ros::Time(t - 0.003);
      proba.header.frame_id = kOptical;
      const int pw = spec.proba_width, ph = spec.proba_height;
      proba.width = pw;
      proba.height = ph;
      const int n = spec.proba_channels;
      const bool wide = spec.proba_encoding == "16UC";
      proba.encoding = spec.proba_encoding + std::to_string(n);
      proba.step = pw * n * (wide ? 2 : 4);
      proba.data.resize(proba.step * ph);
      for (int v = 0; v < ph; ++v)
        for (int u = 0; u < pw; ++u)
          for (int c = 0; c < n; ++c) {
            // Channel 1 on the left half, channel 2 on the right, 0.1 for the others.
            const int main = u < pw / 2 ? 1 : 2;
            const float p = c == main ? 0.8f : 0.2f / static_cast<float>(n - 1);
            std::uint8_t* out = proba.data.data() + v * proba.step + (u * n + c) * (wide ? 2 : 4);
            if (wide) {
              const std::uint16_t value = static_cast<std::uint16_t>(std::lround(p * 65535));
              std::memcpy(out, &value, 2);
            } else {
              std::memcpy(out, &p, 4);
            }
          }
      bag.write("/segmenter/probabilities", proba.header.stamp, proba);
    }
    if (spec.label) {
      sensor_msgs::Image label;
      label.header.stamp = stamp;
      label.header.frame_id = kOptical;
      label.width = kW;
      label.height = kH;
      label.encoding = "mono8";
      label.step = kW;
      label.data.assign(kW * kH, 0);
      for (int i = kW * kH / 2; i < kW * kH; ++i) label.data[i] = 19;
      bag.write("/segmenter/labels", stamp, label);
    }
  }
  bag.close();
}

bool anyNote(const ImportReport& report, const std::string& part) {
  for (const auto& n : report.notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

TEST(ImportRosbag, RoundTripWithTfProbabilitiesAndColour) {
  test::TempDir dir;
  writeBag(dir / "rec.bag", {});
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  const ImportReport report = importSource(std::nullopt, dir / "rec.bag", dir / "seq", options);
  EXPECT_EQ(report.kind, SourceKind::RosBag);
  EXPECT_EQ(report.frames_found, 5u);
  EXPECT_EQ(report.frames_written, 4u) << report.text();
  ASSERT_EQ(report.skipped.size(), 1u) << report.text();
  EXPECT_NE(
      report.skipped[0].reason.find("no transform from 'world' to 'camera_depth_optical_frame'"),
      std::string::npos)
      << report.skipped[0].reason;
  EXPECT_TRUE(anyNote(report, "depth topic: /camera/depth/image_rect_raw")) << report.text();
  EXPECT_TRUE(anyNote(report, "colour topic: /camera/color/image_raw")) << report.text();
  EXPECT_TRUE(anyNote(report, "probability topic: /segmenter/probabilities")) << report.text();
  EXPECT_TRUE(anyNote(report, "in 'world'")) << report.text();

  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_EQ(sequence.frame_id, "world");
  EXPECT_EQ(sequence.camera.fx, 30.0);
  EXPECT_EQ(sequence.camera.cy, 11.5);
  ASSERT_EQ(sequence.labels.size(), 3);
  EXPECT_EQ(sequence.labels.at(2).name, "label_2");
  ASSERT_EQ(sequence.frames.size(), 4u);
  for (int f = 0; f < 4; ++f) {
    const double t = 10.0 + 0.1 * f;
    ASSERT_TRUE(sequence.frames[f].stamp.has_value()) << "a bag keeps its time stamps";
    EXPECT_NEAR(*sequence.frames[f].stamp, t, 1e-9);
    EXPECT_FALSE(sequence.frames[f].proba_from_label) << "the segmenter's probabilities";
    const Eigen::Isometry3d expected = worldBase(t) * baseCamera();
    EXPECT_TRUE(sequence.frames[f].T_world_camera.matrix().isApprox(expected.matrix(), 1e-6))
        << "frame " << f << " (tf interpolated between 20 Hz samples)\n"
        << sequence.frames[f].T_world_camera.matrix() << "\n"
        << expected.matrix();
    const FrameData frame = loadFrame(sequence, f);
    for (int v = 0; v < kH; ++v)
      for (int u = 0; u < kW; ++u) ASSERT_NEAR(frame.depth.at(u, v), depthAt(u, v, f), 1e-6);
    ASSERT_TRUE(frame.color.has_value());
    const size_t i = (5 * kW + 7) * 3;
    EXPECT_EQ(frame.color->rgb[i], 10 * f + 7);  // R (from bgr8 with padded rows)
    EXPECT_EQ(frame.color->rgb[i + 2], 200);     // B
    ASSERT_TRUE(frame.proba.has_value());
    EXPECT_NEAR(frame.proba->pixel(3, 3)[1], 0.8f, 1e-3);
    EXPECT_NEAR(frame.proba->pixel(kW - 3, 3)[2], 0.8f, 1e-3);
    EXPECT_NEAR(frame.proba->pixel(kW - 3, 3)[0], 0.1f, 1e-3);
  }
}

// Writes the bag `spec` describes to dir/rec.bag and imports it into dir/seq.
ImportReport importBag(const test::TempDir& dir, const BagSpec& spec,
                       const ImportOptions& options = {}) {
  writeBag(dir / "rec.bag", spec);
  return importSource(std::nullopt, dir / "rec.bag", dir / "seq", options);
}

// Rectified images (the import does not undistort) have the camera info's
// projection P, not the raw images' K.
TEST(ImportRosbag, RectifiedImagesTakeTheProjection) {
  test::TempDir dir;
  BagSpec spec;
  spec.info_projection = true;
  const ImportReport report = importBag(dir, spec);
  EXPECT_TRUE(anyNote(report, "projection P")) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_DOUBLE_EQ(sequence.camera.fx, 26.0);
  EXPECT_DOUBLE_EQ(sequence.camera.fy, 26.0);
  EXPECT_DOUBLE_EQ(sequence.camera.cx, 16.2);
  EXPECT_DOUBLE_EQ(sequence.camera.cy, 12.1);
}

// A driver publishing zeros until it is calibrated: the first calibrated
// message is used, not a refusal of the whole bag.
TEST(ImportRosbag, TheFirstCalibratedCameraInfoIsUsed) {
  test::TempDir dir;
  BagSpec spec;
  spec.first_info_uncalibrated = true;
  const ImportReport report = importBag(dir, spec);
  EXPECT_EQ(report.frames_written, 4u) << report.text();
  EXPECT_DOUBLE_EQ(loadSequence(dir / "seq").camera.fx, 30.0);
}

// Intrinsics given as an option are for the frames written, whatever size
// the bag's (wrong) camera info names: they used to be halved here.
TEST(ImportRosbag, GivenIntrinsicsAreForTheFramesWritten) {
  test::TempDir dir;
  BagSpec spec;
  spec.info_size_factor = 2;
  ImportOptions options;
  options.intrinsics = parseIntrinsics("30,31,15.5,11.5");
  const ImportReport report = importBag(dir, spec, options);
  EXPECT_FALSE(anyNote(report, "intrinsics scaled")) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_EQ(sequence.camera.width, kW);
  EXPECT_DOUBLE_EQ(sequence.camera.fx, 30.0);
  for (const auto& frame : sequence.frames) EXPECT_FALSE(frame.camera.has_value());
}

// The only camera info found is another camera's (its frame is not the depth
// images'): used, but said.
TEST(ImportRosbag, ACameraInfoOfAnotherFrameIsAWarning) {
  test::TempDir dir;
  BagSpec spec;
  spec.info_frame = "camera_color_optical_frame";
  const ImportReport report = importBag(dir, spec);
  EXPECT_TRUE(anyNote(report,
                      "warning: the camera info /camera/depth/camera_info is of frame "
                      "'camera_color_optical_frame'"))
      << report.text();
  ASSERT_EQ(report.warnings().size(), 1u) << report.text();
  EXPECT_NE(report.warnings()[0].find("its intrinsics may be another camera's"), std::string::npos);
}

// Quaternions of norm 1.05 (/tf) and 0.99 (/tf_static, as (0, 0, 0.7, 0.7))
// are normalised: tf2 refused them without a word, and every frame was
// skipped for a frame "missing" from tf. What tf2 still refuses is counted.
TEST(ImportRosbag, NonUnitQuaternionsAreNormalisedAndRefusedTransformsCounted) {
  test::TempDir dir;
  BagSpec spec;
  spec.tf_quaternion_scale = 1.05;
  spec.static_quaternion_scale = 0.99;
  spec.tf_repeated = true;
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  const ImportReport report = importBag(dir, spec, options);
  ASSERT_EQ(report.frames_written, 4u) << report.text();
  EXPECT_TRUE(anyNote(report,
                      "10 tf transforms have a quaternion that is not of unit length "
                      "(norm 0.99 to 1.05): normalised"))
      << report.text();
  EXPECT_TRUE(anyNote(report, "1 tf transforms were refused by tf2 and ignored")) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  expectPosesOfTheMovingBase(sequence, 4, "");
}

// tf stamped 0 takes its record time, as images do.
TEST(ImportRosbag, TfStampsOfZeroTakeTheRecordTime) {
  test::TempDir dir;
  BagSpec spec;
  spec.tf_zero_stamps = true;
  const ImportReport report = importBag(dir, spec);
  EXPECT_EQ(report.frames_written, 4u) << report.text();
  EXPECT_TRUE(anyNote(report, "tf transforms have a zero header stamp")) << report.text();
}

// /tf moves a frame the camera's chain does not reach: the camera's poses are
// all static, one pose for every frame; said, not taken silently.
TEST(ImportRosbag, ACameraChainOfStaticTransformsOnlyIsAWarning) {
  test::TempDir dir;
  BagSpec spec;
  spec.tf_link_missing = true;
  const ImportReport report = importBag(dir, spec);
  EXPECT_TRUE(anyNote(report, "warning: every transform from 'base_link' to '" +
                                  std::string(kOptical) +
                                  "' is static, so every frame gets the same pose, while /tf "
                                  "moves 'base_footprint'"))
      << report.text();
  // A chain /tf moves: nothing to say.
  test::TempDir other;
  const ImportReport moving = importBag(other, BagSpec{});
  EXPECT_FALSE(anyNote(moving, "is static")) << moving.text();
  EXPECT_TRUE(moving.warnings().empty()) << moving.text();
}

// A bag recorded without /tf (only /tf_static): every frame gets one pose;
// said, as for a chain of static links.
TEST(ImportRosbag, ABagWithoutTfIsAWarning) {
  test::TempDir dir;
  BagSpec spec;
  spec.no_dynamic_tf = true;
  const ImportReport report = importBag(dir, spec);
  EXPECT_TRUE(anyNote(report,
                      "warning: the bag has no /tf messages, only /tf_static, so every "
                      "frame gets the same pose of '" +
                          std::string(kOptical) + "' in 'base_link'"))
      << report.text();
}

// Two depth images with one header stamp get one pose: said, with the stamp.
TEST(ImportRosbag, DepthImagesSharingAStampAreAWarning) {
  test::TempDir dir;
  BagSpec spec;
  spec.restamped_frame = 2;
  const ImportReport report = importBag(dir, spec);
  EXPECT_TRUE(anyNote(report,
                      "warning: 2 depth images share their header stamp with another "
                      "(the first at "))
      << report.text();
  test::TempDir other;
  EXPECT_FALSE(anyNote(importBag(other, BagSpec{}), "share their header stamp"));
}

// Opened in the studio, such a bag is a smeared map: the warning comes with
// every open, fresh or from the import cache, as the command line gives it.
TEST(ImportRosbag, TheStaticPoseWarningIsKeptWithTheCachedConversion) {
  test::TempDir dir;
  BagSpec spec;
  spec.tf_link_missing = true;
  writeBag(dir / "rec.bag", spec);
  for (int open = 0; open < 2; ++open) {
    SCOPED_TRACE(open == 0 ? "converted" : "from the cache");
    const OpenedSource opened = openSource(dir / "rec.bag", {}, dir / "cache");
    EXPECT_EQ(opened.reused_cache, open == 1);
    ASSERT_EQ(opened.warnings.size(), 1u) << test::slurp(opened.folder / kImportNotesFile);
    EXPECT_EQ(opened.warnings[0].rfind("warning: every transform from 'base_link' to '" +
                                           std::string(kOptical) + "' is static",
                                       0),
              0u)
        << opened.warnings[0];
    EXPECT_GT(opened.notes.size(), opened.warnings.size()) << "the topics chosen, for one";
  }
}

// A compressed bag is read through twice before its first frame (its records
// checked, then its messages indexed), which decompresses every chunk: for a
// large bz2 bag, minutes. The progress moves meanwhile, in bytes of the file,
// and a cancel is heard there, not once the whole file is read.
TEST(ImportRosbag, ReadingABagReportsItsProgressAndHearsACancel) {
  test::TempDir dir;
  BagSpec spec;
  spec.compression = rosbag::compression::BZ2;
  spec.chunk_threshold = 4096;  // chunks of a few messages each
  writeBag(dir / "rec.bag", spec);
  const std::uint64_t size = fs::file_size(dir / "rec.bag");
  std::vector<ImportProgress> steps;
  const ImportReport whole = importSource(SourceKind::RosBag, dir / "rec.bag", dir / "seq", {},
                                          [&](const ImportProgress& step) {
                                            steps.push_back(step);
                                            return true;
                                          });
  EXPECT_EQ(whole.frames_written, 4u) << whole.text();
  size_t reading = 0, checking = 0, indexing = 0;
  std::uint64_t last = 0;
  for (; reading < steps.size() && steps[reading].read_total > 0; ++reading) {
    const ImportProgress& step = steps[reading];
    EXPECT_EQ(step.done, 0u) << "before the frames";
    EXPECT_EQ(step.total, 0u);
    EXPECT_EQ(step.read_total, 2 * size) << "two passes over the file";
    EXPECT_GE(step.read, last) << "step " << reading;
    last = step.read;
    ++(step.read < size ? checking : indexing);
  }
  EXPECT_GE(checking, 3u) << "the record check moves through the file";
  EXPECT_GE(indexing, 3u) << "so does the index of messages";
  ASSERT_LT(reading, steps.size());
  EXPECT_EQ(steps[reading].done, 1u) << "then the frames";
  for (size_t i = reading; i < steps.size(); ++i) EXPECT_EQ(steps[i].read_total, 0u);

  // Cancelled while the records are checked, and while the messages are
  // indexed: no frame converted, nothing written, not asked again.
  for (const std::uint64_t cancel_at : {std::uint64_t{0}, size}) {
    SCOPED_TRACE(cancel_at == 0 ? "checking" : "indexing");
    size_t calls_after = 0, frames_seen = 0;
    bool cancelled = false;
    const ImportReport report =
        importSource(SourceKind::RosBag, dir / "rec.bag", dir / "cancelled", {},
                     [&](const ImportProgress& step) {
                       if (cancelled) ++calls_after;
                       frames_seen = std::max(frames_seen, step.done);
                       cancelled = cancelled || (step.read_total > 0 && step.read >= cancel_at);
                       return !cancelled;
                     });
    EXPECT_TRUE(report.cancelled);
    EXPECT_EQ(report.frames_written, 0u);
    EXPECT_EQ(frames_seen, 0u) << "stopped before the first frame";
    EXPECT_EQ(calls_after, 0u);
    EXPECT_FALSE(fs::exists(dir / "cancelled"));
  }
}

// Header stamps spanning far more than the record times (a bag replayed 100
// times faster): tf keeps every transform, and every frame with a pose is
// imported (the cache, sized by the record times, dropped most of them).
TEST(ImportRosbag, TfIsKeptForHeaderStampsBeyondTheRecordTimes) {
  test::TempDir dir;
  BagSpec spec;
  spec.stamp_scale = 100.0;
  spec.color = false;
  spec.proba_channels = 0;
  ImportOptions options;
  options.time_tolerance = 0.02;
  const ImportReport report = importBag(dir, spec, options);
  EXPECT_EQ(report.frames_written, 4u) << report.text();
}

// An 8UC3 colour topic is colour, never probabilities, even when colour is
// not imported.
TEST(ImportRosbag, AColourTopicIsNeverTakenForProbabilities) {
  test::TempDir dir;
  BagSpec spec;
  spec.color_8uc3 = true;
  spec.proba_channels = 0;
  ImportOptions options;
  options.rosbag.no_color = true;
  const ImportReport report = importBag(dir, spec, options);
  EXPECT_FALSE(anyNote(report, "probability topic")) << report.text();
  EXPECT_EQ(loadSequence(dir / "seq").labels.size(), 1);
}

TEST(ImportRosbag, FloatDepthCompressedColourAndLabelImages) {
  test::TempDir dir;
  BagSpec spec;
  spec.depth_encoding = "32FC1";
  spec.compressed_color = true;
  spec.proba_channels = 0;
  spec.label = true;
  spec.frames = 3;
  writeBag(dir / "rec.bag", spec);
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  options.label_confidence = 0.75;
  const ImportReport report =
      importSource(SourceKind::RosBag, dir / "rec.bag", dir / "seq", options);
  ASSERT_EQ(report.frames_written, 3u) << report.text();
  EXPECT_TRUE(anyNote(report, "label topic: /segmenter/labels")) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(validateSequence(sequence).empty());
  EXPECT_EQ(sequence.labels, apc2016Labels());
  const FrameData frame = loadFrame(sequence, 1);
  EXPECT_EQ(frame.depth.at(3, 3), 0.0f) << "NaN is a hole";
  EXPECT_NEAR(frame.depth.at(4, 3), depthAt(4, 3, 1), 0.0006) << "float metres stored in mm";
  ASSERT_TRUE(frame.color.has_value());
  EXPECT_EQ(frame.color->rgb[0], 200);  // R of the decoded PNG (BGR 10, 100, 200)
  EXPECT_EQ(frame.color->rgb[2], 10);
  ASSERT_TRUE(frame.proba.has_value());
  EXPECT_EQ(sequence.frames[1].proba_labels, (std::vector<int>{0, 19}));
  EXPECT_NEAR(frame.proba->pixel(0, kH - 1)[1], 0.75f, 1e-3);
  EXPECT_NEAR(frame.proba->pixel(0, kH - 1)[0], 0.25f, 1e-3);
  ASSERT_TRUE(frame.label.has_value());
  EXPECT_EQ(frame.label->at(0, kH - 1), 19);
  for (const auto& record : sequence.frames)
    EXPECT_TRUE(record.proba_from_label) << "one-hot from the label topic";
}

// Writes a bag from `spec` into `dir` and imports it (no flying-pixel filter);
// `printed` receives what the import wrote on stderr.
ImportReport importPrinting(const test::TempDir& dir, const BagSpec& spec, std::string& printed) {
  writeBag(dir / "rec.bag", spec);
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  testing::internal::CaptureStderr();
  ImportReport report = importSource(SourceKind::RosBag, dir / "rec.bag", dir / "seq", options);
  printed = testing::internal::GetCapturedStderr();
  return report;
}

TEST(ImportRosbag, DamagedPngPayloadsAreReportedByTopicWithoutDecoderMessages) {
  test::TempDir dir;
  BagSpec spec;
  spec.compressed_depth = true;
  spec.compressed_color = true;
  spec.proba_channels = 0;
  spec.flipped_depth_png_frame = 1;
  spec.cut_color_png_frame = 2;
  std::string printed;
  const ImportReport report = importPrinting(dir, spec, printed);
  EXPECT_EQ(printed, "");
  // Frame 1 is skipped (its depth is damaged), frame 4 has no pose; frame 2 has no colour.
  EXPECT_EQ(report.frames_written, 3u) << report.text();
  bool depth_reported = false;
  for (const auto& s : report.skipped)
    depth_reported |=
        s.frame == "depth@10.100" &&
        s.reason.find(
            "/camera/depth/image_rect_raw/compressedDepth: depth PNG data: expected a "
            "complete PNG file, found chunk ") != std::string::npos &&
        s.reason.find(" (IDAT) fails its CRC check") != std::string::npos;
  EXPECT_TRUE(depth_reported) << report.text();
  EXPECT_TRUE(anyNote(report,
                      "(/camera/color/image_raw/compressed: colour PNG data: expected a "
                      "complete PNG file, found the PNG ends inside chunk "))
      << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_NEAR(loadFrame(sequence, 0).depth.at(4, 3), depthAt(4, 3, 0), 1e-6);
  EXPECT_TRUE(loadFrame(sequence, 0).color.has_value());
  EXPECT_FALSE(loadFrame(sequence, 1).color.has_value()) << "frame 2's colour PNG is cut";
}

TEST(ImportRosbag, CutJpegColourIsLeftOutWithLibjpegsReasonAndNothingPrinted) {
  test::TempDir dir;
  BagSpec spec;
  spec.compressed_color = true;
  spec.jpeg_color = true;
  spec.proba_channels = 0;
  spec.cut_color_jpeg_frame = 2;
  std::string printed;
  const ImportReport report = importPrinting(dir, spec, printed);
  EXPECT_EQ(printed, "") << "libjpeg printed on the terminal";
  EXPECT_EQ(report.frames_written, 4u) << report.text();  // frame 4 has no pose
  EXPECT_TRUE(anyNote(report,
                      "(/camera/color/image_raw/compressed: colour JPEG data: expected a JPEG "
                      "whose image data can be decoded, found libjpeg stopped: Premature end "
                      "of JPEG file)"))
      << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  const FrameData first = loadFrame(sequence, 0);
  ASSERT_TRUE(first.color.has_value());
  EXPECT_NEAR(first.color->rgb[0], 200, 3);  // R of BGR (0, 100, 200) through JPEG
  EXPECT_NEAR(first.color->rgb[1], 100, 3);
  EXPECT_FALSE(loadFrame(sequence, 2).color.has_value()) << "frame 2's colour JPEG is cut";
  EXPECT_TRUE(loadFrame(sequence, 3).color.has_value());
}

// A flat depth image 1024 mm away and its camera info, stamped `stamp`, on the
// topics of a RealSense's depth camera.
void writeFlatDepthFrame(rosbag::Bag& bag, const ros::Time& stamp) {
  sensor_msgs::Image depth;
  depth.header.stamp = stamp;
  depth.header.frame_id = kOptical;
  depth.width = kW;
  depth.height = kH;
  depth.encoding = "16UC1";
  depth.step = kW * 2;
  depth.data.assign(depth.step * kH, 0);
  for (size_t i = 0; i < depth.data.size(); i += 2) depth.data[i + 1] = 0x04;  // 1024 mm
  bag.write("/camera/depth/image_rect_raw", depth.header.stamp, depth);
  sensor_msgs::CameraInfo info;
  info.header = depth.header;
  info.width = kW;
  info.height = kH;
  info.K = {30, 0, 15.5, 0, 31, 11.5, 0, 0, 1};
  bag.write("/camera/depth/camera_info", depth.header.stamp, info);
}

// Stamps at epoch times (sec 1700000000), where a double resolves only
// ~0.24 us: an image stamped exactly at a tf sample gets that sample's pose,
// also the first and the last (0.1 s past the second went through a double
// to 95 ns before the first tf sample, outside tf).
void writeEpochBag(const fs::path& path) {
  rosbag::Bag bag(path.string(), rosbag::bagmode::Write);
  const auto at = [](int ms) {
    return ros::Time(1700000000u, static_cast<std::uint32_t>(ms) * 1000000u);
  };
  for (int k = 0; k <= 4; ++k) {  // tf from .100 to .300, every 50 ms
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(transformMsg(worldBase(10.0 + 0.05 * k), "world", "base_link", 1.0));
    tf.transforms.back().header.stamp = at(100 + 50 * k);
    bag.write("/tf", at(100 + 50 * k), tf);
  }
  tf2_msgs::TFMessage static_tf;
  static_tf.transforms.push_back(transformMsg(baseCamera(), "base_link", kOptical, 1.0));
  bag.write("/tf_static", at(100), static_tf);
  for (int f = 0; f < 3; ++f) {  // images at .100, .200, .300
    writeFlatDepthFrame(bag, at(100 + 100 * f));
  }
  bag.close();
}

TEST(ImportRosbag, EpochStampsKeepTheirNanoseconds) {
  test::TempDir dir;
  writeEpochBag(dir / "epoch.bag");
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  const ImportReport report =
      importSource(SourceKind::RosBag, dir / "epoch.bag", dir / "seq", options);
  ASSERT_EQ(report.frames_written, 3u) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  expectPosesOfTheMovingBase(sequence, 3, " gets the tf sample at its own stamp");
  // No tolerance: each stamp must be found as it is.
  options.time_tolerance = 0.0;
  const ImportReport exact =
      importSource(SourceKind::RosBag, dir / "epoch.bag", dir / "exact", options);
  EXPECT_EQ(exact.frames_written, 3u) << exact.text();
}

TEST(ImportRosbag, ClockOffsetIsReportedAndCorrectedByTheOffsetOption) {
  test::TempDir dir;
  BagSpec spec;
  spec.image_clock_offset = 1000.0;
  writeBag(dir / "rec.bag", spec);
  const std::string error =
      errorOf([&] { importSource(SourceKind::RosBag, dir / "rec.bag", dir / "seq"); });
  EXPECT_NE(error.find("no transform"), std::string::npos) << error;
  EXPECT_NE(error.find("tf covers 9.950 to 10.300"), std::string::npos) << error;
  // The error quotes the first frame's reason only: the suggestion is in it.
  EXPECT_NE(error.find("the clocks differ by about -1000 s, give it as the time offset option"),
            std::string::npos)
      << error;
  ImportOptions options;
  options.time_offset = -1000.0;
  const ImportReport report =
      importSource(SourceKind::RosBag, dir / "rec.bag", dir / "seq", options);
  EXPECT_EQ(report.frames_written, 4u) << report.text();
  const Sequence sequence = loadSequence(dir / "seq");
  EXPECT_TRUE(sequence.frames[2].T_world_camera.matrix().isApprox(
      (worldBase(10.2) * baseCamera()).matrix(), 1e-6));
}

TEST(ImportRosbag, StampsOutsideRosTimeHaveNoTransform) {
  test::TempDir dir;
  writeBag(dir / "rec.bag", {});
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  // Offsets that move every stamp past what a ROS time holds (2^32 s), one of
  // them past any 64-bit integer, or below 0.
  for (const double offset : {1e10, 1e30, -1e30}) {
    options.time_offset = offset;
    const std::string error =
        errorOf([&] { importSource(SourceKind::RosBag, dir / "rec.bag", dir / "seq", options); });
    EXPECT_NE(error.find("no transform from 'world' to 'camera_depth_optical_frame'"),
              std::string::npos)
        << offset << ": " << error;
    EXPECT_NE(error.find("tf covers 9.950 to 10.300"), std::string::npos) << error;
    EXPECT_FALSE(fs::exists(dir / "seq"));
  }
  // A tolerance reaching past ROS time: the frame outside tf's range is still
  // the only one skipped.
  options.time_offset = 0.0;
  options.time_tolerance = 1e30;
  const ImportReport report =
      importSource(SourceKind::RosBag, dir / "rec.bag", dir / "seq", options);
  EXPECT_EQ(report.frames_written, 4u) << report.text();
  ASSERT_EQ(report.skipped.size(), 1u) << report.text();
  EXPECT_NE(report.skipped[0].reason.find("no transform"), std::string::npos)
      << report.skipped[0].reason;
}

// A tf sample: a pure translation (x, y) of `child` in `parent`.
struct TfSample {
  std::string parent, child;
  double stamp = 0.0;
  double x = 0.0, y = 0.0;
};

// A bag whose /tf holds `samples` (each in its own message), with
// base_link -> the optical frame static (identity), and a 1.024 m depth image
// with its camera info at each of `image_stamps`.
void writeTfBag(const fs::path& path, const std::vector<TfSample>& samples,
                const std::vector<double>& image_stamps) {
  rosbag::Bag bag(path.string(), rosbag::bagmode::Write);
  for (const TfSample& s : samples) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(s.x, s.y, 0.0);
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(transformMsg(T, s.parent, s.child, s.stamp));
    bag.write("/tf", ros::Time(s.stamp), tf);
  }
  tf2_msgs::TFMessage static_tf;
  static_tf.transforms.push_back(
      transformMsg(Eigen::Isometry3d::Identity(), "base_link", kOptical, samples.front().stamp));
  static_tf.transforms.push_back(
      transformMsg(Eigen::Isometry3d::Identity(), "world", "anchor", samples.front().stamp));
  bag.write("/tf_static", ros::Time(samples.front().stamp), static_tf);
  for (const double stamp : image_stamps) {
    writeFlatDepthFrame(bag, ros::Time(stamp));
  }
  bag.close();
}

// /tf samples 2 s apart (y from 0 to 2): a frame between them, not within the
// time tolerance of either, is skipped naming the link, the samples and the
// gap; --max-pose-gap 3 (or 2: the gap is not more than it) interpolates it.
TEST(ImportRosbag, APoseAcrossAGapInTfIsSkippedUnlessTheMaxPoseGapAllowsIt) {
  test::TempDir dir;
  writeTfBag(dir / "gap.bag",
             {{"world", "base_link", 100.0, 0.0, 0.0}, {"world", "base_link", 102.0, 0.0, 2.0}},
             {100.0, 101.0, 101.99, 102.0});
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  const ImportReport report =
      importSource(SourceKind::RosBag, dir / "gap.bag", dir / "seq", options);
  EXPECT_EQ(report.frames_written, 3u) << report.text();
  ASSERT_EQ(report.skipped.size(), 1u) << report.text();
  EXPECT_EQ(report.skipped[0].frame, "depth@101.000");
  const std::string& reason = report.skipped[0].reason;
  for (const char* part :
       {"no pose at 101.000: the tf link 'world' -> 'base_link' has no sample within 0.02 s of it",
        "its samples around it, at 100.000 and 102.000, are 2 s apart",
        "more than the maximum pose gap of 0.5 s"})
    EXPECT_NE(reason.find(part), std::string::npos) << part << "\n" << reason;
  // Within the tolerance of a sample (101.99), the frame is kept across the gap.
  Sequence sequence = loadSequence(dir / "seq");
  ASSERT_EQ(sequence.frames.size(), 3u);
  EXPECT_NEAR(sequence.frames[1].T_world_camera.translation().y(), 1.99, 1e-6);

  // The chain is the same from a fixed frame beside the camera's (world -> anchor static).
  options.rosbag.fixed_frame = "anchor";
  const ImportReport beside =
      importSource(SourceKind::RosBag, dir / "gap.bag", dir / "beside", options);
  EXPECT_EQ(beside.frames_written, 3u) << beside.text();
  ASSERT_EQ(beside.skipped.size(), 1u) << beside.text();
  EXPECT_NE(beside.skipped[0].reason.find("'world' -> 'base_link'"), std::string::npos)
      << beside.skipped[0].reason;
  options.rosbag.fixed_frame.clear();

  for (const double allowed : {3.0, 2.0}) {
    options.rosbag.max_pose_gap = allowed;
    const fs::path out = dir / ("allowed" + std::to_string(static_cast<int>(allowed)));
    const ImportReport all = importSource(SourceKind::RosBag, dir / "gap.bag", out, options);
    EXPECT_EQ(all.frames_written, 4u) << allowed << "\n" << all.text();
    EXPECT_TRUE(all.skipped.empty()) << all.text();
    sequence = loadSequence(out);
    ASSERT_EQ(sequence.frames.size(), 4u);
    EXPECT_NEAR(sequence.frames[1].T_world_camera.translation().y(), 1.0, 1e-6);
    EXPECT_NEAR(sequence.frames[1].stamp.value_or(0.0), 101.0, 1e-9);
  }

  // Not a positive finite number of seconds: refused, naming the option.
  for (const double bad : {0.0, -1.0, double(INFINITY), double(NAN)}) {
    options.rosbag.max_pose_gap = bad;
    const std::string error =
        errorOf([&] { importSource(SourceKind::RosBag, dir / "gap.bag", dir / "bad", options); });
    EXPECT_NE(error.find("max_pose_gap: expected a positive number of seconds"), std::string::npos)
        << bad << ": " << error;
    EXPECT_FALSE(fs::exists(dir / "bad"));
  }
}

// Gaps that hide no motion are no reason to skip a frame: a slow link whose
// samples around the frame are equal (an identity world -> odom at 1 Hz),
// and a link /tf_static also gives. Both refused every frame.
TEST(ImportRosbag, GapsThatHideNoMotionKeepTheirFrames) {
  test::TempDir dir;
  std::vector<TfSample> samples;
  for (int i = 0; i <= 20; ++i) samples.push_back({"odom", "base_link", 100.0 + 0.1 * i, 0.1 * i});
  samples.push_back({"world", "odom", 100.0, 0.0, 0.0});
  samples.push_back({"world", "odom", 101.0, 0.0, 0.0});
  samples.push_back({"world", "odom", 102.0, 0.0, 0.0});
  writeTfBag(dir / "slow.bag", samples, {100.25, 100.55, 101.45, 101.75});
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  const ImportReport slow =
      importSource(SourceKind::RosBag, dir / "slow.bag", dir / "slow", options);
  EXPECT_EQ(slow.frames_written, 4u) << slow.text();
  EXPECT_TRUE(slow.skipped.empty()) << slow.text();

  // Moved across its gap, the same slow link skips the frames between.
  samples[samples.size() - 2].y = 0.5;
  writeTfBag(dir / "moved.bag", samples, {100.25, 100.55, 101.45, 101.75});
  const std::string moved =
      errorOf([&] { importSource(SourceKind::RosBag, dir / "moved.bag", dir / "moved", options); });
  EXPECT_NE(moved.find("the tf link 'world' -> 'odom' has no sample within"), std::string::npos)
      << moved;

  // world -> anchor is on /tf_static (writeTfBag) and also on /tf 2 s apart.
  writeTfBag(dir / "both.bag",
             {{"world", "anchor", 100.0, 0.0, 0.0},
              {"world", "anchor", 102.0, 0.0, 0.0},
              {"anchor", "base_link", 100.0, 0.0, 0.0},
              {"anchor", "base_link", 100.4, 0.0, 0.4},
              {"anchor", "base_link", 100.8, 0.0, 0.8}},
             {100.2, 100.6});
  const ImportReport both =
      importSource(SourceKind::RosBag, dir / "both.bag", dir / "both", options);
  EXPECT_EQ(both.frames_written, 2u) << both.text();
}

// tf at 30 Hz on two moving links of the chain (world -> odom, odom ->
// base_link, out of phase) and a link outside it with a 2 s gap: images
// midway between samples are all imported, also with no time tolerance.
TEST(ImportRosbag, ImagesBetweenSamplesOf30HzTfAreAllImported) {
  test::TempDir dir;
  std::vector<TfSample> samples;
  for (int k = 0; k <= 60; ++k) {
    const double t = 10.0 + k / 30.0;
    samples.push_back({"world", "odom", t, 0.0, 0.5 * (t - 10.0)});
    if (k < 60) samples.push_back({"odom", "base_link", t + 0.01, 0.2 * (t + 0.01 - 10.0), 0.0});
  }
  samples.push_back({"world", "marker", 10.0, 1.0, 1.0});
  samples.push_back({"world", "marker", 12.0, 1.0, 1.0});
  std::vector<double> images;
  for (int j = 0; j < 30; ++j) images.push_back(10.0 + (2 * j + 1) / 60.0);
  writeTfBag(dir / "tf30.bag", samples, images);
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  for (const double tolerance : {0.02, 0.0}) {
    SCOPED_TRACE(tolerance);
    options.time_tolerance = tolerance;
    const fs::path out = dir / (tolerance > 0 ? "seq" : "exact");
    const ImportReport report = importSource(SourceKind::RosBag, dir / "tf30.bag", out, options);
    EXPECT_EQ(report.frames_written, 30u) << report.text();
    EXPECT_TRUE(report.skipped.empty()) << report.text();
    const Sequence sequence = loadSequence(out);
    ASSERT_EQ(sequence.frames.size(), 30u);
    for (size_t f = 0; f < 30; ++f) {
      const Eigen::Vector3d t = sequence.frames[f].T_world_camera.translation();
      EXPECT_NEAR(t.x(), 0.2 * (images[f] - 10.0), 1e-6) << f;
      EXPECT_NEAR(t.y(), 0.5 * (images[f] - 10.0), 1e-6) << f;
    }
  }
}

// A top-level record of a bag: its offset, header length and data offset
// (a test's own walk of format 2.0 records).
struct BagRecord {
  size_t at = 0, header_bytes = 0, data_at = 0;
};
std::uint32_t u32At(const std::string& bytes, size_t at) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + at, 4);  // little-endian, as the bag and this machine
  return value;
}
// Every top-level record of `op` in bag bytes.
std::vector<BagRecord> recordsOf(const std::string& bytes, std::uint8_t op) {
  std::vector<BagRecord> found;
  for (size_t at = 13; at + 8 <= bytes.size();) {
    const size_t header_bytes = u32At(bytes, at);
    const std::string header = bytes.substr(at + 4, header_bytes);
    const size_t data_at = at + 8 + header_bytes;
    const size_t op_at = header.find(std::string("op=") + static_cast<char>(op));
    if (op_at != std::string::npos && op_at >= 4 && u32At(header, op_at - 4) == 4)
      found.push_back(BagRecord{at, header_bytes, data_at});
    at = data_at + u32At(bytes, at + 4 + header_bytes);
  }
  return found;
}

// The first of them.
std::optional<BagRecord> firstRecord(const std::string& bytes, std::uint8_t op) {
  const std::vector<BagRecord> found = recordsOf(bytes, op);
  if (found.empty()) return std::nullopt;
  return found.front();
}

// Damaged lengths and offsets in a bag's records are an error naming the
// file and the byte, not a crash of the bag library (which trusts them: it
// read past its buffers or asked for gigabytes and aborted).
TEST(ImportRosbag, DamagedRecordStructureIsAnErrorNotACrash) {
  test::TempDir dir;
  writeBag(dir / "good.bag", BagSpec{});
  const std::string good = test::slurp(dir / "good.bag");
  const auto index = firstRecord(good, 0x04);
  ASSERT_TRUE(index) << "an index record";
  auto damaged = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return errorOf([&] { importSource(SourceKind::RosBag, dir / name, dir / ("out-" + name)); });
  };
  // A header length of 4 GiB right after the magic.
  std::string tiny = "#ROSBAG V2.0\n";
  tiny += std::string(4, '\xff');
  std::string error = damaged("tiny.bag", tiny);
  EXPECT_NE(
      error.find("tiny.bag: bag: expected a readable ROS 1 bag (format 2.0), found a record "
                 "header of 4294967295 bytes that does not fit in what follows it at byte 13"),
      std::string::npos)
      << error;
  // An index record's header one byte longer than its fields.
  std::string longer = good;
  const std::uint32_t header_bytes = static_cast<std::uint32_t>(index->header_bytes + 1);
  std::memcpy(longer.data() + index->at, &header_bytes, 4);
  error = damaged("header.bag", longer);
  EXPECT_NE(error.find("at byte " + std::to_string(index->at)), std::string::npos) << error;
  // An index entry pointing far outside its chunk.
  std::string outside = good;
  const std::uint32_t offset = 0x7fffffff;
  std::memcpy(outside.data() + index->data_at + 8, &offset, 4);  // entry 0: time, then offset
  error = damaged("offset.bag", outside);
  EXPECT_NE(error.find("an index entry pointing outside the records of its chunk"),
            std::string::npos)
      << error;
  // The intact bag imports.
  EXPECT_EQ(importSource(SourceKind::RosBag, dir / "good.bag", dir / "good").frames_written, 4u);
}

// Adds `delta` to the 8-byte field `name` (e.g. "index_pos=") in the header of `record`.
void shiftField(std::string& bytes, const BagRecord& record, const std::string& name,
                std::int64_t delta, size_t only_beyond = 0) {
  const size_t at = bytes.find(name, record.at + 4);
  ASSERT_LT(at, record.data_at) << name;
  std::uint64_t value = 0;
  std::memcpy(&value, bytes.data() + at + name.size(), 8);
  if (value <= only_beyond) return;
  value += delta;
  std::memcpy(bytes.data() + at + name.size(), &value, 8);
}

// The bag with the data of its chunk record `chunk` replaced by `data`; what
// follows moves, and the positions that point past it (the bag header's
// index position, later chunks' positions) move with it.
std::string withChunkData(const std::string& bag, const BagRecord& chunk, const std::string& data) {
  const std::uint32_t old_bytes = u32At(bag, chunk.data_at - 4);
  const auto new_bytes = static_cast<std::uint32_t>(data.size());
  std::string out = bag.substr(0, chunk.data_at - 4);
  out.append(reinterpret_cast<const char*>(&new_bytes), 4);
  out += data;
  out += bag.substr(chunk.data_at + old_bytes);
  const std::int64_t delta = static_cast<std::int64_t>(new_bytes) - old_bytes;
  shiftField(out, recordsOf(out, 0x03).at(0), "index_pos=", delta);
  for (const BagRecord& info : recordsOf(out, 0x06))
    shiftField(out, info, "chunk_pos=", delta, chunk.at);
  return out;
}

// The records inside a compressed chunk are checked as those outside: the
// chunk is decompressed first (bz2 and lz4, as the bag library reads them).
TEST(ImportRosbag, DamagedRecordsInsideACompressedChunkAreAnErrorNotACrash) {
  test::TempDir dir;
  for (const auto compression : {rosbag::compression::BZ2, rosbag::compression::LZ4}) {
    BagSpec spec;
    spec.compression = compression;
    writeBag(dir / "packed.bag", spec);
    EXPECT_EQ(importSource(SourceKind::RosBag, dir / "packed.bag", dir / "packed").frames_written,
              4u)
        << "an intact compressed bag imports";
    fs::remove_all(dir / "packed");
  }
  BagSpec spec;
  spec.compression = rosbag::compression::BZ2;
  writeBag(dir / "good.bag", spec);
  const std::string good = test::slurp(dir / "good.bag");
  const auto chunk = firstRecord(good, 0x05);
  ASSERT_TRUE(chunk) << "a chunk record";
  const std::uint32_t packed_bytes = u32At(good, chunk->data_at - 4);
  std::string packed = good.substr(chunk->data_at, packed_bytes);
  // Its first record's header length made 4 GiB, packed again.
  std::vector<char> data(16u << 20);
  unsigned int data_bytes = static_cast<unsigned int>(data.size());
  ASSERT_EQ(BZ2_bzBuffToBuffDecompress(data.data(), &data_bytes, packed.data(), packed_bytes, 0, 0),
            BZ_OK);
  std::memset(data.data(), 0xff, 4);
  std::vector<char> repacked(packed_bytes + 1024);
  unsigned int repacked_bytes = static_cast<unsigned int>(repacked.size());
  ASSERT_EQ(
      BZ2_bzBuffToBuffCompress(repacked.data(), &repacked_bytes, data.data(), data_bytes, 9, 0, 0),
      BZ_OK);
  std::ofstream(dir / "inner.bag", std::ios::binary)
      << withChunkData(good, *chunk, std::string(repacked.data(), repacked_bytes));
  // The same chunk packed again without damage: the rebuilt bag imports.
  data_bytes = static_cast<unsigned int>(data.size());
  ASSERT_EQ(BZ2_bzBuffToBuffDecompress(data.data(), &data_bytes, packed.data(), packed_bytes, 0, 0),
            BZ_OK);
  repacked_bytes = static_cast<unsigned int>(repacked.size());
  ASSERT_EQ(
      BZ2_bzBuffToBuffCompress(repacked.data(), &repacked_bytes, data.data(), data_bytes, 9, 0, 0),
      BZ_OK);
  std::ofstream(dir / "repacked.bag", std::ios::binary)
      << withChunkData(good, *chunk, std::string(repacked.data(), repacked_bytes));
  EXPECT_EQ(importSource(SourceKind::RosBag, dir / "repacked.bag", dir / "repacked").frames_written,
            4u);
  std::string error =
      errorOf([&] { importSource(SourceKind::RosBag, dir / "inner.bag", dir / "inner"); });
  EXPECT_NE(error.find("inner.bag: bag: expected a readable ROS 1 bag (format 2.0), found a "
                       "record header of 4294967295 bytes that does not fit in what follows it "
                       "at byte 0 of the chunk decompressed from the record at byte " +
                       std::to_string(chunk->at)),
            std::string::npos)
      << error;
  EXPECT_FALSE(fs::exists(dir / "inner"));
  // Compressed bytes that are not bz2 at all.
  std::string garbled = good;
  std::memset(garbled.data() + chunk->data_at, 'x', 16);
  std::ofstream(dir / "garbled.bag", std::ios::binary) << garbled;
  error = errorOf([&] { importSource(SourceKind::RosBag, dir / "garbled.bag", dir / "g"); });
  EXPECT_NE(error.find("a bz2 chunk with data that does not decompress as bz2 at byte " +
                       std::to_string(chunk->at)),
            std::string::npos)
      << error;
}

// Replaces the 4-byte length `from` that follows `before` at its `nth`
// occurrence in `bytes` with `to`.
void patchLength(std::string& bytes, const std::string& before, std::uint32_t from,
                 std::uint32_t to, int nth) {
  std::string pattern = before;
  pattern.append(reinterpret_cast<const char*>(&from), 4);
  size_t at = std::string::npos;
  for (int i = 0; i <= nth; ++i) {
    at = bytes.find(pattern, at == std::string::npos ? 0 : at + 1);
    ASSERT_NE(at, std::string::npos) << "occurrence " << i;
  }
  std::memcpy(bytes.data() + at + before.size(), &to, 4);
}

// A corrupted array length inside a message (the record around it intact):
// the ROS deserialiser allocated what it claims (up to gigabytes) before it
// found the message too short. The message is left out, naming its topic
// and field.
TEST(ImportRosbag, ArrayLengthsBeyondTheMessageLeaveItOut) {
  test::TempDir dir;
  BagSpec spec;
  spec.info_projection = true;  // D holds 5 values
  spec.proba_channels = 0;
  writeBag(dir / "good.bag", spec);
  std::string bytes = test::slurp(dir / "good.bag");
  // The first camera info's D (after an empty distortion model): 16 Mi values.
  const std::uint32_t info_size[3] = {kH, kW, 0};  // height, width, distortion model length
  patchLength(bytes, std::string(reinterpret_cast<const char*>(info_size), 12), 5, 1u << 24, 0);
  // Frame 1's depth data (after encoding, is_bigendian and step): 256 MiB.
  const std::uint32_t step = kW * 2;
  patchLength(bytes,
              std::string("16UC1") + '\0' + std::string(reinterpret_cast<const char*>(&step), 4),
              kW * kH * 2, 1u << 28, 1);
  std::ofstream(dir / "lengths.bag", std::ios::binary) << bytes;
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  const ImportReport report =
      importSource(SourceKind::RosBag, dir / "lengths.bag", dir / "seq", options);
  EXPECT_EQ(report.frames_written, 3u) << report.text();
  EXPECT_TRUE(anyNote(report,
                      "1 messages on /camera/depth/camera_info were ignored: a length inside them "
                      "does not fit in the message (the first: /camera/depth/camera_info: D: "
                      "expected a length that fits in the 305 bytes left in the message, found "
                      "16777216 float64 values (134217728 bytes))"))
      << report.text();
  bool depth_reported = false;
  for (const auto& s : report.skipped)
    depth_reported |= s.frame == "depth@10.100" &&
                      s.reason ==
                          "/camera/depth/image_rect_raw: depth data: expected a length that fits "
                          "in the 1536 bytes left in the message, found 268435456 bytes";
  EXPECT_TRUE(depth_reported) << report.text();
}

TEST(ImportRosbag, MalformedBags) {
  test::TempDir dir;
  // Two depth topics: ambiguous unless one is chosen.
  BagSpec two;
  two.second_depth_topic = true;
  writeBag(dir / "two.bag", two);
  std::string error =
      errorOf([&] { importSource(SourceKind::RosBag, dir / "two.bag", dir / "a"); });
  EXPECT_NE(error.find("several: /camera/depth/image_raw, /camera/depth/image_rect_raw"),
            std::string::npos)
      << error;
  ImportOptions chosen;
  chosen.rosbag.depth_topic = "/camera/depth/image_raw";
  EXPECT_EQ(importSource(SourceKind::RosBag, dir / "two.bag", dir / "a", chosen).frames_written,
            4u);
  chosen.rosbag.depth_topic = "/nope";
  error = errorOf([&] { importSource(SourceKind::RosBag, dir / "two.bag", dir / "b", chosen); });
  EXPECT_NE(error.find("'/nope' is not in it"), std::string::npos) << error;

  // No camera info: intrinsics needed.
  BagSpec no_info;
  no_info.camera_info = false;
  writeBag(dir / "noinfo.bag", no_info);
  error = errorOf([&] { importSource(SourceKind::RosBag, dir / "noinfo.bag", dir / "c"); });
  EXPECT_NE(error.find("--intrinsics"), std::string::npos) << error;
  ImportOptions with_intrinsics;
  with_intrinsics.intrinsics = parseIntrinsics("30,31,15.5,11.5");
  EXPECT_EQ(importSource(SourceKind::RosBag, dir / "noinfo.bag", dir / "c", with_intrinsics)
                .frames_written,
            4u);

  // A depth message whose step is too small: that frame is skipped with the reason.
  BagSpec bad_step;
  bad_step.bad_step_in_frame_2 = true;
  writeBag(dir / "step.bag", bad_step);
  const ImportReport report = importSource(SourceKind::RosBag, dir / "step.bag", dir / "d");
  EXPECT_EQ(report.frames_written, 3u);
  bool step_reported = false;
  for (const auto& s : report.skipped) step_reported |= s.reason.find("step") != std::string::npos;
  EXPECT_TRUE(step_reported) << report.text();

  // A label list that does not match the probability channels.
  ImportOptions labels;
  labels.labels = apc2016Labels();
  error = errorOf([&] { importSource(SourceKind::RosBag, dir / "step.bag", dir / "e", labels); });
  EXPECT_NE(error.find("one label per probability channel: 3"), std::string::npos) << error;

  // 16-bit probabilities are read as value / 65535.
  BagSpec wide;
  wide.proba_encoding = "16UC";
  writeBag(dir / "wide.bag", wide);
  ImportOptions options;
  options.depth_filter.flying_pixels = false;
  ASSERT_EQ(importSource(SourceKind::RosBag, dir / "wide.bag", dir / "f", options).frames_written,
            4u);
  const FrameData frame = loadFrame(loadSequence(dir / "f"), 0);
  EXPECT_NEAR(frame.proba->pixel(1, 1)[1], 0.8f, 1e-3);

  // Probabilities at half resolution are resampled; another aspect ratio is refused per frame.
  BagSpec half;
  half.proba_width = kW / 2;
  half.proba_height = kH / 2;
  writeBag(dir / "half.bag", half);
  const ImportReport resampled =
      importSource(SourceKind::RosBag, dir / "half.bag", dir / "h", options);
  ASSERT_EQ(resampled.frames_written, 4u) << resampled.text();
  EXPECT_TRUE(anyNote(resampled, "probability images of 16 x 12 resampled to the depth camera"))
      << resampled.text();
  const FrameData half_frame = loadFrame(loadSequence(dir / "h"), 0);
  EXPECT_NEAR(half_frame.proba->pixel(2, 2)[1], 0.8f, 1e-3);
  EXPECT_NEAR(half_frame.proba->pixel(kW - 3, 2)[2], 0.8f, 1e-3);
  BagSpec odd;
  odd.proba_width = kW;
  odd.proba_height = kH / 2;
  writeBag(dir / "odd.bag", odd);
  error = errorOf([&] { importSource(SourceKind::RosBag, dir / "odd.bag", dir / "o", options); });
  EXPECT_NE(error.find("the probability image is 32 x 12, the depth image 32 x 24"),
            std::string::npos)
      << error;

  // A bag without tf.
  {
    rosbag::Bag bag((dir / "notf.bag").string(), rosbag::bagmode::Write);
    sensor_msgs::Image depth;
    depth.header.stamp = ros::Time(1.0);
    depth.header.frame_id = kOptical;
    depth.width = 2;
    depth.height = 1;
    depth.encoding = "16UC1";
    depth.step = 4;
    depth.data = {0xe8, 0x03, 0xe8, 0x03};
    bag.write("/depth", depth.header.stamp, depth);
  }
  error = errorOf(
      [&] { importSource(SourceKind::RosBag, dir / "notf.bag", dir / "g", with_intrinsics); });
  EXPECT_NE(error.find("/tf or /tf_static"), std::string::npos) << error;
}

#else

TEST(ImportRosbag, BuildWithoutBagSupportSaysSo) { EXPECT_FALSE(rosbagSupported()); }

#endif

}  // namespace
}  // namespace lom
