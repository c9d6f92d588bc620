#pragma once
// PNG encoding through libpng, into memory, as cv::imencode(".png", mat)
// encodes it with its default parameters (fastest compression, the Sub
// filter, run-length strategy): OpenCV's encoder is in imgcodecs, which the
// programs no longer link (core/src/other_images.hpp).
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace lom {

// `mat`: 8 or 16 bits per sample, 1 (grey), 3 (BGR) or 4 (BGRA) channels.
// Throws lom::Error(file, "output", ...) for other images or when libpng fails.
[[nodiscard]] std::vector<std::uint8_t> encodePng(const cv::Mat& mat, const std::string& file);

}  // namespace lom
