#pragma once
// Tiny segmentation networks and RGB-D sequences for the segmenter tests.
// The models are built with ONNX's own protobuf classes (Debian's libonnx-dev)
// and their outputs are known exactly: a 1x1 convolution computes, at every
// pixel, scores s_k = sum_c W[k][c] * x_c + b_k of the pre-processed input x.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "lom/images.hpp"
#include "lom/segmenter.hpp"
#include "lom/sequence.hpp"

namespace lom::test {

struct ConvModelSpec {
  int outputs = 3;               // C: output channels
  int input_channels = 3;        // the image input's channel count (3 for a valid model)
  std::vector<float> weights;    // C x input_channels, row-major
  std::vector<float> bias;       // C
  bool softmax = false;          // end with Softmax over the channels (outputs probabilities)
  int input_width = 0;           // fixed input size; 0 = any size (symbolic dims)
  int input_height = 0;
};

// Serialised onnx.ModelProto of the 1x1 convolution (opset 13).
[[nodiscard]] std::string buildConvModel(const ConvModelSpec& spec);
void writeModel(const std::filesystem::path& path, const std::string& bytes);

// Expected outputs, computed here in double from the specification.
// Pre-processed input of an RGB pixel (as the segmenter documents it).
[[nodiscard]] std::array<double, 3> preprocess(const std::array<std::uint8_t, 3>& rgb,
                                               const SegmenterConfig& config);
// Softmax of the convolution's scores for a pre-processed input.
[[nodiscard]] std::vector<double> expectedProbabilities(const ConvModelSpec& spec,
                                                        const std::array<double, 3>& x);
[[nodiscard]] std::vector<double> expectedProbabilities(const ConvModelSpec& spec,
                                                        const std::array<std::uint8_t, 3>& rgb,
                                                        const SegmenterConfig& config = {});

// A colour image whose pixel (u, v) is colour(u, v).
template <typename F>
ColorImage makeColorImage(int width, int height, F colour) {
  ColorImage image;
  image.width = width;
  image.height = height;
  image.rgb.reserve(static_cast<size_t>(width) * height * 3);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      for (std::uint8_t value : colour(u, v)) image.rgb.push_back(value);
  return image;
}

// Label 1 wins where red is high, label 2 where green is high: scores
// (0.3, 1.5 r, 1.5 g) for r, g in [0, 1], so a pure red pixel gives about
// (0.20, 0.66, 0.15) and a pure green one (0.20, 0.15, 0.66): every probability
// stays inside the map's clamping range.
[[nodiscard]] ConvModelSpec colourChannelModel();

// A one-viewpoint sequence written to `folder`: an 8 x 6 camera (fx = fy = 8,
// cx = 3.5, cy = 2.5) facing a flat wall 1 m away, `frames` frames at the same
// pose whose colour images are red on the left half and green on the right
// (swapped in odd frames), labels {0 "__background__", 1 "red_block",
// 2 "green_block"} (+ `extra_labels` more). No proba and no label images.
[[nodiscard]] Sequence writeColourWallSequence(const std::filesystem::path& folder, int frames = 2,
                                               int extra_labels = 0, bool with_color = true);
[[nodiscard]] std::array<std::uint8_t, 3> colourWallPixel(int frame, int u);

}  // namespace lom::test
