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

// Per-pixel probabilities, row-major H x W x C, values in [0, 1].
// channel_labels[c] is the label id of channel c; labels that are not listed
// have probability 0 in this image.
struct ProbabilityImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<int> channel_labels;
  std::vector<float> values;
  [[nodiscard]] const float* pixel(int u, int v) const {
    return values.data() + (static_cast<size_t>(v) * width + u) * channels;
  }
};

}  // namespace lom
