// The one place that includes PCL's point types and io for voxel clouds
// (PCD, and PLY point clouds).
#define PCL_NO_PRECOMPILE
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
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

namespace {

// PCL's message without the empty file name it starts with (": [pcl::...").
std::string pclReason(const pcl::PCLException& e) {
  std::string reason = e.what();
  const size_t start = reason.find_first_not_of(": ");
  return start == std::string::npos ? reason : reason.substr(start);
}

pcl::PointCloud<LabelledVoxelPoint> voxelCloud(const LabelMap& map,
                                               const std::optional<std::set<int>>& labels,
                                               const std::filesystem::path& path) {
  pcl::PointCloud<LabelledVoxelPoint> cloud;
  for (const auto& [label, keys] : occupiedVoxelsByLabel(map, labels)) {
    const Rgb color = map.labels().at(label).color;
    for (const VoxelKey& key : keys) {
      const Eigen::Vector3d c = map.centerOf(key);
      const VoxelState state = map.voxelAt(key);
      LabelledVoxelPoint point;
      point.x = static_cast<float>(c.x());
      point.y = static_cast<float>(c.y());
      point.z = static_cast<float>(c.z());
      point.data[3] = 1.f;
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
    throw Error(path.string(), "map", "at least one occupied voxel to export",
                labels ? "no occupied voxel of the selected labels" : "an empty map");
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
  return cloud;
}

size_t writePcd(const LabelMap& map, const std::optional<std::set<int>>& labels,
                const std::filesystem::path& path) {
  const auto cloud = voxelCloud(map, labels, path);
  writePathAtomically(path, [&](const std::filesystem::path& temporary) {
    int result = -1;
    try {
      result = pcl::io::savePCDFileBinary(temporary.string(), cloud);
    } catch (const pcl::PCLException& e) {  // e.g. no room for the file
      throw Error(path.string(), "output", "a writable PCD file",
                  "PCL could not write it: " + pclReason(e));
    }
    if (result != 0)
      throw Error(path.string(), "output", "a writable PCD file",
                  libraryWriteFailure(temporary, "PCL"));
  });
  return cloud.size();
}

}  // namespace

size_t writeVoxelsPcd(const LabelMap& map, const std::filesystem::path& path) {
  return writePcd(map, std::nullopt, path);
}

size_t writeVoxelsPcd(const LabelMap& map, const std::set<int>& labels,
                      const std::filesystem::path& path) {
  return writePcd(map, labels, path);
}

size_t writeVoxelsPly(const LabelMap& map, const std::set<int>& labels,
                      const std::filesystem::path& path) {
  const auto cloud = voxelCloud(map, labels, path);
  pcl::PCLPointCloud2 blob;
  pcl::toPCLPointCloud2(cloud, blob);
  writePathAtomically(path, [&](const std::filesystem::path& temporary) {
    pcl::PLYWriter writer;
    int result = -1;
    try {
      // No camera element: a plain vertex list that every PLY reader accepts.
      result = writer.write(temporary.string(), blob, Eigen::Vector4f::Zero(),
                            Eigen::Quaternionf::Identity(), /*binary=*/true, /*use_camera=*/false);
    } catch (const pcl::PCLException& e) {
      throw Error(path.string(), "output", "a writable PLY file",
                  "PCL could not write it: " + pclReason(e));
    }
    if (result != 0)
      throw Error(path.string(), "output", "a writable PLY file",
                  libraryWriteFailure(temporary, "PCL"));
  });
  return cloud.size();
}

}  // namespace lom
