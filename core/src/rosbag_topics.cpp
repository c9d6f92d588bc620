// Choosing a bag's topics and labels: see rosbag_topics.hpp.
#include "rosbag_topics.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "lom/error.hpp"
#include "lom/labels.hpp"

namespace lom::import_detail::bag {

std::vector<double> Topic::stamps() const {
  std::vector<double> s;
  s.reserve(images.size());
  for (const auto& e : images) s.push_back(e.stamp);
  return s;
}

std::vector<std::int64_t> Topic::nanoseconds() const {
  std::vector<std::int64_t> s;
  s.reserve(images.size());
  for (const auto& e : images) s.push_back(e.nanoseconds);
  return s;
}

std::string Topic::firstEncoding() const {
  return images.empty() ? std::string() : images.front().encoding;
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool contains(const std::string& text, const char* part) {
  return text.find(part) != std::string::npos;
}

size_t commonPrefix(const std::string& a, const std::string& b) {
  size_t n = 0;
  while (n < a.size() && n < b.size() && a[n] == b[n]) ++n;
  return n;
}

std::string stampText(double stamp) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << stamp;
  return out.str();
}

std::int64_t toNanoseconds(double seconds) {
  constexpr auto kMax = std::numeric_limits<std::int64_t>::max();
  constexpr auto kMin = std::numeric_limits<std::int64_t>::min();
  const double ns = seconds * 1e9;
  if (std::isnan(ns)) return 0;
  // Just below 2^63: llround of anything beyond overflows.
  if (ns >= 9.2e18) return kMax;
  if (ns <= -9.2e18) return kMin;
  return std::llround(ns);
}

std::int64_t addNanoseconds(std::int64_t a, std::int64_t b) {
  std::int64_t sum = 0;
  if (__builtin_add_overflow(a, b, &sum))
    return b > 0 ? std::numeric_limits<std::int64_t>::max()
                 : std::numeric_limits<std::int64_t>::min();
  return sum;
}

std::optional<size_t> nearestNanoseconds(const std::vector<std::int64_t>& sorted,
                                         std::int64_t stamp, std::int64_t tolerance) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), stamp);
  std::optional<size_t> best;
  // Unsigned: the distance between two int64 stamps may exceed int64.
  std::uint64_t best_distance = 0;
  auto consider = [&](std::vector<std::int64_t>::const_iterator candidate) {
    const std::uint64_t distance =
        *candidate > stamp
            ? static_cast<std::uint64_t>(*candidate) - static_cast<std::uint64_t>(stamp)
            : static_cast<std::uint64_t>(stamp) - static_cast<std::uint64_t>(*candidate);
    if (tolerance < 0 || distance > static_cast<std::uint64_t>(tolerance)) return;
    if (!best || distance < best_distance) {
      best = static_cast<size_t>(candidate - sorted.begin());
      best_distance = distance;
    }
  };
  if (it != sorted.begin()) consider(std::prev(it));
  if (it != sorted.end()) consider(it);
  return best;
}

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

bool isDepthEncoding(const ImageEntry& entry) {
  const std::string enc = lower(entry.encoding);
  if (entry.compressed) return contains(enc, "compresseddepth");
  return enc == "16uc1" || enc == "mono16" || enc == "32fc1";
}

namespace {

bool isColorEncoding(const ImageEntry& entry) {
  const std::string enc = lower(entry.encoding);
  if (entry.compressed) return !contains(enc, "compresseddepth");
  return enc == "rgb8" || enc == "bgr8" || enc == "rgba8" || enc == "bgra8" || enc == "mono8" ||
         enc == "8uc3";
}

bool isLabelEncoding(const ImageEntry& entry) {
  const std::string enc = lower(entry.encoding);
  return !entry.compressed &&
         (enc == "mono8" || enc == "8uc1" || enc == "mono16" || enc == "16uc1");
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

// The topic an image_transport republish carries ("/cam/depth/image/
// compressedDepth" -> "/cam/depth/image"); the name itself otherwise.
std::string transportBase(const std::string& name) {
  const size_t slash = name.rfind('/');
  if (slash == std::string::npos || slash == 0) return name;
  const std::string last = lower(name.substr(slash + 1));
  for (const char* transport : {"compressed", "compresseddepth", "theora", "zstd", "ffmpeg", "h264",
                                "h265", "foxglove", "rvl"})
    if (last == transport) return name.substr(0, slash);
  return name;
}

// Whether `name` carries the depth topic's images in another transport (its
// base + "/compressed", "/theora", or a plugin's one-word name): the depth
// camera's own JPEG republish is no colour image, however close its name.
bool republishOf(const std::string& name, const std::string& depth) {
  const std::string base = transportBase(depth) + "/";
  return name.size() > base.size() && name.compare(0, base.size(), base) == 0 &&
         name.find('/', base.size()) == std::string::npos;
}

// Drops the topics that republish another one of `topics` in another
// transport ("/camera/color/image_raw/compressed" beside
// "/camera/color/image_raw"); republishes without their raw topic stay.
void withoutRepublishes(std::vector<const Topic*>& topics) {
  std::vector<const Topic*> kept;
  for (const Topic* t : topics) {
    const std::string parent = t->name.substr(0, t->name.rfind('/'));
    if (std::none_of(topics.begin(), topics.end(),
                     [&](const Topic* other) { return other->name == parent; }))
      kept.push_back(t);
  }
  topics = kept;
}

std::string listTopics(const std::vector<const Topic*>& topics) {
  std::string text;
  for (const Topic* t : topics) {
    if (!text.empty()) text += ", ";
    text += t->name;
  }
  return text.empty() ? "none" : text;
}

// Detection of each kind of topic when the options do not name it.
class TopicChooser {
 public:
  TopicChooser(const TopicMap& topics, const std::string& file, SequenceWriter& writer)
      : topics_(topics), file_(file), writer_(writer), available_(describeTopics(topics)) {
    for (const auto& [name, topic] : topics)
      if (!topic.images.empty()) image_topics_.push_back(&topic);
  }

  const Topic* depth(const std::string& given) const {
    if (!given.empty()) {
      const Topic& topic = require(given, "depth topic", {kImageType, kCompressedType});
      if (!isDepthEncoding(topic.images.front()))
        throw Error(file_, "depth topic", "depth images: 16UC1 (mm), 32FC1 (m) or compressedDepth",
                    given + " holds " + topic.firstEncoding());
      return &topic;
    }
    std::vector<const Topic*> candidates;
    for (const Topic* t : image_topics_)
      if (isDepthEncoding(t->images.front()) && !labelName(t->name) && !probaName(t->name))
        candidates.push_back(t);
    auto prefer = [&](auto&& keep) {
      std::vector<const Topic*> kept;
      for (const Topic* t : candidates)
        if (keep(lower(t->name))) kept.push_back(t);
      if (!kept.empty()) candidates = kept;
    };
    // A driver's raw depth topic and its compressedDepth republish are one
    // camera's images: the raw one is taken.
    if (candidates.size() > 1) withoutRepublishes(candidates);
    if (candidates.size() > 1) prefer([](const std::string& n) { return contains(n, "depth"); });
    if (candidates.size() > 1)
      prefer(
          [](const std::string& n) { return contains(n, "aligned") || contains(n, "registered"); });
    if (candidates.empty())
      throw Error(file_, "depth topic",
                  "a sensor_msgs/Image topic with 16UC1 (mm) or 32FC1 (m) depth",
                  "none; topics: " + available_);
    if (candidates.size() > 1)
      throw Error(file_, "depth topic", "one depth topic (choose with the depth topic option)",
                  "several: " + listTopics(candidates));
    writer_.note("depth topic: " + candidates.front()->name + " (" +
                 candidates.front()->firstEncoding() + ")");
    return candidates.front();
  }

  const Topic* color(const std::string& given, const Topic* depth) const {
    if (!given.empty()) {
      const Topic& topic = require(given, "color topic", {kImageType, kCompressedType});
      if (!isColorEncoding(topic.images.front()))
        throw Error(file_, "color topic", "rgb8, bgr8, rgba8, bgra8 or mono8 images (or JPEG/PNG)",
                    given + " holds " + topic.firstEncoding());
      return &topic;
    }
    std::vector<const Topic*> candidates, grey;
    for (const Topic* t : image_topics_) {
      if (t == depth || labelName(t->name) || probaName(t->name)) continue;
      if (republishOf(t->name, depth->name)) continue;
      if (!isColorEncoding(t->images.front())) continue;
      (lower(t->firstEncoding()) == "mono8" ? grey : candidates).push_back(t);
    }
    withoutRepublishes(candidates);
    withoutRepublishes(grey);
    const Topic* chosen = closestTo(depth, candidates.empty() ? grey : candidates, "colour");
    if (chosen) writer_.note("colour topic: " + chosen->name);
    return chosen;
  }

  const Topic* proba(const std::string& given, const Topic* depth, const Topic* color) const {
    if (!given.empty()) {
      const Topic& topic = require(given, "probability topic", {kImageType});
      int bytes = 0;
      if (multiChannels(topic.firstEncoding(), bytes) <= 0)
        throw Error(file_, "probability topic",
                    "32FC(N), 16UC(N) or 8UC(N) images, one channel per label",
                    given + " holds " + topic.firstEncoding());
      return &topic;
    }
    std::vector<const Topic*> candidates;
    for (const Topic* t : image_topics_) {
      if (t == depth || t == color || t->images.front().compressed) continue;
      // A colour image (8UC3, rgb8...) is never taken for probabilities
      // unless its name says so (with the no-colour option it is not chosen
      // as colour, and used to end up here).
      if (isColorEncoding(t->images.front()) && !probaName(t->name)) continue;
      int bytes = 0;
      const int channels = multiChannels(t->firstEncoding(), bytes);
      if ((channels >= 2 && !labelName(t->name)) ||
          (channels == 1 && probaName(t->name) && !labelName(t->name)))
        candidates.push_back(t);
    }
    if (candidates.size() > 1)
      throw Error(file_, "probability topic",
                  "one probability topic (choose with the proba topic option)",
                  "several: " + listTopics(candidates));
    if (candidates.empty()) return nullptr;
    writer_.note("probability topic: " + candidates.front()->name + " (" +
                 candidates.front()->firstEncoding() + ")");
    return candidates.front();
  }

  const Topic* label(const std::string& given, const Topic* depth, const Topic* proba) const {
    if (!given.empty()) {
      const Topic& topic = require(given, "label topic", {kImageType});
      if (!isLabelEncoding(topic.images.front()))
        throw Error(file_, "label topic", "mono8, 8UC1, mono16 or 16UC1 label ids",
                    given + " holds " + topic.firstEncoding());
      return &topic;
    }
    std::vector<const Topic*> candidates;
    for (const Topic* t : image_topics_)
      if (t != depth && t != proba && labelName(t->name) && isLabelEncoding(t->images.front()))
        candidates.push_back(t);
    if (candidates.size() > 1)
      throw Error(file_, "label topic", "one label topic (choose with the label topic option)",
                  "several: " + listTopics(candidates));
    if (candidates.empty()) return nullptr;
    writer_.note("label topic: " + candidates.front()->name);
    return candidates.front();
  }

 private:
  const Topic& require(const std::string& name, const std::string& what,
                       std::initializer_list<const char*> types) const {
    return requireTopic(topics_, name, what, types, file_);
  }

  // Of several candidates, the one whose name shares the longest prefix with
  // the depth topic's (the same camera's namespace).
  const Topic* closestTo(const Topic* depth, std::vector<const Topic*> candidates,
                         const std::string& what) const {
    if (candidates.empty()) return nullptr;
    std::stable_sort(candidates.begin(), candidates.end(), [&](const Topic* a, const Topic* b) {
      return commonPrefix(a->name, depth->name) > commonPrefix(b->name, depth->name);
    });
    if (candidates.size() > 1)
      writer_.note("several " + what + " topics (" + listTopics(candidates) + "); using " +
                   candidates.front()->name);
    return candidates.front();
  }

  const TopicMap& topics_;
  const std::string& file_;
  SequenceWriter& writer_;
  std::string available_;
  std::vector<const Topic*> image_topics_;
};

}  // namespace

std::string describeTopics(const TopicMap& topics) {
  std::string available;
  for (const auto& [name, topic] : topics) {
    if (!available.empty()) available += ", ";
    available += name + " (" + topic.type;
    if (!topic.images.empty()) available += " " + topic.firstEncoding();
    available += ")";
  }
  return available;
}

const Topic& requireTopic(const TopicMap& topics, const std::string& name, const std::string& what,
                          std::initializer_list<const char*> types, const std::string& file) {
  const auto it = topics.find(name);
  if (it == topics.end())
    throw Error(file, what, "a topic of the bag",
                "'" + name + "' is not in it; topics: " + describeTopics(topics));
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
}

ChosenTopics chooseTopics(const TopicMap& topics, const ImportOptions& options,
                          const std::string& file, SequenceWriter& writer) {
  const RosbagOptions& given = options.rosbag;
  const TopicChooser chooser(topics, file, writer);
  ChosenTopics chosen;
  chosen.depth = chooser.depth(given.depth_topic);
  if (!given.no_color && options.write_color)
    chosen.color = chooser.color(given.color_topic, chosen.depth);
  chosen.proba = chooser.proba(given.proba_topic, chosen.depth, chosen.color);
  chosen.label = chooser.label(given.label_topic, chosen.depth, chosen.proba);
  return chosen;
}

void chooseLabels(int proba_channels, bool label_topic, const ImportOptions& options,
                  const std::string& file, SequenceWriter& writer) {
  if (proba_channels > 0) {
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
      writer.note(
          "probability channels named __background__, label_1, ... (give a label list "
          "to name them)");
    }
  } else if (label_topic) {
    writer.setLabels(options.labels.value_or(apc2016Labels()));
    if (!options.labels)
      writer.note("label ids read as the APC 2016 labels (give a label list to change)");
    writer.note("label images became one-hot probabilities (confidence " +
                formatNumber(options.label_confidence) + ")");
  } else {
    writer.setLabels(backgroundOnlyLabels());
    writer.setLabelless(true);
    writer.noteOnlyBackground(
        "no probability or label topic: the sequence has the single label __background__");
  }
}

}  // namespace lom::import_detail::bag
