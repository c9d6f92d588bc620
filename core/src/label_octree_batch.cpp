// Depth-first application of a frame's sorted voxel updates, on one thread or
// on two halves of the stream at once.
#include <algorithm>
#include <array>
#include <utility>

#include "lom/octree/label_octree.hpp"
#include "worker_pool.hpp"

namespace lom {

// The nodes both halves of a split stream pass through: path[d] for d <= depth.
struct LabelOcTree::SharedPath {
  std::array<const LabelOcTreeNode*, 17> path{};
  int depth = -1;  // -1: nothing shared (one part)
  [[nodiscard]] bool holds(int d, const LabelOcTreeNode* node) const {
    return d <= depth && path[static_cast<size_t>(d)] == node;
  }
};

namespace {

// Depth of the deepest node containing both keys (0 = root).
int sharedDepth(std::uint64_t a, std::uint64_t b, int depth_max) {
  const std::uint64_t diff = a ^ b;
  const int level = (63 - __builtin_clzll(diff)) / 3;  // 0 = finest bit group
  return depth_max - 1 - level;
}

}  // namespace

long LabelOcTree::applyUpdateRange(const VoxelUpdate* first, const VoxelUpdate* last,
                                   bool root_is_new, const SharedPath& shared, const HitLabels* listed) {
  const int depth_max = static_cast<int>(tree_depth);
  const int n = numLabels();
  long node_delta = 0;
  std::array<LabelOcTreeNode*, 17> path{};  // path[d] = node at depth d on the current path
  path[0] = root;
  int valid_depth = 0;  // path[0..valid_depth] belong to the current key
  std::uint64_t previous = 0;

  auto finish = [&](int depth) {  // the subtree of path[depth] gets no more updates
    LabelOcTreeNode* node = path[static_cast<size_t>(depth)];
    if (!shared.holds(depth, node)) finishNode(node, node_delta);  // else the other part may work below it
  };

  for (const VoxelUpdate* update = first; update != last; ++update) {
    int common = 0;
    if (update != first) {
      if (update->morton == previous) continue;  // duplicates are not expected; keep the first
      // The path may end above the leaves where a miss was skipped.
      common = std::min(sharedDepth(update->morton, previous, depth_max), valid_depth);
      for (int d = valid_depth; d > common; --d)
        if (d < depth_max) finish(d);
    }
    previous = update->morton;
    LabelOcTreeNode* node = path[static_cast<size_t>(common)];
    bool created = common == 0 && root_is_new;
    int d = common;
    bool skipped = false;
    for (; d < depth_max; ++d) {
      // A shared node has children (findCut) and keeps them during the pass,
      // so it is neither saturated free nor a pruned leaf. Its child array is
      // not scanned here (nodeHasChildren): the other part may be adding a
      // child in its own slot meanwhile. Only this part's slot is read.
      const unsigned pos = octomap::computeChildIdx(update->key, depth_max - 1 - d);
      if (shared.holds(d, node)) {
        if (nodeChildExists(node, pos)) {
          node = getNodeChild(node, pos);
          created = false;
        } else {
          node = node->addChild(pos);
          created = true;
          ++node_delta;
        }
      } else {
        if (!update->hit && isSaturatedFree(node, created)) {
          skipped = true;
          break;
        }
        node = childForUpdate(node, pos, created, node_delta);
      }
      path[static_cast<size_t>(d + 1)] = node;
    }
    valid_depth = d;
    if (skipped) continue;
    if (update->hit && listed)
      node->addListedLogOdds(n, listed->count, listed->ids, update->hit, update->hit[listed->count],
                             clamping_thres_min, clamping_thres_max);
    else if (update->hit)
      node->addLabelLogOdds(n, update->hit, clamping_thres_min, clamping_thres_max);
    else
      node->addUniformLogOdds(prob_miss_log, clamping_thres_min, clamping_thres_max);
  }
  for (int d = valid_depth - 1; d >= 0; --d) finish(d);
  return node_delta;
}

// Near the middle of the work (a hit, with its label block, costs several
// times a miss), a cut where every node the two halves share already exists
// with children: then each half only creates nodes in its own subtrees, and no
// shared node is expanded or pruned. Cuts around the middle are tried in turn.
LabelOcTree::SharedPath LabelOcTree::findCut(const std::vector<VoxelUpdate>& updates, size_t& cut) const {
  const int depth_max = static_cast<int>(tree_depth);
  constexpr size_t kHitWeight = 8;
  // The work is estimated from every 16th update: this scan runs before the
  // halves start, on one thread.
  constexpr size_t kSampled = 16;
  size_t total = 0;
  for (size_t i = 0; i < updates.size(); i += kSampled) total += updates[i].hit ? kHitWeight : 1;
  size_t middle = 0;
  for (size_t sum = 0; middle < updates.size() && 2 * sum < total; middle += kSampled)
    sum += updates[middle].hit ? kHitWeight : 1;
  middle = std::min(middle, updates.size() - 1);
  const long step = static_cast<long>(std::max<size_t>(1, updates.size() / 64));
  SharedPath shared;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const long candidate = static_cast<long>(middle) + (attempt + 1) / 2 * step * (attempt % 2 ? 1 : -1);
    if (candidate <= 0 || candidate >= static_cast<long>(updates.size())) continue;
    cut = static_cast<size_t>(candidate);
    if (updates[cut].morton == updates[cut - 1].morton) continue;
    const int depth = sharedDepth(updates[cut].morton, updates[cut - 1].morton, depth_max);
    const LabelOcTreeNode* node = root;
    shared.path[0] = node;
    bool usable = nodeHasChildren(node);
    for (int d = 0; usable && d < depth; ++d) {
      const unsigned pos = octomap::computeChildIdx(updates[cut].key, depth_max - 1 - d);
      usable = nodeChildExists(node, pos) && nodeHasChildren(getNodeChild(node, pos));
      if (usable) node = getNodeChild(node, pos);
      shared.path[static_cast<size_t>(d + 1)] = node;
    }
    if (usable) {
      shared.depth = depth;
      return shared;
    }
  }
  return shared;
}

// A least-significant-digit radix sort over the bytes in which the codes
// differ, without the hard-to-predict comparisons of a comparison sort.
void sortByMorton(std::vector<VoxelUpdate>& updates, std::vector<VoxelUpdate>& spare) {
  if (updates.size() < 2) return;
  std::uint64_t differ = 0;
  for (const VoxelUpdate& u : updates) differ |= u.morton ^ updates[0].morton;
  spare.resize(updates.size());
  for (int shift = 0; shift < 64 && (differ >> shift) != 0; shift += 8) {
    if (((differ >> shift) & 0xff) == 0) continue;  // the same byte everywhere
    std::array<size_t, 256> start{};
    for (const VoxelUpdate& u : updates) ++start[(u.morton >> shift) & 0xff];
    size_t sum = 0;
    for (size_t& s : start) sum += std::exchange(s, sum);
    for (const VoxelUpdate& u : updates) spare[start[(u.morton >> shift) & 0xff]++] = u;
    updates.swap(spare);
  }
}

std::uint64_t LabelOcTree::saturatedFreeBlocks(const octomap::OcTreeKey& corner) const {
  constexpr int kBrickLevels = 4;  // a brick is the subtree of a node four levels above the leaves
  const int depth_max = static_cast<int>(tree_depth);
  const LabelOcTreeNode* node = root;
  for (int d = 0; node && d < depth_max - kBrickLevels; ++d) {
    if (isSaturatedFree(node, false)) return ~std::uint64_t{0};
    if (!nodeHasChildren(node)) return 0;
    const unsigned pos = octomap::computeChildIdx(corner, depth_max - 1 - d);
    node = nodeChildExists(node, pos) ? getNodeChild(node, pos) : nullptr;
  }
  if (!node) return 0;
  if (isSaturatedFree(node, false)) return ~std::uint64_t{0};
  if (!nodeHasChildren(node)) return 0;
  std::uint64_t blocks = 0;
  for (unsigned c = 0; c < 8; ++c) {
    if (!nodeChildExists(node, c)) continue;
    const LabelOcTreeNode* child = getNodeChild(node, c);
    if (isSaturatedFree(child, false)) {
      blocks |= std::uint64_t{0xff} << (8 * c);
      continue;
    }
    if (!nodeHasChildren(child)) continue;
    for (unsigned g = 0; g < 8; ++g)
      if (nodeChildExists(child, g) && isSaturatedFree(getNodeChild(child, g), false))
        blocks |= std::uint64_t{1} << (8 * c + g);
  }
  return blocks;
}

int LabelOcTree::applySortedUpdates(const std::vector<VoxelUpdate>& updates, int threads,
                                    const HitLabels* listed) {
  if (updates.empty()) return 1;
  long node_delta = 0;
  bool root_is_new = false;
  if (!root) {
    root = new LabelOcTreeNode();
    ++node_delta;
    root_is_new = true;
  }

  SharedPath shared;
  size_t cut = 0;
  constexpr size_t kMinimumForTwo = 2048;  // below this, starting a thread costs more than it saves
  if (threads > 1 && !root_is_new && updates.size() >= kMinimumForTwo) shared = findCut(updates, cut);

  if (shared.depth < 0) {
    node_delta += applyUpdateRange(updates.data(), updates.data() + updates.size(), root_is_new, shared, listed);
  } else {
    long deltas[2] = {0, 0};
    runParts(2, [&](int part) {
      deltas[part] = part == 0 ? applyUpdateRange(updates.data(), updates.data() + cut, false, shared, listed)
                               : applyUpdateRange(updates.data() + cut, updates.data() + updates.size(),
                                                  false, shared, listed);
    });
    node_delta += deltas[0] + deltas[1];
    // The shared nodes, bottom-up, now that both halves are done.
    for (int d = shared.depth; d >= 0; --d)
      finishNode(const_cast<LabelOcTreeNode*>(shared.path[static_cast<size_t>(d)]), node_delta);
  }
  addToNodeCount(node_delta);
  return shared.depth < 0 ? 1 : 2;
}

}  // namespace lom
