#include "png_decode.hpp"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "image_header.hpp"
#include "lom/error.hpp"
#include "png_check.hpp"
#include "png_direct.hpp"

namespace lom {

namespace {

// Everything the decoding touches lives here, reached through a pointer: after
// libpng jumps back out of an error, these objects are still valid and their
// destructors run as usual (the jump crosses only libpng's C frames).
struct Decoding {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  std::size_t at = 0;
  char reason[256] = {};
  cv::Mat image;
  std::vector<png_bytep> rows;
  PngSamples samples = PngSamples::AsOpenCv;
};

void readBytes(png_structp png, png_bytep out, png_size_t count) {
  auto* decoding = static_cast<Decoding*>(png_get_io_ptr(png));
  if (count > decoding->size - decoding->at) png_error(png, "the data ends early");
  std::memcpy(out, decoding->data + decoding->at, count);
  decoding->at += count;
}

[[noreturn]] void onError(png_structp png, png_const_charp message) {
  auto* decoding = static_cast<Decoding*>(png_get_error_ptr(png));
  std::snprintf(decoding->reason, sizeof(decoding->reason), "%s", message);
  png_longjmp(png, 1);
}

// Warnings (colour profiles, extra compressed data after the image) do not
// change the pixels read.
void onWarning(png_structp, png_const_charp) {}

// The transformations OpenCV's PNG decoder applies for IMREAD_UNCHANGED.
void readImage(png_structp png, png_infop info, Decoding& decoding) {
  png_set_read_fn(png, &decoding, readBytes);
  // decodePng has checked every chunk's CRC already.
  png_set_crc_action(png, PNG_CRC_QUIET_USE, PNG_CRC_QUIET_USE);
  png_read_info(png, info);
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
  png_get_IHDR(png, info, &width, &height, &bit_depth, &color_type, nullptr, nullptr, nullptr);
  // PNG data from a bag has had no header check: a few bytes can declare billions of pixels.
  if (std::uint64_t{width} * height > kMaxImagePixels)
    png_error(png, "the image declares more than 134217728 (2^27) pixels");
  if (decoding.samples == PngSamples::Indices &&
      (color_type == PNG_COLOR_TYPE_PALETTE ||
       (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8))) {
    // The stored numbers, one byte each: palette indices, or low-bit greys unscaled.
    png_set_packing(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != width) png_error(png, "an unexpected sample layout");
    decoding.image.create(static_cast<int>(height), static_cast<int>(width), CV_8UC1);
    decoding.rows.resize(height);
    for (png_uint_32 v = 0; v < height; ++v)
      decoding.rows[v] = decoding.image.ptr(static_cast<int>(v));
    png_read_image(png, decoding.rows.data());
    png_read_end(png, nullptr);
    return;
  }
  const bool transparency = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
  int channels = 1;
  if (color_type == PNG_COLOR_TYPE_RGB || color_type == PNG_COLOR_TYPE_PALETTE)
    channels = transparency ? 4 : 3;
  else if (color_type == PNG_COLOR_TYPE_GRAY_ALPHA || color_type == PNG_COLOR_TYPE_RGB_ALPHA)
    channels = 4;
  const bool sixteen = bit_depth == 16;
  if (sixteen && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__) png_set_swap(png);
  if (channels < 4) png_set_strip_alpha(png);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if ((color_type & PNG_COLOR_MASK_COLOR) == 0 && bit_depth < 8)
    png_set_expand_gray_1_2_4_to_8(png);
  if (channels > 1 && (color_type & PNG_COLOR_MASK_COLOR) != 0)
    png_set_bgr(png);
  else if (channels > 1)
    png_set_gray_to_rgb(png);
  if (channels == 4 && transparency) png_set_tRNS_to_alpha(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);

  const std::size_t row_bytes =
      static_cast<std::size_t>(width) * static_cast<std::size_t>(channels) * (sixteen ? 2u : 1u);
  if (png_get_rowbytes(png, info) != row_bytes) png_error(png, "an unexpected sample layout");
  decoding.image.create(static_cast<int>(height), static_cast<int>(width),
                        CV_MAKETYPE(sixteen ? CV_16U : CV_8U, channels));
  decoding.rows.resize(height);
  for (png_uint_32 v = 0; v < height; ++v)
    decoding.rows[v] = decoding.image.ptr(static_cast<int>(v));
  png_read_image(png, decoding.rows.data());
  png_read_end(png, nullptr);
}

// False when libpng stopped with an error. No local of this frame changes
// between the setjmp and a jump back to it.
bool readGuarded(png_structp png, png_infop info, Decoding& decoding) {
  if (setjmp(png_jmpbuf(png))) return false;
  readImage(png, info, decoding);
  return true;
}

}  // namespace

cv::Mat decodePng(const std::uint8_t* data, std::size_t size, const std::string& file,
                  PngSamples samples) {
  checkPngChunks(data, size, file);
  // (The direct decoder takes only 8- and 16-bit images without a palette,
  // which both ways read alike.)
  if (std::optional<cv::Mat> direct = decodePngDirectly(data, size)) return std::move(*direct);
  // On the heap, and never reassigned: the jump back from an error must find
  // it as libpng left it.
  const auto owned = std::make_unique<Decoding>();
  Decoding& decoding = *owned;
  decoding.data = data;
  decoding.size = size;
  decoding.samples = samples;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &decoding, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(png ? &png : nullptr, nullptr, nullptr);
    throw Error(file, "PNG data", "a PNG whose image data can be decoded",
                "not enough memory to start decoding");
  }
  bool failed = false;
  try {
    failed = !readGuarded(png, info, decoding);
  } catch (...) {  // out of memory for the image: libpng's structures go too
    png_destroy_read_struct(&png, &info, nullptr);
    throw;
  }
  png_destroy_read_struct(&png, &info, nullptr);
  if (failed)
    throw Error(file, "PNG data", "a PNG whose image data can be decoded",
                std::string("libpng stopped: ") + decoding.reason);
  return std::move(decoding.image);
}

}  // namespace lom
