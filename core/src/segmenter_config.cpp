// MODEL.json: the pre- and post-processing of a segmentation network
// (docs/segmenter.md), parsed with messages naming the file and the key.
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "file_checks.hpp"
#include "json_text.hpp"
#include "lom/error.hpp"
#include "lom/segmenter.hpp"

namespace lom {

namespace fs = std::filesystem;
using Json = nlohmann::json;

using json_text::describe;

namespace {

constexpr int kMaxInputSide = 16384;

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  [[noreturn]] void fail(const std::string& field, const std::string& expected,
                         const std::string& found) const {
    throw Error(file_, field, expected, found);
  }

  double number(const Json& value, const std::string& field) const {
    if (!value.is_number()) fail(field, "a number", describe(value));
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(field, "a finite number", describe(value));
    return x;
  }

  int integer(const Json& value, const std::string& field, int min, int max) const {
    const std::string range = "an integer from " + std::to_string(min) + " to " + std::to_string(max);
    const std::optional<long long> x = integral(value);
    if (!x || *x < min || *x > max) fail(field, range, describe(value));
    return static_cast<int>(*x);
  }

  // A whole number, written as 6 or as 6.0 (sequence.json reads both alike).
  static std::optional<long long> integral(const Json& value) {
    if (value.is_number_integer()) return value.get<long long>();
    if (!value.is_number_float()) return std::nullopt;
    const double x = value.get<double>();
    if (!std::isfinite(x) || std::floor(x) != x || std::abs(x) > 9007199254740992.0)
      return std::nullopt;
    return static_cast<long long>(x);
  }

  std::string choice(const Json& value, const std::string& field,
                     const std::vector<std::string>& choices) const {
    std::string expected;
    for (size_t i = 0; i < choices.size(); ++i)
      expected += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + ("\"" + choices[i] + "\"");
    if (!value.is_string()) fail(field, expected, describe(value));
    const auto text = value.get<std::string>();
    for (const auto& c : choices)
      if (text == c) return text;
    fail(field, expected, describe(value));
  }

  std::array<double, 3> triple(const Json& value, const std::string& field, bool positive) const {
    const std::string expected =
        std::string("3 ") + (positive ? "positive numbers" : "numbers") +
        " (one per input channel, in the network's channel order)";
    if (!value.is_array() || value.size() != 3) fail(field, expected, describe(value));
    std::array<double, 3> out{};
    for (size_t c = 0; c < 3; ++c) {
      const std::string item = field + "[" + std::to_string(c) + "]";
      out[c] = number(value[c], item);
      if (positive && !(out[c] > 0.0)) fail(item, "a positive number", describe(value[c]));
    }
    return out;
  }

 private:
  std::string file_;
};

}  // namespace

fs::path segmenterConfigPath(const fs::path& model) {
  fs::path json = model;
  json.replace_extension(".json");
  return json;
}

SegmenterConfig parseSegmenterConfig(const std::string& json_text, const std::string& file_name) {
  const Reader in(file_name);
  const Json root = lom::json_text::parseText(json_text, file_name);
  if (!root.is_object()) in.fail("(top level)", "a JSON object", describe(root));

  static const std::set<std::string> kKnown = {"input_width", "input_height", "scale", "mean",
                                               "std",         "channel_order", "output", "labels",
                                               "resize"};
  for (const auto& [key, value] : root.items())
    if (!kKnown.count(key))
      in.fail(key, "one of the keys input_width, input_height, scale, mean, std, channel_order, "
                   "output, labels, resize",
              "an unknown key");

  SegmenterConfig config;
  if (root.contains("input_width") != root.contains("input_height"))
    in.fail(root.contains("input_width") ? "input_height" : "input_width",
            "input_width and input_height given together", "only one of them");
  if (root.contains("input_width")) {
    config.input_width = in.integer(root["input_width"], "input_width", 1, kMaxInputSide);
    config.input_height = in.integer(root["input_height"], "input_height", 1, kMaxInputSide);
  }
  if (root.contains("scale")) {
    config.scale = in.number(root["scale"], "scale");
    if (!(config.scale > 0.0)) in.fail("scale", "a positive number", describe(root["scale"]));
  }
  if (root.contains("mean")) config.mean = in.triple(root["mean"], "mean", false);
  if (root.contains("std")) config.stddev = in.triple(root["std"], "std", true);
  if (root.contains("channel_order"))
    config.channel_order = in.choice(root["channel_order"], "channel_order", {"rgb", "bgr"}) == "rgb"
                               ? SegmenterChannelOrder::Rgb
                               : SegmenterChannelOrder::Bgr;
  if (root.contains("output"))
    config.output = in.choice(root["output"], "output", {"scores", "probabilities"}) == "scores"
                        ? SegmenterOutput::Scores
                        : SegmenterOutput::Probabilities;
  if (root.contains("resize"))
    config.resize = in.choice(root["resize"], "resize", {"linear", "nearest"}) == "linear"
                        ? SegmenterResize::Linear
                        : SegmenterResize::Nearest;
  if (root.contains("labels")) {
    const Json& labels = root["labels"];
    if (!labels.is_array() || labels.empty())
      in.fail("labels", "a non-empty array with the label of each output channel",
              describe(labels));
    std::vector<SegmenterLabel> out;
    for (size_t c = 0; c < labels.size(); ++c) {
      const Json& item = labels[c];
      const std::string field = "labels[" + std::to_string(c) + "]";
      SegmenterLabel label;
      if (item.is_null()) {
        // dropped channel
      } else if (item.is_string()) {
        label.name = item.get<std::string>();
        if (label.name.empty()) in.fail(field, "a label name, a label id or null", "an empty string");
      } else if (const auto id = Reader::integral(item); id && *id >= 0 && *id < 65536) {
        label.id = static_cast<int>(*id);
      } else {
        in.fail(field, "a label id (integer >= 0), a label name or null (channel not used)",
                describe(item));
      }
      out.push_back(label);
    }
    bool any = false;
    for (const auto& l : out) any = any || !l.dropped();
    if (!any) in.fail("labels", "at least one channel with a label", "only null entries");
    config.labels = std::move(out);
  }
  return config;
}

SegmenterConfig readSegmenterConfig(const fs::path& json) {
  if (const std::string why = notARegularFile(json); !why.empty())
    throw Error(json.string(), "(file)", "a segmenter configuration file (JSON)", why);
  std::ifstream in(json, std::ios::binary);
  if (!in)
    throw Error(json.string(), "(file)", "a readable segmenter configuration (JSON)",
                "a file that cannot be opened");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parseSegmenterConfig(buffer.str(), json.string());
}

}  // namespace lom
