// Depth-first application of a frame's sorted voxel updates.
#include <algorithm>
#include <array>

#include "lom/octree/label_octree.hpp"

namespace lom {

void LabelOcTree::applySortedUpdates(const std::vector<VoxelUpdate>& updates) {
  if (updates.empty()) return;
  const int depth_max = static_cast<int>(tree_depth);
  const int n = numLabels();
  bool root_is_new = false;
  if (!root) {
    root = new LabelOcTreeNode();
    ++tree_size;
    root_is_new = true;
  }
  std::array<LabelOcTreeNode*, 17> path{};  // path[d] = node at depth d on the current path
  path[0] = root;
  int valid_depth = 0;  // path[0..valid_depth] belong to the current key
  std::uint64_t previous = 0;

  auto finish = [&](int depth) {  // the subtree of path[depth] gets no more updates
    LabelOcTreeNode* node = path[static_cast<size_t>(depth)];
    if (nodeHasChildren(node) && !pruneSaturated(node)) node->updateOccupancyChildren();
  };

  for (size_t i = 0; i < updates.size(); ++i) {
    const VoxelUpdate& update = updates[i];
    int shared = 0;
    if (i > 0) {
      const std::uint64_t diff = update.morton ^ previous;
      if (diff == 0) continue;  // duplicates are not expected; keep the first
      const int level = (63 - __builtin_clzll(diff)) / 3;  // 0 = finest bit group
      // The path may end above the leaves where a miss was skipped.
      shared = std::min(depth_max - 1 - level, valid_depth);
      for (int d = valid_depth; d > shared; --d)
        if (d < depth_max) finish(d);
    }
    previous = update.morton;
    LabelOcTreeNode* node = path[static_cast<size_t>(shared)];
    bool created = shared == 0 && root_is_new;
    int d = shared;
    bool skipped = false;
    for (; d < depth_max; ++d) {
      if (!update.hit && isSaturatedFree(node, created)) {
        skipped = true;
        break;
      }
      node = childForUpdate(node, octomap::computeChildIdx(update.key, depth_max - 1 - d), created);
      path[static_cast<size_t>(d + 1)] = node;
    }
    valid_depth = d;
    if (skipped) continue;
    if (update.hit)
      node->addLabelLogOdds(n, update.hit, clamping_thres_min, clamping_thres_max);
    else
      node->addUniformLogOdds(prob_miss_log, clamping_thres_min, clamping_thres_max);
  }
  for (int d = valid_depth - 1; d >= 0; --d) finish(d);
}

}  // namespace lom
