#pragma once
// Which topics of a ROS 1 bag become the depth, colour, probability and label
// images of a sequence, and which labels the probability channels get. Plain
// names and encodings only (no ROS headers), so the choice is tested without
// writing bags. Not a public API: used by import_rosbag.cpp.
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "import_internal.hpp"

namespace lom::import_detail::bag {

inline constexpr const char* kImageType = "sensor_msgs/Image";
inline constexpr const char* kCompressedType = "sensor_msgs/CompressedImage";
inline constexpr const char* kInfoType = "sensor_msgs/CameraInfo";

// One image message, as the first pass over the bag saw it.
struct ImageEntry {
  double stamp = 0.0;  // seconds, for messages only: see nanoseconds
  // The stamp as ROS holds it (sec * 10^9 + nsec), for matching: at epoch
  // times a double resolves only ~0.2 us, and a tf sample or an image at the
  // very same stamp was missed.
  std::int64_t nanoseconds = 0;
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
  [[nodiscard]] std::vector<double> stamps() const;
  [[nodiscard]] std::vector<std::int64_t> nanoseconds() const;
  [[nodiscard]] std::string firstEncoding() const;
};

using TopicMap = std::map<std::string, Topic>;

std::string lower(std::string text);
bool contains(const std::string& text, const char* part);
size_t commonPrefix(const std::string& a, const std::string& b);
// Seconds with three decimals, for messages.
std::string stampText(double stamp);

// Seconds (an option's offset or tolerance) as nanoseconds, rounded;
// saturated at the int64 limits (an offset of 1e30 s is no error, it only
// leaves every stamp outside ROS time).
std::int64_t toNanoseconds(double seconds);
// a + b, saturated at the int64 limits.
std::int64_t addNanoseconds(std::int64_t a, std::int64_t b);
// Index of the stamp nearest to `stamp` within `tolerance` (all nanoseconds)
// in a sorted list; the earlier one of two equally near.
std::optional<size_t> nearestNanoseconds(const std::vector<std::int64_t>& sorted,
                                         std::int64_t stamp, std::int64_t tolerance);

// Channels of "32FC3" / "16UC5" / "8UC2" encodings (bytes per value in
// `bytes`); 0 when not that form.
int multiChannels(const std::string& encoding, int& bytes);
bool isDepthEncoding(const ImageEntry& entry);

// "name (type encoding), ..." of every topic, for messages that list what the
// bag holds.
std::string describeTopics(const TopicMap& topics);

// Throws lom::Error (file, `what`) unless `name` is a topic of one of `types`
// with readable images (camera info topics need none).
const Topic& requireTopic(const TopicMap& topics, const std::string& name, const std::string& what,
                          std::initializer_list<const char*> types, const std::string& file);

struct ChosenTopics {
  const Topic* depth = nullptr;  // never null once chosen
  const Topic* color = nullptr;
  const Topic* proba = nullptr;
  const Topic* label = nullptr;
};

// The topics given in the options, else the ones detected by encoding and
// name (noted on the writer). Throws lom::Error naming `file` and the option
// when a given topic does not fit or the detection is ambiguous.
ChosenTopics chooseTopics(const TopicMap& topics, const ImportOptions& options,
                          const std::string& file, SequenceWriter& writer);

// Labels of the sequence: one per probability channel (the options' list, the
// APC 2016 labels for 40 channels, or label_N), the APC 2016 labels for label
// images, else the background only. `proba_channels` is 0 without a
// probability topic.
void chooseLabels(int proba_channels, bool label_topic, const ImportOptions& options,
                  const std::string& file, SequenceWriter& writer);

}  // namespace lom::import_detail::bag
