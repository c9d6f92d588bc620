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
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "png_check.hpp"
#include "png_decode.hpp"

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
#define LOM_ROSBAG_ANY_TRAITS(T)                                   \
  template <>                                                      \
  struct MD5Sum<T> {                                               \
    static const char* value() { return "*"; }                     \
    static const char* value(const T&) { return "*"; }             \
  };                                                               \
  template <>                                                      \
  struct DataType<T> {                                             \
    static const char* value() { return "*"; }                     \
    static const char* value(const T&) { return "*"; }             \
  };                                                               \
  template <>                                                      \
  struct Definition<T> {                                           \
    static const char* value() { return ""; }                      \
    static const char* value(const T&) { return ""; }              \
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

constexpr const char* kImageType = "sensor_msgs/Image";
constexpr const char* kCompressedType = "sensor_msgs/CompressedImage";
constexpr const char* kInfoType = "sensor_msgs/CameraInfo";

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}
bool contains(const std::string& text, const char* part) { return text.find(part) != std::string::npos; }

std::string stripSlash(std::string frame) {
  while (!frame.empty() && frame.front() == '/') frame.erase(frame.begin());
  return frame;
}

std::string stampText(double stamp) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << stamp;
  return out.str();
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

struct ImageEntry {
  double stamp = 0.0;
  bool stamp_from_bag = false;  // header stamp was 0: the bag's record time is used
  std::string frame_id;
  int width = 0, height = 0;
  std::string encoding;  // Image encoding, or CompressedImage format
  bool compressed = false;
  size_t message = 0;  // index into the message list
};

struct Topic {
  std::string name;
  std::string type;
  std::vector<ImageEntry> images;  // sorted by stamp (image topics)
  [[nodiscard]] std::vector<double> stamps() const {
    std::vector<double> s;
    for (const auto& e : images) s.push_back(e.stamp);
    return s;
  }
  [[nodiscard]] std::string firstEncoding() const {
    return images.empty() ? std::string() : images.front().encoding;
  }
};

// Channels of "32FC3" / "16UC5" / "8UC2" encodings; 0 when not that form.
int multiChannels(const std::string& encoding, int& bytes) {
  const std::string e = lower(encoding);
  std::string digits;
  if (e.rfind("32fc", 0) == 0) {
    bytes = 4;
    digits = e.substr(4);
  } else if (e.rfind("16uc", 0) == 0) {
    bytes = 2;
    digits = e.substr(4);
  } else if (e.rfind("8uc", 0) == 0) {
    bytes = 1;
    digits = e.substr(3);
  } else {
    return 0;
  }
  if (digits.empty()) return 1;  // "8UC" alone is not a ROS encoding but harmless
  if (!std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
    return 0;
  return std::atoi(digits.c_str());
}

bool isDepthEncoding(const ImageEntry& e) {
  const std::string enc = lower(e.encoding);
  if (e.compressed) return contains(enc, "compresseddepth");
  return enc == "16uc1" || enc == "mono16" || enc == "32fc1";
}
bool isColorEncoding(const ImageEntry& e) {
  const std::string enc = lower(e.encoding);
  if (e.compressed) return !contains(enc, "compresseddepth");
  return enc == "rgb8" || enc == "bgr8" || enc == "rgba8" || enc == "bgra8" || enc == "mono8" ||
         enc == "8uc3";
}
bool isLabelEncoding(const ImageEntry& e) {
  const std::string enc = lower(e.encoding);
  return !e.compressed && (enc == "mono8" || enc == "8uc1" || enc == "mono16" || enc == "16uc1");
}
bool probaName(const std::string& topic) {
  const std::string t = lower(topic);
  return contains(t, "prob") || contains(t, "score") || contains(t, "softmax") ||
         contains(t, "posterior");
}
// Probability names win: "/segmenter/probabilities" is not a label topic.
bool labelName(const std::string& topic) {
  const std::string t = lower(topic);
  return !probaName(topic) && (contains(t, "label") || contains(t, "segm") ||
                               contains(t, "semantic") || contains(t, "class"));
}

size_t commonPrefix(const std::string& a, const std::string& b) {
  size_t n = 0;
  while (n < a.size() && n < b.size() && a[n] == b[n]) ++n;
  return n;
}

std::string listTopics(const std::vector<const Topic*>& topics) {
  std::string text;
  for (const Topic* t : topics) {
    if (!text.empty()) text += ", ";
    text += t->name;
  }
  return text.empty() ? "none" : text;
}

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
  if (image.width == 0 || image.height == 0)
    throw Error("", "image", "a non-empty image", "0 x 0");
  if (image.step < row)
    throw Error("", "step", "at least width x bytes per pixel = " + std::to_string(row),
                std::to_string(image.step));
  if (image.data.size() < static_cast<size_t>(image.step) * image.height)
    throw Error("", "data", "step x height = " +
                               std::to_string(static_cast<size_t>(image.step) * image.height) +
                               " bytes",
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
      out[u] = is_float ? readValue<float>(row + 4 * u, big)
                        : static_cast<float>(readValue<std::uint16_t>(row + 2 * u, big) *
                                             millimetre_scale);
  }
  return depth;
}

// Throws lom::Error (field "PNG data", no file: the caller names the topic) for
// a damaged PNG, decoded without libpng printing about it; other formats are
// only decoded.
cv::Mat decodeBytes(const std::vector<std::uint8_t>& data, size_t offset, int flags) {
  if (data.size() <= offset) return {};
  if (hasPngSignature(data.data() + offset, data.size() - offset)) {
    cv::Mat image = decodePng(data.data() + offset, data.size() - offset, "");
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
  const cv::Mat buffer(1, static_cast<int>(data.size() - offset), CV_8UC1,
                       const_cast<std::uint8_t*>(data.data() + offset));
  try {
    return cv::imdecode(buffer, flags);
  } catch (const cv::Exception&) {
    return {};
  }
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
    throw Error("", "compressedDepth", "a 16-bit PNG after the header", "data OpenCV cannot decode");
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

// The message as T; a lom::Error (not a null pointer) when its definition differs.
template <typename T>
boost::shared_ptr<T> load(const rosbag::MessageInstance& m) {
  boost::shared_ptr<T> message = m.instantiate<T>();
  if (!message)
    throw Error(m.getTopic(), "message", std::string("a ") + ros::message_traits::DataType<T>::value() +
                    " with the standard definition",
                m.getDataType() + " with MD5 " + m.getMD5Sum());
  return message;
}

std::optional<CameraIntrinsics> intrinsicsOf(const sensor_msgs::CameraInfo& info) {
  if (!(info.K[0] > 0.0) || !(info.K[4] > 0.0)) return std::nullopt;
  CameraIntrinsics camera;
  camera.width = static_cast<int>(info.width);
  camera.height = static_cast<int>(info.height);
  camera.fx = info.K[0];
  camera.fy = info.K[4];
  camera.cx = info.K[2];
  camera.cy = info.K[5];
  return camera;
}

}  // namespace

void importRosbag(const fs::path& source, const ImportOptions& options, SequenceWriter& writer) {
  QuietConsole quiet;
  const std::string file = source.string();
  rosbag::Bag bag;
  try {
    bag.open(file, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw Error(file, "bag", "a readable ROS 1 bag (format 2.0)", e.what());
  }

  // ---- pass 1: topics, image stamps and encodings, camera infos, all of tf.
  std::map<std::string, Topic> topics;
  std::vector<rosbag::MessageInstance> messages;
  std::map<std::string, std::vector<std::pair<double, sensor_msgs::CameraInfo>>> infos;
  std::vector<geometry_msgs::TransformStamped> dynamic_tf, static_tf;
  size_t bad_transforms = 0;
  size_t unreadable = 0;
  double begin = 0.0, end = 0.0;
  // One message of the first pass: image stamps, camera infos, tf.
  auto readMessage = [&](const rosbag::MessageInstance& m) {
    const std::string& type = m.getDataType();
    const std::string& topic = m.getTopic();
    if (type == kImageType || type == kCompressedType) {
      ImageEntry entry;
      std_msgs::Header header;
      if (type == kImageType) {
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
      entry.stamp = header.stamp.toSec();
      if (header.stamp.isZero()) {
        entry.stamp = m.getTime().toSec();
        entry.stamp_from_bag = true;
      }
      entry.frame_id = stripSlash(header.frame_id);
      entry.message = messages.size();
      messages.push_back(m);
      topics[topic].images.push_back(entry);
    } else if (type == kInfoType) {
      if (const auto info = m.instantiate<sensor_msgs::CameraInfo>()) {
        const double stamp = info->header.stamp.isZero() ? m.getTime().toSec()
                                                         : info->header.stamp.toSec();
        infos[topic].emplace_back(stamp, *info);
      }
    } else if (type == "tf2_msgs/TFMessage" || type == "tf/tfMessage") {
      const auto tf = m.instantiate<tf2_msgs::TFMessage>();
      if (!tf) return;
      const bool is_static = topic == "/tf_static" || topic == "tf_static";
      if (!is_static && topic != "/tf" && topic != "tf") return;
      for (auto t : tf->transforms) {
        t.header.frame_id = stripSlash(t.header.frame_id);
        t.child_frame_id = stripSlash(t.child_frame_id);
        const auto& q = t.transform.rotation;
        const auto& p = t.transform.translation;
        const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
        if (!std::isfinite(norm) || norm < 1e-6 || !std::isfinite(p.x) || !std::isfinite(p.y) ||
            !std::isfinite(p.z) || t.header.frame_id.empty() || t.child_frame_id.empty() ||
            t.header.frame_id == t.child_frame_id) {
          ++bad_transforms;
          continue;
        }
        (is_static ? static_tf : dynamic_tf).push_back(t);
      }
    }
  };
  try {
    rosbag::View view(bag);
    if (view.size() == 0) throw Error(file, "bag", "a bag with messages", "an empty bag");
    begin = view.getBeginTime().toSec();
    end = view.getEndTime().toSec();
    for (const rosbag::ConnectionInfo* c : view.getConnections())
      topics[c->topic] = Topic{c->topic, c->datatype, {}};
    for (const rosbag::MessageInstance& m : view) {
      try {
        readMessage(m);
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
    writer.note(std::to_string(unreadable) + " messages could not be read (truncated or corrupt) and were ignored");
  for (auto& [name, topic] : topics)
    std::stable_sort(topic.images.begin(), topic.images.end(),
                     [](const ImageEntry& a, const ImageEntry& b) { return a.stamp < b.stamp; });
  for (auto& [name, list] : infos)
    std::stable_sort(list.begin(), list.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });

  std::string available;
  for (const auto& [name, topic] : topics) {
    if (!available.empty()) available += ", ";
    available += name + " (" + topic.type;
    if (!topic.images.empty()) available += " " + topic.firstEncoding();
    available += ")";
  }

  // ---- topics: given or detected.
  auto requireTopic = [&](const std::string& name, const std::string& what,
                          std::initializer_list<const char*> types) -> const Topic& {
    const auto it = topics.find(name);
    if (it == topics.end())
      throw Error(file, what, "a topic of the bag", "'" + name + "' is not in it; topics: " + available);
    bool ok = false;
    std::string expected;
    for (const char* t : types) {
      ok |= it->second.type == t;
      expected += (expected.empty() ? "" : " or ") + std::string(t);
    }
    if (!ok) throw Error(file, what, "a " + expected + " topic", name + " is " + it->second.type);
    if (it->second.images.empty() && it->second.type != kInfoType)
      throw Error(file, what, "a topic with readable images", name + " has none");
    return it->second;
  };
  std::vector<const Topic*> image_topics;
  for (const auto& [name, topic] : topics)
    if (!topic.images.empty()) image_topics.push_back(&topic);

  const RosbagOptions& ro = options.rosbag;
  const Topic* depth_topic = nullptr;
  if (!ro.depth_topic.empty()) {
    depth_topic = &requireTopic(ro.depth_topic, "depth topic", {kImageType, kCompressedType});
    if (!isDepthEncoding(depth_topic->images.front()))
      throw Error(file, "depth topic", "depth images: 16UC1 (mm), 32FC1 (m) or compressedDepth",
                  ro.depth_topic + " holds " + depth_topic->firstEncoding());
  } else {
    std::vector<const Topic*> candidates;
    for (const Topic* t : image_topics)
      if (isDepthEncoding(t->images.front()) && !labelName(t->name) && !probaName(t->name))
        candidates.push_back(t);
    auto prefer = [&](auto&& keep) {
      std::vector<const Topic*> kept;
      for (const Topic* t : candidates)
        if (keep(lower(t->name))) kept.push_back(t);
      if (!kept.empty()) candidates = kept;
    };
    if (candidates.size() > 1) prefer([](const std::string& n) { return contains(n, "depth"); });
    if (candidates.size() > 1)
      prefer([](const std::string& n) { return contains(n, "aligned") || contains(n, "registered"); });
    if (candidates.empty())
      throw Error(file, "depth topic",
                  "a sensor_msgs/Image topic with 16UC1 (mm) or 32FC1 (m) depth", "none; topics: " + available);
    if (candidates.size() > 1)
      throw Error(file, "depth topic", "one depth topic (choose with the depth topic option)",
                  "several: " + listTopics(candidates));
    depth_topic = candidates.front();
    writer.note("depth topic: " + depth_topic->name + " (" + depth_topic->firstEncoding() + ")");
  }

  auto pickByPrefix = [&](std::vector<const Topic*> candidates, const std::string& what) -> const Topic* {
    if (candidates.empty()) return nullptr;
    std::stable_sort(candidates.begin(), candidates.end(), [&](const Topic* a, const Topic* b) {
      return commonPrefix(a->name, depth_topic->name) > commonPrefix(b->name, depth_topic->name);
    });
    if (candidates.size() > 1)
      writer.note("several " + what + " topics (" + listTopics(candidates) + "); using " +
                  candidates.front()->name);
    return candidates.front();
  };

  const Topic* color_topic = nullptr;
  if (!ro.no_color && options.write_color) {
    if (!ro.color_topic.empty()) {
      color_topic = &requireTopic(ro.color_topic, "color topic", {kImageType, kCompressedType});
      if (!isColorEncoding(color_topic->images.front()))
        throw Error(file, "color topic", "rgb8, bgr8, rgba8, bgra8 or mono8 images (or JPEG/PNG)",
                    ro.color_topic + " holds " + color_topic->firstEncoding());
    } else {
      std::vector<const Topic*> candidates, grey;
      for (const Topic* t : image_topics) {
        if (t == depth_topic || labelName(t->name) || probaName(t->name)) continue;
        if (!isColorEncoding(t->images.front())) continue;
        (lower(t->firstEncoding()) == "mono8" ? grey : candidates).push_back(t);
      }
      color_topic = pickByPrefix(candidates.empty() ? grey : candidates, "colour");
      if (color_topic) writer.note("colour topic: " + color_topic->name);
    }
  }

  const Topic* proba_topic = nullptr;
  if (!ro.proba_topic.empty()) {
    proba_topic = &requireTopic(ro.proba_topic, "probability topic", {kImageType});
    int bytes = 0;
    if (multiChannels(proba_topic->firstEncoding(), bytes) <= 0)
      throw Error(file, "probability topic", "32FC(N), 16UC(N) or 8UC(N) images, one channel per label",
                  ro.proba_topic + " holds " + proba_topic->firstEncoding());
  } else {
    std::vector<const Topic*> candidates;
    for (const Topic* t : image_topics) {
      if (t == depth_topic || t == color_topic || t->images.front().compressed) continue;
      int bytes = 0;
      const int channels = multiChannels(t->firstEncoding(), bytes);
      if ((channels >= 2 && !labelName(t->name)) ||
          (channels == 1 && probaName(t->name) && !labelName(t->name)))
        candidates.push_back(t);
    }
    if (candidates.size() > 1)
      throw Error(file, "probability topic", "one probability topic (choose with the proba topic option)",
                  "several: " + listTopics(candidates));
    if (!candidates.empty()) {
      proba_topic = candidates.front();
      writer.note("probability topic: " + proba_topic->name + " (" + proba_topic->firstEncoding() + ")");
    }
  }

  const Topic* label_topic = nullptr;
  if (!ro.label_topic.empty()) {
    label_topic = &requireTopic(ro.label_topic, "label topic", {kImageType});
    if (!isLabelEncoding(label_topic->images.front()))
      throw Error(file, "label topic", "mono8, 8UC1, mono16 or 16UC1 label ids",
                  ro.label_topic + " holds " + label_topic->firstEncoding());
  } else {
    std::vector<const Topic*> candidates;
    for (const Topic* t : image_topics)
      if (t != depth_topic && t != proba_topic && labelName(t->name) &&
          isLabelEncoding(t->images.front()))
        candidates.push_back(t);
    if (candidates.size() > 1)
      throw Error(file, "label topic", "one label topic (choose with the label topic option)",
                  "several: " + listTopics(candidates));
    if (!candidates.empty()) {
      label_topic = candidates.front();
      writer.note("label topic: " + label_topic->name);
    }
  }

  // ---- camera: CameraInfo of the depth images (or the intrinsics option).
  auto pickInfo = [&](const Topic* image_topic, const std::string& exclude) -> std::string {
    std::string best;
    size_t best_prefix = 0;
    for (const auto& [name, list] : infos) {
      if (name == exclude || list.empty()) continue;
      const size_t prefix = commonPrefix(name, image_topic->name);
      const bool same_frame = stripSlash(list.front().second.header.frame_id) ==
                              image_topic->images.front().frame_id;
      const size_t score = prefix * 2 + (same_frame ? 1 : 0);
      if (best.empty() || score > best_prefix) {
        best = name;
        best_prefix = score;
      }
    }
    return best;
  };
  std::string info_topic = ro.camera_info_topic;
  if (!info_topic.empty()) {
    requireTopic(info_topic, "camera info topic", {kInfoType});
  } else if (!infos.empty()) {
    info_topic = pickInfo(depth_topic, "");
  }
  std::optional<CameraIntrinsics> info_camera;
  std::string info_description = "no camera info";
  if (!info_topic.empty() && infos.count(info_topic)) {
    const auto& info = infos[info_topic].front().second;
    info_camera = intrinsicsOf(info);
    info_description = info_topic;
    if (!info_camera && !options.intrinsics)
      throw Error(file, "camera info", "a calibrated camera (K with fx, fy > 0) on " + info_topic,
                  "K = [" + formatNumber(info.K[0]) + " ... " + formatNumber(info.K[4]) + " ...]");
    if (!options.intrinsics) writer.note("camera info topic: " + info_topic);
    bool distorted = false;
    for (double d : info.D) distorted |= std::abs(d) > 1e-9;
    if (distorted)
      writer.note("the camera info has distortion coefficients; images are used as they are "
                  "(rectified images are expected)");
    if (info_camera && (info_camera->width <= 0 || info_camera->height <= 0)) {
      info_camera->width = depth_topic->images.front().width;
      info_camera->height = depth_topic->images.front().height;
    }
  }
  CameraIntrinsics camera = chooseCamera(
      info_camera, info_description, options, writer, source,
      "a sensor_msgs/CameraInfo topic for the depth images or the intrinsics option "
      "(--intrinsics fx,fy,cx,cy)");
  if (options.intrinsics && (camera.width <= 0 || camera.height <= 0) && info_camera) {
    camera.width = info_camera->width;
    camera.height = info_camera->height;
  }
  writer.setCamera(camera);
  std::optional<CameraIntrinsics> color_camera;
  if (color_topic) {
    const std::string color_info = pickInfo(color_topic, info_topic);
    if (!color_info.empty() && commonPrefix(color_info, color_topic->name) >
                                   commonPrefix(color_info, depth_topic->name))
      color_camera = intrinsicsOf(infos[color_info].front().second);
  }
  const double millimetres = options.depth_scale.value_or(0.001);
  {
    const std::string enc = lower(depth_topic->firstEncoding());
    const bool float_depth = contains(enc, "32fc1");
    writer.setDepthScale(float_depth ? 0.001 : millimetres);
  }

  // ---- labels.
  int proba_channels = 0;
  if (proba_topic) {
    int bytes = 0;
    proba_channels = multiChannels(proba_topic->firstEncoding(), bytes);
    if (options.labels) {
      if (options.labels->size() != proba_channels)
        throw Error(file, "labels",
                    "one label per probability channel: " + std::to_string(proba_channels) +
                        " (channel 0 = background)",
                    std::to_string(options.labels->size()) + " labels given");
      writer.setLabels(*options.labels);
    } else if (proba_channels == apc2016Labels().size()) {
      writer.setLabels(apc2016Labels());
      writer.note("40 probability channels: read as the APC 2016 labels");
    } else {
      std::vector<std::string> names;
      for (int c = 1; c < proba_channels; ++c) names.push_back("label_" + std::to_string(c));
      writer.setLabels(proba_channels == 1 ? backgroundOnlyLabels() : makeLabels(names));
      writer.note("probability channels named __background__, label_1, ... (give a label list "
                  "to name them)");
    }
  } else if (label_topic) {
    writer.setLabels(options.labels.value_or(apc2016Labels()));
    if (!options.labels) writer.note("label ids read as the APC 2016 labels (give a label list to change)");
    writer.note("label images became one-hot probabilities (confidence " +
                formatNumber(options.label_confidence) + ")");
  } else {
    writer.setLabels(backgroundOnlyLabels());
    writer.setLabelless(true);
    writer.note("no probability or label topic: the sequence has the single label __background__");
  }

  // ---- tf.
  std::string camera_frame = stripSlash(ro.camera_frame);
  if (camera_frame.empty()) camera_frame = depth_topic->images.front().frame_id;
  if (camera_frame.empty())
    throw Error(file, "camera frame", "a frame_id in the depth images' header (or the camera frame option)",
                "an empty frame_id");
  if (dynamic_tf.empty() && static_tf.empty())
    throw Error(file, "tf", "/tf or /tf_static messages giving the camera pose",
                bad_transforms ? std::to_string(bad_transforms) + " invalid transforms only"
                               : "none; topics: " + available);
  if (bad_transforms)
    writer.note(std::to_string(bad_transforms) +
                " tf transforms were invalid (NaN, zero quaternion, empty frame) and ignored");
  std::map<std::string, std::string> parent_of;
  std::set<std::string> frames;
  double tf_begin = INFINITY, tf_end = -INFINITY;
  for (const auto* list : {&static_tf, &dynamic_tf})
    for (const auto& t : *list) {
      parent_of[t.child_frame_id] = t.header.frame_id;
      frames.insert(t.child_frame_id);
      frames.insert(t.header.frame_id);
    }
  for (const auto& t : dynamic_tf) {
    tf_begin = std::min(tf_begin, t.header.stamp.toSec());
    tf_end = std::max(tf_end, t.header.stamp.toSec());
  }
  if (!frames.count(camera_frame)) {
    std::string names;
    for (const auto& f : frames) names += (names.empty() ? "" : ", ") + f;
    throw Error(file, "camera frame", "frame '" + camera_frame + "' in /tf or /tf_static",
                "frames " + names);
  }
  std::string fixed_frame = stripSlash(ro.fixed_frame);
  if (fixed_frame.empty()) {
    fixed_frame = camera_frame;
    std::set<std::string> seen{fixed_frame};
    while (parent_of.count(fixed_frame) && seen.insert(parent_of[fixed_frame]).second)
      fixed_frame = parent_of[fixed_frame];
    if (fixed_frame == camera_frame)
      throw Error(file, "fixed frame", "a frame above the camera frame '" + camera_frame + "' in tf",
                  "the camera frame has no parent");
    writer.note("poses of '" + camera_frame + "' in '" + fixed_frame +
                "' (the root of its tf tree; choose another with the fixed frame option)");
  } else if (!frames.count(fixed_frame)) {
    throw Error(file, "fixed frame", "a frame of /tf or /tf_static", "'" + fixed_frame + "' is not one");
  }
  if (lower(camera_frame).find("optical") == std::string::npos)
    writer.note("camera frame '" + camera_frame +
                "' is not named *optical*: it must have z forward, x right, y down");
  writer.setFrameId(fixed_frame);

  tf2::BufferCore buffer(ros::Duration(std::max(10.0, end - begin + 10.0)));
  for (const auto& t : static_tf) buffer.setTransform(t, "bag", true);
  for (const auto& t : dynamic_tf) buffer.setTransform(t, "bag", false);

  // ---- matching.
  const auto& depth_entries = depth_topic->images;
  const auto color_stamps = color_topic ? color_topic->stamps() : std::vector<double>{};
  const auto proba_stamps = proba_topic ? proba_topic->stamps() : std::vector<double>{};
  const auto label_stamps = label_topic ? label_topic->stamps() : std::vector<double>{};
  const double tol = options.time_tolerance;
  {
    size_t from_bag = 0;
    for (const auto& e : depth_entries) from_bag += e.stamp_from_bag;
    if (from_bag)
      writer.note(std::to_string(from_bag) +
                  " depth images have a zero header stamp: the bag's record time is used");
    const double image_begin = depth_entries.front().stamp + options.time_offset;
    const double image_end = depth_entries.back().stamp + options.time_offset;
    if (!dynamic_tf.empty() && (image_end < tf_begin - tol || image_begin > tf_end + tol))
      writer.note("depth image stamps (" + stampText(image_begin) + " to " + stampText(image_end) +
                  ") and tf stamps (" + stampText(tf_begin) + " to " + stampText(tf_end) +
                  ") do not overlap: the clocks differ by about " +
                  formatNumber(0.5 * (tf_begin + tf_end) - 0.5 * (image_begin + image_end), 4) +
                  " s (give it as the time offset option)");
  }
  auto unmatchedNote = [&](const std::vector<double>& stamps, const std::string& what) {
    if (stamps.empty()) return;
    std::vector<double> gaps;
    for (const auto& e : depth_entries) {
      const auto it = std::lower_bound(stamps.begin(), stamps.end(), e.stamp);
      double gap = INFINITY;
      if (it != stamps.end()) gap = *it - e.stamp;
      if (it != stamps.begin() && std::abs(*std::prev(it) - e.stamp) < std::abs(gap))
        gap = *std::prev(it) - e.stamp;
      gaps.push_back(gap);
    }
    std::sort(gaps.begin(), gaps.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    if (std::abs(gaps.front()) > tol)
      writer.note("no " + what + " image lies within " + formatNumber(tol) +
                  " s of a depth image (nearest " + formatNumber(gaps.front(), 4) +
                  " s away: a clock offset between the topics? raise the time tolerance)");
  };
  unmatchedNote(color_stamps, "colour");
  unmatchedNote(proba_stamps, "probability");
  unmatchedNote(label_stamps, "label");

  writer.setFound(depth_entries.size());

  const auto selected = selectFrames(depth_entries.size(), options);
  writer.setTotal(selected.size());
  size_t clamped = 0;
  for (size_t index : selected) {
    const ImageEntry& entry = depth_entries[index];
    const std::string name = "depth@" + stampText(entry.stamp);
    SourceFrame frame;
    frame.name = name;
    frame.stamp = entry.stamp;
    std::optional<std::string> error;

    // Pose at stamp + offset; at the edges of tf's range, within the tolerance.
    const double pose_stamp = entry.stamp + options.time_offset;
    std::optional<geometry_msgs::TransformStamped> pose;
    std::string tf_error;
    for (double t : {pose_stamp, pose_stamp - tol, pose_stamp + tol}) {
      if (t <= 0.0) continue;
      try {
        pose = buffer.lookupTransform(fixed_frame, camera_frame, ros::Time(t));
        break;
      } catch (const tf2::TransformException& e) {
        if (tf_error.empty()) tf_error = e.what();
      }
      if (tol == 0.0) break;
    }
    if (!pose) {
      std::string reason = "no transform from '" + fixed_frame + "' to '" + camera_frame + "' at " +
                           stampText(pose_stamp);
      if (!dynamic_tf.empty())
        reason += " (tf covers " + stampText(tf_begin) + " to " + stampText(tf_end) + ")";
      if (!tf_error.empty()) reason += ": " + tf_error;
      if (!writer.skip(name, reason)) return;
      continue;
    }
    {
      const auto& tr = pose->transform;
      const Eigen::Quaterniond q(tr.rotation.w, tr.rotation.x, tr.rotation.y, tr.rotation.z);
      frame.pose = Eigen::Matrix4d::Identity();
      frame.pose.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
      frame.pose.topRightCorner<3, 1>() =
          Eigen::Vector3d(tr.translation.x, tr.translation.y, tr.translation.z);
    }

    try {
      const rosbag::MessageInstance& m = messages[entry.message];
      try {
        if (entry.compressed) {
          const auto msg = load<sensor_msgs::CompressedImage>(m);
          frame.depth = decodeCompressedDepth(*msg, millimetres);
        } else {
          const auto msg = load<sensor_msgs::Image>(m);
          frame.depth = decodeDepth(*msg, millimetres);
        }
      } catch (const Error& e) {
        throw Error(depth_topic->name, "depth " + e.problem().field, e.problem().expected,
                    e.problem().found);
      }
      if (color_topic) {
        if (auto i = nearestStamp(color_stamps, entry.stamp, tol)) {
          const ImageEntry& c = color_topic->images[*i];
          const rosbag::MessageInstance& cm = messages[c.message];
          try {
            frame.color = c.compressed
                              ? decodeCompressedColor(*load<sensor_msgs::CompressedImage>(cm))
                              : decodeColor(*load<sensor_msgs::Image>(cm));
            frame.color_camera = color_camera;
          } catch (const Error& e) {
            // Named by topic like the depth, probability and label errors.
            const Error named(color_topic->name, "colour " + e.problem().field,
                              e.problem().expected, e.problem().found);
            writer.note("colour images that could not be decoded were left out (" +
                        std::string(named.what()) + ")");
          }
        } else {
          writer.note("depth images without a colour image within the time tolerance were "
                      "imported without colour");
        }
      }
      if (proba_topic) {
        auto i = nearestStamp(proba_stamps, entry.stamp, tol);
        if (!i)
          throw Error(proba_topic->name, "stamp",
                      "a probability image within " + formatNumber(tol) + " s of the depth image",
                      "none");
        const auto msg = load<sensor_msgs::Image>(messages[proba_topic->images[*i].message]);
        int bytes = 0;
        if (multiChannels(msg->encoding, bytes) != proba_channels)
          throw Error(proba_topic->name, "encoding",
                      std::to_string(proba_channels) + " channels as in the first message",
                      msg->encoding);
        try {
          frame.proba = decodeProba(*msg, &clamped);
        } catch (const Error& e) {
          throw Error(proba_topic->name, e.problem().field, e.problem().expected, e.problem().found);
        }
      }
      if (label_topic) {
        auto i = nearestStamp(label_stamps, entry.stamp, tol);
        if (!i) {
          if (!proba_topic)
            throw Error(label_topic->name, "stamp",
                        "a label image within " + formatNumber(tol) + " s of the depth image",
                        "none");
        } else {
          const auto msg = load<sensor_msgs::Image>(messages[label_topic->images[*i].message]);
          try {
            frame.label = decodeLabel(*msg);
          } catch (const Error& e) {
            throw Error(label_topic->name, e.problem().field, e.problem().expected, e.problem().found);
          }
        }
      }
    } catch (const Error& e) {
      error = e.what();
    } catch (const std::exception& e) {
      error = std::string("unreadable message: ") + e.what();
    }
    if (error) {
      if (!writer.skip(name, *error)) return;
      continue;
    }
    if (!writer.add(std::move(frame))) return;
  }
  if (clamped)
    writer.note(std::to_string(clamped) +
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
