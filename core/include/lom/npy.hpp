#pragma once
// NumPy .npy reading and writing (format versions 1.0-3.0).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace lom {

enum class NpyType { Float32, Float16, UInt8, UInt16, Float64 };

// An array as stored in the file, converted to native byte order and C order.
struct NpyArray {
  NpyType type = NpyType::Float32;
  std::vector<size_t> shape;
  std::vector<std::uint8_t> bytes;  // native byte order, C (row-major) order

  [[nodiscard]] size_t size() const;  // number of elements
  // Elements as float: float16/32/64 as is, uint8/uint16 scaled to [0, 1]
  // when `scale_integers` (probabilities), raw values otherwise.
  [[nodiscard]] std::vector<float> toFloat(bool scale_integers) const;
};

// Throws lom::Error naming `path` for unreadable files, bad headers, unsupported
// dtypes (the message lists the supported ones) and truncated data. Handles
// both byte orders and Fortran order.
[[nodiscard]] NpyArray readNpy(const std::filesystem::path& path);

// Writes a float32 (or other) array in C order, little endian, atomically.
void writeNpy(const std::filesystem::path& path, const NpyArray& array);
void writeNpyFloat32(const std::filesystem::path& path, const std::vector<size_t>& shape,
                     const std::vector<float>& values);

}  // namespace lom
