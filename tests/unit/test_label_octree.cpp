// The label octree as an OctoMap tree: storage, pruning, invariants, files.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <random>

#include <octomap/OcTree.h>

#include "lom/error.hpp"
#include "lom/label_map.hpp"
#include "lom/octree/label_octree.hpp"
#include "test_support.hpp"
#include "voxel_grid.hpp"

namespace {

using lom::LabelMap;
using lom::LabelOcTree;
using lom::LabelOcTreeNode;

lom::LabelSet labels(int n) {
  std::vector<lom::LabelInfo> list;
  for (int i = 0; i < n; ++i) list.push_back({i, "label" + std::to_string(i), lom::vocColor(i)});
  return lom::LabelSet(list);
}

octomap::OcTreeKey keyAt(const LabelOcTree& tree, double x, double y, double z) {
  return tree.coordToKey(octomap::point3d(static_cast<float>(x), static_cast<float>(y),
                                          static_cast<float>(z)));
}

// The eight 1 cm voxels that share one parent node.
std::vector<octomap::OcTreeKey> siblingKeys(const LabelOcTree& tree) {
  std::vector<octomap::OcTreeKey> keys;
  for (int i = 0; i < 8; ++i)
    keys.push_back(keyAt(tree, 0.005 + 0.01 * (i & 1), 0.005 + 0.01 * ((i >> 1) & 1),
                         0.005 + 0.01 * ((i >> 2) & 1)));
  return keys;
}

// A small map with occupied voxels of several labels and free space around them.
LabelMap sampleMap() {
  LabelMap map(labels(4));
  LabelOcTree& tree = map.tree();
  std::vector<octomap::OcTreeKey> touched;
  for (int i = 0; i < 20; ++i) {
    const float update[4] = {-1.f, i % 3 == 0 ? 2.f : -0.5f, i % 3 == 1 ? 1.5f : -2.f, 0.25f * i};
    const auto key = keyAt(tree, 0.01 * i, 0.02, 0.3);
    tree.applyHit(key, update);
    touched.push_back(key);
    for (int j = 0; j < 10; ++j) {
      const auto miss = keyAt(tree, 0.01 * i, 0.02, 0.01 * j);
      tree.applyMiss(miss);
      touched.push_back(miss);
    }
  }
  tree.refreshAncestors(touched);
  return map;
}

TEST(LabelOcTreeTest, MissedOnlyVoxelsStoreNoLabelArray) {
  LabelMap map(labels(40));
  LabelOcTree& tree = map.tree();
  const auto key = keyAt(tree, 0.1, 0.1, 0.1);
  tree.applyMiss(key);
  tree.refreshAncestors({key});
  const LabelOcTreeNode* node = tree.search(key);
  ASSERT_NE(node, nullptr);
  EXPECT_TRUE(node->isUniform());
  EXPECT_EQ(node->labelBytes(), 0u);
  EXPECT_EQ(tree.labelArrayBytes(), 0u);
  std::vector<float> hit(40, -3.f);
  hit[7] = 2.f;
  tree.applyHit(key, hit.data());
  EXPECT_FALSE(tree.search(key)->isUniform());
  EXPECT_EQ(tree.search(key)->argmaxLabel(40), 7);
}

TEST(LabelOcTreeTest, BecomesUniformAgainWhenAllLabelsClampToTheSameValue) {
  LabelMap map(labels(3));
  LabelOcTree& tree = map.tree();
  const auto key = keyAt(tree, 0.2, 0.2, 0.2);
  const float hit[3] = {-0.5f, 0.4f, -1.f};
  tree.applyHit(key, hit);
  EXPECT_FALSE(tree.search(key)->isUniform());
  for (int i = 0; i < 10; ++i) tree.applyMiss(key);
  EXPECT_TRUE(tree.search(key)->isUniform());
  EXPECT_FLOAT_EQ(tree.search(key)->getLogOdds(), tree.clampMinLogOdds());
}

TEST(LabelOcTreeTest, InnerNodesCarryTheMaximumOfTheirChildrenAndItsLabel) {
  LabelMap map(labels(3));
  LabelOcTree& tree = map.tree();
  const auto a = keyAt(tree, 0.005, 0.005, 0.005);
  const auto b = keyAt(tree, 0.015, 0.005, 0.005);  // sibling of a
  const float hit_a[3] = {1.f, -1.f, 0.5f};
  const float hit_b[3] = {-1.f, 2.f, 0.25f};
  tree.applyHit(a, hit_a);
  tree.applyHit(b, hit_b);
  tree.refreshAncestors({a, b});
  const LabelOcTreeNode* parent = tree.search(a, tree.getTreeDepth() - 1);
  ASSERT_NE(parent, nullptr);
  EXPECT_TRUE(parent->isSummary());
  EXPECT_FLOAT_EQ(parent->getLogOdds(), 2.f);
  EXPECT_EQ(parent->argmaxLabel(3), 1);
  EXPECT_FLOAT_EQ(tree.getRoot()->getLogOdds(), 2.f);
  EXPECT_EQ(tree.getRoot()->argmaxLabel(3), 1);
  // Coarse-depth iteration reports the occupied label.
  size_t coarse = 0;
  for (auto it = tree.begin_leafs(tree.getTreeDepth() - 2); it != tree.end_leafs(); ++it) {
    ++coarse;
    EXPECT_TRUE(tree.isNodeOccupied(*it));
    EXPECT_EQ(it->argmaxLabel(3), 1);
  }
  EXPECT_EQ(coarse, 1u);
}

TEST(LabelOcTreeTest, InnerNodesBreakTiesBetweenChildrenByTheLowerLabel) {
  LabelMap map(labels(3));
  LabelOcTree& tree = map.tree();
  const auto a = keyAt(tree, 0.005, 0.005, 0.005);  // child 0 of its parent
  const auto b = keyAt(tree, 0.015, 0.005, 0.005);  // child 1
  const auto c = keyAt(tree, 0.005, 0.015, 0.005);  // child 2
  const float hit_a[3] = {-1.f, -1.f, 1.5f};        // maximum 1.5, label 2
  const float hit_b[3] = {-1.f, 1.5f, -1.f};        // the same maximum, label 1
  const float hit_c[3] = {0.5f, -1.f, -1.f};        // a lower maximum, label 0
  tree.applyHit(a, hit_a);
  tree.applyHit(b, hit_b);
  tree.applyHit(c, hit_c);
  tree.refreshAncestors({a, b, c});
  const LabelOcTreeNode* parent = tree.search(a, tree.getTreeDepth() - 1);
  ASSERT_NE(parent, nullptr);
  EXPECT_FLOAT_EQ(parent->getLogOdds(), 1.5f);
  EXPECT_EQ(parent->argmaxLabel(3), 1);  // the lower of the two tied labels; not the lower-valued 0
}

TEST(LabelOcTreeTest, LeafBlocksKeepOnlyLabelsAboveTheSmallest) {
  LabelMap map(labels(40));
  LabelOcTree& tree = map.tree();
  const auto key = keyAt(tree, 0.3, 0.3, 0.3);
  std::vector<float> hit(40, -20.f);  // clamps to the lower bound
  hit[4] = 1.f;
  hit[30] = 0.5f;
  tree.applyHit(key, hit.data());
  const LabelOcTreeNode* node = tree.search(key);
  // Two listed labels instead of forty values.
  EXPECT_LT(node->labelBytes(), 40 * sizeof(float) / 4);
  std::vector<float> values(40);
  node->labelLogOdds(40, values.data());
  EXPECT_FLOAT_EQ(values[4], 1.f);
  EXPECT_FLOAT_EQ(values[30], 0.5f);
  EXPECT_FLOAT_EQ(values[0], tree.clampMinLogOdds());
  EXPECT_FLOAT_EQ(node->labelLogOdds(39), tree.clampMinLogOdds());
  EXPECT_EQ(node->argmaxLabel(40), 4);
}

// A hit that lists a few labels and gives every other label one value must
// leave the node exactly as the same update written out for every label:
// same values to the bit, same block (so operator== holds), from uniform
// leaves and from leaves with blocks, with labels listed by both, by one or
// by neither, clamped at either end, and when the other labels do not end up
// the smallest.
TEST(LabelOcTreeTest, ListedHitsGiveTheSameNodeAsHitsWrittenOut) {
  std::mt19937 random(17);
  std::uniform_real_distribution<float> log_odds(-3.f, 4.f);
  const float lo = -2.f, hi = 3.5f;
  for (const int n : {1, 2, 5, 40}) {
    std::uniform_int_distribution<int> label(0, n - 1);
    for (int trial = 0; trial < 2000; ++trial) {
      LabelOcTreeNode dense, listed;
      // A starting node: uniform, or the result of one or two written-out hits.
      const int earlier = trial % 3;
      for (int h = 0; h < earlier; ++h) {
        std::vector<float> update(static_cast<size_t>(n), trial % 2 ? -30.f : log_odds(random));
        for (int k = 0; k < 1 + trial % 4; ++k) update[static_cast<size_t>(label(random))] = log_odds(random);
        dense.addLabelLogOdds(n, update.data(), lo, hi);
        listed.addLabelLogOdds(n, update.data(), lo, hi);
      }
      if (earlier == 0) {
        dense.setUniformLogOdds(log_odds(random));
        listed.setUniformLogOdds(dense.getLogOdds());
      }
      ASSERT_TRUE(dense == listed);
      // The listed update: distinct labels, ascending.
      std::vector<std::uint8_t> ids;
      for (int k = 0; k < n; ++k)
        if (std::uniform_int_distribution<int>(0, 3)(random) == 0) ids.push_back(static_cast<std::uint8_t>(k));
      std::vector<float> values;
      for (size_t i = 0; i < ids.size(); ++i) values.push_back(log_odds(random));
      // Mostly far below (the log-odds of labels without a channel), sometimes above the listed values.
      const float rest = trial % 5 == 0 ? 2.f : -30.f + log_odds(random);
      std::vector<float> update(static_cast<size_t>(n), rest);
      for (size_t i = 0; i < ids.size(); ++i) update[ids[i]] = values[i];
      dense.addLabelLogOdds(n, update.data(), lo, hi);
      listed.addListedLogOdds(n, static_cast<int>(ids.size()), ids.data(), values.data(), rest, lo, hi);
      ASSERT_TRUE(dense == listed) << "n " << n << ", trial " << trial;
      EXPECT_EQ(dense.isUniform(), listed.isUniform());
      EXPECT_EQ(dense.labelBytes(), listed.labelBytes());
      for (int k = 0; k < n; ++k) ASSERT_EQ(dense.labelLogOdds(k), listed.labelLogOdds(k)) << "label " << k;
    }
  }
}

TEST(LabelOcTreeTest, MergesSaturatedFreeSpaceWhileFusing) {
  LabelMap map(labels(3));
  LabelOcTree& tree = map.tree();
  const std::vector<octomap::OcTreeKey> keys = siblingKeys(tree);
  // One miss each: identical, but a later miss would change them, so they stay apart.
  for (const auto& key : keys) tree.applyMiss(key);
  tree.refreshAncestors(keys);
  EXPECT_EQ(tree.getNumLeafNodes(), 8u);
  // At the lower clamp (3 x logit(0.3) < logit(0.12)) they merge into their parent.
  for (int frame = 0; frame < 2; ++frame) {
    for (const auto& key : keys) tree.applyMiss(key);
    tree.refreshAncestors(keys);
  }
  EXPECT_EQ(tree.size(), tree.calcNumNodes());
  EXPECT_EQ(tree.getNumLeafNodes(), 1u);
  EXPECT_FLOAT_EQ(tree.search(keys[3])->getLogOdds(), tree.clampMinLogOdds());
  // Further misses leave the merged node alone.
  tree.applyMiss(keys[5]);
  EXPECT_EQ(tree.getNumLeafNodes(), 1u);
  // A hit expands it again with the other seven unchanged.
  const float hit[3] = {0.f, 1.f, 0.f};
  tree.applyHit(keys[3], hit);
  tree.refreshAncestors({keys[3]});
  EXPECT_EQ(tree.getNumLeafNodes(), 8u);
  EXPECT_FLOAT_EQ(tree.search(keys[0])->getLogOdds(), tree.clampMinLogOdds());
  EXPECT_EQ(tree.search(keys[3])->argmaxLabel(3), 1);
  EXPECT_EQ(tree.size(), tree.calcNumNodes());
}

TEST(LabelOcTreeTest, PruneMergesEveryIdenticalSetAndNothingElse) {
  LabelMap map(labels(3));
  LabelOcTree& tree = map.tree();
  const std::vector<octomap::OcTreeKey> keys = siblingKeys(tree);
  for (const auto& key : keys) tree.applyMiss(key);
  tree.refreshAncestors(keys);
  map.prune();
  EXPECT_EQ(tree.getNumLeafNodes(), 1u);
  EXPECT_FLOAT_EQ(tree.search(keys[6])->getLogOdds(), tree.missLogOdds());
  // Siblings that differ in one label are not merged.
  const float hit[3] = {0.f, 0.5f, 0.f};
  tree.applyHit(keys[2], hit);
  tree.refreshAncestors({keys[2]});
  map.prune();
  EXPECT_EQ(tree.getNumLeafNodes(), 8u);
  EXPECT_EQ(tree.size(), tree.calcNumNodes());
}

TEST(LabelOcTreeTest, SizeMatchesNodeCountAfterPruning) {
  LabelMap map = sampleMap();
  map.prune();
  EXPECT_EQ(map.tree().size(), map.tree().calcNumNodes());
  EXPECT_GT(map.numLeaves(), 0u);
}

void expectSameTrees(const LabelMap& a, const LabelMap& b) {
  ASSERT_EQ(a.numNodes(), b.numNodes());
  EXPECT_EQ(a.labels(), b.labels());
  EXPECT_EQ(a.parameters().resolution, b.parameters().resolution);
  EXPECT_EQ(a.parameters().p_miss, b.parameters().p_miss);
  EXPECT_EQ(a.parameters().max_range, b.parameters().max_range);
  auto ia = a.tree().begin_tree(), ib = b.tree().begin_tree();
  for (; ia != a.tree().end_tree(); ++ia, ++ib) {
    ASSERT_TRUE(ib != b.tree().end_tree());
    EXPECT_EQ(ia.getKey(), ib.getKey());
    EXPECT_EQ(ia.getDepth(), ib.getDepth());
    EXPECT_TRUE(*ia == *ib);
  }
}

TEST(LabelOcTreeTest, SaveAndLoadGiveTheSameMap) {
  lom::test::TempDir dir;
  LabelMap map = sampleMap();
  map.save(dir / "map.ot");
  const LabelMap loaded = LabelMap::load(dir / "map.ot");
  expectSameTrees(map, loaded);
  EXPECT_EQ(loaded.occupiedCountPerLabel(), map.occupiedCountPerLabel());
}

TEST(LabelOcTreeTest, OctomapsFactoryReadsTheFile) {
  lom::test::TempDir dir;
  LabelMap map = sampleMap();
  map.save(dir / "map.ot");
  std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read((dir / "map.ot").string()));
  ASSERT_NE(tree, nullptr);
  auto* label_tree = dynamic_cast<LabelOcTree*>(tree.get());
  ASSERT_NE(label_tree, nullptr);
  EXPECT_EQ(label_tree->numLabels(), 4);
  EXPECT_EQ(label_tree->size(), map.numNodes());
}

TEST(LabelOcTreeTest, AnEmptyMapRoundTripsWithItsLabels) {
  lom::test::TempDir dir;
  LabelMap map(labels(5));
  map.save(dir / "empty.ot");
  const LabelMap loaded = LabelMap::load(dir / "empty.ot");
  EXPECT_EQ(loaded.numNodes(), 0u);
  EXPECT_EQ(loaded.labels(), map.labels());
  EXPECT_FALSE(loaded.bounds().has_value());
}

TEST(LabelOcTreeTest, LoadingAnotherTreeTypeNamesTheType) {
  lom::test::TempDir dir;
  octomap::OcTree plain(0.05);
  plain.updateNode(octomap::point3d(0.1f, 0.1f, 0.1f), true);
  ASSERT_TRUE(plain.write((dir / "plain.ot").string()));
  try {
    (void)LabelMap::load(dir / "plain.ot");
    FAIL() << "expected an error";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "id");
    EXPECT_NE(std::string(e.what()).find("OcTree"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("plain.ot"), std::string::npos);
  }
}

TEST(LabelOcTreeTest, LoadingATruncatedOrForeignFileFails) {
  lom::test::TempDir dir;
  sampleMap().save(dir / "map.ot");
  const auto full = std::filesystem::file_size(dir / "map.ot");
  std::filesystem::copy_file(dir / "map.ot", dir / "cut.ot");
  std::filesystem::resize_file(dir / "cut.ot", full - 40);
  EXPECT_THROW((void)LabelMap::load(dir / "cut.ot"), lom::Error);
  std::ofstream(dir / "text.ot") << "hello\n";
  EXPECT_THROW((void)LabelMap::load(dir / "text.ot"), lom::Error);
  EXPECT_THROW((void)LabelMap::load(dir / "missing.ot"), lom::Error);
}

TEST(LabelOcTreeTest, SavingToAnUnwritablePlaceFailsWithoutLeavingFiles) {
  lom::test::TempDir dir;
  EXPECT_THROW(sampleMap().save(dir / "no-such-folder" / "map.ot"), lom::Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(LabelOcTreeTest, VoxelsOfLabelExpandPrunedLeaves) {
  LabelMap map(labels(2));
  LabelOcTree& tree = map.tree();
  const std::vector<octomap::OcTreeKey> keys = siblingKeys(tree);
  const float hit[2] = {-1.f, 1.f};
  for (const auto& key : keys) tree.applyHit(key, hit);
  tree.refreshAncestors(keys);
  map.prune();
  EXPECT_EQ(tree.getNumLeafNodes(), 1u);  // pruned
  EXPECT_EQ(map.voxelsOfLabel(1).size(), 8u);
  EXPECT_EQ(map.occupiedCountPerLabel().at(1), 8u);
  size_t visited = 0;
  map.forEachOccupied([&](const lom::OccupiedVoxel& v) {
    ++visited;
    EXPECT_NEAR(v.size, 0.02, 1e-9);
    EXPECT_EQ(v.label, 1);
  });
  EXPECT_EQ(visited, 1u);
}

// Frames of sorted updates over a 48^3 block: hits of mixed labels on a
// changing surface, misses in front of it (repeated, so free space saturates
// and is merged), and some misses on voxels that were hit before.
std::vector<std::vector<lom::VoxelUpdate>> randomFrames(const LabelOcTree& tree, int num_labels,
                                                        std::vector<float>& hit_values) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(-3.f, 3.f);
  const octomap::OcTreeKey corner = keyAt(tree, -0.2, -0.2, 0.1);
  std::vector<std::vector<std::pair<octomap::OcTreeKey, size_t>>> frames(6);  // key, hit index + 1
  for (auto& frame : frames) {
    const int surface = 30 + static_cast<int>(rng() % 6);
    for (int x = 0; x < 48; ++x)
      for (int y = 0; y < 48; ++y)
        for (int z = 0; z <= surface; ++z) {
          const octomap::OcTreeKey key(static_cast<std::uint16_t>(corner[0] + x),
                                       static_cast<std::uint16_t>(corner[1] + y),
                                       static_cast<std::uint16_t>(corner[2] + z));
          if (z < surface) {
            if (rng() % 4 != 0) frame.emplace_back(key, 0);  // most of the free space, each frame
          } else {
            for (int k = 0; k < num_labels; ++k) hit_values.push_back(value(rng));
            frame.emplace_back(key, hit_values.size() / static_cast<size_t>(num_labels));
          }
        }
  }
  std::vector<std::vector<lom::VoxelUpdate>> out;
  for (const auto& frame : frames) {
    std::vector<lom::VoxelUpdate> updates;
    for (const auto& [key, hit] : frame) {
      lom::VoxelUpdate u;
      u.key = key;
      u.morton = lom::grid::mortonCode(key[0], key[1], key[2]);
      u.hit = hit ? hit_values.data() + (hit - 1) * static_cast<size_t>(num_labels) : nullptr;
      updates.push_back(u);
    }
    std::sort(updates.begin(), updates.end(),
              [](const lom::VoxelUpdate& a, const lom::VoxelUpdate& b) { return a.morton < b.morton; });
    out.push_back(std::move(updates));
  }
  return out;
}

TEST(LabelOcTreeTest, TwoPartPassBuildsTheSameTreeAsOne) {
  const int n = 5;
  LabelMap one(labels(n)), two(labels(n));
  std::vector<float> hit_values;
  hit_values.reserve(1 << 20);  // pointers into it must stay valid
  const auto frames = randomFrames(one.tree(), n, hit_values);
  int split_frames = 0;
  for (const auto& updates : frames) {
    EXPECT_EQ(one.tree().applySortedUpdates(updates, 1), 1);
    split_frames += two.tree().applySortedUpdates(updates, 2) == 2 ? 1 : 0;
    expectSameTrees(one, two);
    EXPECT_EQ(two.tree().size(), two.tree().calcNumNodes());
  }
  // The first frame builds the tree on one thread; the later ones are split.
  EXPECT_EQ(split_frames, static_cast<int>(frames.size()) - 1);
  EXPECT_GT(one.numLeaves(), 1000u);
  one.prune();
  two.prune();
  expectSameTrees(one, two);
}

TEST(LabelOcTreeTest, SortByMortonGivesTheOrderOfAStableSort) {
  std::mt19937 rng(11);
  std::vector<float> tags(64);  // distinct addresses tell equal codes apart
  std::vector<lom::VoxelUpdate> spare;
  for (int round = 0; round < 60; ++round) {
    // Keys in a small box across the middle of the key range (codes that
    // differ in their high bytes too), anywhere, and in a box so small that
    // codes repeat (the order of equal codes must be kept).
    const int kind = round % 3;
    const int size = kind == 0 ? 64 : kind == 1 ? 65536 : 3;
    const int low = kind == 1 ? 0 : 32768 - size / 2;
    std::uniform_int_distribution<int> coordinate(low, low + size - 1);
    std::vector<lom::VoxelUpdate> updates(static_cast<size_t>(round * 37));
    for (auto& u : updates) {
      const auto x = static_cast<std::uint16_t>(coordinate(rng));
      const auto y = static_cast<std::uint16_t>(coordinate(rng));
      const auto z = static_cast<std::uint16_t>(coordinate(rng));
      u.key = octomap::OcTreeKey(x, y, z);
      u.morton = lom::grid::mortonCode(x, y, z);
      u.hit = &tags[static_cast<size_t>(rng() % tags.size())];
    }
    std::vector<lom::VoxelUpdate> expected = updates;
    std::stable_sort(expected.begin(), expected.end(),
                     [](const lom::VoxelUpdate& a, const lom::VoxelUpdate& b) { return a.morton < b.morton; });
    lom::sortByMorton(updates, spare);
    ASSERT_EQ(updates.size(), expected.size());
    for (size_t i = 0; i < updates.size(); ++i) {
      ASSERT_EQ(updates[i].morton, expected[i].morton) << "round " << round << ", position " << i;
      ASSERT_EQ(updates[i].key, expected[i].key);
      ASSERT_EQ(updates[i].hit, expected[i].hit) << "round " << round << ": equal codes reordered";
    }
  }
}

}  // namespace
