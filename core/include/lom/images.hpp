#pragma once
// Plain image structs that cross the core API (no OpenCV in public headers).
#include <cstdint>
#include <vector>

namespace lom {

// Depth in metres, row-major; 0 or NaN = no measurement.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<float> metres;
  [[nodiscard]] float at(int u, int v) const { return metres[static_cast<size_t>(v) * width + u]; }
};

// 8-bit RGB, row-major, 3 bytes per pixel.
struct ColorImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

// Label ids, row-major.
struct LabelImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> ids;
  [[nodiscard]] int at(int u, int v) const { return ids[static_cast<size_t>(v) * width + u]; }
};

// The probability an 8-bit probability value stands for.
inline float probabilityOfCode(std::uint8_t code) { return static_cast<float>(code) / 255.0f; }

// Per-pixel probabilities, row-major H x W x C, values in [0, 1].
// channel_labels[c] is the label id of channel c; labels that are not listed
// have probability 0 in this image.
struct ProbabilityImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<int> channel_labels;
  std::vector<float> values;
  // When the image was read from 8-bit values: those values, one per element
  // of `values` (values[i] == probabilityOfCode(codes[i])); empty otherwise.
  // Fast fusion turns a code into log-odds with a 256-entry table. Whoever
  // changes `values` of a read image must clear `codes`. An image read for
  // fusion only (FrameParts::proba_floats false) has its codes and no
  // `values`: read it through probability(), or pixel() once hasValues().
  std::vector<std::uint8_t> codes;
  [[nodiscard]] bool hasValues() const { return codes.empty() || !values.empty(); }
  [[nodiscard]] float probability(size_t i) const {
    return values.empty() ? probabilityOfCode(codes[i]) : values[i];
  }
  [[nodiscard]] const float* pixel(int u, int v) const {
    return values.data() + (static_cast<size_t>(v) * width + u) * channels;
  }
};

}  // namespace lom
