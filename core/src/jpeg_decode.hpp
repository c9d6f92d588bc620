#pragma once
// JPEG decoding through libjpeg with its messages captured. OpenCV's JPEG
// reader leaves libjpeg's message handler in place, which prints "Corrupt
// JPEG data: ..." or "Premature end of JPEG file" on stderr and hands back
// an image made up where the data was damaged; here such data is an error
// naming the file, and nothing reaches the terminal.
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace lom {

// True when `data` starts as a JPEG file does (start of image, then a marker).
[[nodiscard]] bool hasJpegSignature(const std::uint8_t* data, std::size_t size);

// Decodes JPEG data as cv::imdecode(data, cv::IMREAD_UNCHANGED) does: grey
// images as 1 channel, every other colour space (YCbCr, RGB, CMYK, YCCK) as 3
// channels of 8-bit BGR; no EXIF rotation. Throws lom::Error(file, "JPEG
// data", "a JPEG whose image data can be decoded", libjpeg's reason) for data
// libjpeg rejects and for damaged data it would decode anyway (a truncated
// file, a bad Huffman code, data missing or left over in a segment);
// harmless warnings (an unknown JFIF revision or Adobe transform code, a
// damaged colour profile) are dropped.
[[nodiscard]] cv::Mat decodeJpeg(const std::uint8_t* data, std::size_t size,
                                 const std::string& file);

}  // namespace lom
