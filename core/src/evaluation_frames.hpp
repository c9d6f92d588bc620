#pragma once
// The per-frame part of the evaluation: single-view projection voxels and the
// 2D confusion matrices, gathered in one pass over the frames.
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "lom/evaluation.hpp"

namespace lom::detail {

struct FrameScan {
  std::vector<size_t> views;
  // For each view (same order), the voxels each scored label occupies in that view alone.
  std::vector<std::map<int, std::vector<VoxelKey>>> view_voxels;
  // The centres of the voxels every view's background points fall in (every
  // label's when the views hold under 400 such voxels), in key order: the
  // floor and walls as the projection baselines see them, which level their
  // boxes.
  std::vector<Eigen::Vector3d> view_centres;
  // The scored labels some pixel of some view takes (its argmax), with a
  // depth or without one (a transparent object's pixels have none).
  std::set<int> labels_in_views;
  std::optional<ConfusionMatrix> confusion;             // frames with label and proba images
  std::optional<ConfusionMatrix> confusion_candidates;  // the same, after candidates
  std::vector<size_t> excluded_2d;  // frames with label and proba, the proba made from the label
  // Frames with probabilities whose label image is a placeholder (an import
  // without labels): no ground truth to compare them with.
  size_t placeholder_labels_2d = 0;
};

// Frames [first_frame, last_frame) of options.fusion; voxel keys as in `map`
// (its resolution and max range).
[[nodiscard]] FrameScan scanFrames(const Sequence& sequence, const LabelMap& map,
                                   const std::vector<int>& scored_labels,
                                   const EvaluationOptions& options,
                                   const EvaluationProgressFn& progress);

}  // namespace lom::detail
