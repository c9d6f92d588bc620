#include "jpeg_decode.hpp"

// jpeglib.h needs FILE and size_t declared before it.
#include <cstdio>
// clang-format off
#include <jpeglib.h>
#include <jerror.h>
// clang-format on

#include <csetjmp>
#include <memory>
#include <vector>

#include "image_header.hpp"
#include "lom/error.hpp"

namespace lom {

namespace {

// Everything the decoding touches lives here, reached through a pointer: after
// libjpeg's error handler jumps back, these objects are still valid and their
// destructors run as usual (the jump crosses only libjpeg's C frames and the
// handlers below, which hold nothing to destroy).
struct Decoding {
  jpeg_decompress_struct info{};
  jpeg_error_mgr messages{};
  std::jmp_buf jump{};
  char reason[JMSG_LENGTH_MAX] = {};
  cv::Mat image;
  std::vector<JSAMPLE> cmyk_row;
};

[[noreturn]] void stop(j_common_ptr info) {
  auto* decoding = static_cast<Decoding*>(info->client_data);
  (*info->err->format_message)(info, decoding->reason);
  std::longjmp(decoding->jump, 1);
}

[[noreturn]] void stopWith(Decoding& decoding, const char* reason) {
  std::snprintf(decoding.reason, sizeof(decoding.reason), "%s", reason);
  std::longjmp(decoding.jump, 1);
}

// Warnings after which libjpeg goes on with pixels it made up: a file that
// ends early, entropy-coded data that cannot be decoded, or data missing or
// left over in a segment.
bool damagesPixels(int code) {
  switch (code) {
    case JWRN_ARITH_BAD_CODE:
    case JWRN_BOGUS_PROGRESSION:
    case JWRN_EXTRANEOUS_DATA:
    case JWRN_HIT_MARKER:
    case JWRN_HUFF_BAD_CODE:
    case JWRN_JPEG_EOF:
    case JWRN_MUST_RESYNC:
    case JWRN_NOT_SEQUENTIAL:
      return true;
    default:
      return false;
  }
}

// level -1: a warning; 0 and above: trace messages, which are never shown.
void onMessage(j_common_ptr info, int level) {
  if (level < 0 && damagesPixels(info->err->msg_code)) stop(info);
}

void printNothing(j_common_ptr) {}

// Adobe's inverted CMYK to BGR, as OpenCV's JPEG reader converts it.
void cmykToBgr(const JSAMPLE* cmyk, std::uint8_t* bgr, JDIMENSION width) {
  for (JDIMENSION u = 0; u < width; ++u, cmyk += 4, bgr += 3) {
    const int k = cmyk[3];
    bgr[0] = static_cast<std::uint8_t>(k - ((255 - cmyk[2]) * k >> 8));
    bgr[1] = static_cast<std::uint8_t>(k - ((255 - cmyk[1]) * k >> 8));
    bgr[2] = static_cast<std::uint8_t>(k - ((255 - cmyk[0]) * k >> 8));
  }
}

void readImage(const std::uint8_t* data, std::size_t size, Decoding& decoding) {
  jpeg_decompress_struct& info = decoding.info;
  jpeg_mem_src(&info, data, static_cast<unsigned long>(size));
  jpeg_read_header(&info, TRUE);  // an image, not only tables: else libjpeg stops
  // JPEG data from a bag has had no header check: a few bytes can declare billions of pixels.
  if (std::uint64_t{info.image_width} * info.image_height > kMaxImagePixels)
    stopWith(decoding, "the image declares more than 134217728 (2^27) pixels");
  const bool grey = info.num_components == 1;
  const bool cmyk = info.jpeg_color_space == JCS_CMYK || info.jpeg_color_space == JCS_YCCK;
  info.out_color_space = grey ? JCS_GRAYSCALE : cmyk ? JCS_CMYK : JCS_EXT_BGR;
  jpeg_start_decompress(&info);
  if (info.output_components != (grey ? 1 : cmyk ? 4 : 3))
    stopWith(decoding, "an unexpected number of components");
  decoding.image.create(static_cast<int>(info.output_height), static_cast<int>(info.output_width),
                        grey ? CV_8UC1 : CV_8UC3);
  if (cmyk) decoding.cmyk_row.resize(static_cast<std::size_t>(info.output_width) * 4);
  while (info.output_scanline < info.output_height) {
    const int v = static_cast<int>(info.output_scanline);
    JSAMPROW row = cmyk ? decoding.cmyk_row.data() : decoding.image.ptr<JSAMPLE>(v);
    if (jpeg_read_scanlines(&info, &row, 1) != 1) stopWith(decoding, "a row could not be read");
    if (cmyk) cmykToBgr(row, decoding.image.ptr<std::uint8_t>(v), info.output_width);
  }
  // Reads up to the end of the image, so that damage after the last row is seen too.
  jpeg_finish_decompress(&info);
}

// False when libjpeg stopped. No local of this frame changes between the
// setjmp and a jump back to it.
bool readGuarded(const std::uint8_t* data, std::size_t size, Decoding& decoding) {
  if (setjmp(decoding.jump)) return false;
  readImage(data, size, decoding);
  return true;
}

// False when libjpeg could not allocate its structures.
bool createGuarded(Decoding& decoding) {
  if (setjmp(decoding.jump)) return false;
  jpeg_create_decompress(&decoding.info);
  return true;
}

}  // namespace

bool hasJpegSignature(const std::uint8_t* data, std::size_t size) {
  return size >= 3 && data[0] == 0xff && data[1] == 0xd8 && data[2] == 0xff;
}

cv::Mat decodeJpeg(const std::uint8_t* data, std::size_t size, const std::string& file) {
  const char* expected = "a JPEG whose image data can be decoded";
  if (size == 0) throw Error(file, "JPEG data", expected, "no data");
  // On the heap, and never reassigned: the jump back must find it as libjpeg left it.
  const auto owned = std::make_unique<Decoding>();
  Decoding& decoding = *owned;
  decoding.info.err = jpeg_std_error(&decoding.messages);
  decoding.messages.error_exit = stop;
  decoding.messages.emit_message = onMessage;
  decoding.messages.output_message = printNothing;
  decoding.info.client_data = &decoding;
  if (!createGuarded(decoding)) throw Error(file, "JPEG data", expected, "not enough memory to start decoding");
  bool failed = false;
  try {
    failed = !readGuarded(data, size, decoding);
  } catch (...) {  // out of memory for the image: libjpeg's structures go too
    jpeg_destroy_decompress(&decoding.info);
    throw;
  }
  jpeg_destroy_decompress(&decoding.info);
  if (failed)
    throw Error(file, "JPEG data", expected, std::string("libjpeg stopped: ") + decoding.reason);
  return std::move(decoding.image);
}

}  // namespace lom
