// The one place that includes PCL's point types and io for voxel clouds.
#define PCL_NO_PRECOMPILE
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"

namespace lom {

struct EIGEN_ALIGN16 LabelledVoxelPoint {
  PCL_ADD_POINT4D;
  PCL_ADD_RGB;
  std::uint32_t label;
  float probability;
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace lom

POINT_CLOUD_REGISTER_POINT_STRUCT(lom::LabelledVoxelPoint,
                                  (float, x, x)(float, y, y)(float, z, z)(float, rgb, rgb)(
                                      std::uint32_t, label, label)(float, probability, probability))

namespace lom {

size_t writeVoxelsPcd(const LabelMap& map, const std::filesystem::path& path) {
  pcl::PointCloud<LabelledVoxelPoint> cloud;
  for (const auto& [label, count] : map.occupiedCountPerLabel()) {
    (void)count;
    for (const VoxelKey& key : map.voxelsOfLabel(label)) {
      const Eigen::Vector3d c = map.centerOf(key);
      const VoxelState state = map.voxelAt(key);
      LabelledVoxelPoint point;
      point.x = static_cast<float>(c.x());
      point.y = static_cast<float>(c.y());
      point.z = static_cast<float>(c.z());
      point.data[3] = 1.f;
      const Rgb color = map.labels().at(label).color;
      point.r = color[0];
      point.g = color[1];
      point.b = color[2];
      point.a = 255;
      point.label = static_cast<std::uint32_t>(label);
      point.probability = state.probabilities[static_cast<size_t>(label)];
      cloud.push_back(point);
    }
  }
  if (cloud.empty())
    throw Error(path.string(), "map", "at least one occupied voxel to export", "an empty map");
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
  writePathAtomically(path, [&](const std::filesystem::path& temporary) {
    if (pcl::io::savePCDFileBinary(temporary.string(), cloud) != 0)
      throw Error(path.string(), "output", "a writable PCD file", "PCL could not write it");
  });
  return cloud.size();
}

}  // namespace lom
