#include "lom/ui/projection_voxels.hpp"

#include <cmath>
#include <map>
#include <tuple>

namespace lom::ui {

MapSnapshot projectionVoxels(const Sequence& sequence, size_t index, const FrameData& frame,
                             const FusionOptions& options) {
  MapSnapshot snapshot;
  const double resolution = options.map.resolution;
  snapshot.resolution = resolution;
  if (!frame.proba && !frame.label) return snapshot;
  const FrameEvidence evidence = makeEvidence(sequence, index, frame, options);
  const CameraIntrinsics& camera = sequence.cameraOf(index);
  const Eigen::Isometry3d& T = sequence.frames[index].T_world_camera;
  const DepthImage& depth = frame.depth;
  // One voxel per grid cell (OctoMap's grid: cell = floor(p / resolution)); the
  // label seen there first wins, as a view has one prediction per voxel and label.
  std::map<std::tuple<long, long, long, int>, bool> cells;
  for (int v = 0; v < depth.height && v < evidence.height(); ++v)
    for (int u = 0; u < depth.width && u < evidence.width(); ++u) {
      const float z = depth.at(u, v);
      if (!std::isfinite(z) || z <= 0.f) continue;
      const Eigen::Vector3d p_camera = camera.backProject(u, v, z);
      if (options.map.max_range > 0 && p_camera.norm() > options.map.max_range) continue;
      const int label = evidence.argmax(u, v);
      if (label <= 0) continue;  // background, or no probability for any candidate
      const Eigen::Vector3d p = T * p_camera;
      // Outside the map's extent: the fusion and the scored baseline leave such
      // points out too (and their cell would not fit the grid's integers).
      if (!insideMapExtent(p, resolution)) continue;
      const auto key = std::make_tuple(static_cast<long>(std::floor(p.x() / resolution)),
                                       static_cast<long>(std::floor(p.y() / resolution)),
                                       static_cast<long>(std::floor(p.z() / resolution)), label);
      if (!cells.emplace(key, true).second) continue;
      OccupiedVoxel voxel;
      voxel.center = (Eigen::Vector3d(std::get<0>(key), std::get<1>(key), std::get<2>(key)) +
                      Eigen::Vector3d::Constant(0.5)) * resolution;
      voxel.size = resolution;
      voxel.label = label;
      voxel.probability = 1.f;
      snapshot.voxels.push_back(voxel);
      ++snapshot.counts[label];
    }
  return snapshot;
}

}  // namespace lom::ui
