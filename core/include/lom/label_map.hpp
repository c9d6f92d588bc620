#pragma once
// The multilabel occupancy map (LabelOctoMap). A thin, OctoMap-free facade over
// lom::LabelOcTree (lom/octree/label_octree.hpp) so that most code never
// compiles OctoMap's templates.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "lom/labels.hpp"
#include "lom/level_plane.hpp"

namespace lom {

class LabelOcTree;

// A voxel whose largest probability is within this of the occupancy threshold
// counts as at it (occupied): its log-odds are floats, so a probability equal
// to the threshold may be stored a few units in the last place below it.
inline constexpr double kOccupancyThresholdTolerance = 1e-6;

// Defaults are the paper's experimental settings and OctoMap's clamping.
struct MapParameters {
  double resolution = 0.01;           // voxel edge, metres
  double p_miss = 0.3;                // probability given to every label of a missed voxel
  double occupancy_threshold = 0.5;   // occupied iff max_k p_k >= threshold (within
                                      // kOccupancyThresholdTolerance: the log-odds are floats)
  double clamp_min = 0.12;            // per-label probability clamping range
  double clamp_max = 0.97;
  double max_range = 1.0;             // metres from the camera; <= 0 means unlimited
};

// Voxel sizes a map may have, in metres: 0.1 mm to 10 m. Finer voxels would
// leave the map (65536 voxels a side) smaller than a room; coarser ones map no
// object, and sizes far beyond would overflow the map's coordinates.
inline constexpr double kMinResolution = 1e-4;
inline constexpr double kMaxResolution = 10.0;

// Throws lom::Error naming the parameter when a value is out of range
// (resolution from kMinResolution to kMaxResolution; probabilities strictly
// between 0 and 1; clamp_min < clamp_max; max_range finite).
void checkMapParameters(const MapParameters& parameters);

// OctoMap key of a finest-resolution voxel.
struct VoxelKey {
  std::uint16_t x = 0, y = 0, z = 0;
  bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator<(const VoxelKey& o) const {
    return x != o.x ? x < o.x : (y != o.y ? y < o.y : z < o.z);
  }
};

// Occupied leaves larger than the resolution (pruned, or written so by another
// program) stand for all their finest-resolution voxels. Listing them one by
// one (voxelsByLabel, exports, objects, evaluation) stops with lom::Error
// beyond this many voxels instead of allocating without bound: a single leaf at
// the root of a 1 cm map stands for 65536^3 voxels, 655 m a side.
inline constexpr size_t kMaxExpandedVoxels = size_t{1} << 24;

struct OccupiedVoxel {
  Eigen::Vector3d center;
  double size = 0.0;        // edge length (larger than the resolution for pruned nodes)
  int label = 0;            // argmax label
  float probability = 0.f;  // probability of that label
};

// The cameras a map was fused from: each fused view adds its camera's up (the
// negated image y axis) and viewing direction (the z axis), in world
// coordinates, and counts one view.
struct CameraViewRecord {
  double up_sum[3] = {0.0, 0.0, 0.0};
  double forward_sum[3] = {0.0, 0.0, 0.0};
  std::uint32_t views = 0;
};

// Adds the view of a camera with rotation `R_world_camera` to `record` (as
// LabelMap::noteCameraView does); false, and nothing added, for a rotation
// that is not finite or a record that holds as many views as it can count.
bool addCameraView(CameraViewRecord& record, const Eigen::Matrix3d& R_world_camera);
// Whether two records hold the same views: the same count and the same summed
// directions, up to the rounding of adding them in another order.
[[nodiscard]] bool sameCameraViews(const CameraViewRecord& a, const CameraViewRecord& b);

// The class candidates the fused frames were restricted to (fuse --candidates):
// the labels the fusion may have put in the map, which the projection
// baselines of a score of the map must use too. `labels` is nullopt when some
// frame was fused with every label. `recorded` is false for maps written
// before the record existed (data versions 1 and 2).
struct FusedCandidates {
  bool recorded = true;
  std::optional<std::vector<int>> labels;
};

// Where the fused frames' probabilities came from, so that a score whose
// baselines read other ones can say so: whether some frame was fused with
// probabilities of its own (a proba image, or one made from its label
// image), and the file names of the segmentation models the other frames
// ran through (ascending, each once). `recorded` is false for maps written
// before the record (data versions 1 to 3), and stays so when frames are
// fused into them.
struct FusedEvidence {
  bool recorded = true;
  bool own_probabilities = false;
  std::vector<std::string> models;
  [[nodiscard]] bool empty() const { return !own_probabilities && models.empty(); }
  bool operator==(const FusedEvidence& other) const {
    return recorded == other.recorded && own_probabilities == other.own_probabilities &&
           models == other.models;
  }
  bool operator!=(const FusedEvidence& other) const { return !(*this == other); }
};
// "the frames' own probabilities", "segmenter m.onnx", or both joined by "and".
[[nodiscard]] std::string describeEvidence(const FusedEvidence& evidence);

// The world frame the fused cameras' poses were in (the sequence's frame_id),
// which the sequence's boxes and any frames fused into the map later must be
// in too. `frame_id` is empty until a frame is fused. `recorded` is false for
// maps written before the record (data versions 1 to 4), and stays so when
// frames are fused into them.
struct WorldFrameRecord {
  bool recorded = true;
  std::string frame_id;
};

struct VoxelState {
  bool known = false;       // observed at least once
  bool occupied = false;
  int label = -1;           // argmax label (valid when known)
  std::vector<float> probabilities;  // one per label (empty when unknown)
  // The leaf that holds the point (valid when known): a pruned leaf is larger
  // than the map's resolution.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double size = 0.0;
};

class LabelMap {
 public:
  explicit LabelMap(LabelSet labels, const MapParameters& parameters = {});
  ~LabelMap();
  LabelMap(LabelMap&&) noexcept;
  LabelMap& operator=(LabelMap&&) noexcept;
  LabelMap(const LabelMap&) = delete;
  LabelMap& operator=(const LabelMap&) = delete;

  [[nodiscard]] const LabelSet& labels() const { return labels_; }
  [[nodiscard]] int numLabels() const { return labels_.size(); }
  [[nodiscard]] const MapParameters& parameters() const { return parameters_; }
  // Records a fused view's camera (integrateFrame does, for every frame). A
  // map read from a file that records no views and no candidates (written
  // before the record) keeps recording none: its earlier views are unknown.
  void noteCameraView(const Eigen::Matrix3d& R_world_camera);
  [[nodiscard]] const CameraViewRecord& cameraViews() const;
  // Records the candidates of a frame about to be fused (integrateFrame
  // does): the first view sets them, later views widen them to the union
  // (every label once a frame had none).
  void noteFusedCandidates(const std::optional<std::vector<int>>& candidates);
  [[nodiscard]] const FusedCandidates& fusedCandidates() const;
  // Records where a fused frame's probabilities came from: the file name of
  // the segmentation model it ran through, or "" for its own (the fusion of
  // a sequence does, for every frame).
  void noteFusedEvidence(const std::string& model);
  [[nodiscard]] const FusedEvidence& fusedEvidence() const;
  // Records the world frame of a fused frame's pose (the fusion of a sequence
  // does, for every frame): the first sets it. Throws lom::Error (field
  // "world frame") for another frame than the one recorded: its coordinates
  // are not the map's (callers check first, with checkMapMatchesSequence).
  void noteWorldFrame(const std::string& frame_id);
  [[nodiscard]] const WorldFrameRecord& worldFrame() const;
  // Which way is up in the map's world, as its cameras saw it: the mean of
  // their up directions, normalised, when they agree (the mean is at least
  // half a unit long); nullopt when no view was recorded (maps of data
  // version 1, or built without cameras) or when the views disagree.
  [[nodiscard]] std::optional<Eigen::Vector3d> camerasUp() const;
  // The largest plane of occupied voxels near the cameras' up (findLevelPlane
  // of lom/level_plane.hpp); nullopt without camerasUp or without such a plane.
  [[nodiscard]] std::optional<LevelPlane> levelPlane() const;
  // Up in the map: the level plane's normal when there is one (cameras pitched
  // towards the scene tilt their mean up), else camerasUp.
  [[nodiscard]] std::optional<Eigen::Vector3d> upDirection() const;
  // Centres of the occupied leaves (forEachOccupied), for levelledUp.
  [[nodiscard]] std::vector<Eigen::Vector3d> occupiedCentres() const;
  // The cameras' mean viewing direction, normalised (the same as
  // meanViewingDirection of the fused sequence); nullopt without recorded
  // views or when the directions cancel out.
  [[nodiscard]] std::optional<Eigen::Vector3d> meanViewingDirection() const;

  // Re-thresholds the whole map at once (no re-fusion needed).
  void setOccupancyThreshold(double threshold);
  // Changes max range and p_miss for later fusion (resolution and clamping are fixed).
  void setIntegrationParameters(double p_miss, double max_range);

  [[nodiscard]] VoxelKey keyOf(const Eigen::Vector3d& point_world) const;  // throws if out of map
  [[nodiscard]] Eigen::Vector3d centerOf(const VoxelKey& key) const;
  [[nodiscard]] VoxelState voxelAt(const Eigen::Vector3d& point_world) const;
  [[nodiscard]] VoxelState voxelAt(const VoxelKey& key) const;

  // Visits occupied leaves (pruned leaves once, with their larger size).
  void forEachOccupied(const std::function<void(const OccupiedVoxel&)>& visit) const;
  // Number of finest-resolution voxels of the occupied leaves of the labels in
  // `only` (every label when absent). Throws lom::Error (field "map") when it
  // exceeds kMaxExpandedVoxels, naming the count and the largest such leaf.
  [[nodiscard]] size_t expandableOccupiedVoxels(
      const std::optional<std::set<int>>& only = std::nullopt) const;
  // Finest-resolution keys of the voxels occupied by `label` (pruned leaves
  // expanded, at most kMaxExpandedVoxels), sorted.
  [[nodiscard]] std::vector<VoxelKey> voxelsOfLabel(int label) const;
  // The same for every label in one pass (only those in `only`, when given);
  // labels without occupied voxels are absent.
  [[nodiscard]] std::map<int, std::vector<VoxelKey>> voxelsByLabel(
      const std::optional<std::set<int>>& only = std::nullopt) const;
  // Number of finest-resolution occupied voxels per label (labels with none omitted).
  [[nodiscard]] std::map<int, size_t> occupiedCountPerLabel() const;
  // Axis-aligned bounds of all known voxels; nullopt for an empty map.
  [[nodiscard]] std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> bounds() const;

  [[nodiscard]] size_t numNodes() const;
  [[nodiscard]] size_t numLeaves() const;
  [[nodiscard]] size_t memoryBytes() const;  // nodes + label blocks
  void prune();

  // Native .ot file (OctoMap's format, tree type "LabelOcTree"), written atomically.
  void save(const std::filesystem::path& path) const;
  // Throws lom::Error naming the file for unreadable files, trees of another
  // type and header values out of range (docs/fusion.md, "The .ot file").
  [[nodiscard]] static LabelMap load(const std::filesystem::path& path);
  // Whether `path` is a regular file whose header says it is a labelled map
  // (OctoMap's header, tree type LabelOcTree): only the header is read.
  [[nodiscard]] static bool isMapFile(const std::filesystem::path& path);
  // The file the map was loaded from (empty for a map made in memory); errors
  // about the map's content name it.
  [[nodiscard]] const std::filesystem::path& sourceFile() const { return source_file_; }

  [[nodiscard]] LabelOcTree& tree() { return *tree_; }
  [[nodiscard]] const LabelOcTree& tree() const { return *tree_; }

 private:
  LabelMap(LabelSet labels, const MapParameters& parameters, std::unique_ptr<LabelOcTree> tree);
  LabelSet labels_;
  MapParameters parameters_;
  std::unique_ptr<LabelOcTree> tree_;
  std::filesystem::path source_file_;
};

}  // namespace lom
