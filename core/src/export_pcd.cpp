// The one place that includes PCL's point types and io for voxel clouds
// (PCD, and PLY point clouds).
#define PCL_NO_PRECOMPILE
#include <pcl/console/print.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <fstream>
#include <functional>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"
#include "lom/height_colours.hpp"

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

// Bytes per point after the header: PCD x y z rgb label probability (six 4-byte
// fields); PLY x y z (floats), red green blue (bytes), label, probability.
constexpr std::uintmax_t kPcdPointBytes = 24;
constexpr std::uintmax_t kPlyPointBytes = 23;

// Whether PCL wrote the whole file: its header (up to and with `header_end`)
// and then `points` x `point_bytes`. PCL's PLY writer does not check its
// stream, so a file cut short by a full disk would otherwise pass as written.
bool completeFile(const std::filesystem::path& file, const std::string& header_end,
                  size_t points, std::uintmax_t point_bytes) {
  std::ifstream in(file, std::ios::binary);
  std::string header;
  for (std::string line; header.size() < 65536 && std::getline(in, line);) {
    header += line + "\n";
    if (line == header_end) {
      std::error_code ec;
      const std::uintmax_t size = std::filesystem::file_size(file, ec);
      return !ec && size == header.size() + points * point_bytes;
    }
  }
  return false;
}

// PCL prints its own errors on the terminal (pcl::console); the product says
// what went wrong itself. Quiet while one of its writers runs.
class QuietPcl {
 public:
  QuietPcl() : before_(pcl::console::getVerbosityLevel()) {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(before_); }
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;

 private:
  pcl::console::VERBOSITY_LEVEL before_;
};

// Runs PCL's `write` into `temporary` and checks the file it leaves.
void writeWithPcl(const std::filesystem::path& path, const std::filesystem::path& temporary,
                  const char* format, const std::string& header_end, size_t points,
                  std::uintmax_t point_bytes, const std::function<int()>& write) {
  int result = -1;
  try {
    const QuietPcl quiet;
    result = write();
  } catch (const pcl::PCLException&) {  // e.g. no room for the file
    result = -1;
  }
  const std::string expected = std::string("a writable ") + format + " file";
  if (result != 0) throw Error(path.string(), "output", expected, libraryWriteFailure(temporary, "PCL"));
  if (!completeFile(temporary, header_end, points, point_bytes))
    throw Error(path.string(), "output", expected,
                streamWriteFailure(temporary, "write failed: PCL's file was cut short"));
}

pcl::PointCloud<LabelledVoxelPoint> voxelCloud(const LabelMap& map,
                                               const std::optional<std::set<int>>& labels,
                                               const std::filesystem::path& path,
                                               const std::optional<Eigen::Matrix3d>& rotation) {
  pcl::PointCloud<LabelledVoxelPoint> cloud;
  for (const auto& [label, keys] : occupiedVoxelsByLabel(map, labels)) {
    // The studio's shading: the background's black (VOC palette) would hide
    // the points of a geometry-only recording on a viewer's black background.
    const Rgb color = shadedLabelColour(map.labels(), label);
    for (const VoxelKey& key : keys) {
      const Eigen::Vector3d c =
          rotation ? Eigen::Vector3d(*rotation * map.centerOf(key)) : map.centerOf(key);
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
                const std::filesystem::path& path,
                const std::optional<Eigen::Matrix3d>& rotation = std::nullopt) {
  const auto cloud = voxelCloud(map, labels, path, rotation);
  writePathAtomically(path, [&](const std::filesystem::path& temporary) {
    writeWithPcl(path, temporary, "PCD", "DATA binary", cloud.size(), kPcdPointBytes,
                 [&] { return pcl::io::savePCDFileBinary(temporary.string(), cloud); });
  });
  return cloud.size();
}

}  // namespace

size_t writeVoxelsPcd(const LabelMap& map, const std::filesystem::path& path) {
  return writePcd(map, std::nullopt, path);
}

size_t writeVoxelsPcd(const LabelMap& map, const std::set<int>& labels,
                      const std::filesystem::path& path,
                      const std::optional<Eigen::Matrix3d>& rotation) {
  return writePcd(map, labels, path, rotation);
}

size_t writeVoxelsPly(const LabelMap& map, const std::set<int>& labels,
                      const std::filesystem::path& path,
                      const std::optional<Eigen::Matrix3d>& rotation) {
  const auto cloud = voxelCloud(map, labels, path, rotation);
  pcl::PCLPointCloud2 blob;
  pcl::toPCLPointCloud2(cloud, blob);
  writePathAtomically(path, [&](const std::filesystem::path& temporary) {
    writeWithPcl(path, temporary, "PLY", "end_header", cloud.size(), kPlyPointBytes, [&] {
      // No camera element: a plain vertex list that every PLY reader accepts.
      return pcl::PLYWriter().write(temporary.string(), blob, Eigen::Vector4f::Zero(),
                                    Eigen::Quaternionf::Identity(), /*binary=*/true,
                                    /*use_camera=*/false);
    });
  });
  return cloud.size();
}

}  // namespace lom
