// Objects of a labelled map: clusters, boxes, centroids (docs/planning.md, "Objects").
#include "lom/objects.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <set>
#include <utility>

#include "lom/box_fit.hpp"
#include "lom/error.hpp"
#include "lom/octree/label_octree.hpp"

namespace lom {

namespace {

std::string fieldList(const std::vector<int>& values) {
  std::string out;
  for (size_t i = 0; i < values.size(); ++i) out += (i ? "," : "") + std::to_string(values[i]);
  return out;
}

void checkObjectOptions(const LabelMap& map, const ObjectOptions& options) {
  if (!(options.cluster_tolerance_voxels > 0.0 &&
        options.cluster_tolerance_voxels <= kMaxClusterTolerance))
    throw Error(options.map_file, "cluster_tolerance_voxels",
                "a number of voxel edges above 0 and at most " +
                    std::to_string(static_cast<int>(kMaxClusterTolerance)),
                std::to_string(options.cluster_tolerance_voxels));
  if (options.min_cluster_voxels < 1)
    throw Error(options.map_file, "min_cluster_voxels", "at least 1", "0");
  if (options.labels) {
    for (int id : *options.labels)
      if (!map.labels().contains(id))
        throw Error(options.map_file, "candidates",
                    "label ids of the map (0.." + std::to_string(map.numLabels() - 1) + ")",
                    std::to_string(id) + " in " + fieldList(*options.labels));
  }
}

// A finest-resolution voxel of one label with that label's probability.
struct LabelledKey {
  VoxelKey key;
  float probability = 0.f;
};

// One pass over the leaves: the occupied voxels of every wanted label (pruned leaves expanded).
std::map<int, std::vector<LabelledKey>> occupiedByLabel(const LabelMap& map,
                                                        const std::vector<bool>& wanted,
                                                        const std::string& map_file) {
  std::set<int> labels;
  for (size_t id = 0; id < wanted.size(); ++id)
    if (wanted[id]) labels.insert(static_cast<int>(id));
  try {
    (void)map.expandableOccupiedVoxels(labels);
  } catch (const Error& e) {
    Problem problem = e.problem();
    if (problem.file.empty()) problem.file = map_file;
    throw Error(problem);
  }
  std::map<int, std::vector<LabelledKey>> by_label;
  const LabelOcTree& tree = map.tree();
  const int n = map.numLabels();
  const unsigned max_depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const int label = it->argmaxLabel(n);
    if (label < 0 || label >= n || !wanted[static_cast<size_t>(label)]) continue;
    const auto probability = static_cast<float>(probabilityFromLogOdds(it->labelLogOdds(label)));
    const octomap::OcTreeKey base = it.getIndexKey();
    const unsigned span = 1u << (max_depth - it.getDepth());
    auto& list = by_label[label];
    for (unsigned dx = 0; dx < span; ++dx)
      for (unsigned dy = 0; dy < span; ++dy)
        for (unsigned dz = 0; dz < span; ++dz)
          list.push_back({{static_cast<std::uint16_t>(base[0] + dx), static_cast<std::uint16_t>(base[1] + dy),
                           static_cast<std::uint16_t>(base[2] + dz)},
                          probability});
  }
  for (auto& [label, list] : by_label)
    std::sort(list.begin(), list.end(), [](const LabelledKey& a, const LabelledKey& b) { return a.key < b.key; });
  return by_label;
}

ObjectInstance makeObject(const LabelMap& map, int label, int instance,
                          std::vector<VoxelKey> cluster, const std::vector<LabelledKey>& all,
                          const SceneLevel& level) {
  ObjectInstance object;
  object.label = label;
  object.name = map.labels().at(label).name;
  object.instance = instance;
  object.voxels = std::move(cluster);
  double probability_sum = 0.0;
  auto cursor = all.begin();  // both lists are sorted by key
  for (const auto& key : object.voxels) {
    object.centroid += map.centerOf(key);
    cursor = std::lower_bound(cursor, all.end(), key,
                              [](const LabelledKey& a, const VoxelKey& k) { return a.key < k; });
    if (cursor != all.end() && cursor->key == key) probability_sum += cursor->probability;
  }
  const auto count = static_cast<double>(object.voxels.size());
  object.centroid /= count;
  object.mean_probability = probability_sum / count;
  object.box = fitOrientedBox(object.voxels, map.parameters().resolution, level.up, level.plane);
  return object;
}

octomap::OcTreeKey toOctomap(const VoxelKey& key) { return octomap::OcTreeKey(key.x, key.y, key.z); }

// The finest voxels whose centres lie inside `box`.
std::vector<VoxelKey> keysInside(const LabelMap& map, const OrientedBox& box) {
  const Eigen::Matrix3d rotation = box.rotation.normalized().toRotationMatrix();
  const Eigen::Vector3d half = 0.5 * rotation.cwiseAbs() * box.size;
  const VoxelKey low = map.keyOf(box.center - half);
  const VoxelKey high = map.keyOf(box.center + half);
  std::vector<VoxelKey> keys;
  for (int x = low.x; x <= high.x; ++x)
    for (int y = low.y; y <= high.y; ++y)
      for (int z = low.z; z <= high.z; ++z) {
        const VoxelKey key{static_cast<std::uint16_t>(x), static_cast<std::uint16_t>(y),
                           static_cast<std::uint16_t>(z)};
        if (box.contains(map.centerOf(key))) keys.push_back(key);
      }
  return keys;
}

}  // namespace

std::string ObjectInstance::id() const {
  return instance == 0 ? std::to_string(label) : std::to_string(label) + "#" + std::to_string(instance);
}

std::string leftOutNote(const ObjectInstance& object) {
  if (object.instance != 0 || object.label_voxels <= object.voxelCount()) return {};
  const size_t left_out = object.label_voxels - object.voxelCount();
  if (static_cast<double>(left_out) <= kLeftOutShare * static_cast<double>(object.label_voxels))
    return {};
  const size_t others = object.label_clusters > 0 ? object.label_clusters - 1 : 0;
  std::string where;
  if (others == 0)
    where = "specks too small to be objects";
  else if (others == 1)
    where = "another cluster";
  else
    where = std::to_string(others) + " other clusters";
  return "the box of label " + std::to_string(object.label) + " (" + object.name + ") holds the " +
         std::to_string(object.voxelCount()) + " voxels of its largest cluster; " +
         std::to_string(left_out) + " more of its " + std::to_string(object.label_voxels) +
         " lie in " + where + ", left out";
}

std::vector<std::vector<VoxelKey>> euclideanClusters(const std::vector<VoxelKey>& keys, double tolerance_voxels,
                                                     size_t min_size) {
  // Clusters are connected components: taking the largest of what is left
  // each time would find the same ones in the same order (voxelClusters'
  // order), one flood fill of all the voxels per cluster.
  std::vector<std::vector<VoxelKey>> clusters = voxelClusters(keys, tolerance_voxels);
  const size_t smallest = std::max<size_t>(min_size, 1);
  clusters.erase(std::find_if(clusters.begin(), clusters.end(),
                              [&](const std::vector<VoxelKey>& c) { return c.size() < smallest; }),
                 clusters.end());
  return clusters;
}

std::vector<ObjectInstance> extractObjects(const LabelMap& map, const ObjectOptions& options) {
  checkObjectOptions(map, options);
  std::vector<bool> wanted(static_cast<size_t>(map.numLabels()), false);
  if (options.labels) {
    for (int id : *options.labels) wanted[static_cast<size_t>(id)] = true;
  } else {
    for (int id = 1; id < map.numLabels(); ++id) wanted[static_cast<size_t>(id)] = true;
  }

  std::vector<ObjectInstance> objects;
  const auto by_label = occupiedByLabel(map, wanted, options.map_file);
  // Boxes stand level with the scene, as the studio's do (once for all objects).
  const SceneLevel level = by_label.empty() ? SceneLevel{} : sceneLevelOf(map, options.cameras_up);
  for (const auto& [label, list] : by_label) {
    std::vector<VoxelKey> keys;
    keys.reserve(list.size());
    for (const auto& v : list) keys.push_back(v.key);
    std::vector<std::vector<VoxelKey>> clusters =
        euclideanClusters(keys, options.cluster_tolerance_voxels, options.min_cluster_voxels);
    const size_t label_clusters = clusters.size();
    if (!options.all_clusters && clusters.size() > 1) clusters.resize(1);  // the others are outliers
    for (size_t i = 0; i < clusters.size(); ++i) {
      ObjectInstance object =
          makeObject(map, label, static_cast<int>(i), std::move(clusters[i]), list, level);
      object.label_voxels = keys.size();
      object.label_clusters = label_clusters;
      objects.push_back(std::move(object));
    }
  }
  return objects;
}

size_t rasterizeBox(LabelMap& map, const OrientedBox& box, int label, double probability) {
  if (!map.labels().contains(label))
    throw Error("", "label", "a label id of the map (0.." + std::to_string(map.numLabels() - 1) + ")",
                std::to_string(label));
  if (!(probability > 0.0 && probability < 1.0))
    throw Error("", "probability", "a probability strictly between 0 and 1", std::to_string(probability));
  LabelOcTree& tree = map.tree();
  std::vector<float> hit(static_cast<size_t>(map.numLabels()), tree.clampMinLogOdds());
  hit[static_cast<size_t>(label)] = logit(probability);
  std::vector<octomap::OcTreeKey> touched;
  for (const auto& key : keysInside(map, box)) {
    touched.push_back(toOctomap(key));
    tree.applyHit(touched.back(), hit.data());
  }
  const size_t count = touched.size();
  tree.refreshAncestors(std::move(touched));
  return count;
}

size_t rasterizeFreeBox(LabelMap& map, const OrientedBox& box, int misses) {
  LabelOcTree& tree = map.tree();
  std::vector<octomap::OcTreeKey> touched;
  for (const auto& key : keysInside(map, box)) {
    touched.push_back(toOctomap(key));
    for (int i = 0; i < misses; ++i) tree.applyMiss(touched.back());
  }
  const size_t count = touched.size();
  tree.refreshAncestors(std::move(touched));
  return count;
}

}  // namespace lom
