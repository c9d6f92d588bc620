#pragma once
// PNG decoding through libpng with its messages captured. OpenCV's PNG reader
// leaves libpng's default handlers in place, which print "libpng error: ..."
// and "libpng warning: ..." on stderr for damaged image data or for harmless
// quirks such as colour profiles; here errors become lom::Error and warnings
// are dropped, so nothing reaches the terminal.
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace lom {

// Checks the chunks first (checkPngChunks: one error naming the chunk of a
// truncated or damaged file; libpng then skips its own CRC pass), then
// decodes the common kinds directly (png_direct.hpp) and the others, or data
// that does not decode that way, with libpng. It decodes PNG data as cv::imdecode(data,
// cv::IMREAD_UNCHANGED) does: grey (1 channel), BGR (3) or BGRA (4; with an alpha channel or a
// transparency chunk), 8 or 16 bits per sample; palette and 1-, 2- and 4-bit greys are expanded to
// 8 bits. Throws lom::Error(file, "PNG data", "a PNG whose image data can be decoded", libpng's
// reason) for data libpng rejects.
// With PngSamples::Indices, palette images and 1-, 2- and 4-bit greys are
// read as the numbers they store instead (one 8-bit channel: the palette
// index, the grey unscaled), as label images need: a 4-bit grey 3 is label 3,
// not 51.
enum class PngSamples { AsOpenCv, Indices };
[[nodiscard]] cv::Mat decodePng(const std::uint8_t* data, std::size_t size, const std::string& file,
                                PngSamples samples = PngSamples::AsOpenCv);

}  // namespace lom
