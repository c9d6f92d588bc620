#include "lom/score_breakdown.hpp"

#include <algorithm>
#include <cmath>

#include "lom/box_fit.hpp"

namespace lom {

namespace {

ScoreBreakdown fromCentres(std::vector<Eigen::Vector3d> centres, double resolution,
                           const GroundTruthBox& box, IouMode mode) {
  ScoreBreakdown breakdown;
  breakdown.label = box.label;
  breakdown.resolution = resolution;
  breakdown.shares = voxelSharesInBox(centres, resolution, box.box, mode);
  breakdown.centres = std::move(centres);
  double share_sum = 0.0;
  for (const double share : breakdown.shares) {
    if (share >= 1.0)
      ++breakdown.inside;
    else if (share <= 0.0)
      ++breakdown.outside;
    else
      ++breakdown.partly;
    share_sum += share;
  }
  breakdown.volumes = iouVolumesOf(share_sum, breakdown.centres.size(), resolution, box.box, mode);
  return breakdown;
}

}  // namespace

ScoreBreakdown scoreBreakdown(const std::vector<VoxelKey>& voxels, double resolution,
                              const GroundTruthBox& box, IouMode mode) {
  std::vector<Eigen::Vector3d> centres;
  centres.reserve(voxels.size());
  for (const VoxelKey& key : voxels) centres.push_back(voxelCenter(key, resolution));
  return fromCentres(std::move(centres), resolution, box, mode);
}

ScoreBreakdown scoreBreakdown(const std::vector<OccupiedVoxel>& leaves, double resolution,
                              const GroundTruthBox& box, IouMode mode) {
  return fromCentres(finestVoxelCentres(leaves, resolution, box.label), resolution, box, mode);
}

Rgb scoreShareColour(double share) {
  constexpr Rgb kInside{40, 200, 70}, kHalf{255, 180, 0}, kOutside{230, 45, 45};
  if (share >= 1.0) return kInside;
  if (share <= 0.0 || !std::isfinite(share)) return kOutside;
  const bool upper = share >= 0.5;
  const Rgb& from = upper ? kHalf : kOutside;
  const Rgb& to = upper ? kInside : kHalf;
  const double t = upper ? (share - 0.5) * 2.0 : share * 2.0;
  Rgb colour;
  for (int c = 0; c < 3; ++c)
    colour[static_cast<size_t>(c)] = static_cast<std::uint8_t>(
        std::lround(from[static_cast<size_t>(c)] +
                    t * (to[static_cast<size_t>(c)] - from[static_cast<size_t>(c)])));
  return colour;
}

}  // namespace lom
