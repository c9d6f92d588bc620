#include "onnx_model_builder.hpp"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include <onnx/onnx_pb.h>

namespace lom::test {

namespace {

void addDim(onnx::TensorShapeProto* shape, int value, const std::string& symbol) {
  auto* dim = shape->add_dim();
  if (value > 0)
    dim->set_dim_value(value);
  else
    dim->set_dim_param(symbol);
}

void setFloatTensorType(onnx::ValueInfoProto* info, const std::string& name,
                        const std::vector<std::pair<int, std::string>>& dims) {
  info->set_name(name);
  auto* tensor = info->mutable_type()->mutable_tensor_type();
  tensor->set_elem_type(onnx::TensorProto::FLOAT);
  auto* shape = tensor->mutable_shape();
  for (const auto& [value, symbol] : dims) addDim(shape, value, symbol);
}

}  // namespace

std::string buildConvModel(const ConvModelSpec& spec) {
  const int c_in = spec.input_channels;
  if (static_cast<int>(spec.weights.size()) != spec.outputs * c_in ||
      static_cast<int>(spec.bias.size()) != spec.outputs)
    throw std::invalid_argument("ConvModelSpec: weights must be outputs x input_channels, bias outputs");

  onnx::ModelProto model;
  model.set_ir_version(7);
  model.set_producer_name("labeloctomap-tests");
  auto* opset = model.add_opset_import();
  opset->set_domain("");
  opset->set_version(13);

  auto* graph = model.mutable_graph();
  graph->set_name("conv1x1");

  auto* w = graph->add_initializer();
  w->set_name("W");
  w->set_data_type(onnx::TensorProto::FLOAT);
  for (int d : {spec.outputs, c_in, 1, 1}) w->add_dims(d);
  for (float value : spec.weights) w->add_float_data(value);
  auto* b = graph->add_initializer();
  b->set_name("B");
  b->set_data_type(onnx::TensorProto::FLOAT);
  b->add_dims(spec.outputs);
  for (float value : spec.bias) b->add_float_data(value);

  auto* conv = graph->add_node();
  conv->set_name("conv");
  conv->set_op_type("Conv");
  conv->add_input("image");
  conv->add_input("W");
  conv->add_input("B");
  conv->add_output("scores");
  auto* kernel = conv->add_attribute();
  kernel->set_name("kernel_shape");
  kernel->set_type(onnx::AttributeProto::INTS);
  kernel->add_ints(1);
  kernel->add_ints(1);

  std::string output = "scores";
  if (spec.softmax) {
    auto* softmax = graph->add_node();
    softmax->set_name("softmax");
    softmax->set_op_type("Softmax");
    softmax->add_input("scores");
    softmax->add_output("probabilities");
    auto* axis = softmax->add_attribute();
    axis->set_name("axis");
    axis->set_type(onnx::AttributeProto::INT);
    axis->set_i(1);
    output = "probabilities";
  }

  setFloatTensorType(graph->add_input(), "image",
                     {{1, ""}, {c_in, ""}, {spec.input_height, "H"}, {spec.input_width, "W"}});
  setFloatTensorType(graph->add_output(), output,
                     {{1, ""}, {spec.outputs, ""}, {spec.input_height, "H"}, {spec.input_width, "W"}});
  return model.SerializeAsString();
}

void writeModel(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::array<double, 3> preprocess(const std::array<std::uint8_t, 3>& rgb,
                                 const SegmenterConfig& config) {
  std::array<double, 3> x{};
  for (int c = 0; c < 3; ++c) {
    const int source = config.channel_order == SegmenterChannelOrder::Rgb ? c : 2 - c;
    x[c] = (rgb[source] * config.scale - config.mean[c]) / config.stddev[c];
  }
  return x;
}

std::vector<double> expectedProbabilities(const ConvModelSpec& spec, const std::array<double, 3>& x) {
  std::vector<double> scores(static_cast<size_t>(spec.outputs));
  double top = -INFINITY;
  for (int k = 0; k < spec.outputs; ++k) {
    double s = spec.bias[k];
    for (int c = 0; c < 3; ++c) s += static_cast<double>(spec.weights[k * 3 + c]) * x[c];
    scores[k] = s;
    top = std::max(top, s);
  }
  double sum = 0.0;
  for (double& s : scores) sum += (s = std::exp(s - top));
  for (double& s : scores) s /= sum;
  return scores;
}

std::vector<double> expectedProbabilities(const ConvModelSpec& spec,
                                          const std::array<std::uint8_t, 3>& rgb,
                                          const SegmenterConfig& config) {
  return expectedProbabilities(spec, preprocess(rgb, config));
}

ConvModelSpec colourChannelModel() {
  ConvModelSpec spec;
  spec.outputs = 3;
  spec.weights = {0.f, 0.f, 0.f,   // label 0: background, a constant score
                  1.5f, 0.f, 0.f,  // label 1: red
                  0.f, 1.5f, 0.f}; // label 2: green
  spec.bias = {0.3f, 0.f, 0.f};
  return spec;
}

std::array<std::uint8_t, 3> colourWallPixel(int frame, int u) {
  const bool left = u < 4;
  const bool red = (frame % 2 == 0) ? left : !left;
  return red ? std::array<std::uint8_t, 3>{255, 0, 0} : std::array<std::uint8_t, 3>{0, 255, 0};
}

Sequence writeColourWallSequence(const std::filesystem::path& folder, int frames, int extra_labels,
                                 bool with_color) {
  std::filesystem::create_directories(folder);
  Sequence sequence;
  sequence.root = folder;
  std::vector<LabelInfo> labels = {{0, "__background__", {0, 0, 0}},
                                   {1, "red_block", {200, 30, 30}},
                                   {2, "green_block", {30, 200, 30}}};
  for (int i = 0; i < extra_labels; ++i)
    labels.push_back({3 + i, "extra_" + std::to_string(i), {90, 90, 90}});
  sequence.labels = LabelSet(labels);
  sequence.camera = CameraIntrinsics{8, 6, 8.0, 8.0, 3.5, 2.5, 0.001};

  DepthImage depth;
  depth.width = 8;
  depth.height = 6;
  depth.metres.assign(48, 1.0f);
  for (int i = 0; i < frames; ++i) {
    const std::string n = std::to_string(i);
    FrameRecord frame;
    frame.stamp = i;
    frame.depth = "depth_" + n + ".png";
    writeDepthPng(folder / frame.depth, depth, sequence.camera.depth_scale);
    if (with_color) {
      frame.color = "color_" + n + ".png";
      writeColorPng(folder / frame.color,
                    makeColorImage(8, 6, [&](int u, int) { return colourWallPixel(i, u); }));
    }
    sequence.frames.push_back(frame);
  }
  saveSequence(sequence, folder);
  return sequence;
}

}  // namespace lom::test
