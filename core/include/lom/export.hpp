#pragma once
// Writing the fused map for other tools.
#include <filesystem>

#include "lom/label_map.hpp"

namespace lom {

// Occupied voxel centres as a binary PCD that PCL reads, with fields
// x y z (float, metres), rgb (packed float, the label's colour), label (uint32)
// and probability (float, of that label). Pruned leaves are written as their
// finest-resolution voxels so every point stands for one voxel. Atomic.
// Returns the number of points written.
size_t writeVoxelsPcd(const LabelMap& map, const std::filesystem::path& path);

}  // namespace lom
