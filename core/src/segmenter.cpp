// Segmentation network in the loop (docs/segmenter.md): an ONNX model run with
// OpenCV's DNN module on colour frames, its output turned into per-pixel label
// probabilities at the depth image's size, with memory and disk caches.
#include "lom/segmenter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <list>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "file_checks.hpp"
#include "lom/error.hpp"
#include "lom/npy.hpp"

namespace lom {

namespace fs = std::filesystem;

namespace {

// Probabilities declared by the model may overshoot [0, 1] by rounding.
constexpr double kProbabilityTolerance = 1e-3;
constexpr const char* kCacheFolder = ".segmenter-cache";

// ---------------------------------------------------------------------------
// Hashing (cache keys): 64-bit FNV-1a.

constexpr std::uint64_t kFnvOffset = 1469598103934665603ull;
constexpr std::uint64_t kFnvPrime = 1099511628211ull;

std::uint64_t fnv1a(const void* data, size_t size, std::uint64_t hash = kFnvOffset) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  for (size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= kFnvPrime;
  }
  return hash;
}

std::string hex64(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

std::string numberText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// ---------------------------------------------------------------------------
// The few ONNX fields needed before OpenCV sees the model (input name and
// shape, output names), read straight from the protobuf wire format:
// ModelProto.graph = 7; GraphProto.initializer = 5, .input = 11, .output = 12;
// TensorProto.name = 8; ValueInfoProto.name = 1, .type = 2; TypeProto.tensor_type = 1;
// TypeProto.Tensor.shape = 2; TensorShapeProto.dim = 1; Dimension.dim_value = 1, .dim_param = 2;
// and, to tell whether the output is already probabilities, ModelProto.opset_import = 8
// (OperatorSetIdProto.domain = 1, .version = 2), GraphProto.node = 1 (NodeProto.input = 1,
// .output = 2, .op_type = 4, .attribute = 5, .domain = 7; AttributeProto.name = 1, .i = 3).

struct WireField {
  std::uint32_t number = 0;
  std::uint32_t type = 0;
  std::uint64_t value = 0;     // varint / fixed
  std::string_view bytes;      // length-delimited
};

class WireReader {
 public:
  explicit WireReader(std::string_view data) : data_(data) {}
  // False at the end; throws std::runtime_error on malformed data.
  bool next(WireField& field) {
    if (pos_ >= data_.size()) return false;
    const std::uint64_t tag = varint();
    field.number = static_cast<std::uint32_t>(tag >> 3);
    field.type = static_cast<std::uint32_t>(tag & 7);
    field.bytes = {};
    field.value = 0;
    if (field.number == 0) throw std::runtime_error("field number 0");
    switch (field.type) {
      case 0:
        field.value = varint();
        break;
      case 1:
        field.value = fixed(8);
        break;
      case 5:
        field.value = fixed(4);
        break;
      case 2: {
        const std::uint64_t length = varint();
        if (length > data_.size() - pos_) throw std::runtime_error("truncated field");
        field.bytes = data_.substr(pos_, static_cast<size_t>(length));
        pos_ += static_cast<size_t>(length);
        break;
      }
      default:
        throw std::runtime_error("unsupported wire type " + std::to_string(field.type));
    }
    return true;
  }

 private:
  std::uint64_t varint() {
    std::uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (pos_ >= data_.size()) throw std::runtime_error("truncated varint");
      const auto byte = static_cast<std::uint8_t>(data_[pos_++]);
      value |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
      if (!(byte & 0x80)) return value;
    }
    throw std::runtime_error("varint too long");
  }
  std::uint64_t fixed(size_t size) {
    if (size > data_.size() - pos_) throw std::runtime_error("truncated fixed field");
    std::uint64_t value = 0;
    for (size_t i = 0; i < size; ++i)
      value |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(data_[pos_ + i])) << (8 * i);
    pos_ += size;
    return value;
  }
  std::string_view data_;
  size_t pos_ = 0;
};

struct OnnxValueInfo {
  std::string name;
  bool has_shape = false;
  std::vector<std::int64_t> dims;  // -1 = not fixed (symbolic or absent)
};

struct OnnxNode {
  std::string op_type;
  std::string domain;
  std::vector<std::string> inputs;
  std::vector<std::string> outputs;
  std::optional<std::int64_t> axis;  // the "axis" attribute
};

struct OnnxGraphInfo {
  std::vector<OnnxValueInfo> inputs;  // graph inputs that are not initializers
  std::vector<OnnxValueInfo> outputs;
  std::vector<OnnxNode> nodes;
  std::int64_t opset = 0;  // of the default domain; 0 = not given
};

OnnxNode readNode(std::string_view bytes) {
  OnnxNode node;
  WireReader reader(bytes);
  WireField f;
  while (reader.next(f)) {
    if (f.type != 2) continue;
    if (f.number == 1) node.inputs.emplace_back(f.bytes);
    if (f.number == 2) node.outputs.emplace_back(f.bytes);
    if (f.number == 4) node.op_type = std::string(f.bytes);
    if (f.number == 7) node.domain = std::string(f.bytes);
    if (f.number != 5) continue;
    WireReader attribute(f.bytes);
    WireField a;
    std::string name;
    std::optional<std::int64_t> value;
    while (attribute.next(a)) {
      if (a.number == 1 && a.type == 2) name = std::string(a.bytes);
      if (a.number == 3 && a.type == 0) value = static_cast<std::int64_t>(a.value);
    }
    if (name == "axis" && value) node.axis = value;
  }
  return node;
}

// Whether the graph output `name` is made by a Softmax over the channel axis
// (axis 1 of N x C x H x W), through Identity nodes: the values are then
// probabilities already. Softmax's default axis is 1 before opset 13, -1 since.
bool endsWithChannelSoftmax(const OnnxGraphInfo& graph, std::string name) {
  for (size_t step = 0; step <= graph.nodes.size(); ++step) {
    const auto producer =
        std::find_if(graph.nodes.begin(), graph.nodes.end(), [&](const OnnxNode& node) {
          return std::find(node.outputs.begin(), node.outputs.end(), name) != node.outputs.end();
        });
    if (producer == graph.nodes.end()) return false;
    if (!producer->domain.empty() && producer->domain != "ai.onnx") return false;
    if (producer->op_type == "Identity" && !producer->inputs.empty()) {
      name = producer->inputs.front();
      continue;
    }
    if (producer->op_type != "Softmax") return false;
    const std::int64_t axis = producer->axis                          ? *producer->axis
                              : (graph.opset > 0 && graph.opset < 13) ? 1
                                                                      : -1;
    return axis == 1 || axis == -3;
  }
  return false;
}

OnnxValueInfo readValueInfo(std::string_view bytes) {
  OnnxValueInfo info;
  WireReader value_info(bytes);
  WireField f;
  while (value_info.next(f)) {
    if (f.number == 1 && f.type == 2) info.name = std::string(f.bytes);
    if (f.number != 2 || f.type != 2) continue;
    WireReader type(f.bytes);
    WireField t;
    while (type.next(t)) {
      if (t.number != 1 || t.type != 2) continue;
      WireReader tensor(t.bytes);
      WireField s;
      while (tensor.next(s)) {
        if (s.number != 2 || s.type != 2) continue;
        info.has_shape = true;
        WireReader shape(s.bytes);
        WireField d;
        while (shape.next(d)) {
          if (d.number != 1 || d.type != 2) continue;
          std::int64_t dim = -1;
          WireReader dimension(d.bytes);
          WireField v;
          while (dimension.next(v))
            if (v.number == 1 && v.type == 0) dim = static_cast<std::int64_t>(v.value);
          info.dims.push_back(dim > 0 ? dim : -1);
        }
      }
    }
  }
  return info;
}

// Throws std::runtime_error when the bytes are not an ONNX model.
OnnxGraphInfo readOnnxGraphInfo(std::string_view model) {
  WireReader reader(model);
  WireField field;
  std::string_view graph;
  bool has_graph = false;
  OnnxGraphInfo info;
  while (reader.next(field)) {
    if (field.number == 7 && field.type == 2) {
      graph = field.bytes;
      has_graph = true;
    } else if (field.number == 8 && field.type == 2) {
      WireReader opset(field.bytes);
      WireField o;
      std::string domain;
      std::int64_t version = 0;
      while (opset.next(o)) {
        if (o.number == 1 && o.type == 2) domain = std::string(o.bytes);
        if (o.number == 2 && o.type == 0) version = static_cast<std::int64_t>(o.value);
      }
      if (domain.empty() || domain == "ai.onnx") info.opset = version;
    }
  }
  if (!has_graph) throw std::runtime_error("no graph");
  std::set<std::string> initializers;
  std::vector<OnnxValueInfo> inputs;
  WireReader g(graph);
  while (g.next(field)) {
    if (field.type != 2) continue;
    if (field.number == 1) {
      info.nodes.push_back(readNode(field.bytes));
    } else if (field.number == 5) {
      WireReader tensor(field.bytes);
      WireField t;
      while (tensor.next(t))
        if (t.number == 8 && t.type == 2) initializers.insert(std::string(t.bytes));
    } else if (field.number == 11) {
      inputs.push_back(readValueInfo(field.bytes));
    } else if (field.number == 12) {
      info.outputs.push_back(readValueInfo(field.bytes));
    }
  }
  for (auto& input : inputs)
    if (!initializers.count(input.name)) info.inputs.push_back(std::move(input));
  return info;
}

std::string dimsText(const std::vector<std::int64_t>& dims) {
  std::string text;
  for (size_t i = 0; i < dims.size(); ++i)
    text += (i ? " x " : "") + (dims[i] > 0 ? std::to_string(dims[i]) : std::string("?"));
  return text.empty() ? "a scalar" : text;
}

// ---------------------------------------------------------------------------
// Network outputs (after the softmax), as cached: C x H x W float32.

struct NetOutput {
  int channels = 0;
  int height = 0;
  int width = 0;
  std::vector<float> chw;
  [[nodiscard]] size_t bytes() const { return chw.size() * sizeof(float) + sizeof(NetOutput); }
  [[nodiscard]] const float* plane(int c) const {
    return chw.data() + static_cast<size_t>(c) * static_cast<size_t>(height) * width;
  }
};
using NetOutputPtr = std::shared_ptr<const NetOutput>;

class MemoryCache {
 public:
  explicit MemoryCache(size_t budget) : budget_(budget) {}
  NetOutputPtr get(const std::string& key) {
    const auto it = index_.find(key);
    if (it == index_.end()) return nullptr;
    entries_.splice(entries_.begin(), entries_, it->second);
    return it->second->second;
  }
  void put(const std::string& key, NetOutputPtr value) {
    if (value->bytes() > budget_ || index_.count(key)) return;
    used_ += value->bytes();
    entries_.emplace_front(key, std::move(value));
    index_[key] = entries_.begin();
    while (used_ > budget_) {
      used_ -= entries_.back().second->bytes();
      index_.erase(entries_.back().first);
      entries_.pop_back();
    }
  }

 private:
  size_t budget_;
  size_t used_ = 0;
  std::list<std::pair<std::string, NetOutputPtr>> entries_;
  std::unordered_map<std::string, std::list<std::pair<std::string, NetOutputPtr>>::iterator> index_;
};

NetOutputPtr readCachedOutput(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return nullptr;
  try {
    const NpyArray array = readNpy(path);
    if (array.type != NpyType::Float32 || array.shape.size() != 3) return nullptr;
    auto out = std::make_shared<NetOutput>();
    out->channels = static_cast<int>(array.shape[0]);
    out->height = static_cast<int>(array.shape[1]);
    out->width = static_cast<int>(array.shape[2]);
    out->chw.resize(array.size());
    if (array.bytes.size() != out->chw.size() * sizeof(float) || out->chw.empty()) return nullptr;
    std::memcpy(out->chw.data(), array.bytes.data(), array.bytes.size());
    // What the network's output became after checkOutputValues: probabilities.
    for (float p : out->chw)
      if (!(p >= 0.f && p <= 1.f)) return nullptr;  // also NaN
    return out;
  } catch (const std::exception&) {
    return nullptr;  // an unreadable cache file is recomputed and replaced
  }
}

void writeCachedOutput(const fs::path& path, const NetOutput& output) {
  writeNpyFloat32(path,
                  {static_cast<size_t>(output.channels), static_cast<size_t>(output.height),
                   static_cast<size_t>(output.width)},
                  output.chw);
}

std::string labelText(const SegmenterLabel& label) {
  if (label.dropped()) return "null";
  return label.name.empty() ? std::to_string(label.id) : "\"" + label.name + "\"";
}

}  // namespace

// ---------------------------------------------------------------------------

struct Segmenter::Impl {
  fs::path model_path;
  fs::path config_path;
  SegmenterConfig config;
  SegmenterOptions options;
  std::uint64_t model_hash = 0;
  std::string input_name;
  std::string output_name;
  std::optional<int> model_width, model_height;  // fixed input size of the model
  bool output_from_graph = false;                // config.output said by the model's final Softmax

  std::mutex net_mutex;  // guards the network, held while it runs
  cv::dnn::Net net;
  std::mutex probe_mutex;  // one channel probe at a time
  std::mutex mutex;        // guards everything below (never held while the network runs)
  SegmenterStats stats;
  MemoryCache memory{0};
  bool disk_write_failed = false;
  std::optional<int> output_channels;  // known after a run or a probe
  std::string output_shape;            // "1 x C x H' x W'" of that run, for messages
  bool probed = false;                 // a probe ran (and maybe failed)
  // The probe's output was refused for its values (not for the image's size):
  // a model that gives no valid output on a grey image gives none on any.
  std::optional<Problem> probe_value_problem;

  [[nodiscard]] std::string modelFile() const { return model_path.string(); }
  [[nodiscard]] std::string configFile() const {
    return config_path.empty() ? segmenterConfigPath(model_path).string() : config_path.string();
  }

  [[nodiscard]] std::string cacheKey(const ColorImage& color, int input_width,
                                     int input_height) const {
    std::ostringstream text;
    text << "labeloctomap-segmenter-cache-1|model=" << hex64(model_hash) << "|input=" << input_width
         << "x" << input_height << "|scale=" << numberText(config.scale) << "|mean="
         << numberText(config.mean[0]) << "," << numberText(config.mean[1]) << ","
         << numberText(config.mean[2]) << "|std=" << numberText(config.stddev[0]) << ","
         << numberText(config.stddev[1]) << "," << numberText(config.stddev[2]) << "|order="
         << (config.channel_order == SegmenterChannelOrder::Rgb ? "rgb" : "bgr") << "|output="
         << (config.output == SegmenterOutput::Scores ? "scores" : "probabilities") << "|image="
         << color.width << "x" << color.height << ":"
         << hex64(fnv1a(color.rgb.data(), color.rgb.size()));
    const std::string key = text.str();
    return hex64(fnv1a(key.data(), key.size()));
  }

  NetOutputPtr infer(const ColorImage& color, int input_width, int input_height);
  void checkOutputValues(NetOutput& output) const;
  // Throws the error for `channels` output channels that do not fit `labels`
  // (`shape` = the output's shape, for the message).
  void checkChannels(int channels, const LabelSet& labels, const std::string& shape) const;
};

void Segmenter::Impl::checkChannels(int channels, const LabelSet& labels,
                                    const std::string& shape) const {
  const std::string found = std::to_string(channels) + " channels (output " + shape + ")";
  if (config.labels) {
    if (static_cast<int>(config.labels->size()) != channels)
      throw Error(modelFile(), "output channels",
                  std::to_string(config.labels->size()) +
                      " channels (one per entry of \"labels\" in " + configFile() + ")",
                  found);
  } else if (channels != labels.size()) {
    throw Error(modelFile(), "output channels",
                std::to_string(labels.size()) + (labels.size() == 1 ? " channel" : " channels") +
                    ", one per label of the sequence (or list the label of each "
                    "channel as \"labels\" in " +
                    configFile() + ")",
                found);
  }
}

NetOutputPtr Segmenter::Impl::infer(const ColorImage& color, int input_width, int input_height) {
  // Pre-processing in float: resize (area when shrinking, bilinear otherwise),
  // channel order, scale, mean, std; N x C x H x W blob.
  cv::Mat rgb8(color.height, color.width, CV_8UC3, const_cast<std::uint8_t*>(color.rgb.data()));
  cv::Mat rgb;
  rgb8.convertTo(rgb, CV_32FC3);
  if (input_width != color.width || input_height != color.height) {
    const bool shrinking = input_width <= color.width && input_height <= color.height;
    cv::Mat resized;
    cv::resize(rgb, resized, cv::Size(input_width, input_height), 0, 0,
               shrinking ? cv::INTER_AREA : cv::INTER_LINEAR);
    rgb = resized;
  }
  const int blob_shape[] = {1, 3, input_height, input_width};
  cv::Mat blob(4, blob_shape, CV_32F);
  const size_t plane = static_cast<size_t>(input_width) * input_height;
  auto* blob_data = blob.ptr<float>();
  for (int c = 0; c < 3; ++c) {
    const int source = config.channel_order == SegmenterChannelOrder::Rgb ? c : 2 - c;
    const double scale = config.scale, mean = config.mean[c], stddev = config.stddev[c];
    float* out = blob_data + static_cast<size_t>(c) * plane;
    for (int v = 0; v < input_height; ++v) {
      const float* row = rgb.ptr<float>(v);
      for (int u = 0; u < input_width; ++u)
        out[static_cast<size_t>(v) * input_width + u] =
            static_cast<float>((row[3 * u + source] * scale - mean) / stddev);
    }
  }

  cv::Mat result;
  try {
    net.setInput(blob, input_name);
    result = output_name.empty() ? net.forward() : net.forward(output_name);
  } catch (const cv::Exception& e) {
    throw Error(modelFile(), "(inference)",
                "a model that OpenCV's DNN module runs on a 1 x 3 x " + std::to_string(input_height) +
                    " x " + std::to_string(input_width) + " image",
                std::string("OpenCV: ") + e.what());
  }
  std::vector<std::int64_t> shape;
  for (int i = 0; i < result.dims; ++i) shape.push_back(result.size[i]);
  if (result.dims != 4 || result.size[0] != 1 || result.size[1] < 1)
    throw Error(modelFile(), "output",
                "an output of shape 1 x C x H x W (per-pixel scores of C channels)",
                "shape " + dimsText(shape));
  if (result.type() != CV_32F) result.convertTo(result, CV_32F);
  if (!result.isContinuous()) result = result.clone();
  auto output = std::make_shared<NetOutput>();
  output->channels = result.size[1];
  output->height = result.size[2];
  output->width = result.size[3];
  output->chw.assign(result.ptr<float>(), result.ptr<float>() + result.total());
  checkOutputValues(*output);
  return output;
}

void Segmenter::Impl::checkOutputValues(NetOutput& output) const {
  const size_t plane = static_cast<size_t>(output.width) * output.height;
  const int channels = output.channels;
  auto where = [&](size_t index) {
    const size_t c = index / plane, pixel = index % plane;
    return "at channel " + std::to_string(c) + ", output pixel (u=" +
           std::to_string(pixel % output.width) + ", v=" + std::to_string(pixel / output.width) + ")";
  };
  for (size_t i = 0; i < output.chw.size(); ++i)
    if (!std::isfinite(output.chw[i]))
      throw Error(modelFile(), "output", "finite scores", "a non-finite value " + where(i));
  if (config.output == SegmenterOutput::Probabilities) {
    const std::string why =
        output_from_graph
            ? "the model ends with a Softmax over the channels; write \"output\": \"scores\" in " +
                  configFile() + " for a model whose output needs a softmax"
            : configFile() +
                  " says \"output\": \"probabilities\"; use \"scores\" for a model whose "
                  "output needs a softmax";
    for (size_t i = 0; i < output.chw.size(); ++i) {
      const float p = output.chw[i];
      if (p < -kProbabilityTolerance || p > 1.0 + kProbabilityTolerance)
        throw Error(modelFile(), "output", "probabilities in [0, 1] (" + why + ")",
                    "the value " + numberText(p) + " " + where(i));
      output.chw[i] = std::clamp(p, 0.f, 1.f);
    }
    return;
  }
  // Pixel-wise softmax over the channels (in double, max subtracted).
  std::vector<double> e(static_cast<size_t>(channels));
  for (size_t pixel = 0; pixel < plane; ++pixel) {
    double top = -INFINITY;
    for (int c = 0; c < channels; ++c)
      top = std::max(top, static_cast<double>(output.chw[c * plane + pixel]));
    double sum = 0.0;
    for (int c = 0; c < channels; ++c) {
      e[c] = std::exp(static_cast<double>(output.chw[c * plane + pixel]) - top);
      sum += e[c];
    }
    for (int c = 0; c < channels; ++c) output.chw[c * plane + pixel] = static_cast<float>(e[c] / sum);
  }
}

Segmenter::Segmenter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Segmenter::~Segmenter() = default;

std::shared_ptr<Segmenter> Segmenter::load(const fs::path& model, SegmenterOptions options) {
  const fs::path json = segmenterConfigPath(model);
  std::error_code ec;
  if (fs::exists(json, ec) && json != model)
    return load(model, readSegmenterConfig(json), std::move(options), json);
  return load(model, SegmenterConfig{}, std::move(options), {});
}

std::shared_ptr<Segmenter> Segmenter::load(const fs::path& model, const SegmenterConfig& config,
                                           SegmenterOptions options, const fs::path& config_file) {
  auto impl = std::make_unique<Impl>();
  impl->model_path = model;
  impl->config_path = config_file;
  impl->config = config;
  impl->options = std::move(options);
  impl->memory = MemoryCache(impl->options.memory_cache_bytes);
  const std::string file = model.string();

  std::error_code ec;
  if (fs::is_directory(model, ec))
    throw Error(file, "model", "an ONNX model file (.onnx)", "a folder");
  // Checked before opening: a device would be read without end, a FIFO would block.
  if (const std::string why = notARegularFile(model); !why.empty())
    throw Error(file, "model", "a readable ONNX model file (.onnx)", why);
  std::ifstream in(model, std::ios::binary);
  if (!in)
    throw Error(file, "model", "a readable ONNX model file (.onnx)",
                "a file that cannot be opened");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) throw Error(file, "model", "an ONNX model file (.onnx)", "an empty file");
  impl->model_hash = fnv1a(bytes.data(), bytes.size());

  OnnxGraphInfo graph;
  try {
    graph = readOnnxGraphInfo(bytes);
  } catch (const std::exception& e) {
    throw Error(file, "model", "an ONNX model file (a serialised onnx.ModelProto)",
                std::string("data that is not one (") + e.what() + ")");
  }
  if (graph.inputs.size() != 1)
    throw Error(file, "graph inputs", "one image input (N x 3 x H x W)",
                std::to_string(graph.inputs.size()) + " inputs");
  if (graph.outputs.empty()) throw Error(file, "graph outputs", "one output", "none");
  const OnnxValueInfo& input = graph.inputs.front();
  impl->input_name = input.name;
  impl->output_name = graph.outputs.front().name;
  // A network whose output comes out of a Softmax over the channels gives
  // probabilities: a second softmax would flatten them to about 1/C.
  if (!impl->config.output) {
    impl->output_from_graph = endsWithChannelSoftmax(graph, impl->output_name);
    impl->config.output =
        impl->output_from_graph ? SegmenterOutput::Probabilities : SegmenterOutput::Scores;
  }
  if (input.has_shape) {
    const auto& dims = input.dims;
    if (dims.size() != 4)
      throw Error(file, "input " + input.name, "an image input of shape N x 3 x H x W",
                  "shape " + dimsText(dims));
    if (dims[1] > 0 && dims[1] != 3)
      throw Error(file, "input " + input.name, "3 input channels (a colour image, N x 3 x H x W)",
                  "shape " + dimsText(dims));
    if (dims[2] > 0 && dims[3] > 0) {
      impl->model_height = static_cast<int>(dims[2]);
      impl->model_width = static_cast<int>(dims[3]);
    }
  }
  if (impl->model_width && config.input_width &&
      (*impl->model_width != *config.input_width || *impl->model_height != *config.input_height))
    throw Error(impl->configFile(), "input_width",
                "the model's fixed input size " + std::to_string(*impl->model_width) + " x " +
                    std::to_string(*impl->model_height) + " (or no input_width/input_height)",
                std::to_string(*config.input_width) + " x " + std::to_string(*config.input_height));

  try {
    // OpenCV logs its own "[ERROR:0@...] onnx_importer.cpp ..." line before it
    // throws: the error below says it, naming the model file.
    const cv::utils::logging::LogLevel level = cv::utils::logging::getLogLevel();
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    try {
      impl->net = cv::dnn::readNetFromONNX(bytes.data(), bytes.size());
    } catch (...) {
      cv::utils::logging::setLogLevel(level);
      throw;
    }
    cv::utils::logging::setLogLevel(level);
  } catch (const cv::Exception& e) {
    throw Error(file, "model", "an ONNX model that OpenCV's DNN module can load",
                std::string("OpenCV: ") + e.what());
  }
  if (impl->net.empty())
    throw Error(file, "model", "an ONNX model that OpenCV's DNN module can load", "an empty network");
  impl->net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  impl->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  // OpenCV names the layer producing a graph output after it; fall back to the
  // last layer when it does not.
  try {
    const auto names = impl->net.getLayerNames();
    if (std::find(names.begin(), names.end(), impl->output_name) == names.end())
      impl->output_name.clear();
  } catch (const cv::Exception&) {
    impl->output_name.clear();
  }
  return std::shared_ptr<Segmenter>(new Segmenter(std::move(impl)));
}

const fs::path& Segmenter::modelPath() const { return impl_->model_path; }
const fs::path& Segmenter::configPath() const { return impl_->config_path; }
const SegmenterConfig& Segmenter::config() const { return impl_->config; }

std::pair<int, int> Segmenter::inputSize(int image_width, int image_height) const {
  if (impl_->config.input_width) return {*impl_->config.input_width, *impl_->config.input_height};
  if (impl_->model_width) return {*impl_->model_width, *impl_->model_height};
  return {image_width, image_height};
}

void Segmenter::checkLabels(const LabelSet& labels) const {
  const auto& configured = impl_->config.labels;
  if (!configured) return;
  const std::string file = impl_->configFile();
  std::set<int> seen;
  for (size_t c = 0; c < configured->size(); ++c) {
    const SegmenterLabel& label = (*configured)[c];
    if (label.dropped()) continue;
    const std::string field = "labels[" + std::to_string(c) + "]";
    int id = label.id;
    if (!label.name.empty()) {
      const auto found = labels.findByName(label.name);
      if (!found)
        throw Error(file, field, "the name of a label of the sequence", "\"" + label.name + "\"");
      id = *found;
    } else if (!labels.contains(id)) {
      throw Error(file, field,
                  "a label id from 0 to " + std::to_string(labels.size() - 1) +
                      " (the labels of the sequence)",
                  std::to_string(id));
    }
    if (!seen.insert(id).second)
      throw Error(file, field, "each label once (use null for a channel that is not used)",
                  labelText(label) + " again");
  }
}

ProbabilityImage Segmenter::segment(const ColorImage& color, int width, int height,
                                    const LabelSet& labels, const fs::path& cache_dir) const {
  Impl& impl = *impl_;
  if (color.width <= 0 || color.height <= 0 ||
      color.rgb.size() != static_cast<size_t>(color.width) * color.height * 3)
    throw Error("", "color", "an RGB image", "an empty or inconsistent image");
  if (width <= 0 || height <= 0)
    throw Error("", "size", "a positive output size",
                std::to_string(width) + " x " + std::to_string(height));
  checkLabels(labels);
  const auto [input_width, input_height] = inputSize(color.width, color.height);
  const std::string key = impl.cacheKey(color, input_width, input_height);
  const fs::path folder = !impl.options.disk_cache ? fs::path()
                          : !cache_dir.empty()     ? cache_dir
                                                   : impl.options.cache_dir;

  // The sequence label of each output channel (-1: dropped); throws when the
  // channels do not match the labels, before a bad output reaches the cache.
  const auto labelsOfChannels = [&](const NetOutputPtr& output) {
    const int channels = output->channels;
    impl.checkChannels(channels, labels,
                       "1 x " + std::to_string(channels) + " x " + std::to_string(output->height) +
                           " x " + std::to_string(output->width));
    std::vector<int> channel_label(static_cast<size_t>(channels), -1);
    if (impl.config.labels) {
      const auto& configured = *impl.config.labels;
      for (int c = 0; c < channels; ++c) {
        const SegmenterLabel& label = configured[static_cast<size_t>(c)];
        if (!label.dropped())
          channel_label[static_cast<size_t>(c)] =
              label.name.empty() ? label.id : *labels.findByName(label.name);
      }
    } else {
      for (int c = 0; c < channels; ++c) channel_label[static_cast<size_t>(c)] = c;
    }
    return channel_label;
  };

  // A disk cache entry of a shape this model does not give (or that does not
  // fit the labels, as this model's output would) is damaged: recomputed and replaced.
  const auto cachedFits = [&](const NetOutputPtr& cached) {
    if (impl.output_channels && cached->channels != *impl.output_channels) return false;
    try {
      (void)labelsOfChannels(cached);
    } catch (const Error&) {
      return false;
    }
    return true;
  };

  // The state lock is never held while the network runs (net_mutex is): a
  // caller asking for the channels or the statistics (the studio's GUI thread,
  // on a sequence switch) does not wait for a slow model's inference.
  NetOutputPtr output;
  {
    const std::lock_guard<std::mutex> lock(impl.mutex);
    output = impl.memory.get(key);
    if (output) ++impl.stats.memory_hits;
  }
  if (!output && !folder.empty()) {
    NetOutputPtr cached = readCachedOutput(folder / (key + ".npy"));
    const std::lock_guard<std::mutex> lock(impl.mutex);
    if (cached && cachedFits(cached)) {
      output = std::move(cached);
      ++impl.stats.disk_hits;
      impl.memory.put(key, output);
    }
  }
  if (!output) {
    {
      const std::lock_guard<std::mutex> lock(impl.mutex);
      ++impl.stats.running;
    }
    try {
      const std::lock_guard<std::mutex> net_lock(impl.net_mutex);
      output = impl.infer(color, input_width, input_height);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(impl.mutex);
      --impl.stats.running;
      throw;
    }
    bool write_cache = false;
    {
      const std::lock_guard<std::mutex> lock(impl.mutex);
      --impl.stats.running;
      ++impl.stats.inferences;
      impl.output_channels = output->channels;
      impl.output_shape = "1 x " + std::to_string(output->channels) + " x " +
                          std::to_string(output->height) + " x " + std::to_string(output->width);
      (void)labelsOfChannels(output);  // an output of the wrong shape is not kept
      impl.memory.put(key, output);
      write_cache = !folder.empty() && !impl.disk_write_failed;
    }
    if (write_cache) {
      try {
        std::error_code ec;
        fs::create_directories(folder, ec);
        // The reason itself (a read-only file system, a file in its place),
        // not the writer's later "folder does not exist".
        if (ec || !fs::is_directory(folder))
          throw std::runtime_error(ec ? ec.message() : "a file stands in its place");
        writeCachedOutput(folder / (key + ".npy"), *output);
      } catch (const std::exception& e) {
        bool first = false;
        {
          const std::lock_guard<std::mutex> lock(impl.mutex);
          first = !std::exchange(impl.disk_write_failed, true);
        }
        if (first && impl.options.warn)
          impl.options.warn("cannot write the segmenter cache in " + folder.string() +
                            " (results are kept in memory only): " + e.what());
      }
    }
  }

  const std::vector<int> channel_label = labelsOfChannels(output);
  const int channels = output->channels;

  // Resize every kept channel to the requested size and interleave.
  ProbabilityImage proba;
  proba.width = width;
  proba.height = height;
  for (int c = 0; c < channels; ++c)
    if (channel_label[static_cast<size_t>(c)] >= 0)
      proba.channel_labels.push_back(channel_label[static_cast<size_t>(c)]);
  proba.channels = static_cast<int>(proba.channel_labels.size());
  proba.values.resize(static_cast<size_t>(width) * height * proba.channels);
  const bool same_size = output->width == width && output->height == height;
  const int interpolation = impl.config.resize == SegmenterResize::Nearest ? cv::INTER_NEAREST_EXACT
                            : (width <= output->width && height <= output->height)
                                ? cv::INTER_AREA
                                : cv::INTER_LINEAR;
  int k = 0;
  cv::Mat resized;
  for (int c = 0; c < channels; ++c) {
    if (channel_label[static_cast<size_t>(c)] < 0) continue;
    const cv::Mat source(output->height, output->width, CV_32F,
                         const_cast<float*>(output->plane(c)));
    if (same_size)
      resized = source;
    else
      cv::resize(source, resized, cv::Size(width, height), 0, 0, interpolation);
    for (int v = 0; v < height; ++v) {
      const float* row = resized.ptr<float>(v);
      float* out = proba.values.data() + static_cast<size_t>(v) * width * proba.channels + k;
      for (int u = 0; u < width; ++u) out[static_cast<size_t>(u) * proba.channels] = row[u];
    }
    ++k;
  }
  return proba;
}

std::optional<int> Segmenter::outputChannels() const {
  Impl& impl = *impl_;
  // One probe at a time; the state lock is not held while it runs.
  const std::lock_guard<std::mutex> probe_lock(impl.probe_mutex);
  {
    const std::lock_guard<std::mutex> lock(impl.mutex);
    if (impl.output_channels || impl.probed) return impl.output_channels;
  }
  const auto [width, height] = inputSize(64, 64);
  ColorImage grey;
  grey.width = width;
  grey.height = height;
  grey.rgb.assign(static_cast<size_t>(width) * height * 3, 128);
  NetOutputPtr output;
  std::optional<Problem> value_problem;
  try {
    const std::lock_guard<std::mutex> net_lock(impl.net_mutex);
    output = impl.infer(grey, width, height);
  } catch (const Error& error) {
    // Values checkOutputValues refuses are kept for checkFits; another
    // failure may be this image's size: the first real run says.
    if (error.problem().field == "output") value_problem = error.problem();
  } catch (const std::exception&) {
  }
  const std::lock_guard<std::mutex> lock(impl.mutex);
  impl.probed = true;
  if (value_problem) impl.probe_value_problem = std::move(value_problem);
  if (output && !impl.output_channels) {
    impl.output_channels = output->channels;
    impl.output_shape = "1 x " + std::to_string(output->channels) + " x " +
                        std::to_string(output->height) + " x " + std::to_string(output->width) +
                        " for a " + std::to_string(width) + " x " + std::to_string(height) +
                        " image";
  }
  return impl.output_channels;
}

void Segmenter::checkFits(const LabelSet& labels) const {
  checkLabels(labels);
  const auto channels = outputChannels();
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    if (impl_->probe_value_problem) {
      Problem problem = *impl_->probe_value_problem;
      problem.found += " (on a uniform grey test image; its output is refused for any image)";
      throw Error(problem);
    }
  }
  if (channels) {
    std::string shape;
    {
      const std::lock_guard<std::mutex> lock(impl_->mutex);
      shape = impl_->output_shape;
    }
    impl_->checkChannels(*channels, labels, shape);
  }
}

SegmenterStats Segmenter::stats() const {
  const std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->stats;
}

fs::path Segmenter::cacheDirFor(const Sequence& sequence) const {
  if (!impl_->options.disk_cache) return {};
  if (!impl_->options.cache_dir.empty()) return impl_->options.cache_dir;
  if (sequence.root.empty()) return {};
  return sequence.root / kCacheFolder;
}

// ---------------------------------------------------------------------------

ProbabilityImage segmentFrame(const Sequence& sequence, size_t index, const ColorImage& color,
                              const Segmenter& segmenter) {
  const CameraIntrinsics& camera = sequence.cameraOf(index);
  return segmenter.segment(color, camera.width, camera.height, sequence.labels,
                           segmenter.cacheDirFor(sequence));
}

FrameData loadFrameWithSegmenter(const Sequence& sequence, size_t index,
                                 const Segmenter* segmenter) {
  FrameData frame = loadFrame(sequence, index);
  addSegmenterProbabilities(sequence, index, segmenter, frame);
  return frame;
}

bool segmenterRunsOn(const Sequence& sequence, size_t index, const Segmenter* segmenter) {
  // A proba an import made from the frame's own label image is no segmenter's
  // output: the network's replaces it.
  const FrameRecord& record = sequence.frames.at(index);
  return segmenter && (record.proba.empty() || record.proba_from_label);
}

void addSegmenterProbabilities(const Sequence& sequence, size_t index, const Segmenter* segmenter,
                               FrameData& frame) {
  if (!segmenterRunsOn(sequence, index, segmenter)) return;
  if (!frame.color)
    throw Error((sequence.root / "sequence.json").string(),
                "frames[" + std::to_string(index) + "].color",
                "a colour image for the segmenter " + segmenter->modelPath().filename().string() +
                    " to run on (the frame has no proba)",
                "none");
  frame.proba = segmenter->segment(*frame.color, frame.depth.width, frame.depth.height,
                                   sequence.labels, segmenter->cacheDirFor(sequence));
}

void writeProbabilityNpy(const fs::path& path, const ProbabilityImage& proba, NpyType dtype) {
  const std::vector<size_t> shape = {static_cast<size_t>(proba.height),
                                     static_cast<size_t>(proba.width),
                                     static_cast<size_t>(proba.channels)};
  if (proba.values.size() != shape[0] * shape[1] * shape[2])
    throw Error(path.string(), "proba", "H x W x C values", std::to_string(proba.values.size()));
  if (dtype == NpyType::Float32) {
    writeNpyFloat32(path, shape, proba.values);
    return;
  }
  NpyArray array;
  array.type = dtype;
  array.shape = shape;
  if (dtype == NpyType::Float16) {
    const cv::Mat values(1, static_cast<int>(proba.values.size()), CV_32F,
                         const_cast<float*>(proba.values.data()));
    cv::Mat half;
    values.convertTo(half, CV_16F);
    array.bytes.assign(half.data, half.data + half.total() * half.elemSize());
  } else if (dtype == NpyType::UInt8) {
    array.bytes.reserve(proba.values.size());
    for (float p : proba.values)
      array.bytes.push_back(static_cast<std::uint8_t>(std::lround(std::clamp(p, 0.f, 1.f) * 255.f)));
  } else {
    throw Error(path.string(), "dtype", "float32, float16 or uint8 probabilities", "another type");
  }
  writeNpy(path, array);
}

}  // namespace lom
