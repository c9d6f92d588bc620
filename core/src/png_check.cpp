#include "png_check.hpp"

#include <libdeflate.h>

#include <cstring>

#include "lom/error.hpp"

namespace lom {

namespace {

constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// The CRC-32 of PNG chunks (ISO 3309), libdeflate's (folded with carry-less
// multiplies where the processor has them), so checking a frame's PNGs costs
// a small part of decoding them.
std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
  return libdeflate_crc32(0, data, size);
}

// Chunk types are four ASCII letters; anything else would print as garbage.
bool isChunkType(const std::uint8_t* p) {
  for (int i = 0; i < 4; ++i)
    if ((p[i] | 0x20) < 'a' || (p[i] | 0x20) > 'z') return false;
  return true;
}

}  // namespace

std::uint32_t readBigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

bool hasPngSignature(const std::uint8_t* data, std::size_t size) {
  return size >= sizeof(kSignature) && std::memcmp(data, kSignature, sizeof(kSignature)) == 0;
}

void checkPngChunks(const std::uint8_t* data, std::size_t size, const std::string& file) {
  const auto fail = [&](const std::string& found) {
    throw Error(file, "PNG data", "a complete PNG file", found);
  };
  const std::string ends = "the PNG ends after " + std::to_string(size) + " bytes";
  std::string last;  // the chunk before, for a PNG that stops between chunks
  bool has_image_data = false;
  std::size_t at = sizeof(kSignature);
  for (int number = 1;; ++number) {
    const std::string chunk = "chunk " + std::to_string(number);
    if (at == size)
      fail(number == 1 ? ends + ", right after the signature"
                       : ends + ", after " + last + ", without an IEND chunk");
    if (size - at < 8) fail(ends + ", inside the length and type of " + chunk);
    if (!isChunkType(data + at + 4))
      fail(chunk + " (at byte " + std::to_string(at) + ") has no valid type (four letters)");
    const std::string type(reinterpret_cast<const char*>(data + at + 4), 4);
    const std::string named = chunk + " (" + type + ")";
    // 64-bit, so that a length field near 2^32 cannot wrap around.
    const std::uint64_t length = readBigEndian32(data + at);
    if (length + 12 > size - at)
      fail("the PNG ends inside " + named + ", after " + std::to_string(size) + " of at least " +
           std::to_string(at + length + 12) + " bytes");
    if (number == 1 && type != "IHDR") fail(named + " comes first instead of IHDR");
    if (number == 1 && length != 13)
      fail(named + " is " + std::to_string(length) + " bytes long instead of 13");
    const std::size_t data_size = static_cast<std::size_t>(length);
    if (crc32(data + at + 4, data_size + 4) != readBigEndian32(data + at + 8 + data_size))
      fail(named + " fails its CRC check");
    has_image_data = has_image_data || type == "IDAT";
    at += data_size + 12;
    last = named;
    if (type != "IEND") continue;
    if (!has_image_data) fail("no IDAT chunk (image data) before " + named);
    return;
  }
}

}  // namespace lom
