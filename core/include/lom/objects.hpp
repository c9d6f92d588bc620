#pragma once
// Objects of a labelled map: per label, its occupied voxels split into
// Euclidean clusters, the largest kept as the object (or every cluster as an
// instance), with its oriented box, centroid and mean probability. Used by the
// pick planner (lom/planning.hpp) and the studio's Objects panel.
// Definitions: docs/planning.md.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lom/geometry.hpp"
#include "lom/label_map.hpp"

namespace lom {

// The smallest cluster that is an object by default: 8 voxels (2x2x2; 8 cm^3
// at 1 cm), as the bulk of a map in views (kBulkPartVoxels).
inline constexpr size_t kDefaultMinObjectVoxels = 8;

struct ObjectOptions {
  // Labels to extract (the bin's candidate objects); every label but the
  // background (0) when absent. Unknown ids are an error.
  std::optional<std::vector<int>> labels;
  // Two voxels are in the same cluster when their centres are at most this many
  // voxel edges apart (26-neighbours are always connected). Must be > 0.
  double cluster_tolerance_voxels = 2.0;
  // false: only the largest cluster of each label is the object (the others are
  // outliers). true: every cluster is reported as a separate instance.
  bool all_clusters = false;
  // Clusters with fewer voxels are never objects. Must be >= 1. The default
  // leaves out specks of a misread label (a few voxels where a segmenter
  // called a pixel or two of another object that label), which a pick plan
  // would otherwise ask the robot to remove.
  size_t min_cluster_voxels = kDefaultMinObjectVoxels;
  // The up of a map that records no camera (fused before the record, or
  // built without cameras): the mean up of the cameras it was fused from
  // (meanCameraUp of lom/level_plane.hpp), which the boxes stand level on, as
  // the score's do (sceneLevelOf). A map's recorded up comes first; without
  // either, boxes stand on the world's +z.
  std::optional<Eigen::Vector3d> cameras_up;
  // Only for error messages.
  std::string map_file;
};

// One object of the map: a Euclidean cluster of one label's occupied voxels.
struct ObjectInstance {
  int label = 0;
  std::string name;
  // 0 for the largest cluster of the label; with all_clusters, 1, 2, ... for the
  // next clusters by decreasing size (ties: the cluster holding the smaller key first).
  int instance = 0;
  std::vector<VoxelKey> voxels;      // the cluster's finest-resolution voxels, sorted
  size_t label_voxels = 0;           // all occupied voxels of the label, before clustering
  size_t label_clusters = 0;         // clusters of the label with >= min_cluster_voxels voxels
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // mean of the voxel centres
  // Fitted to the cluster (fitOrientedBox of lom/box_fit.hpp), level with the
  // map's up (sceneLevelOf: its cameras' mean up levelled by its largest
  // plane; +z for a map that records no camera): holds the cluster's voxels
  // but those under the level plane and in sparse end layers.
  OrientedBox box;
  double mean_probability = 0.0;     // mean over the voxels of p(label)

  [[nodiscard]] size_t voxelCount() const { return voxels.size(); }
  // "19" for instance 0, "19#2" for instance 2.
  [[nodiscard]] std::string id() const;
};

// Share of a label's voxels above which a box that leaves them out (in other
// clusters, or specks too small to be objects) says so, as the studio's do.
inline constexpr double kLeftOutShare = 0.05;

// "the box of label 3 (mug) holds the 120 voxels of its largest cluster; 80
// more of its 200 lie in 2 other clusters, left out", or empty when the
// object's cluster holds all but at most kLeftOutShare of the label's voxels
// (instance 0 only, of objects extracted without all_clusters: with it the
// other clusters are objects of their own).
[[nodiscard]] std::string leftOutNote(const ObjectInstance& object);

// Euclidean clusters of voxel keys (largestCluster of lom/box_fit.hpp applied
// repeatedly): by decreasing size, ties to the cluster holding the smallest key;
// clusters smaller than `min_size` are dropped. Each cluster is sorted.
[[nodiscard]] std::vector<std::vector<VoxelKey>> euclideanClusters(const std::vector<VoxelKey>& keys,
                                                                   double tolerance_voxels,
                                                                   size_t min_size = 1);

// The objects of `map`, by ascending label then instance. Labels without
// occupied voxels (or whose clusters are all too small) have no object.
// Throws lom::Error naming options.map_file for unknown labels and bad options.
[[nodiscard]] std::vector<ObjectInstance> extractObjects(const LabelMap& map, const ObjectOptions& options = {});

// Generated scenes with known layouts (tests, demos): every voxel whose centre
// lies inside `box` gets a hit that leaves a fresh voxel with probability
// `probability` for `label` and the lower clamp for the other labels (evidence
// adds up where boxes overlap). Returns the number of voxels touched.
size_t rasterizeBox(LabelMap& map, const OrientedBox& box, int label, double probability = 0.9);
// Every voxel whose centre lies inside `box` gets `misses` misses (observed free space).
size_t rasterizeFreeBox(LabelMap& map, const OrientedBox& box, int misses = 3);

}  // namespace lom
