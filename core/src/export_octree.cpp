// Export that walks the label octree itself: voxels of each label in one
// pass, and plain OctoMap trees (ColorOcTree .ot, OcTree .bt) built node by
// node with the same structure (pruned leaves stay pruned).
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <fstream>
#include <type_traits>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"
#include "lom/height_colours.hpp"
#include "lom/octree/label_octree.hpp"

namespace lom {

std::map<int, std::vector<VoxelKey>> occupiedVoxelsByLabel(
    const LabelMap& map, const std::optional<std::set<int>>& only) {
  return map.voxelsByLabel(only);
}

namespace {

// Gives the copy access to the root, which OctoMap only creates on updates.
template <class Tree>
class TreeBuilder : public Tree {
 public:
  using Node = typename Tree::NodeType;
  explicit TreeBuilder(double resolution) : Tree(resolution) {}
  Node* makeRoot() {
    if (!this->root) {
      this->root = new Node();
      this->tree_size++;
      this->size_changed = true;
    }
    return this->root;
  }
};

template <class Tree>
class OctreeCopy {
 public:
  using Node = typename Tree::NodeType;

  OctreeCopy(const LabelMap& map, const OctreeExportOptions& options, TreeBuilder<Tree>& target)
      : map_(map),
        source_(map.tree()),
        options_(options),
        target_(target),
        // OctoMap's tools threshold at 0.5 (log-odds 0): shift the map's values so
        // that exactly the map's occupied voxels are occupied there (by the
        // tree's own float threshold: v - t >= 0 exactly when v >= t).
        shift_(-map.tree().getOccupancyThresLog()) {}

  // Returns the number of leaves copied.
  size_t run() {
    const LabelOcTreeNode* root = source_.getRoot();
    if (!root) return 0;
    Slot slot;
    if (!copy(root, slot)) return 0;
    target_.updateInnerOccupancy();
    return leaves_;
  }

 private:
  // A target node created only once something below it is kept, so that no
  // empty inner node is ever made.
  struct Slot {
    Slot* parent = nullptr;
    unsigned index = 0;
    Node* node = nullptr;
  };

  Node* ensure(Slot& slot) {
    if (!slot.node)
      slot.node = slot.parent ? target_.createNodeChild(ensure(*slot.parent), slot.index)
                              : target_.makeRoot();
    return slot.node;
  }

  // Copies the subtree of `from` into `slot`; false when nothing of it is kept.
  bool copy(const LabelOcTreeNode* from, Slot& slot) {
    if (!source_.nodeHasChildren(from)) {
      const bool occupied = source_.isNodeOccupied(from);
      const int label = from->argmaxLabel(map_.numLabels());
      if (occupied && options_.labels && !options_.labels->count(label)) return false;
      if (!occupied && !options_.include_free) return false;
      Node* to = ensure(slot);
      to->setLogOdds(from->getLogOdds() + shift_);
      if constexpr (std::is_same_v<Tree, octomap::ColorOcTree>) {
        if (occupied) {
          const Rgb c = shadedLabelColour(map_.labels(), label);  // as the meshes
          to->setColor(c[0], c[1], c[2]);
        }
      }
      ++leaves_;
      return true;
    }
    bool kept = false;
    for (unsigned i = 0; i < 8; ++i) {
      if (!source_.nodeChildExists(from, i)) continue;
      Slot child{&slot, i, nullptr};
      kept = copy(source_.getNodeChild(from, i), child) || kept;
    }
    return kept;
  }

  const LabelMap& map_;
  const LabelOcTree& source_;
  const OctreeExportOptions& options_;
  TreeBuilder<Tree>& target_;
  float shift_;
  size_t leaves_ = 0;
};

// Copies the map into a new `Tree` and writes it with `write(tree, stream)`.
// Returns the number of leaves written.
template <class Tree, class Write>
size_t writeOctree(const LabelMap& map, const std::filesystem::path& path,
                   const OctreeExportOptions& options, const char* what, Write write) {
  TreeBuilder<Tree> tree(map.parameters().resolution);
  const size_t leaves = OctreeCopy<Tree>(map, options, tree).run();
  if (leaves == 0)
    throw Error(path.string(), "map", "at least one voxel to export", "nothing selected");
  writeFileAtomically(path, [&](std::ostream& out) {
    if (!write(tree, out))
      throw Error(path.string(), "output", what, libraryWriteFailure(path, "OctoMap"));
  });
  // The leaves the file holds: writing a binary tree prunes it first.
  return tree.getNumLeafNodes();
}

}  // namespace

size_t writeColorOcTree(const LabelMap& map, const std::filesystem::path& path,
                        const OctreeExportOptions& options) {
  return writeOctree<octomap::ColorOcTree>(
      map, path, options, "a complete ColorOcTree",
      [](octomap::ColorOcTree& tree, std::ostream& out) { return tree.write(out); });
}

size_t writeBinaryOcTree(const LabelMap& map, const std::filesystem::path& path,
                         const OctreeExportOptions& options) {
  // writeBinary (not the const variant) first turns the tree into maximum likelihood and prunes it.
  return writeOctree<octomap::OcTree>(
      map, path, options, "a complete binary OcTree",
      [](octomap::OcTree& tree, std::ostream& out) { return tree.writeBinary(out); });
}

}  // namespace lom
