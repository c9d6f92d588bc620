#pragma once
// The multilabel octree, built on OctoMap the way OctoMap extends itself
// (compare octomap::ColorOcTree). This header pulls in OctoMap's templates:
// include it only from the few .cpp files that work on the tree directly;
// everything else goes through lom::LabelMap.
#include <cstdint>
#include <iosfwd>
#include <vector>

#include <octomap/OcTreeNode.h>
#include <octomap/OccupancyOcTreeBase.h>

#include "lom/label_map.hpp"
#include "lom/labels.hpp"

namespace lom {

// One log-odds value per label, stored compactly because most voxels are
// free space that only ever got misses:
// - a leaf whose labels are all equal stores nothing extra: its OctoMap value
//   is the common log-odds (every missed-only voxel, and new nodes);
// - any other leaf owns a sparse block: the smallest label value ("base",
//   usually the lower clamp, where labels with no evidence end up) and the
//   labels above it with their values;
// - an inner node keeps OctoMap's conservative value (the maximum over its
//   children, which is also the maximum over labels) and the label of that
//   maximum, so coarse-depth iteration sees occupancy and label.
// The leaf value is always max_k L_k, so OctoMap's own occupancy test
// (value >= logit(threshold)) is exactly the paper's rule max_k p_k >= threshold.
// The representation is canonical, so operator== and pruning compare like for like.
class LabelOcTreeNode : public octomap::OcTreeNode {
 public:
  friend class LabelOcTree;

  LabelOcTreeNode() = default;
  // Copies the data only; children are copied by the tree.
  LabelOcTreeNode(const LabelOcTreeNode& rhs);
  LabelOcTreeNode& operator=(const LabelOcTreeNode&) = delete;
  ~LabelOcTreeNode();

  bool operator==(const LabelOcTreeNode& rhs) const;
  void copyData(const LabelOcTreeNode& from);

  // True for leaves whose labels are all equal (no label block).
  [[nodiscard]] bool isUniform() const { return data_ == 0; }
  [[nodiscard]] bool isSummary() const { return (data_ & 1u) != 0; }  // inner-node form
  // Log-odds of label k (k < the tree's number of labels). Inner nodes only
  // know their maximum: every label reads as that maximum.
  [[nodiscard]] float labelLogOdds(int k) const;
  void labelLogOdds(int num_labels, float* out) const;
  // Argmax label, ties to the lower id (for inner nodes: the label of the maximum).
  [[nodiscard]] int argmaxLabel(int num_labels) const;

  // Sets all labels (canonicalises: an all-equal vector frees the block).
  void setLabelLogOdds(int num_labels, const float* values);
  void setUniformLogOdds(float log_odds);
  // Adds `update` per label and clamps each to [lo, hi].
  void addLabelLogOdds(int num_labels, const float* update, float lo, float hi);
  // Adds the same update to every label and clamps.
  void addUniformLogOdds(float update, float lo, float hi);
  // Adds values[i] to label ids[i] (`count` ids, ascending) and `rest` to
  // every other label, clamping each to [lo, hi]: the same values as
  // addLabelLogOdds with that update written out, without writing it out.
  void addListedLogOdds(int num_labels, int count, const std::uint8_t* ids, const float* values, float rest,
                        float lo, float hi);

  // Inner nodes: the maximum over the existing children and its label.
  void updateOccupancyChildren();

  // Self-describing: value, a kind byte, then the block or the summary label.
  std::istream& readData(std::istream& s);
  std::ostream& writeData(std::ostream& s) const;

  [[nodiscard]] size_t labelBytes() const;

 private:
  // Structure changes as OctoMap's createNodeChild / expandNode / pruneNode
  // make them, but without the tree's shared node count, so that threads can
  // change disjoint subtrees at once (LabelOcTree::applySortedUpdates counts
  // the nodes per thread and adds them up afterwards).
  LabelOcTreeNode* addChild(unsigned pos);  // allocates the child array when needed
  void expandChildren();                    // eight children with this node's data
  void collapseChildren();                  // takes child 0's data, deletes the eight leaves

  struct SparseLabels;
  // Stores `count` labels (ids ascending) of which those above `low` are kept
  // in the block and the others read as `low`; `high` is the largest value.
  void storeLabels(int num_labels, float low, float high, const std::uint8_t* ids, const float* values,
                   unsigned count);
  [[nodiscard]] const SparseLabels* block() const {
    return (data_ != 0 && !isSummary()) ? reinterpret_cast<const SparseLabels*>(data_) : nullptr;
  }
  void release();
  // Either 0 (uniform leaf), a pointer to a SparseLabels block (even), or
  // (label << 1) | 1 for an inner node's summary.
  std::uintptr_t data_ = 0;
};

// One voxel's update in a frame, for LabelOcTree::applySortedUpdates.
struct VoxelUpdate {
  std::uint64_t morton = 0;     // grid::mortonCode of the key: depth-first order of the tree
  octomap::OcTreeKey key;
  // A hit's summed log-odds (nullptr for a miss): one per label, or with
  // HitLabels one per listed label and then the one every other label gets.
  const float* hit = nullptr;
};

// Sorts updates by Morton code, keeping the order of equal codes (`spare` is
// scratch memory, kept by the caller from one call to the next).
void sortByMorton(std::vector<VoxelUpdate>& updates, std::vector<VoxelUpdate>& spare);

// The labels a frame's hits list (ascending): a frame whose probability
// images have a few channels gives every other label the same log-odds.
struct HitLabels {
  int count = 0;
  std::uint8_t ids[256] = {};
};

class LabelOcTree : public octomap::OccupancyOcTreeBase<LabelOcTreeNode> {
 public:
  explicit LabelOcTree(double resolution);
  LabelOcTree(const LabelSet& labels, const MapParameters& parameters);
  LabelOcTree(const LabelOcTree&) = delete;
  LabelOcTree& operator=(const LabelOcTree&) = delete;

  [[nodiscard]] LabelOcTree* create() const override;
  [[nodiscard]] std::string getTreeType() const override { return "LabelOcTree"; }

  [[nodiscard]] int numLabels() const { return labels_.size(); }
  [[nodiscard]] const LabelSet& labels() const { return labels_; }
  [[nodiscard]] const MapParameters& parameters() const { return parameters_; }
  void setOccupancyThreshold(double threshold);
  void setIntegrationParameters(double p_miss, double max_range);
  // The fused views' cameras (LabelMap::noteCameraView); written with the
  // map (data version 2).
  [[nodiscard]] const CameraViewRecord& cameraViews() const { return camera_views_; }
  void setCameraViews(const CameraViewRecord& record) { camera_views_ = record; }
  // The fused frames' class candidates (LabelMap::noteFusedCandidates);
  // written with the map (data version 3).
  [[nodiscard]] const FusedCandidates& fusedCandidates() const { return fused_candidates_; }
  void setFusedCandidates(const FusedCandidates& record) { fused_candidates_ = record; }
  [[nodiscard]] const FusedEvidence& fusedEvidence() const { return fused_evidence_; }
  void setFusedEvidence(const FusedEvidence& record) { fused_evidence_ = record; }
  // The fused poses' world frame (LabelMap::noteWorldFrame); data version 5.
  [[nodiscard]] const WorldFrameRecord& worldFrame() const { return world_frame_; }
  void setWorldFrame(const WorldFrameRecord& record) { world_frame_ = record; }

  // Whether a miss of `key` (applyMiss) adds no node: the finest-depth node
  // of `key` exists, or a node on its path is saturated free space, which a
  // miss leaves as it is (often a merged leaf). A voxel inside a merged leaf
  // that is not saturated free does not: the miss splits that leaf.
  [[nodiscard]] bool missAddsNoNode(const octomap::OcTreeKey& key) const {
    const LabelOcTreeNode* node = root;
    if (node == nullptr) return false;
    for (int depth = static_cast<int>(tree_depth) - 1; depth >= 0; --depth) {
      if (isSaturatedFree(node, false)) return true;
      const unsigned pos = octomap::computeChildIdx(key, depth);
      if (!nodeChildExists(node, pos)) return false;
      node = getNodeChild(node, pos);
    }
    return true;
  }

  // Finest-depth leaf for `key`, created (and pruned ancestors expanded) when
  // needed. Inner nodes are not refreshed: call refreshAncestors afterwards.
  LabelOcTreeNode* touchLeaf(const octomap::OcTreeKey& key);
  // Hit: adds per-label log-odds, clamped. Miss: adds logit(p_miss) to every label, clamped.
  void applyHit(const octomap::OcTreeKey& key, const float* log_odds);
  void applyMiss(const octomap::OcTreeKey& key);
  // Brings the ancestors of the given finest-depth keys up to date, bottom-up,
  // merging eight identical children of saturated free space (see pruneSaturated).
  void refreshAncestors(std::vector<octomap::OcTreeKey> keys);
  // Applies updates sorted by Morton code (one per key) in a single depth-first
  // pass: the path from the root is reused between consecutive keys, and each
  // inner node is refreshed (or pruned, see pruneSaturated) once, when its
  // subtree is finished. Misses on saturated free space are skipped.
  // With threads > 1 the stream is cut in two at its middle and the halves run
  // at once when the nodes the halves share (the path from the root to where
  // the two keys at the cut part) already exist as inner nodes; those nodes
  // are refreshed after both halves are done. Same tree as one thread.
  // With `listed`, every hit holds the listed labels' log-odds and then the
  // one every other label gets (LabelOcTreeNode::addListedLogOdds); without
  // it, one per label. Returns how many parts ran at once (1 or 2).
  int applySortedUpdates(const std::vector<VoxelUpdate>& updates, int threads = 1,
                         const HitLabels* listed = nullptr);

  // Which 4 x 4 x 4 blocks of the 16 x 16 x 16 brick whose first key is
  // `corner` (low four bits of each component zero) are saturated free space,
  // a miss on any of their voxels changing nothing: bit 8c + g for the
  // block at child g of the brick's child c (the blocks' depth-first order).
  // Reads the tree only, so threads may call it at once.
  [[nodiscard]] std::uint64_t saturatedFreeBlocks(const octomap::OcTreeKey& corner) const;

  [[nodiscard]] float missLogOdds() const { return prob_miss_log; }
  [[nodiscard]] float clampMinLogOdds() const { return clamping_thres_min; }
  [[nodiscard]] float clampMaxLogOdds() const { return clamping_thres_max; }
  [[nodiscard]] size_t labelArrayBytes() const;

  // The file carries the label set and the parameters before OctoMap's node stream.
  // readData (OctoMap's interface) reports any problem as a failed stream.
  std::istream& readData(std::istream& s) override;
  std::ostream& writeData(std::ostream& s) const override;
  // Reads what writeData writes into this (empty) tree. Throws lom::Error
  // naming the field for an unknown data version, a label count out of range
  // or disagreeing with the nodes, parameters out of range
  // (checkMapParameters) and truncated or corrupt node data.
  void readLabelledData(std::istream& s);

 private:
  void applyParameters();
  void applyOccupancyThreshold();
  // One node and its subtree, at most down to the finest depth (no recursion
  // deeper than the tree's 16 levels, whatever the file says).
  void readNodes(LabelOcTreeNode* node, unsigned depth, std::istream& s);
  // The child at `pos` for an update, created when missing. `created` says
  // whether `node` itself was created by this descent (then its children start
  // unknown; otherwise a childless node is a pruned leaf and is expanded).
  LabelOcTreeNode* childForUpdate(LabelOcTreeNode* node, unsigned pos, bool& created);
  // The same, counting created nodes in `node_delta` instead of tree_size.
  // An existing child (almost every step of the fast path's tree pass) is
  // found here, inline; the pass's file cannot inline across files.
  LabelOcTreeNode* childForUpdate(LabelOcTreeNode* node, unsigned pos, bool& created,
                                  long& node_delta) const {
    if (nodeChildExists(node, pos)) {
      created = false;
      return getNodeChild(node, pos);
    }
    return missingChildForUpdate(node, pos, created, node_delta);
  }
  // childForUpdate when the child does not exist: a pruned leaf is expanded,
  // else the child is created.
  LabelOcTreeNode* missingChildForUpdate(LabelOcTreeNode* node, unsigned pos, bool& created,
                                         long& node_delta) const;
  // One part of applySortedUpdates: updates [first, last) from the root. Nodes
  // listed in `shared` (by depth, up to shared_depth) are left unfinished.
  struct SharedPath;
  long applyUpdateRange(const VoxelUpdate* first, const VoxelUpdate* last, bool root_is_new,
                        const SharedPath& shared, const HitLabels* listed);
  // Where applySortedUpdates cuts the stream, and the nodes both halves share
  // (depth -1 when no usable cut was found).
  SharedPath findCut(const std::vector<VoxelUpdate>& updates, size_t& cut) const;
  // A node whose subtree got its last update: pruned when saturated free space, else refreshed.
  void finishNode(LabelOcTreeNode* node, long& node_delta) const;
  // Adds nodes counted apart (negative: removed) to OctoMap's node count.
  void addToNodeCount(long node_delta);
  // While fusing, only children that are identical free space at the lower
  // clamp are merged: no later miss can change them, so they are never
  // expanded again (merging anything identical would make the next frame's
  // misses expand it again). LabelMap::prune merges every identical set.
  // Removed nodes are counted in `node_delta`.
  bool pruneSaturated(LabelOcTreeNode* node, long& node_delta) const;
  // A leaf (possibly pruned) of free space at the lower clamp, which a miss cannot change.
  [[nodiscard]] bool isSaturatedFree(const LabelOcTreeNode* node, bool created) const {
    return !created && !nodeHasChildren(node) && node->isUniform() && node->getLogOdds() <= clamping_thres_min;
  }

  LabelSet labels_;
  MapParameters parameters_;
  CameraViewRecord camera_views_;
  FusedCandidates fused_candidates_;
  FusedEvidence fused_evidence_;
  WorldFrameRecord world_frame_;

  // Registers the tree type with OctoMap's factory so AbstractOcTree::read works.
  class StaticMemberInitializer {
   public:
    StaticMemberInitializer();
    void ensureLinking() {}
  };
  static StaticMemberInitializer label_octree_member_init_;
};

// Log-odds helpers shared by the engine.
[[nodiscard]] float logit(double p);
[[nodiscard]] double probabilityFromLogOdds(double log_odds);

}  // namespace lom
