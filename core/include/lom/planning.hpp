#pragma once
// Pick planning on a labelled map (the paper's section V.C): the objects in
// front of a target along the approach direction are removed first, front-most
// first, then the target is picked. Definitions and the plan.json contract:
// docs/planning.md.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lom/geometry.hpp"
#include "lom/label_map.hpp"
#include "lom/labels.hpp"
#include "lom/objects.hpp"
#include "lom/sequence.hpp"

namespace lom {

// Where the approach direction came from.
enum class ApproachSource {
  Given,       // set by the caller (--approach)
  Sequence,    // the mean viewing direction of a sequence's frames (--sequence)
  MapCameras,  // the mean viewing direction of the cameras the map was fused from
  FreeSpace,   // estimated from the map: from the observed free space toward the objects
};
// "given" | "sequence" | "map-cameras" | "free-space"
[[nodiscard]] const char* approachSourceName(ApproachSource source);

// Which objects are in the target's way. Path (the default): the objects
// whose box is in the target's path (boxInPathOf). Centroid: the paper's rule
// (section V.C), every object whose centroid lies nearer the cameras along the
// approach than the target's, beside the path or not.
enum class OccluderRule { Path, Centroid };
[[nodiscard]] const char* occluderRuleName(OccluderRule rule);  // "path" | "centroid"

struct PlanOptions {
  ObjectOptions objects;  // objects.labels (candidates) always gets the target added
  // Unit or not (it is normalised). When absent: the mean viewing direction of
  // the cameras the map records (LabelMap::meanViewingDirection), else the
  // map's free-space estimate.
  std::optional<Eigen::Vector3d> approach;
  ApproachSource approach_source = ApproachSource::Given;  // reported when `approach` is set
  // Boxes overlap across the approach when their projections onto the plane
  // perpendicular to it overlap by more than this many voxel edges on every
  // separating axis (touching neighbours do not overlap). >= 0.
  double overlap_margin_voxels = 1.0;
  OccluderRule occluder_rule = OccluderRule::Path;
  // Also remove the objects in front of each object to be removed (and so on).
  bool transitive = false;
  // Empty bin (axis-aligned box in the map's frame, z up) for the removed objects;
  // every removed object is placed "outside" when absent.
  std::optional<OrientedBox> empty_bin;
  double placement_gap = 0.01;  // metres between placed objects and from the bin's walls
};

struct Grasp {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // on the front face, nearest the centroid
  Eigen::Vector3d approach = Eigen::Vector3d::UnitX();  // unit: the plan's approach direction
  Eigen::Vector3d face_normal = -Eigen::Vector3d::UnitX();  // outward normal of the front face
  int face_axis = 0;                                   // box axis the front face is perpendicular to
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: box axes in world
  Eigen::Vector3d size = Eigen::Vector3d::Zero();      // box edge lengths along those axes
};

struct Placement {
  bool in_bin = false;                                 // false: "outside"
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // centre of the placed object (in_bin only)
};

enum class StepAction { Remove, Pick };
[[nodiscard]] const char* stepActionName(StepAction action);  // "remove" | "pick"

struct PlanStep {
  StepAction action = StepAction::Remove;
  size_t object = 0;  // index into PickPlan::objects
  Grasp grasp;
  std::optional<Placement> placement;  // removed objects only
};

enum class ObjectRole { Target, Occluder, Other };
[[nodiscard]] const char* objectRoleName(ObjectRole role);  // "target" | "occluder" | "other"

struct PickPlan {
  int target_label = 0;
  std::string target_name;
  double resolution = 0.0;
  // The threshold the map's voxels were read at (planPickInMap: the map's;
  // the studio's, when re-thresholded); plan.json keeps it, when known.
  std::optional<double> occupancy_threshold;
  Eigen::Vector3d approach = Eigen::Vector3d::UnitX();  // unit
  ApproachSource approach_source = ApproachSource::Given;
  std::vector<ObjectInstance> objects;  // all extracted objects, by label then instance
  size_t target = 0;               // index into objects
  // Per object: (centroid - target centroid) . approach; negative = in front of the target.
  std::vector<double> depth;
  std::vector<ObjectRole> roles;   // per object
  std::vector<size_t> occluders;   // indices into objects, front-most first
  std::vector<PlanStep> steps;     // the occluders to remove in order, then the pick
  std::optional<OrientedBox> empty_bin;
  PlanOptions options;
};

// "19" or a label name of `labels` -> the label id. Throws lom::Error naming
// `file` and `field` for unknown labels and for the background (0).
[[nodiscard]] int resolveObjectLabel(const LabelSet& labels, const std::string& id_or_name,
                                     const std::string& file, const std::string& field);

// Average of the frames' camera z axes (optical axes) in world, normalised.
// Throws lom::Error naming the sequence for no frames or axes that cancel out.
[[nodiscard]] Eigen::Vector3d meanViewingDirection(const Sequence& sequence);

// Direction from the centroid of the map's observed free space (volume-weighted)
// to the centroid of the objects' voxels, normalised: the cameras looked through
// the free space at the objects. Throws lom::Error naming `map_file` when the map
// has no free space or no objects.
[[nodiscard]] Eigen::Vector3d approachFromFreeSpace(const LabelMap& map, const std::vector<ObjectInstance>& objects,
                                                    const std::string& map_file = {});

// Whether the projections of the boxes onto the plane perpendicular to
// `direction` overlap by more than `margin` metres on every separating axis.
[[nodiscard]] bool boxesOverlapAcross(const OrientedBox& a, const OrientedBox& b,
                                      const Eigen::Vector3d& direction, double margin = 0.0);

// Whether `object`'s box is in the way of a gripper moving along `direction`
// to `target`: it reaches nearer the camera along `direction` than the
// target's box does, and it meets the target's box moved back along
// -direction (its path), overlapping it by more than `margin` metres on every
// separating axis. An object behind the target whose top rises above the
// line of sight is not in the way, however high its centroid.
[[nodiscard]] bool boxInPathOf(const OrientedBox& object, const OrientedBox& target,
                               const Eigen::Vector3d& direction, double margin = 0.0);

// Puts `removals` (indices into `objects`) in an order a robot can follow:
// each after every removal in its path (boxInPathOf along `approach`, with
// `margin`), otherwise front-most first by centroid along `approach` (ties:
// by label, then instance). Objects in each other's paths go front-most
// first.
void orderForRemoval(std::vector<size_t>& removals, const std::vector<ObjectInstance>& objects,
                     const Eigen::Vector3d& approach, double margin = 0.0);

// Indices of the objects (other than `target`) in the target's way by `rule`
// (by default in its path, boxInPathOf), in removal order (orderForRemoval).
[[nodiscard]] std::vector<size_t> findOccluders(const std::vector<ObjectInstance>& objects,
                                                size_t target, const Eigen::Vector3d& approach,
                                                double margin = 0.0,
                                                OccluderRule rule = OccluderRule::Path);

// Grasp on the face of the object's box that faces the approach the most.
[[nodiscard]] Grasp graspFor(const ObjectInstance& object, const Eigen::Vector3d& approach);

// Places boxes (in the given order) into an axis-aligned empty bin, packed along
// its longer horizontal axis (x or y; ties: x) on its floor (z), `gap` metres
// apart and from the walls; a box that does not fit is "outside" (a later,
// smaller one may still fit). One placement per box.
// A warning when the empty bin is not empty in the map: the occupied voxels
// of objects (labels 1 and up; the background is the bin's own floor and
// walls) whose centres lie in `bin`, counted per label; empty when none.
// Placements ignore the map, so objects placed there would collide with them
// (a bin given in other coordinates, or over the source bin).
[[nodiscard]] std::string binContentsWarning(const LabelMap& map, const OrientedBox& bin,
                                             const std::string& map_file);

[[nodiscard]] std::vector<Placement> placeInBin(const std::vector<OrientedBox>& boxes,
                                                const std::optional<OrientedBox>& bin, double gap);

// The plan for already extracted objects. Throws lom::Error naming
// options.objects.map_file when the target label has no object.
[[nodiscard]] PickPlan planPick(const std::vector<ObjectInstance>& objects, const LabelSet& labels, int target_label,
                                const Eigen::Vector3d& approach, const PlanOptions& options, double resolution);

// Extracts the objects of `map` and plans; the approach is options.approach or,
// when absent, approachFromFreeSpace.
[[nodiscard]] PickPlan planPick(const LabelMap& map, int target_label, const PlanOptions& options);

// plan.json ("labeloctomap-plan", version 1) and the human-readable table.
[[nodiscard]] std::string planJson(const PickPlan& plan, const std::string& map_file = {});
[[nodiscard]] std::string planTable(const PickPlan& plan);
// Written atomically.
void writePlanJson(const PickPlan& plan, const std::filesystem::path& path, const std::string& map_file = {});

}  // namespace lom
