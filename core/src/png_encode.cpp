#include "png_encode.hpp"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <cstdio>
#include <memory>

#include "lom/error.hpp"

namespace lom {

namespace {

// Reached through a pointer, as in png_decode.cpp: after libpng jumps back out
// of an error these objects are intact and are destroyed as usual.
struct Encoding {
  const cv::Mat* mat = nullptr;
  std::vector<std::uint8_t> bytes;
  std::vector<png_bytep> rows;
  char reason[256] = {};
};

void writeBytes(png_structp png, png_bytep data, png_size_t count) {
  auto* encoding = static_cast<Encoding*>(png_get_io_ptr(png));
  encoding->bytes.insert(encoding->bytes.end(), data, data + count);
}

void flushNothing(png_structp) {}

[[noreturn]] void onError(png_structp png, png_const_charp message) {
  auto* encoding = static_cast<Encoding*>(png_get_error_ptr(png));
  std::snprintf(encoding->reason, sizeof(encoding->reason), "%s", message);
  png_longjmp(png, 1);
}

void onWarning(png_structp, png_const_charp) {}

void writeImage(png_structp png, png_infop info, Encoding& encoding) {
  const cv::Mat& mat = *encoding.mat;
  png_set_write_fn(png, &encoding, writeBytes, flushNothing);
  // OpenCV's defaults for PNG: speed over size.
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_RLE);
  const int channels = mat.channels();
  const int type = channels == 1   ? PNG_COLOR_TYPE_GRAY
                   : channels == 3 ? PNG_COLOR_TYPE_RGB
                                   : PNG_COLOR_TYPE_RGB_ALPHA;
  const bool sixteen = mat.depth() == CV_16U;
  png_set_IHDR(png, info, static_cast<png_uint_32>(mat.cols), static_cast<png_uint_32>(mat.rows),
               sixteen ? 16 : 8, type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (sixteen && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__) png_set_swap(png);
  if (channels > 1) png_set_bgr(png);
  encoding.rows.resize(static_cast<size_t>(mat.rows));
  for (int v = 0; v < mat.rows; ++v)
    encoding.rows[static_cast<size_t>(v)] = const_cast<png_bytep>(mat.ptr(v));
  png_write_image(png, encoding.rows.data());
  png_write_end(png, nullptr);
}

// False when libpng stopped with an error. No local of this frame changes
// between the setjmp and a jump back to it.
bool writeGuarded(png_structp png, png_infop info, Encoding& encoding) {
  if (setjmp(png_jmpbuf(png))) return false;
  writeImage(png, info, encoding);
  return true;
}

}  // namespace

std::vector<std::uint8_t> encodePng(const cv::Mat& mat, const std::string& file) {
  const int channels = mat.channels();
  if ((mat.depth() != CV_8U && mat.depth() != CV_16U) ||
      (channels != 1 && channels != 3 && channels != 4) || mat.empty())
    throw Error(file, "output", "an image of 8 or 16 bits per sample with 1, 3 or 4 channels",
                std::to_string(mat.cols) + " x " + std::to_string(mat.rows) + " of " +
                    std::to_string(mat.channels()) + " channel(s), OpenCV depth " +
                    std::to_string(mat.depth()));
  const auto owned = std::make_unique<Encoding>();
  Encoding& encoding = *owned;
  encoding.mat = &mat;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &encoding, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(png ? &png : nullptr, nullptr);
    throw Error(file, "output", "a writable PNG", "not enough memory to start encoding");
  }
  bool failed = false;
  try {
    failed = !writeGuarded(png, info, encoding);
  } catch (...) {  // out of memory for the bytes: libpng's structures go too
    png_destroy_write_struct(&png, &info);
    throw;
  }
  png_destroy_write_struct(&png, &info);
  if (failed)
    throw Error(file, "output", "a writable PNG",
                std::string("libpng stopped: ") + encoding.reason);
  return std::move(encoding.bytes);
}

}  // namespace lom
