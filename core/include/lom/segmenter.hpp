#pragma once
// A trained 2D segmentation network (ONNX, run with OpenCV's DNN module) that
// turns a colour image into per-pixel label probabilities, for frames that
// have no probability image. Configuration and cache: docs/segmenter.md.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lom/images.hpp"
#include "lom/labels.hpp"
#include "lom/npy.hpp"
#include "lom/sequence.hpp"

namespace lom {

enum class SegmenterChannelOrder { Rgb, Bgr };
enum class SegmenterOutput {
  Scores,         // unnormalised scores (logits): a pixel-wise softmax is applied
  Probabilities,  // already probabilities (the model ends with a softmax)
};
enum class SegmenterResize {
  Linear,   // bilinear when enlarging, pixel-area averaging when shrinking
  Nearest,  // nearest pixel centre
};

// One output channel of the network: the label it holds.
struct SegmenterLabel {
  int id = -1;       // label id, or -1 when given by name or dropped
  std::string name;  // label name, resolved against the sequence's labels
  [[nodiscard]] bool dropped() const { return id < 0 && name.empty(); }
};

// The pre- and post-processing of a model: MODEL.json beside MODEL.onnx.
// Every field has a default; see docs/segmenter.md.
struct SegmenterConfig {
  // Network input size; absent = the model's own fixed size, or the image size
  // when the model accepts any size.
  std::optional<int> input_width;
  std::optional<int> input_height;
  // input value of channel c = (pixel value * scale - mean[c]) / stddev[c], with c
  // in the network's channel order (channel_order).
  double scale = 1.0 / 255.0;
  std::array<double, 3> mean{0.0, 0.0, 0.0};
  std::array<double, 3> stddev{1.0, 1.0, 1.0};  // "std" in MODEL.json
  SegmenterChannelOrder channel_order = SegmenterChannelOrder::Rgb;
  // Absent ("output" not in MODEL.json): Probabilities when the node producing
  // the network's output is a Softmax over the channel axis, else Scores.
  // Segmenter::config() holds the value used.
  std::optional<SegmenterOutput> output;
  // The label of each output channel; absent = channel c is label c (and the
  // network must have one channel per label of the sequence).
  std::optional<std::vector<SegmenterLabel>> labels;
  SegmenterResize resize = SegmenterResize::Linear;
};

// MODEL.json for MODEL.onnx (the extension replaced by ".json").
[[nodiscard]] std::filesystem::path segmenterConfigPath(const std::filesystem::path& model);

// Reads a segmenter configuration. Unknown keys, wrong types and out-of-range
// values throw lom::Error naming the file and the key.
[[nodiscard]] SegmenterConfig readSegmenterConfig(const std::filesystem::path& json);
[[nodiscard]] SegmenterConfig parseSegmenterConfig(const std::string& json_text,
                                                   const std::string& file_name);

struct SegmenterOptions {
  // Folder of the on-disk cache; empty = "<sequence folder>/.segmenter-cache"
  // (segmentFrame / loadFrameWithSegmenter) or no disk cache (segment()).
  std::filesystem::path cache_dir;
  bool disk_cache = true;
  // Network outputs kept in memory (least recently used dropped first).
  size_t memory_cache_bytes = size_t{256} << 20;
  // Told about problems that do not stop segmentation (e.g. an unwritable cache folder).
  std::function<void(const std::string&)> warn;
};

// Counters, e.g. to show how much work a cache saved.
struct SegmenterStats {
  size_t inferences = 0;     // network runs
  size_t memory_hits = 0;    // outputs found in memory
  size_t disk_hits = 0;      // outputs read from the disk cache
  size_t running = 0;        // network runs in progress now
};

class Segmenter {
 public:
  // Loads MODEL.onnx and, when it exists, MODEL.json beside it (defaults otherwise).
  // Throws lom::Error naming the file for an unreadable or invalid model or config.
  [[nodiscard]] static std::shared_ptr<Segmenter> load(const std::filesystem::path& model,
                                                       SegmenterOptions options = {});
  // Same with an explicit configuration (`config_file` only names it in messages).
  [[nodiscard]] static std::shared_ptr<Segmenter> load(const std::filesystem::path& model,
                                                       const SegmenterConfig& config,
                                                       SegmenterOptions options = {},
                                                       const std::filesystem::path& config_file = {});
  ~Segmenter();
  Segmenter(const Segmenter&) = delete;
  Segmenter& operator=(const Segmenter&) = delete;

  [[nodiscard]] const std::filesystem::path& modelPath() const;
  // The configuration file read (empty when the defaults are used).
  [[nodiscard]] const std::filesystem::path& configPath() const;
  [[nodiscard]] const SegmenterConfig& config() const;
  // The input size the network gets for an image of the given size.
  [[nodiscard]] std::pair<int, int> inputSize(int image_width, int image_height) const;

  // Checks the configured channel labels against a label set (ids in range, names
  // known, each label once). The channel count itself is checked on the first run.
  void checkLabels(const LabelSet& labels) const;

  // The number of output channels, learnt from the first run, or else from one
  // run on a grey image of the model's input size (64 x 64 for a model that
  // accepts any size; not counted in stats()). nullopt when the network cannot
  // run on that image: its first real run then tells.
  [[nodiscard]] std::optional<int> outputChannels() const;
  // checkLabels, plus the channel count (outputChannels) against the labels:
  // throws the lom::Error segment() would throw on its first run, before any work.
  void checkFits(const LabelSet& labels) const;

  // Probabilities of `color`, `width` x `height` (the depth image's size), one
  // channel per kept network channel, channel_labels = their label ids. Runs the
  // network unless the output for this image is cached (in memory, or in
  // `cache_dir` when not empty and disk caching is on). Throws lom::Error for an
  // output that does not match the labels.
  [[nodiscard]] ProbabilityImage segment(const ColorImage& color, int width, int height,
                                         const LabelSet& labels,
                                         const std::filesystem::path& cache_dir = {}) const;

  [[nodiscard]] SegmenterStats stats() const;
  // The cache folder used for a sequence: options.cache_dir or <root>/.segmenter-cache.
  [[nodiscard]] std::filesystem::path cacheDirFor(const Sequence& sequence) const;

 private:
  struct Impl;
  explicit Segmenter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Runs `segmenter` on frame `index` of `sequence` (its colour image), at the size
// of the frame's camera. Throws lom::Error naming sequence.json and the frame when
// the frame has no colour image.
[[nodiscard]] ProbabilityImage segmentFrame(const Sequence& sequence, size_t index,
                                            const ColorImage& color, const Segmenter& segmenter);

// loadFrame, plus the segmenter's probabilities for a frame without `proba`, or
// whose `proba` was made from its label image (proba_from_label; the frame's
// label image, if any, then stays as 2D ground truth). With a null
// segmenter this is loadFrame.
[[nodiscard]] FrameData loadFrameWithSegmenter(const Sequence& sequence, size_t index,
                                               const Segmenter* segmenter);
// Whether `segmenter` (may be null) gives frame `index` its probabilities:
// the frame has no proba, or one an import made from its label image.
[[nodiscard]] bool segmenterRunsOn(const Sequence& sequence, size_t index,
                                   const Segmenter* segmenter);

// The second half of loadFrameWithSegmenter, for a frame loaded already:
// replaces or adds its proba with the segmenter's where the rule above says so.
void addSegmenterProbabilities(const Sequence& sequence, size_t index, const Segmenter* segmenter,
                               FrameData& frame);

// Writes a probability image as an H x W x C .npy of `dtype` (Float32, Float16 or
// UInt8 = round(p * 255)), atomically; the format of a sequence's proba files.
void writeProbabilityNpy(const std::filesystem::path& path, const ProbabilityImage& proba,
                         NpyType dtype);

}  // namespace lom
