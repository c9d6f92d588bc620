#pragma once
// A three-frame 160x120 sequence written through the core's writers: a tilted
// plane seen by a sliding camera, with a labelled square standing out of it.
#include <filesystem>
#include <vector>

#include "lom/images.hpp"
#include "lom/labels.hpp"

namespace lom::test {

inline constexpr int kTinyFrames = 3;
inline constexpr int kTinyWidth = 160;
inline constexpr int kTinyHeight = 120;
inline constexpr int kSquareLabel = 1;
// A colour nothing else in the window has (not the axes, frustums or background).
inline constexpr Rgb kSquareColor{230, 60, 160};

struct TinySequence {
  std::filesystem::path folder;
  std::vector<DepthImage> depths;  // as written, per frame
};

TinySequence writeTinySequence(const std::filesystem::path& folder);

// The tiny sequence's frames in the frame-folder layout of many RGB-D tools
// (frame-NNNNNN.color.png, .depth.png in mm, .pose.txt, intrinsics.K.txt): a
// dataset folder the studio converts when it opens it.
void writeFramesLayout(const TinySequence& tiny, const std::filesystem::path& folder);

// Pixels with a finite, positive depth.
size_t countValidDepth(const DepthImage& depth);

}  // namespace lom::test
