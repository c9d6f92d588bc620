#pragma once
// The chunk structure of PNG data, checked before decoding: for a truncated or
// damaged PNG, libpng prints its own message to stderr before OpenCV gives up,
// so the readers check first and report one error naming the file and chunk.
#include <cstddef>
#include <cstdint>
#include <string>

namespace lom {

// The 32-bit big-endian number at `p` (PNG's lengths, sizes and CRCs).
[[nodiscard]] std::uint32_t readBigEndian32(const std::uint8_t* p);

// True when `data` starts with the 8-byte PNG signature.
[[nodiscard]] bool hasPngSignature(const std::uint8_t* data, std::size_t size);

// Walks the chunks of PNG data that starts with the signature: IHDR first and
// 13 bytes long, every chunk complete with a matching CRC-32, at least one IDAT
// and an IEND chunk (bytes after IEND are ignored, as libpng does). Throws
// lom::Error(file, "PNG data", "a complete PNG file", what is wrong), naming
// the chunk by its number (from 1) and type.
void checkPngChunks(const std::uint8_t* data, std::size_t size, const std::string& file);

}  // namespace lom
