// labeloctomap export: the fused map for other tools.
#include <iostream>

#include "args.hpp"
#include "commands.hpp"
#include "lom/export.hpp"
#include "lom/label_map.hpp"

namespace lom::cli {

int runExport(const Words& words) {
  const Args args(words, {});
  args.expectOnly({"voxels"}, 1);
  const std::filesystem::path map_path = args.positional(0, "MAP.ot");
  const auto voxels = args.option("voxels");
  if (!voxels) throw UsageError("nothing to export: give --voxels OUT.pcd");
  const LabelMap map = LabelMap::load(map_path);
  const size_t points = writeVoxelsPcd(map, *voxels);
  std::cout << "wrote " << points << " occupied voxels to " << *voxels << "\n";
  return 0;
}

}  // namespace lom::cli
