#pragma once
// Helpers of the tests of hostile or unusual inputs: small files written
// byte for byte and the lom::Error a call throws.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "lom/error.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace lom::test {

inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

inline lom::Problem errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const lom::Error& e) {
    return e.problem();
  }
  ADD_FAILURE() << "no lom::Error thrown";
  return {};
}

inline constexpr int kWidth = 4;
inline constexpr int kHeight = 3;

inline lom::LabelSet twoLabels() {
  return lom::LabelSet({{0, "__background__", {0, 0, 0}}, {1, "mug", {200, 10, 10}}});
}

// A valid one-frame sequence of 4 x 3 pixels (depth and label PNGs).
inline lom::Sequence writeSequence(const std::filesystem::path& root) {
  std::filesystem::create_directories(root / "depth");
  std::filesystem::create_directories(root / "label");
  lom::Sequence sequence;
  sequence.root = root;
  sequence.labels = twoLabels();
  sequence.camera.width = kWidth;
  sequence.camera.height = kHeight;
  sequence.camera.fx = sequence.camera.fy = 5.0;
  sequence.camera.cx = 1.5;
  sequence.camera.cy = 1.0;
  lom::FrameRecord frame;
  frame.depth = "depth/0.png";
  frame.label = "label/0.png";
  lom::writeDepthPng(root / frame.depth, {kWidth, kHeight, std::vector<float>(12, 0.5f)}, 0.001);
  lom::writeLabelPng(root / frame.label, {kWidth, kHeight, std::vector<std::uint16_t>(12, 1)});
  sequence.frames.push_back(frame);
  lom::saveSequence(sequence, root);
  return sequence;
}

}  // namespace lom::test
