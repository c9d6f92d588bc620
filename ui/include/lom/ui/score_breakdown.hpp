#pragma once
// Where a box's label's voxels stand against the box, voxel by voxel, as
// IU_3d counts them (docs/evaluation.md): inside, partly inside (exact mode
// only) or outside. For View > Show Score Breakdown of Selected Box, which
// colours them in the 3D view while the box is being edited.
#include <Eigen/Core>
#include <QColor>
#include <cstddef>
#include <vector>

#include "lom/annotations.hpp"
#include "lom/evaluation.hpp"
#include "lom/ui/map_snapshot.hpp"

namespace lom::ui {

struct ScoreBreakdown {
  struct Voxel {
    Eigen::Vector3d center;
    double share = 0.0;  // of the voxel's volume counted inside the box, 0 to 1
  };
  int label = 0;
  double resolution = 0.0;
  std::vector<Voxel> voxels;  // the label's voxels at the finest resolution (pruned ones split)
  size_t inside = 0;          // share 1
  size_t partly = 0;          // share between 0 and 1
  size_t outside = 0;         // share 0
  // The terms of the label's IU_3d against the box, from these voxels.
  IouVolumes volumes;
};

// Its colour in the 3D view: green for a voxel wholly inside the box, amber
// for one partly inside, red for one outside.
[[nodiscard]] QColor scoreBreakdownColour(double share);

// The breakdown of `box.label`'s voxels in `snapshot` against `box.box`.
[[nodiscard]] ScoreBreakdown scoreBreakdown(const MapSnapshot& snapshot, const GroundTruthBox& box,
                                            IouMode mode);

}  // namespace lom::ui
