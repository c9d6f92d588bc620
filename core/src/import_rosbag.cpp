// ROS 1 bag import: depth, colour, camera info, probability or label images and
// the camera pose from /tf + /tf_static (tf2 BufferCore), matched by time stamp.
// This is the only file that includes ROS headers; without LOM_WITH_ROSBAG it
// only says that the build has no bag support.
#include "import_internal.hpp"

#ifdef LOM_WITH_ROSBAG

#include <console_bridge/console.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>  // the IMREAD_ flags only
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "jpeg_decode.hpp"
#include "other_images.hpp"
#include "png_check.hpp"
#include "png_decode.hpp"
#include "rosbag_check.hpp"
#include "rosbag_topics.hpp"

// Header-only views of image messages: the first pass reads stamps and
// encodings without copying pixel data.
namespace lom_rosbag {
struct ImageMeta {
  std_msgs::Header header;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::string encoding;
};
struct CompressedMeta {
  std_msgs::Header header;
  std::string format;
};
}  // namespace lom_rosbag

namespace ros {
namespace message_traits {
#define LOM_ROSBAG_ANY_TRAITS(T)                       \
  template <>                                          \
  struct MD5Sum<T> {                                   \
    static const char* value() { return "*"; }         \
    static const char* value(const T&) { return "*"; } \
  };                                                   \
  template <>                                          \
  struct DataType<T> {                                 \
    static const char* value() { return "*"; }         \
    static const char* value(const T&) { return "*"; } \
  };                                                   \
  template <>                                          \
  struct Definition<T> {                               \
    static const char* value() { return ""; }          \
    static const char* value(const T&) { return ""; }  \
  };
LOM_ROSBAG_ANY_TRAITS(lom_rosbag::ImageMeta)
LOM_ROSBAG_ANY_TRAITS(lom_rosbag::CompressedMeta)
#undef LOM_ROSBAG_ANY_TRAITS
}  // namespace message_traits
namespace serialization {
template <>
struct Serializer<lom_rosbag::ImageMeta> {
  template <typename Stream>
  static void read(Stream& stream, lom_rosbag::ImageMeta& m) {
    stream.next(m.header);
    stream.next(m.height);
    stream.next(m.width);
    stream.next(m.encoding);
  }
};
template <>
struct Serializer<lom_rosbag::CompressedMeta> {
  template <typename Stream>
  static void read(Stream& stream, lom_rosbag::CompressedMeta& m) {
    stream.next(m.header);
    stream.next(m.format);
  }
};
}  // namespace serialization
}  // namespace ros

namespace lom::import_detail {

namespace {

using bag::ChosenTopics;
using bag::contains;
using bag::ImageEntry;
using bag::lower;
using bag::multiChannels;
using bag::stampText;
using bag::Topic;

std::string stripSlash(std::string frame) {
  while (!frame.empty() && frame.front() == '/') frame.erase(frame.begin());
  return frame;
}

// console_bridge (rosbag, tf2) prints to stderr; problems are reported instead.
class QuietConsole {
 public:
  QuietConsole() : level_(console_bridge::getLogLevel()) {
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  }
  ~QuietConsole() { console_bridge::setLogLevel(level_); }
  QuietConsole(const QuietConsole&) = delete;
  QuietConsole& operator=(const QuietConsole&) = delete;

 private:
  console_bridge::LogLevel level_;
};

// ----- decoding -------------------------------------------------------------

template <typename T>
T readValue(const std::uint8_t* p, bool big_endian) {
  T value;
  std::uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (big_endian) std::reverse(bytes, bytes + sizeof(T));
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

void checkLayout(const sensor_msgs::Image& image, size_t bytes_per_pixel) {
  const size_t row = static_cast<size_t>(image.width) * bytes_per_pixel;
  if (image.width == 0 || image.height == 0) throw Error("", "image", "a non-empty image", "0 x 0");
  if (image.step < row)
    throw Error("", "step", "at least width x bytes per pixel = " + std::to_string(row),
                std::to_string(image.step));
  if (image.data.size() < static_cast<size_t>(image.step) * image.height)
    throw Error("", "data",
                "step x height = " +
                    std::to_string(static_cast<size_t>(image.step) * image.height) + " bytes",
                std::to_string(image.data.size()) + " bytes");
}

DepthImage decodeDepth(const sensor_msgs::Image& image, double millimetre_scale) {
  const std::string enc = lower(image.encoding);
  const bool is_float = enc == "32fc1";
  checkLayout(image, is_float ? 4 : 2);
  DepthImage depth;
  depth.width = static_cast<int>(image.width);
  depth.height = static_cast<int>(image.height);
  depth.metres.resize(static_cast<size_t>(depth.width) * depth.height);
  const bool big = image.is_bigendian != 0;
  for (int v = 0; v < depth.height; ++v) {
    const std::uint8_t* row = image.data.data() + static_cast<size_t>(v) * image.step;
    float* out = depth.metres.data() + static_cast<size_t>(v) * depth.width;
    for (int u = 0; u < depth.width; ++u)
      out[u] =
          is_float
              ? readValue<float>(row + 4 * u, big)
              : static_cast<float>(readValue<std::uint16_t>(row + 2 * u, big) * millimetre_scale);
  }
  return depth;
}

// Throws lom::Error (field "PNG data" or "JPEG data", no file: the caller
// names the topic) for a damaged PNG or JPEG, decoded without libpng or
// libjpeg printing about it; other formats are only decoded.
cv::Mat decodeBytes(const std::vector<std::uint8_t>& data, size_t offset, int flags) {
  if (data.size() <= offset) return {};
  const std::uint8_t* bytes = data.data() + offset;
  const size_t size = data.size() - offset;
  const bool png = hasPngSignature(bytes, size);
  if (png || hasJpegSignature(bytes, size)) {
    cv::Mat image = png ? decodePng(bytes, size, "") : decodeJpeg(bytes, size, "");
    if (flags == cv::IMREAD_UNCHANGED || image.empty()) return image;
    // As cv::imdecode would decode it with `flags` (colour: 8-bit BGR, of a
    // 16-bit PNG the high bytes, as libpng's png_set_strip_16).
    if (image.depth() == CV_16U) {
      cv::Mat high(image.rows, image.cols, CV_MAKETYPE(CV_8U, image.channels()));
      for (int v = 0; v < image.rows; ++v) {
        const auto* in = image.ptr<std::uint16_t>(v);
        auto* out = high.ptr<std::uint8_t>(v);
        for (int i = 0; i < image.cols * image.channels(); ++i)
          out[i] = static_cast<std::uint8_t>(in[i] >> 8);
      }
      image = high;
    }
    cv::Mat bgr;
    if (image.channels() == 1)
      cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
    else if (image.channels() == 4)
      cv::cvtColor(image, bgr, cv::COLOR_BGRA2BGR);
    else
      bgr = image;
    return bgr;
  }
  return decodeOtherImage(bytes, size, flags, "a compressed image of the bag");
}

// compressed_depth_image_transport: optional 12-byte header (format, quantA, quantB), then PNG.
DepthImage decodeCompressedDepth(const sensor_msgs::CompressedImage& message,
                                 double millimetre_scale) {
  static const std::uint8_t kPng[4] = {0x89, 'P', 'N', 'G'};
  const auto& data = message.data;
  size_t offset = 0;
  float quant_a = 0.0f, quant_b = 0.0f;
  if (data.size() >= 16 && std::memcmp(data.data(), kPng, 4) != 0) {
    offset = 12;
    std::memcpy(&quant_a, data.data() + 4, 4);
    std::memcpy(&quant_b, data.data() + 8, 4);
  }
  const cv::Mat mat = decodeBytes(data, offset, cv::IMREAD_UNCHANGED);
  if (mat.empty() || mat.type() != CV_16UC1)
    throw Error("", "compressedDepth", "a 16-bit PNG after the header",
                "data OpenCV cannot decode");
  const bool inverse = contains(lower(message.format), "32fc1");
  DepthImage depth;
  depth.width = mat.cols;
  depth.height = mat.rows;
  depth.metres.resize(static_cast<size_t>(mat.cols) * mat.rows);
  for (int v = 0; v < mat.rows; ++v) {
    const auto* row = mat.ptr<std::uint16_t>(v);
    for (int u = 0; u < mat.cols; ++u) {
      float z = 0.0f;
      if (row[u] != 0)
        z = inverse ? quant_a / (static_cast<float>(row[u]) - quant_b)
                    : static_cast<float>(row[u] * millimetre_scale);
      depth.metres[static_cast<size_t>(v) * mat.cols + u] = z;
    }
  }
  return depth;
}

ColorImage colorFromMat(const cv::Mat& bgr_or_grey) {
  cv::Mat rgb;
  if (bgr_or_grey.channels() == 1)
    cv::cvtColor(bgr_or_grey, rgb, cv::COLOR_GRAY2RGB);
  else
    cv::cvtColor(bgr_or_grey, rgb, cv::COLOR_BGR2RGB);
  ColorImage color;
  color.width = rgb.cols;
  color.height = rgb.rows;
  color.rgb.resize(static_cast<size_t>(rgb.cols) * rgb.rows * 3);
  for (int v = 0; v < rgb.rows; ++v)
    std::memcpy(color.rgb.data() + static_cast<size_t>(v) * rgb.cols * 3, rgb.ptr<std::uint8_t>(v),
                static_cast<size_t>(rgb.cols) * 3);
  return color;
}

ColorImage decodeColor(const sensor_msgs::Image& image) {
  const std::string enc = lower(image.encoding);
  const int channels = enc == "mono8" ? 1 : (enc == "rgba8" || enc == "bgra8") ? 4 : 3;
  checkLayout(image, static_cast<size_t>(channels));
  ColorImage color;
  color.width = static_cast<int>(image.width);
  color.height = static_cast<int>(image.height);
  color.rgb.resize(static_cast<size_t>(color.width) * color.height * 3);
  const bool bgr = enc == "bgr8" || enc == "bgra8" || enc == "8uc3";
  for (int v = 0; v < color.height; ++v) {
    const std::uint8_t* row = image.data.data() + static_cast<size_t>(v) * image.step;
    std::uint8_t* out = color.rgb.data() + static_cast<size_t>(v) * color.width * 3;
    for (int u = 0; u < color.width; ++u) {
      const std::uint8_t* p = row + static_cast<size_t>(u) * channels;
      if (channels == 1) {
        out[3 * u] = out[3 * u + 1] = out[3 * u + 2] = p[0];
      } else {
        out[3 * u] = bgr ? p[2] : p[0];
        out[3 * u + 1] = p[1];
        out[3 * u + 2] = bgr ? p[0] : p[2];
      }
    }
  }
  return color;
}

ColorImage decodeCompressedColor(const sensor_msgs::CompressedImage& message) {
  const cv::Mat mat = decodeBytes(message.data, 0, cv::IMREAD_COLOR);
  if (mat.empty())
    throw Error("", "CompressedImage", "JPEG or PNG data", "data OpenCV cannot decode");
  return colorFromMat(mat);
}

ProbabilityImage decodeProba(const sensor_msgs::Image& image, size_t* clamped) {
  int bytes = 0;
  const int channels = multiChannels(image.encoding, bytes);
  if (channels <= 0)
    throw Error("", "encoding", "32FC(N), 16UC(N) or 8UC(N) probabilities", image.encoding);
  checkLayout(image, static_cast<size_t>(channels) * bytes);
  ProbabilityImage proba;
  proba.width = static_cast<int>(image.width);
  proba.height = static_cast<int>(image.height);
  proba.channels = channels;
  for (int c = 0; c < channels; ++c) proba.channel_labels.push_back(c);
  proba.values.resize(static_cast<size_t>(proba.width) * proba.height * channels);
  const bool big = image.is_bigendian != 0;
  float* out = proba.values.data();
  for (int v = 0; v < proba.height; ++v) {
    const std::uint8_t* row = image.data.data() + static_cast<size_t>(v) * image.step;
    for (int i = 0; i < proba.width * channels; ++i) {
      float p;
      if (bytes == 4)
        p = readValue<float>(row + 4 * i, big);
      else if (bytes == 2)
        p = readValue<std::uint16_t>(row + 2 * i, big) / 65535.0f;
      else
        p = row[i] / 255.0f;
      if (!std::isfinite(p) || p < 0.0f || p > 1.0f) {
        ++*clamped;
        p = std::isfinite(p) ? std::clamp(p, 0.0f, 1.0f) : 0.0f;
      }
      *out++ = p;
    }
  }
  return proba;
}

LabelImage decodeLabel(const sensor_msgs::Image& image) {
  const std::string enc = lower(image.encoding);
  const bool wide = enc == "mono16" || enc == "16uc1";
  checkLayout(image, wide ? 2 : 1);
  LabelImage label;
  label.width = static_cast<int>(image.width);
  label.height = static_cast<int>(image.height);
  label.ids.resize(static_cast<size_t>(label.width) * label.height);
  const bool big = image.is_bigendian != 0;
  for (int v = 0; v < label.height; ++v) {
    const std::uint8_t* row = image.data.data() + static_cast<size_t>(v) * image.step;
    for (int u = 0; u < label.width; ++u)
      label.ids[static_cast<size_t>(v) * label.width + u] =
          wide ? readValue<std::uint16_t>(row + 2 * u, big) : row[u];
  }
  return label;
}

// Throws lom::Error naming the topic and the field when a length inside the
// message does not fit in its bytes: the ROS deserialiser allocates a stated
// length before it reads it (a corrupted one asked for gigabytes).
void checkLengths(const rosbag::MessageInstance& m) {
  std::vector<std::uint8_t> bytes(m.size());
  ros::serialization::OStream stream(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  m.write(stream);
  if (const auto problem = messageLengthProblem(m.getDataType(), bytes.data(), bytes.size()))
    throw Error(m.getTopic(), problem->field, problem->expected, problem->found);
}

// The message as T; a lom::Error (not a null pointer) when its definition
// differs or a length inside it does not fit.
template <typename T>
boost::shared_ptr<T> load(const rosbag::MessageInstance& m) {
  if (m.getMD5Sum() == ros::message_traits::MD5Sum<T>::value()) checkLengths(m);
  boost::shared_ptr<T> message = m.instantiate<T>();
  if (!message)
    throw Error(m.getTopic(), "message",
                std::string("a ") + ros::message_traits::DataType<T>::value() +
                    " with the standard definition",
                m.getDataType() + " with MD5 " + m.getMD5Sum());
  return message;
}

// The images are taken as rectified (the import does not undistort): their
// camera is the projection P (what ROS's image_geometry uses for rectified
// images), and K only where a driver left P empty. The two differ when the
// raw images had distortion.
bool hasProjection(const sensor_msgs::CameraInfo& info) {
  return info.P[0] > 0.0 && info.P[5] > 0.0 && std::isfinite(info.P[2]) && std::isfinite(info.P[6]);
}

std::optional<CameraIntrinsics> intrinsicsOf(const sensor_msgs::CameraInfo& info) {
  CameraIntrinsics camera;
  camera.width = static_cast<int>(info.width);
  camera.height = static_cast<int>(info.height);
  if (hasProjection(info)) {
    camera.fx = info.P[0];
    camera.fy = info.P[5];
    camera.cx = info.P[2];
    camera.cy = info.P[6];
    return camera;
  }
  if (!(info.K[0] > 0.0) || !(info.K[4] > 0.0)) return std::nullopt;
  camera.fx = info.K[0];
  camera.fy = info.K[4];
  camera.cx = info.K[2];
  camera.cy = info.K[5];
  return camera;
}

bool sameIntrinsics(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  const auto close = [](double x, double y) {
    return std::abs(x - y) <= 1e-6 * std::max(1.0, std::abs(x));
  };
  return a.width == b.width && a.height == b.height && close(a.fx, b.fx) && close(a.fy, b.fy) &&
         close(a.cx, b.cx) && close(a.cy, b.cy);
}

using CameraInfoList = std::vector<std::pair<double, sensor_msgs::CameraInfo>>;

// What the first pass over the bag keeps: every topic with its image stamps
// and encodings (pixel data stays in the bag), the camera infos and all of tf.
struct BagContents {
  bag::TopicMap topics;
  std::vector<rosbag::MessageInstance> messages;
  std::map<std::string, CameraInfoList> infos;
  std::vector<geometry_msgs::TransformStamped> dynamic_tf, static_tf;
  // The header stamps (nanoseconds, sorted once read) of the valid /tf
  // transforms of each link, by (parent, child); /tf_static is not in it.
  std::map<std::pair<std::string, std::string>, std::vector<std::int64_t>> link_stamps;
  size_t bad_transforms = 0;
  // Transforms whose quaternion was far from unit length (not mere
  // rounding), normalised, and the range of those norms.
  size_t normalised = 0;
  double min_norm = INFINITY, max_norm = 0.0;
  size_t zero_tf_stamps = 0;  // dynamic transforms stamped 0, given their record time
  // Messages left out for a length inside them that does not fit in their
  // bytes: by topic, how many and the first one's reason.
  std::map<std::string, std::pair<size_t, std::string>> bad_lengths;
  double begin = 0.0, end = 0.0;

  void read(const rosbag::MessageInstance& m) {
    const std::string& type = m.getDataType();
    if (type == bag::kImageType || type == bag::kCompressedType)
      readImage(m);
    else if (type == bag::kInfoType)
      readCameraInfo(m);
    else if (type == "tf2_msgs/TFMessage" || type == "tf/tfMessage")
      readTransforms(m);
  }

 private:
  void readImage(const rosbag::MessageInstance& m) {
    ImageEntry entry;
    std_msgs::Header header;
    if (m.getDataType() == bag::kImageType) {
      const auto meta = m.instantiate<lom_rosbag::ImageMeta>();
      header = meta->header;
      entry.width = static_cast<int>(meta->width);
      entry.height = static_cast<int>(meta->height);
      entry.encoding = meta->encoding;
    } else {
      const auto meta = m.instantiate<lom_rosbag::CompressedMeta>();
      header = meta->header;
      entry.encoding = meta->format;
      entry.compressed = true;
    }
    ros::Time stamp = header.stamp;
    if (stamp.isZero()) {
      stamp = m.getTime();
      entry.stamp_from_bag = true;
    }
    entry.stamp = stamp.toSec();
    entry.nanoseconds = static_cast<std::int64_t>(stamp.toNSec());
    entry.frame_id = stripSlash(header.frame_id);
    entry.message = messages.size();
    messages.push_back(m);
    topics[m.getTopic()].images.push_back(entry);
  }

  // Whether m's lengths fit (else it is counted in bad_lengths).
  bool lengthsFit(const rosbag::MessageInstance& m) {
    try {
      checkLengths(m);
      return true;
    } catch (const Error& e) {
      auto& [count, first] = bad_lengths[m.getTopic()];
      if (count++ == 0) first = e.what();
      return false;
    }
  }

  void readCameraInfo(const rosbag::MessageInstance& m) {
    if (!lengthsFit(m)) return;
    if (const auto info = m.instantiate<sensor_msgs::CameraInfo>()) {
      const double stamp =
          info->header.stamp.isZero() ? m.getTime().toSec() : info->header.stamp.toSec();
      infos[m.getTopic()].emplace_back(stamp, *info);
    }
  }

  void readTransforms(const rosbag::MessageInstance& m) {
    const std::string& topic = m.getTopic();
    const bool is_static = topic == "/tf_static" || topic == "tf_static";
    if (!is_static && topic != "/tf" && topic != "tf") return;
    if (!lengthsFit(m)) return;
    const auto tf = m.instantiate<tf2_msgs::TFMessage>();
    if (!tf) return;
    for (auto t : tf->transforms) {
      // As for images: a header stamp of 0 is replaced by the record time.
      if (!is_static && t.header.stamp.isZero()) {
        t.header.stamp = m.getTime();
        ++zero_tf_stamps;
      }
      t.header.frame_id = stripSlash(t.header.frame_id);
      t.child_frame_id = stripSlash(t.child_frame_id);
      auto& q = t.transform.rotation;
      const auto& p = t.transform.translation;
      const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
      if (!std::isfinite(norm) || norm < 1e-6 || !std::isfinite(p.x) || !std::isfinite(p.y) ||
          !std::isfinite(p.z) || t.header.frame_id.empty() || t.child_frame_id.empty() ||
          t.header.frame_id == t.child_frame_id) {
        ++bad_transforms;
        continue;
      }
      // tf2 silently refuses a quaternion whose squared norm is 1% off (and
      // a lookup then blamed a missing frame); the rotation it stands for is
      // the normalised one, as the pose building takes it.
      if (norm != 1.0) {
        if (std::abs(norm - 1.0) > 1e-3) {
          ++normalised;
          min_norm = std::min(min_norm, norm);
          max_norm = std::max(max_norm, norm);
        }
        q.x /= norm;
        q.y /= norm;
        q.z /= norm;
        q.w /= norm;
      }
      if (!is_static)
        link_stamps[{t.header.frame_id, t.child_frame_id}].push_back(
            static_cast<std::int64_t>(t.header.stamp.toNSec()));
      (is_static ? static_tf : dynamic_tf).push_back(t);
    }
  }
};

// The first pass. Unreadable messages are counted and noted, not fatal.
// Its progress is the second half of the reading (`bytes`, the file's size,
// after the check's); false when the progress callback asked to cancel.
bool readBag(rosbag::Bag& opened, const std::string& file, std::uint64_t bytes,
             SequenceWriter& writer, BagContents& contents) {
  size_t unreadable = 0;
  try {
    rosbag::View view(opened);
    const std::uint64_t messages = view.size();
    if (messages == 0) throw Error(file, "bag", "a bag with messages", "an empty bag");
    contents.begin = view.getBeginTime().toSec();
    contents.end = view.getEndTime().toSec();
    for (const rosbag::ConnectionInfo* c : view.getConnections())
      contents.topics[c->topic] = Topic{c->topic, c->datatype, {}};
    // Messages come in time order, not in file order: their count stands for
    // the bytes read (the chunks are decompressed as they are reached).
    const std::uint64_t pass = bytes > 0 ? bytes : messages;
    std::uint64_t read = 0;
    for (const rosbag::MessageInstance& m : view) {
      if (!writer.reading(pass + pass * read++ / messages, 2 * pass)) return false;
      try {
        contents.read(m);
      } catch (const std::exception&) {
        ++unreadable;  // a truncated or corrupt message: the others are still used
      }
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(file, "bag", "a readable ROS 1 bag", e.what());
  }
  if (unreadable)
    writer.note(std::to_string(unreadable) +
                " messages could not be read (truncated or corrupt) and were ignored");
  for (const auto& [topic, problem] : contents.bad_lengths)
    writer.note(std::to_string(problem.first) + " messages on " + topic +
                " were ignored: a length inside them does not fit in the message (the first: " +
                problem.second + ")");
  for (auto& [name, topic] : contents.topics)
    std::stable_sort(
        topic.images.begin(), topic.images.end(),
        [](const ImageEntry& a, const ImageEntry& b) { return a.nanoseconds < b.nanoseconds; });
  for (auto& [name, list] : contents.infos)
    std::stable_sort(list.begin(), list.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [link, stamps] : contents.link_stamps) {
    std::sort(stamps.begin(), stamps.end());
    stamps.erase(std::unique(stamps.begin(), stamps.end()), stamps.end());
  }
  return true;
}

// The camera info topic that best matches an image topic: the longest common
// name prefix, then the same frame; `exclude` is skipped.
std::string infoTopicFor(const BagContents& contents, const Topic& image_topic,
                         const std::string& exclude) {
  std::string best;
  size_t best_score = 0;
  for (const auto& [name, list] : contents.infos) {
    if (name == exclude || list.empty()) continue;
    const size_t prefix = bag::commonPrefix(name, image_topic.name);
    const bool same_frame =
        stripSlash(list.front().second.header.frame_id) == image_topic.images.front().frame_id;
    const size_t score = prefix * 2 + (same_frame ? 1 : 0);
    if (best.empty() || score > best_score) {
      best = name;
      best_score = score;
    }
  }
  return best;
}

struct BagCameras {
  CameraIntrinsics depth;
  std::optional<CameraIntrinsics> color;  // when the colour images have their own camera info
};

// The depth camera from its CameraInfo topic (or the intrinsics option), and
// the colour camera's when it has its own.
BagCameras chooseCameras(const BagContents& contents, const ChosenTopics& chosen,
                         const ImportOptions& options, const fs::path& source,
                         SequenceWriter& writer) {
  const std::string file = source.string();
  const Topic& depth_topic = *chosen.depth;
  std::string info_topic = options.rosbag.camera_info_topic;
  if (!info_topic.empty())
    bag::requireTopic(contents.topics, info_topic, "camera info topic", {bag::kInfoType}, file);
  else if (!contents.infos.empty())
    info_topic = infoTopicFor(contents, depth_topic, "");
  std::optional<CameraIntrinsics> info_camera;
  std::string info_description = "no camera info";
  if (!info_topic.empty() && contents.infos.count(info_topic)) {
    // The first calibrated message (a driver may publish zeros until it is).
    const CameraInfoList& list = contents.infos.at(info_topic);
    const sensor_msgs::CameraInfo* chosen_info = &list.front().second;
    for (const auto& [stamp, candidate] : list)
      if (intrinsicsOf(candidate)) {
        chosen_info = &candidate;
        break;
      }
    const auto& info = *chosen_info;
    info_camera = intrinsicsOf(info);
    info_description = info_topic;
    if (!info_camera && !options.intrinsics)
      throw Error(file, "camera info", "a calibrated camera (K with fx, fy > 0) on " + info_topic,
                  "K = [" + formatNumber(info.K[0]) + " ... " + formatNumber(info.K[4]) + " ...]");
    if (!options.intrinsics) {
      writer.note("camera info topic: " + info_topic);
      if (info_camera) {
        if (hasProjection(info) &&
            (std::abs(info.P[0] - info.K[0]) > 1e-9 || std::abs(info.P[5] - info.K[4]) > 1e-9 ||
             std::abs(info.P[2] - info.K[2]) > 1e-9 || std::abs(info.P[6] - info.K[5]) > 1e-9))
          writer.note(
              "intrinsics from the camera info's projection P (that of rectified "
              "images), which differs from its K (that of the raw images)");
        size_t differing = 0;
        for (const auto& [stamp, other] : list)
          if (const auto camera = intrinsicsOf(other);
              camera && !sameIntrinsics(*camera, *info_camera))
            ++differing;
        if (differing)
          writer.note(std::to_string(differing) + " of the " + std::to_string(list.size()) +
                      " messages on " + info_topic +
                      " give other intrinsics than the first calibrated one, which is used for "
                      "every frame (give the intrinsics option if another is right)");
      }
      // Another camera's info (the colour camera's) is the wrong one for depth.
      const std::string info_frame = stripSlash(info.header.frame_id);
      const std::string depth_frame = depth_topic.images.front().frame_id;
      if (options.rosbag.camera_info_topic.empty() && !info_frame.empty() && !depth_frame.empty() &&
          info_frame != depth_frame)
        writer.note("warning: the camera info " + info_topic + " is of frame '" + info_frame +
                    "', the depth images of frame '" + depth_frame +
                    "': its intrinsics may be another camera's (give the camera info topic or "
                    "the intrinsics option)");
    }
    bool distorted = false;
    for (double d : info.D) distorted |= std::abs(d) > 1e-9;
    if (distorted)
      writer.note(
          "the camera info has distortion coefficients; images are used as they are "
          "(rectified images are expected)");
    if (info_camera && (info_camera->width <= 0 || info_camera->height <= 0)) {
      info_camera->width = depth_topic.images.front().width;
      info_camera->height = depth_topic.images.front().height;
    }
  }
  BagCameras cameras;
  cameras.depth =
      chooseCamera(info_camera, info_description, options, writer, source,
                   "a sensor_msgs/CameraInfo topic for the depth images or the intrinsics option "
                   "(--intrinsics fx,fy,cx,cy)");
  // Intrinsics given without a size are for the frames written (the first
  // one's size), not for the size the bag's camera info names.
  if (chosen.color) {
    const std::string color_info = infoTopicFor(contents, *chosen.color, info_topic);
    if (!color_info.empty() && bag::commonPrefix(color_info, chosen.color->name) >
                                   bag::commonPrefix(color_info, depth_topic.name))
      cameras.color = intrinsicsOf(contents.infos.at(color_info).front().second);
  }
  return cameras;
}

// Camera poses from tf: the camera frame in the fixed frame at an image's stamp.
class PoseLookup {
  // tf2 drops transforms older than its cache by their header stamps, which
  // may span far more than the bag's record times (a bag written without
  // record times, or replayed faster): the cache holds them all.
  static double cacheSeconds(const BagContents& contents) {
    double low = INFINITY, high = -INFINITY;
    for (const auto& t : contents.dynamic_tf) {
      low = std::min(low, t.header.stamp.toSec());
      high = std::max(high, t.header.stamp.toSec());
    }
    const double stamps = high > low ? high - low : 0.0;
    return std::max({10.0, contents.end - contents.begin + 10.0, stamps + 10.0});
  }

 public:
  PoseLookup(const BagContents& contents, const Topic& depth_topic, const ImportOptions& options,
             const std::string& file, SequenceWriter& writer)
      : buffer_(ros::Duration(cacheSeconds(contents))),
        tolerance_(bag::toNanoseconds(options.time_tolerance)),
        max_gap_(bag::toNanoseconds(options.rosbag.max_pose_gap)),
        max_gap_seconds_(options.rosbag.max_pose_gap),
        has_dynamic_(!contents.dynamic_tf.empty()) {
    const RosbagOptions& given = options.rosbag;
    camera_frame_ = stripSlash(given.camera_frame);
    if (camera_frame_.empty()) camera_frame_ = depth_topic.images.front().frame_id;
    if (camera_frame_.empty())
      throw Error(file, "camera frame",
                  "a frame_id in the depth images' header (or the camera frame option)",
                  "an empty frame_id");
    if (contents.dynamic_tf.empty() && contents.static_tf.empty())
      throw Error(file, "tf", "/tf or /tf_static messages giving the camera pose",
                  contents.bad_transforms
                      ? std::to_string(contents.bad_transforms) + " invalid transforms only"
                      : "none; topics: " + bag::describeTopics(contents.topics));
    if (contents.bad_transforms)
      writer.note(std::to_string(contents.bad_transforms) +
                  " tf transforms were invalid (NaN, zero quaternion, empty frame) and ignored");
    if (contents.normalised)
      writer.note(std::to_string(contents.normalised) +
                  " tf transforms have a quaternion that is not of unit length (norm " +
                  formatNumber(contents.min_norm, 4) +
                  (contents.max_norm != contents.min_norm
                       ? " to " + formatNumber(contents.max_norm, 4)
                       : std::string()) +
                  "): normalised");
    if (contents.zero_tf_stamps)
      writer.note(std::to_string(contents.zero_tf_stamps) +
                  " tf transforms have a zero header stamp: the bag's record time is used");
    std::map<std::string, std::string> parent_of;
    std::set<std::string> frames;
    for (const auto* list : {&contents.static_tf, &contents.dynamic_tf})
      for (const auto& t : *list) {
        parent_of[t.child_frame_id] = t.header.frame_id;
        frames.insert(t.child_frame_id);
        frames.insert(t.header.frame_id);
      }
    for (const auto& t : contents.dynamic_tf) {
      begin_ = std::min(begin_, t.header.stamp.toSec());
      end_ = std::max(end_, t.header.stamp.toSec());
    }
    if (!frames.count(camera_frame_)) {
      std::string names;
      for (const auto& f : frames) names += (names.empty() ? "" : ", ") + f;
      throw Error(file, "camera frame", "frame '" + camera_frame_ + "' in /tf or /tf_static",
                  "frames " + names);
    }
    fixed_frame_ = stripSlash(given.fixed_frame);
    if (fixed_frame_.empty()) {
      fixed_frame_ = camera_frame_;
      std::set<std::string> seen{fixed_frame_};
      while (parent_of.count(fixed_frame_) && seen.insert(parent_of[fixed_frame_]).second)
        fixed_frame_ = parent_of[fixed_frame_];
      if (fixed_frame_ == camera_frame_)
        throw Error(file, "fixed frame",
                    "a frame above the camera frame '" + camera_frame_ + "' in tf",
                    "the camera frame has no parent");
      writer.note("poses of '" + camera_frame_ + "' in '" + fixed_frame_ +
                  "' (the root of its tf tree; choose another with the fixed frame option)");
    } else if (!frames.count(fixed_frame_)) {
      throw Error(file, "fixed frame", "a frame of /tf or /tf_static",
                  "'" + fixed_frame_ + "' is not one");
    }
    // A camera whose every link up to the fixed frame is static stands still
    // in it: while /tf moves other frames, a link between them is likely
    // missing from the bag (every frame would be fused at one pose).
    if (!contents.dynamic_tf.empty()) {
      std::set<std::string> moving;  // frames /tf moves against their parent
      for (const auto& t : contents.dynamic_tf) moving.insert(t.child_frame_id);
      bool moves = false;
      std::set<std::string> seen;
      for (std::string f = camera_frame_;
           f != fixed_frame_ && parent_of.count(f) && seen.insert(f).second; f = parent_of[f])
        moves = moves || moving.count(f) > 0;
      if (!moves) {
        std::string names;
        for (const auto& f : moving) names += (names.empty() ? "'" : "', '") + f;
        writer.note("warning: every transform from '" + fixed_frame_ + "' to '" + camera_frame_ +
                    "' is static, so every frame gets the same pose, while /tf moves " + names +
                    "': is a tf link between them missing from the bag? (a camera that truly "
                    "stands still can ignore this)");
      }
    } else {
      // Only /tf_static: no link moves, so neither does the camera.
      writer.note(
          "warning: the bag has no /tf messages, only /tf_static, so every frame gets "
          "the same pose of '" +
          camera_frame_ + "' in '" + fixed_frame_ +
          "': was /tf left out of the recording? (a camera that truly stands still "
          "can ignore this)");
    }
    findMovingLinks(contents, parent_of);
    if (lower(camera_frame_).find("optical") == std::string::npos)
      writer.note("camera frame '" + camera_frame_ +
                  "' is not named *optical*: it must have z forward, x right, y down");
    // What tf2 still refuses (it only logs why) is counted, not lost unsaid.
    size_t refused = 0;
    for (const auto& t : contents.static_tf) refused += !buffer_.setTransform(t, "bag", true);
    for (const auto& t : contents.dynamic_tf) refused += !buffer_.setTransform(t, "bag", false);
    if (refused)
      writer.note(std::to_string(refused) +
                  " tf transforms were refused by tf2 and ignored (a second transform of a "
                  "frame at the same stamp, or one older than the rest by more than tf2 keeps)");
  }

  [[nodiscard]] const std::string& fixedFrame() const { return fixed_frame_; }
  // Said with every missing transform: when no frame can be imported, the
  // error quotes only the first frame's reason, not the report's notes.
  void setClockNote(std::string note) { clock_note_ = std::move(note); }
  // The time span of /tf (none when only /tf_static gives the pose).
  [[nodiscard]] bool hasDynamic() const { return has_dynamic_; }
  [[nodiscard]] double begin() const { return begin_; }
  [[nodiscard]] double end() const { return end_; }

  // The camera-to-fixed-frame pose at `nanoseconds` (at the edges of tf's
  // range, within the time tolerance); empty with the reason when tf has
  // none. `seconds` is the same stamp for the reason.
  std::optional<Eigen::Matrix4d> at(std::int64_t nanoseconds, double seconds,
                                    std::string& reason) const {
    // A ROS 1 time holds whole seconds from 0 to 2^32 - 1: tf has nothing
    // outside that span (a large time offset or tolerance); 0 would ask tf2
    // for its latest transform.
    constexpr std::int64_t kRosTimeEnd = std::int64_t{1} << 32;
    std::optional<geometry_msgs::TransformStamped> found;
    std::string tf_error;
    for (std::int64_t t : {nanoseconds, bag::addNanoseconds(nanoseconds, -tolerance_),
                           bag::addNanoseconds(nanoseconds, tolerance_)}) {
      if (!(t > 0 && t / 1000000000 < kRosTimeEnd)) continue;
      try {
        ros::Time time;
        time.fromNSec(static_cast<std::uint64_t>(t));
        found = buffer_.lookupTransform(fixed_frame_, camera_frame_, time);
        break;
      } catch (const tf2::TransformException& e) {
        if (tf_error.empty()) tf_error = e.what();
      }
      if (tolerance_ == 0) break;
    }
    if (!found) {
      reason = "no transform from '" + fixed_frame_ + "' to '" + camera_frame_ + "' at " +
               stampText(seconds);
      if (has_dynamic_)
        reason += " (tf covers " + stampText(begin_) + " to " + stampText(end_) +
                  (clock_note_.empty() ? "" : "; " + clock_note_) + ")";
      if (!tf_error.empty()) reason += ": " + tf_error;
      return std::nullopt;
    }
    if (auto gap = gapAt(nanoseconds, seconds)) {
      reason = std::move(*gap);
      return std::nullopt;
    }
    const auto& tr = found->transform;
    const Eigen::Quaterniond q(tr.rotation.w, tr.rotation.x, tr.rotation.y, tr.rotation.z);
    Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
    pose.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
    pose.topRightCorner<3, 1>() =
        Eigen::Vector3d(tr.translation.x, tr.translation.y, tr.translation.z);
    return pose;
  }

 private:
  // A link of the camera's chain that /tf moves, with its sample stamps.
  struct MovingLink {
    std::string parent, child;
    const std::vector<std::int64_t>* stamps = nullptr;  // sorted nanoseconds, in BagContents
  };

  // The links tf2 chains between the camera frame and the fixed frame (both
  // walked up, child -> parent, to the first frame they share) that /tf
  // moves; links of /tf_static stand still and are left out.
  void findMovingLinks(const BagContents& contents,
                       const std::map<std::string, std::string>& parent_of) {
    const auto parentOf = [&](const std::string& f) -> const std::string* {
      const auto it = parent_of.find(f);
      return it == parent_of.end() ? nullptr : &it->second;
    };
    std::vector<std::string> above_fixed{fixed_frame_};  // the fixed frame and its ancestors
    for (const std::string* p = parentOf(fixed_frame_);
         p && std::find(above_fixed.begin(), above_fixed.end(), *p) == above_fixed.end();
         p = parentOf(*p))
      above_fixed.push_back(*p);
    const auto isAboveFixed = [&](const std::string& f) {
      return std::find(above_fixed.begin(), above_fixed.end(), f) != above_fixed.end();
    };
    std::vector<std::pair<std::string, std::string>> chain;  // (parent, child)
    std::set<std::string> seen{camera_frame_};
    std::string f = camera_frame_;
    for (const std::string* p = parentOf(f); !isAboveFixed(f) && p && seen.insert(*p).second;
         p = parentOf(f)) {
      chain.emplace_back(*p, f);
      f = *p;
    }
    if (isAboveFixed(f))
      for (const auto& g : above_fixed) {
        if (g == f) break;
        chain.emplace_back(*parentOf(g), g);
      }
    // A link /tf_static also gives stands still whatever /tf adds to it.
    std::set<std::pair<std::string, std::string>> fixed_links;
    for (const auto& t : contents.static_tf)
      fixed_links.emplace(t.header.frame_id, t.child_frame_id);
    for (const auto& link : chain)
      if (const auto it = contents.link_stamps.find(link);
          it != contents.link_stamps.end() && !fixed_links.count(link))
        moving_links_.push_back({link.first, link.second, &it->second});
  }

  // Whether `link` holds the same transform (within a micrometre and a
  // microradian) at its samples `a` and `b`: interpolating between them is
  // exact then, however far apart (a slow link that does not move).
  [[nodiscard]] bool sameAt(const MovingLink& link, std::int64_t a, std::int64_t b) const {
    try {
      ros::Time at_a, at_b;
      at_a.fromNSec(static_cast<std::uint64_t>(a));
      at_b.fromNSec(static_cast<std::uint64_t>(b));
      const auto x = buffer_.lookupTransform(link.parent, link.child, at_a).transform;
      const auto y = buffer_.lookupTransform(link.parent, link.child, at_b).transform;
      const Eigen::Vector3d dt(x.translation.x - y.translation.x, x.translation.y - y.translation.y,
                               x.translation.z - y.translation.z);
      const Eigen::Quaterniond qx(x.rotation.w, x.rotation.x, x.rotation.y, x.rotation.z);
      const Eigen::Quaterniond qy(y.rotation.w, y.rotation.x, y.rotation.y, y.rotation.z);
      return dt.norm() <= 1e-6 && qx.normalized().angularDistance(qy.normalized()) <= 1e-6;
    } catch (const tf2::TransformException&) {
      return false;
    }
  }

  // Why the pose at `nanoseconds` would be a guess: on a moving link of the
  // chain, no sample lies within the tolerance and the samples around the
  // stamp are farther apart than the maximum pose gap. Nothing otherwise,
  // also when the stamp lies before a link's first or after its last sample
  // (tf2 decides there). `seconds` is the same stamp for the reason.
  [[nodiscard]] std::optional<std::string> gapAt(std::int64_t nanoseconds, double seconds) const {
    for (const MovingLink& link : moving_links_) {
      const std::vector<std::int64_t>& stamps = *link.stamps;
      if (bag::nearestNanoseconds(stamps, nanoseconds, tolerance_)) continue;
      const auto after = std::upper_bound(stamps.begin(), stamps.end(), nanoseconds);
      if (after == stamps.begin() || after == stamps.end()) continue;
      const std::int64_t before = *std::prev(after);
      const std::int64_t gap = *after - before;  // ROS times: no overflow
      if (gap <= max_gap_ || sameAt(link, before, *after)) continue;
      return "no pose at " + stampText(seconds) + ": the tf link '" + link.parent + "' -> '" +
             link.child + "' has no sample within " +
             formatNumber(1e-9 * static_cast<double>(tolerance_)) +
             " s of it, and its samples around it, at " +
             stampText(1e-9 * static_cast<double>(before)) + " and " +
             stampText(1e-9 * static_cast<double>(*after)) + ", are " +
             formatNumber(1e-9 * static_cast<double>(gap)) +
             " s apart, more than the maximum pose gap of " + formatNumber(max_gap_seconds_) +
             " s (a pose interpolated across a hole in the motion data is a guess; raise the "
             "max pose gap option to interpolate across it)";
    }
    return std::nullopt;
  }

  tf2::BufferCore buffer_;
  std::int64_t tolerance_;  // nanoseconds
  std::int64_t max_gap_;    // nanoseconds
  double max_gap_seconds_;  // the same, for messages
  std::vector<MovingLink> moving_links_;
  bool has_dynamic_;
  std::string camera_frame_, fixed_frame_;
  std::string clock_note_;
  double begin_ = INFINITY, end_ = -INFINITY;
};

// Notes on stamps that cannot match: zero header stamps, image and tf clocks
// that do not overlap (also given to `poses`), topics with no image near any
// depth image.
void noteStampProblems(const ChosenTopics& chosen, PoseLookup& poses, const ImportOptions& options,
                       SequenceWriter& writer) {
  const auto& depth_entries = chosen.depth->images;
  const double tol = options.time_tolerance;
  const std::int64_t tol_ns = bag::toNanoseconds(tol);
  size_t from_bag = 0;
  for (const auto& e : depth_entries) from_bag += e.stamp_from_bag;
  if (from_bag)
    writer.note(std::to_string(from_bag) +
                " depth images have a zero header stamp: the bag's record time is used");
  // Two depth images at one stamp (sorted by it) get one pose: one of them
  // is stamped wrong (a driver that restamps, a bag merged from two).
  const auto same_stamp = [&](size_t a, size_t b) {
    return depth_entries[a].nanoseconds == depth_entries[b].nanoseconds &&
           !depth_entries[a].stamp_from_bag && !depth_entries[b].stamp_from_bag;
  };
  size_t shared = 0;  // images that share their stamp with another
  std::string first_shared;
  for (size_t i = 0; i < depth_entries.size(); ++i) {
    const bool with_previous = i > 0 && same_stamp(i - 1, i);
    const bool with_next = i + 1 < depth_entries.size() && same_stamp(i, i + 1);
    if (!with_previous && !with_next) continue;
    if (shared++ == 0) first_shared = stampText(depth_entries[i].stamp);
  }
  if (shared)
    writer.note("warning: " + std::to_string(shared) +
                " depth images share their header stamp with another (the first at " +
                first_shared +
                "): such images get the same pose, so at most one of them is placed right (is "
                "the recording's driver restamping, or are two recordings merged?)");
  const double image_begin = depth_entries.front().stamp + options.time_offset;
  const double image_end = depth_entries.back().stamp + options.time_offset;
  if (poses.hasDynamic() && (image_end < poses.begin() - tol || image_begin > poses.end() + tol)) {
    const std::string offset =
        formatNumber(0.5 * (poses.begin() + poses.end()) - 0.5 * (image_begin + image_end), 4);
    writer.note("depth image stamps (" + stampText(image_begin) + " to " + stampText(image_end) +
                ") and tf stamps (" + stampText(poses.begin()) + " to " + stampText(poses.end()) +
                ") do not overlap: the clocks differ by about " + offset +
                " s (give it as the time offset option)");
    poses.setClockNote("the image and tf stamps do not overlap: the clocks differ by about " +
                       offset + " s, give it as the time offset option");
  }
  auto unmatchedNote = [&](const Topic* topic, const std::string& what) {
    if (!topic) return;
    const std::vector<std::int64_t> stamps = topic->nanoseconds();
    if (stamps.empty()) return;
    // In nanoseconds, as the matching: through doubles, an image exactly
    // at the tolerance could be said to be none.
    std::optional<std::int64_t> nearest;  // image stamp - depth stamp
    for (const auto& e : depth_entries) {
      const auto i =
          bag::nearestNanoseconds(stamps, e.nanoseconds, std::numeric_limits<std::int64_t>::max());
      if (!i) continue;
      const std::int64_t gap = stamps[*i] - e.nanoseconds;
      if (!nearest || std::abs(gap) < std::abs(*nearest)) nearest = gap;
    }
    if (nearest && std::abs(*nearest) > tol_ns)
      writer.note("no " + what + " image lies within " + formatNumber(tol) +
                  " s of a depth image (nearest " +
                  formatNumber(static_cast<double>(*nearest) * 1e-9, 4) +
                  " s away: a clock offset between the topics? raise the time tolerance)");
  };
  unmatchedNote(chosen.color, "colour");
  unmatchedNote(chosen.proba, "probability");
  unmatchedNote(chosen.label, "label");
}

// Reads the images of one depth image's frame: the depth, and the colour,
// probability and label images nearest in time. Throws lom::Error naming the
// topic when an image the frame needs is missing or damaged; a colour image
// that cannot be used is noted and left out.
class FrameReader {
 public:
  FrameReader(const BagContents& contents, const ChosenTopics& chosen, const ImportOptions& options,
              const BagCameras& cameras, SequenceWriter& writer)
      : contents_(contents),
        chosen_(chosen),
        cameras_(cameras),
        writer_(writer),
        millimetres_(options.depth_scale.value_or(0.001)),
        tolerance_(options.time_tolerance),
        tolerance_ns_(bag::toNanoseconds(options.time_tolerance)) {
    if (chosen.color) color_stamps_ = chosen.color->nanoseconds();
    if (chosen.proba) {
      proba_stamps_ = chosen.proba->nanoseconds();
      int bytes = 0;
      proba_channels_ = multiChannels(chosen.proba->firstEncoding(), bytes);
    }
    if (chosen.label) label_stamps_ = chosen.label->nanoseconds();
  }

  [[nodiscard]] double millimetres() const { return millimetres_; }
  [[nodiscard]] int probaChannels() const { return proba_channels_; }
  // Probability values outside [0, 1] or NaN clamped so far.
  [[nodiscard]] size_t clamped() const { return clamped_; }

  void read(const ImageEntry& entry, SourceFrame& frame) {
    readDepth(entry, frame);
    if (chosen_.color) readColor(entry, frame);
    if (chosen_.proba) readProba(entry, frame);
    if (chosen_.label) readLabel(entry, frame);
  }

 private:
  const rosbag::MessageInstance& message(const Topic& topic, size_t index) const {
    return contents_.messages[topic.images[index].message];
  }

  void readDepth(const ImageEntry& entry, SourceFrame& frame) const {
    const rosbag::MessageInstance& m = contents_.messages[entry.message];
    try {
      if (entry.compressed)
        frame.depth = decodeCompressedDepth(*load<sensor_msgs::CompressedImage>(m), millimetres_);
      else
        frame.depth = decodeDepth(*load<sensor_msgs::Image>(m), millimetres_);
    } catch (const Error& e) {
      throw Error(chosen_.depth->name, "depth " + e.problem().field, e.problem().expected,
                  e.problem().found);
    }
  }

  void readColor(const ImageEntry& entry, SourceFrame& frame) const {
    const Topic& topic = *chosen_.color;
    const auto i = bag::nearestNanoseconds(color_stamps_, entry.nanoseconds, tolerance_ns_);
    if (!i) {
      writer_.note(
          "depth images without a colour image within the time tolerance were "
          "imported without colour");
      return;
    }
    const rosbag::MessageInstance& m = message(topic, *i);
    try {
      frame.color = topic.images[*i].compressed
                        ? decodeCompressedColor(*load<sensor_msgs::CompressedImage>(m))
                        : decodeColor(*load<sensor_msgs::Image>(m));
      frame.color_camera = cameras_.color;
    } catch (const Error& e) {
      // Named by topic like the depth, probability and label errors.
      const Error named(topic.name, "colour " + e.problem().field, e.problem().expected,
                        e.problem().found);
      writer_.note("colour images that could not be decoded were left out (" +
                   std::string(named.what()) + ")");
    }
  }

  void readProba(const ImageEntry& entry, SourceFrame& frame) {
    const Topic& topic = *chosen_.proba;
    const auto i = bag::nearestNanoseconds(proba_stamps_, entry.nanoseconds, tolerance_ns_);
    if (!i)
      throw Error(
          topic.name, "stamp",
          "a probability image within " + formatNumber(tolerance_) + " s of the depth image",
          "none");
    const auto msg = load<sensor_msgs::Image>(message(topic, *i));
    int bytes = 0;
    if (multiChannels(msg->encoding, bytes) != proba_channels_)
      throw Error(topic.name, "encoding",
                  std::to_string(proba_channels_) + " channels as in the first message",
                  msg->encoding);
    try {
      frame.proba = decodeProba(*msg, &clamped_);
    } catch (const Error& e) {
      throw Error(topic.name, e.problem().field, e.problem().expected, e.problem().found);
    }
  }

  void readLabel(const ImageEntry& entry, SourceFrame& frame) const {
    const Topic& topic = *chosen_.label;
    const auto i = bag::nearestNanoseconds(label_stamps_, entry.nanoseconds, tolerance_ns_);
    if (!i) {
      // With probabilities the labels are only the ground truth: a frame may lack them.
      if (!chosen_.proba)
        throw Error(topic.name, "stamp",
                    "a label image within " + formatNumber(tolerance_) + " s of the depth image",
                    "none");
      return;
    }
    const auto msg = load<sensor_msgs::Image>(message(topic, *i));
    try {
      frame.label = decodeLabel(*msg);
    } catch (const Error& e) {
      throw Error(topic.name, e.problem().field, e.problem().expected, e.problem().found);
    }
  }

  const BagContents& contents_;
  const ChosenTopics& chosen_;
  const BagCameras& cameras_;
  SequenceWriter& writer_;
  double millimetres_;
  double tolerance_;           // seconds, for messages
  std::int64_t tolerance_ns_;  // the same, for matching
  std::vector<std::int64_t> color_stamps_, proba_stamps_, label_stamps_;
  int proba_channels_ = 0;
  size_t clamped_ = 0;
};

}  // namespace

void importRosbag(const fs::path& source, const ImportOptions& options, SequenceWriter& writer) {
  const double max_gap = options.rosbag.max_pose_gap;
  if (!(max_gap > 0.0) || !std::isfinite(max_gap))
    throw Error("", "max_pose_gap", "a positive number of seconds (a large one allows any gap)",
                formatNumber(max_gap));
  QuietConsole quiet;
  const std::string file = source.string();
  rosbag::Bag opened;
  // Before the first frame the whole file is read twice, the check and the
  // index of messages, which for a compressed bag decompress every chunk: a
  // cancel is heard every thousandth of the way, and the progress moves.
  std::error_code size_error;
  std::uint64_t bytes = fs::file_size(source, size_error);
  if (size_error) bytes = 0;
  const auto checked = [&](std::uint64_t at, std::uint64_t size) {
    return writer.reading(at, 2 * size);
  };
  // The bag library trusts every length and offset.
  if (!checkBagStructure(file, checked)) return;
  try {
    opened.open(file, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    // A recording cut short (disk full, killed) has no index at its end.
    const std::string what = e.what();
    const bool cut_short = what.find("unindexed") != std::string::npos ||
                           what.find("wanted") != std::string::npos ||
                           what.find("Error reading") != std::string::npos;
    throw Error(file, "bag", "a readable ROS 1 bag (format 2.0)",
                what + (cut_short ? " (the bag looks truncated or was not closed when recorded: "
                                    "`rosbag reindex` on a copy may recover it)"
                                  : ""));
  }
  BagContents contents;
  if (!readBag(opened, file, bytes, writer, contents)) return;

  const ChosenTopics chosen = bag::chooseTopics(contents.topics, options, file, writer);
  const BagCameras cameras = chooseCameras(contents, chosen, options, source, writer);
  writer.setCamera(cameras.depth);
  FrameReader reader(contents, chosen, options, cameras, writer);
  // 32FC1 depth is in metres: written as millimetres whatever the depth scale option.
  const bool float_depth = contains(lower(chosen.depth->firstEncoding()), "32fc1");
  writer.setDepthScale(float_depth ? 0.001 : reader.millimetres());
  bag::chooseLabels(reader.probaChannels(), chosen.label != nullptr, options, file, writer);

  PoseLookup poses(contents, *chosen.depth, options, file, writer);
  writer.setFrameId(poses.fixedFrame());
  noteStampProblems(chosen, poses, options, writer);

  const auto& depth_entries = chosen.depth->images;
  writer.setFound(depth_entries.size());
  const auto selected = selectFrames(depth_entries.size(), options);
  const std::int64_t offset = bag::toNanoseconds(options.time_offset);
  writer.setTotal(selected.size());
  for (size_t index : selected) {
    const ImageEntry& entry = depth_entries[index];
    SourceFrame frame;
    frame.name = "depth@" + stampText(entry.stamp);
    frame.stamp = entry.stamp;
    std::string reason;
    const auto pose = poses.at(bag::addNanoseconds(entry.nanoseconds, offset),
                               entry.stamp + options.time_offset, reason);
    if (!pose) {
      if (!writer.skip(frame.name, reason)) return;
      continue;
    }
    frame.pose = *pose;
    std::optional<std::string> error;
    try {
      reader.read(entry, frame);
    } catch (const Error& e) {
      error = e.what();
    } catch (const std::exception& e) {
      error = std::string("unreadable message: ") + e.what();
    }
    if (error) {
      if (!writer.skip(frame.name, *error)) return;
      continue;
    }
    if (!writer.add(std::move(frame))) return;
  }
  if (reader.clamped())
    writer.note(std::to_string(reader.clamped()) +
                " probability values outside [0, 1] or NaN were clamped (NaN to 0)");
}

}  // namespace lom::import_detail

namespace lom {
bool rosbagSupported() { return true; }
}  // namespace lom

#else  // no ROS

namespace lom::import_detail {
void importRosbag(const fs::path& source, const ImportOptions&, SequenceWriter&) {
  throw Error(source.string(), "rosbag",
              "a build with ROS 1 bag support (CMake option LOM_WITH_ROSBAG; Debian packages "
              "librosbag-dev, libsensor-msgs-dev, libtf2-dev, libtf2-msgs-dev)",
              "this build of labeloctomap has no ROS bag support; convert the bag with another "
              "build or export its frames to a folder layout");
}
}  // namespace lom::import_detail

namespace lom {
bool rosbagSupported() { return false; }
}  // namespace lom

#endif
