#pragma once
// The single-view projection baseline of one frame (docs/evaluation.md): each
// pixel's argmax label (after candidates) at its depth, on the map's voxel
// grid, background left out. For display next to the fused map.
#include "lom/fusion.hpp"
#include "lom/ui/map_snapshot.hpp"

namespace lom::ui {

[[nodiscard]] MapSnapshot projectionVoxels(const Sequence& sequence, size_t index,
                                           const FrameData& frame, const FusionOptions& options);

}  // namespace lom::ui
