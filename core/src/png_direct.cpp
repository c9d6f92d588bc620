#include "png_direct.hpp"

#include <libdeflate.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "image_header.hpp"
#include "png_check.hpp"

namespace lom {

namespace {

struct DirectLayout {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int sample_bytes = 1;  // 8- or 16-bit samples
  int channels = 1;      // grey, RGB or RGBA
  struct Span {
    std::size_t at, size;
  };
  std::vector<Span> image_data;  // the IDAT chunks' data, in order
};

// What libpng alone should handle (other kinds of image, odd chunk layouts)
// gives nullopt. The chunks' lengths were checked already, but this is also
// safe on data that was not checked.
std::optional<DirectLayout> directLayoutOf(const std::uint8_t* data, std::size_t size) {
  if (!hasPngSignature(data, size)) return std::nullopt;
  DirectLayout layout;
  bool header = false, image_data_ended = false;
  for (std::size_t at = 8; size - at >= 12;) {
    const std::uint64_t length = readBigEndian32(data + at);
    if (length + 12 > size - at) return std::nullopt;
    const char* type = reinterpret_cast<const char*>(data + at + 4);
    const std::uint8_t* body = data + at + 8;
    auto is = [type](const char* name) { return std::memcmp(type, name, 4) == 0; };
    if (!header) {
      if (!is("IHDR") || length != 13) return std::nullopt;
      layout.width = readBigEndian32(body);
      layout.height = readBigEndian32(body + 4);
      const int bit_depth = body[8], colour_type = body[9];
      layout.channels = colour_type == 0 ? 1 : colour_type == 2 ? 3 : colour_type == 6 ? 4 : 0;
      // Compression, filter method and interlacing: only the standard
      // methods, not interlaced.
      if (layout.channels == 0 || (bit_depth != 8 && bit_depth != 16) || body[10] != 0 ||
          body[11] != 0 || body[12] != 0)
        return std::nullopt;
      if (layout.width == 0 || layout.height == 0 || layout.width > 0x7fffffffu ||
          layout.height > 0x7fffffffu ||
          std::uint64_t{layout.width} * layout.height > kMaxImagePixels)
        return std::nullopt;
      layout.sample_bytes = bit_depth / 8;
      header = true;
    } else if (is("IDAT")) {
      if (image_data_ended) return std::nullopt;
      layout.image_data.push_back({at + 8, static_cast<std::size_t>(length)});
    } else if (is("IEND")) {
      if (layout.image_data.empty()) return std::nullopt;
      return layout;
    } else {
      image_data_ended = !layout.image_data.empty();
      // A palette or transparency changes the pixels; other critical chunks
      // (upper-case first letter) are libpng's to accept or refuse.
      if (is("PLTE") || is("tRNS") || (type[0] & 0x20) == 0) return std::nullopt;
    }
    at += static_cast<std::size_t>(length) + 12;
  }
  return std::nullopt;
}

// The predictor of filter type 4 (PNG specification, 9.4).
inline std::uint8_t paeth(int a, int b, int c) {
  const int p = b - c, q = a - c;
  const int pa = std::abs(p), pb = std::abs(q), pc = std::abs(p + q);
  if (pa <= pb && pa <= pc) return static_cast<std::uint8_t>(a);
  return static_cast<std::uint8_t>(pb <= pc ? b : c);
}

// Undoes one row's filter in place; `prior` is the row above, unfiltered
// (zeros above the first row). False for an unknown filter type.
template <int bpp>
bool unfilterRow(std::uint8_t filter, std::uint8_t* x, const std::uint8_t* prior,
                 std::size_t bytes) {
  switch (filter) {
    case 0:
      return true;
    case 1:
      for (std::size_t i = bpp; i < bytes; ++i) x[i] = static_cast<std::uint8_t>(x[i] + x[i - bpp]);
      return true;
    case 2:
      for (std::size_t i = 0; i < bytes; ++i) x[i] = static_cast<std::uint8_t>(x[i] + prior[i]);
      return true;
    case 3:
      for (std::size_t i = 0; i < bpp; ++i)
        x[i] = static_cast<std::uint8_t>(x[i] + (prior[i] >> 1));
      for (std::size_t i = bpp; i < bytes; ++i)
        x[i] = static_cast<std::uint8_t>(x[i] + ((x[i - bpp] + prior[i]) >> 1));
      return true;
    case 4:
      for (std::size_t i = 0; i < bpp; ++i) x[i] = static_cast<std::uint8_t>(x[i] + prior[i]);
      for (std::size_t i = bpp; i < bytes; ++i)
        x[i] = static_cast<std::uint8_t>(x[i] + paeth(x[i - bpp], prior[i], prior[i - bpp]));
      return true;
    default:
      return false;
  }
}

bool unfilterRow(int bpp, std::uint8_t filter, std::uint8_t* x, const std::uint8_t* prior,
                 std::size_t bytes) {
  switch (bpp) {
    case 1:
      return unfilterRow<1>(filter, x, prior, bytes);
    case 2:
      return unfilterRow<2>(filter, x, prior, bytes);
    case 3:
      return unfilterRow<3>(filter, x, prior, bytes);
    case 4:
      return unfilterRow<4>(filter, x, prior, bytes);
    case 6:
      return unfilterRow<6>(filter, x, prior, bytes);
    default:
      return unfilterRow<8>(filter, x, prior, bytes);
  }
}

// One unfiltered row into the image's row: colour samples in BGR(A) order,
// 16-bit samples (big-endian in PNG) in the machine's order.
void storeRow(const std::uint8_t* x, std::uint8_t* out, std::uint32_t width, int channels,
              int sample_bytes) {
  const std::size_t samples = std::size_t{width} * static_cast<std::size_t>(channels);
  if (sample_bytes == 1) {
    if (channels == 1) {
      std::memcpy(out, x, samples);
      return;
    }
    for (std::size_t i = 0; i < samples; i += static_cast<std::size_t>(channels)) {
      out[i] = x[i + 2];
      out[i + 1] = x[i + 1];
      out[i + 2] = x[i];
      if (channels == 4) out[i + 3] = x[i + 3];
    }
    return;
  }
  auto* out16 = reinterpret_cast<std::uint16_t*>(out);
  auto sample = [x](std::size_t i) {
    return static_cast<std::uint16_t>((x[2 * i] << 8) | x[2 * i + 1]);
  };
  if (channels == 1) {
    for (std::size_t i = 0; i < samples; ++i) out16[i] = sample(i);
    return;
  }
  for (std::size_t i = 0; i < samples; i += static_cast<std::size_t>(channels)) {
    out16[i] = sample(i + 2);
    out16[i + 1] = sample(i + 1);
    out16[i + 2] = sample(i);
    if (channels == 4) out16[i + 3] = sample(i + 3);
  }
}

struct FreeDecompressor {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

}  // namespace

bool isDirectPng(const std::uint8_t* data, std::size_t size) {
  return directLayoutOf(data, size).has_value();
}

std::optional<cv::Mat> decodePngDirectly(const std::uint8_t* data, std::size_t size) {
  const std::optional<DirectLayout> layout = directLayoutOf(data, size);
  if (!layout) return std::nullopt;
  const int bpp = layout->channels * layout->sample_bytes;
  const std::size_t row_bytes = std::size_t{layout->width} * static_cast<std::size_t>(bpp);
  const std::size_t filtered_bytes = (row_bytes + 1) * layout->height;

  // The image data is one zlib stream split over the IDAT chunks.
  const std::uint8_t* stream = data + layout->image_data.front().at;
  std::size_t stream_bytes = layout->image_data.front().size;
  std::vector<std::uint8_t> joined;
  if (layout->image_data.size() > 1) {
    for (const auto& span : layout->image_data)
      joined.insert(joined.end(), data + span.at, data + span.at + span.size);
    stream = joined.data();
    stream_bytes = joined.size();
  }
  const std::unique_ptr<libdeflate_decompressor, FreeDecompressor> decompressor(
      libdeflate_alloc_decompressor());
  if (!decompressor) return std::nullopt;
  const std::unique_ptr<std::uint8_t[]> rows(new std::uint8_t[filtered_bytes]);
  std::size_t read = 0, written = 0;
  // The stream must hold exactly the image's rows (libpng handles, and warns
  // about, data before or after them).
  if (libdeflate_zlib_decompress_ex(decompressor.get(), stream, stream_bytes, rows.get(),
                                    filtered_bytes, &read, &written) != LIBDEFLATE_SUCCESS ||
      read != stream_bytes || written != filtered_bytes)
    return std::nullopt;

  cv::Mat image(static_cast<int>(layout->height), static_cast<int>(layout->width),
                CV_MAKETYPE(layout->sample_bytes == 2 ? CV_16U : CV_8U, layout->channels));
  const std::vector<std::uint8_t> zeros(row_bytes, 0);
  const std::uint8_t* prior = zeros.data();
  for (std::uint32_t v = 0; v < layout->height; ++v) {
    std::uint8_t* row = rows.get() + (row_bytes + 1) * v;
    if (!unfilterRow(bpp, row[0], row + 1, prior, row_bytes)) return std::nullopt;
    storeRow(row + 1, image.ptr(static_cast<int>(v)), layout->width, layout->channels,
             layout->sample_bytes);
    prior = row + 1;
  }
  return image;
}

}  // namespace lom
