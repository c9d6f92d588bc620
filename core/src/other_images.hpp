#pragma once
// Images that are neither PNG nor JPEG (TIFF, BMP, PNM, WebP, ...), read by
// OpenCV's imgcodecs in a module loaded on first use (core/codecs): linked
// into the programs, imgcodecs and the 139 libraries it needs made every
// start of `labeloctomap` take 0.2 s instead of 0.05 s.
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace lom {

// cv::imread(file, flags). Throws lom::Error naming the file when OpenCV
// cannot read it, or when the module cannot be loaded (it says where it
// looked).
[[nodiscard]] cv::Mat readOtherImage(const std::string& file, int flags);

// cv::imdecode of `size` bytes; an empty Mat when OpenCV cannot decode them.
// Throws lom::Error naming `what` when the module cannot be loaded.
[[nodiscard]] cv::Mat decodeOtherImage(const std::uint8_t* data, std::size_t size, int flags,
                                       const std::string& what);

}  // namespace lom
