#pragma once
// The PNGs that cameras and this program write (8- or 16-bit grey, RGB or
// RGBA, not interlaced) decoded without libpng: the image data inflated in one
// call by libdeflate (about three times as fast as zlib's inflate on a depth
// image) and unfiltered here. decodePng tries this first and falls back to
// libpng for every other kind of PNG and for data this route does not decode
// whole, so libpng still reports what is wrong with damaged data.
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>

namespace lom {

// True when `data` (a PNG whose chunks checkPngChunks accepted) is of a kind
// decodePngDirectly takes: IHDR of 8- or 16-bit grey, RGB or RGBA, standard
// compression and filtering, not interlaced, at most kMaxImagePixels pixels;
// consecutive IDAT chunks; no PLTE, tRNS or unknown critical chunk.
[[nodiscard]] bool isDirectPng(const std::uint8_t* data, std::size_t size);

// The image as decodePng gives it (grey, BGR or BGRA; 16-bit samples in the
// machine's byte order), or nullopt when `data` is not a direct PNG or its
// image data does not inflate to exactly the image's rows with valid filters.
[[nodiscard]] std::optional<cv::Mat> decodePngDirectly(const std::uint8_t* data, std::size_t size);

}  // namespace lom
