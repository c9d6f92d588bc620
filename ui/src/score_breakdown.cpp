#include "lom/ui/score_breakdown.hpp"

#include <algorithm>
#include <cmath>

namespace lom::ui {

QColor scoreBreakdownColour(double share) {
  if (share >= 1.0) return {40, 200, 70};
  if (share <= 0.0) return {230, 45, 45};
  return {255, 180, 0};
}

ScoreBreakdown scoreBreakdown(const MapSnapshot& snapshot, const GroundTruthBox& box, IouMode mode) {
  ScoreBreakdown breakdown;
  breakdown.label = box.label;
  const double resolution = snapshot.resolution;
  breakdown.resolution = resolution;
  breakdown.volumes.ground_truth = box.box.volume();
  if (!(resolution > 0.0)) return breakdown;
  // Scores count the finest voxels: a pruned node of edge 2^d voxels stands
  // for (2^d)^3 of them, centred on its sub-grid.
  std::vector<Eigen::Vector3d> centres;
  for (const OccupiedVoxel& voxel : snapshot.voxels) {
    if (voxel.label != box.label) continue;
    const int per_edge = std::max(1, static_cast<int>(std::lround(voxel.size / resolution)));
    const Eigen::Vector3d first =
        voxel.center - Eigen::Vector3d::Constant(0.5 * voxel.size - 0.5 * resolution);
    for (int i = 0; i < per_edge; ++i)
      for (int j = 0; j < per_edge; ++j)
        for (int k = 0; k < per_edge; ++k)
          centres.push_back(first + resolution * Eigen::Vector3d(i, j, k));
  }
  const std::vector<double> shares = voxelSharesInBox(centres, resolution, box.box, mode);
  const double voxel_volume = resolution * resolution * resolution;
  breakdown.voxels.reserve(centres.size());
  for (size_t i = 0; i < centres.size(); ++i) {
    const double share = shares[i];
    breakdown.voxels.push_back({centres[i], share});
    if (share >= 1.0)
      ++breakdown.inside;
    else if (share <= 0.0)
      ++breakdown.outside;
    else
      ++breakdown.partly;
    breakdown.volumes.true_positive += share * voxel_volume;
  }
  breakdown.volumes.predicted = voxel_volume * static_cast<double>(centres.size());
  return breakdown;
}

}  // namespace lom::ui
