#pragma once
// Image sizes read from file headers, before anything is decoded.
#include <cstdint>
#include <filesystem>
#include <optional>

namespace lom {

// Images declaring more pixels than this are refused before decoding (a small
// compressed file can declare billions of pixels): 16384 x 8192, far beyond
// any depth or colour camera.
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 27;

struct ImageHeaderSize {
  std::uint64_t width = 0;
  std::uint64_t height = 0;
  const char* format = "";  // "PNG", "PGM", "JPEG", "TIFF", ...
  // Binary PGM and PPM: the file size that holds every pixel (header + data),
  // so that a truncated file is refused before the decoder reads it.
  std::uint64_t complete_file_bytes = 0;
};

// The width and height a PNG (IHDR), PNM (PBM, PGM, PPM), JPEG (frame header),
// TIFF (first image's tags) or BMP file declares in its header; nullopt for other formats and for
// files whose header cannot be read (the decoder reports those).
[[nodiscard]] std::optional<ImageHeaderSize> readImageHeaderSize(const std::filesystem::path& path);

}  // namespace lom
