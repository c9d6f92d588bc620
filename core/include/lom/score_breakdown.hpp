#pragma once
// Where a box's label's voxels stand against the box, voxel by voxel, as
// IU_3d counts them (docs/evaluation.md): wholly inside, partly inside (exact
// mode only) or outside. The studio's View > Show Score Breakdown and
// `labeloctomap render --colour score` show it.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "lom/annotations.hpp"
#include "lom/evaluation.hpp"
#include "lom/label_map.hpp"
#include "lom/labels.hpp"

namespace lom {

struct ScoreBreakdown {
  int label = 0;
  double resolution = 0.0;
  std::vector<Eigen::Vector3d> centres;  // the label's voxels at the finest resolution
  std::vector<double> shares;            // of each voxel's volume counted inside the box, 0 to 1
  size_t inside = 0;                     // share 1
  size_t partly = 0;                     // share between 0 and 1
  size_t outside = 0;                    // share 0
  IouVolumes volumes;                    // the terms of the label's IU_3d, from these voxels
};

// The breakdown of `box.label`'s voxels, given as finest-resolution keys
// (LabelMap::voxelsOfLabel).
[[nodiscard]] ScoreBreakdown scoreBreakdown(const std::vector<VoxelKey>& voxels, double resolution,
                                            const GroundTruthBox& box, IouMode mode);
// The same from occupied leaves of any labels (LabelMap::forEachOccupied):
// those of `box.label` only, pruned leaves split into their finest voxels.
[[nodiscard]] ScoreBreakdown scoreBreakdown(const std::vector<OccupiedVoxel>& leaves,
                                            double resolution, const GroundTruthBox& box,
                                            IouMode mode);

// The colour of a voxel with this share in pictures of the breakdown: green
// (40, 200, 70) wholly inside the box, red (230, 45, 45) outside, and for a
// voxel partly inside a blend from red through amber (255, 180, 0, half
// inside) to green by its share.
[[nodiscard]] Rgb scoreShareColour(double share);

}  // namespace lom
