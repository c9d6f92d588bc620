// Pick planning: occluders, grasps, placements (docs/planning.md).
#include "lom/planning.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "lom/error.hpp"
#include "lom/octree/label_octree.hpp"

namespace lom {

namespace {

std::string vectorText(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << v.x() << "," << v.y() << "," << v.z();
  return out.str();
}

std::string labelText(const LabelSet& labels, int label) {
  std::string text = std::to_string(label);
  if (labels.contains(label) && !labels.at(label).name.empty()) text += " (" + labels.at(label).name + ")";
  return text;
}

Eigen::Vector3d normalizedApproach(const Eigen::Vector3d& approach, const std::string& file) {
  const double norm = approach.norm();
  if (!approach.allFinite() || !(norm > 1e-12))
    throw Error(file, "approach", "a finite, non-zero direction x,y,z", vectorText(approach));
  return approach / norm;
}

Eigen::Matrix3d axesOf(const OrientedBox& box) { return box.rotation.normalized().toRotationMatrix(); }

// The interval a box (with its `axes`) covers along the unit direction n.
std::pair<double, double> interval(const OrientedBox& box, const Eigen::Matrix3d& axes,
                                   const Eigen::Vector3d& n) {
  const double centre = box.center.dot(n);
  double reach = 0.0;
  for (int k = 0; k < 3; ++k) reach += 0.5 * box.size[k] * std::abs(axes.col(k).dot(n));
  return {centre - reach, centre + reach};
}

// Front-most first; ties by label, then instance.
void sortFrontToBack(std::vector<size_t>& indices, const std::vector<ObjectInstance>& objects,
                     const Eigen::Vector3d& approach) {
  std::sort(indices.begin(), indices.end(), [&](size_t a, size_t b) {
    const double da = objects[a].centroid.dot(approach);
    const double db = objects[b].centroid.dot(approach);
    if (da != db) return da < db;
    if (objects[a].label != objects[b].label) return objects[a].label < objects[b].label;
    return objects[a].instance < objects[b].instance;
  });
}

}  // namespace

const char* approachSourceName(ApproachSource source) {
  switch (source) {
    case ApproachSource::Given: return "given";
    case ApproachSource::Sequence: return "sequence";
    case ApproachSource::MapCameras:
      return "map-cameras";
    case ApproachSource::FreeSpace: return "free-space";
  }
  return "given";
}

const char* occluderRuleName(OccluderRule rule) {
  return rule == OccluderRule::Centroid ? "centroid" : "path";
}

const char* stepActionName(StepAction action) { return action == StepAction::Pick ? "pick" : "remove"; }

const char* objectRoleName(ObjectRole role) {
  switch (role) {
    case ObjectRole::Target: return "target";
    case ObjectRole::Occluder: return "occluder";
    case ObjectRole::Other: return "other";
  }
  return "other";
}

int resolveObjectLabel(const LabelSet& labels, const std::string& id_or_name, const std::string& file,
                       const std::string& field) {
  const std::string expected = "a label id 1.." + std::to_string(labels.size() - 1) + " or a label name of the map";
  int label = -1;
  const bool numeric = !id_or_name.empty() && std::all_of(id_or_name.begin(), id_or_name.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  });
  if (numeric) {
    // Leading zeros are no part of the id (007 is label 7); more digits than
    // any label id has cannot name a label.
    const std::string digits =
        id_or_name.substr(std::min(id_or_name.find_first_not_of('0'), id_or_name.size() - 1));
    if (digits.size() > 6 || !labels.contains(std::atoi(digits.c_str())))
      throw Error(file, field, expected, "label " + id_or_name + ", which the map does not have");
    label = std::atoi(digits.c_str());
  } else if (const auto found = labels.findByName(id_or_name)) {
    label = *found;
  } else {
    throw Error(file, field, expected, "'" + id_or_name + "', which is no label name of the map");
  }
  if (label == 0)
    throw Error(file, field, "an object label (1.." + std::to_string(labels.size() - 1) + ")",
                labelText(labels, 0) + ", the background");
  return label;
}

Eigen::Vector3d meanViewingDirection(const Sequence& sequence) {
  const std::string file = (sequence.root / "sequence.json").string();
  if (sequence.frames.empty())
    throw Error(file, "frames", "at least one frame to take the mean viewing direction from", "no frame");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& frame : sequence.frames) sum += frame.T_world_camera.linear().col(2);
  if (!(sum.norm() > 1e-9 * static_cast<double>(sequence.frames.size())))
    throw Error(file, "frames[].pose", "cameras whose viewing directions (z axes) do not cancel out",
                "a mean viewing direction of length 0");
  return sum.normalized();
}

Eigen::Vector3d approachFromFreeSpace(const LabelMap& map, const std::vector<ObjectInstance>& objects,
                                      const std::string& map_file) {
  const std::string expected =
      "a map with observed free space and objects, or an approach given with --approach x,y,z or "
      "--sequence SEQ";
  Eigen::Vector3d object_sum = Eigen::Vector3d::Zero();
  double object_count = 0.0;
  for (const auto& object : objects) {
    object_sum += object.centroid * static_cast<double>(object.voxelCount());
    object_count += static_cast<double>(object.voxelCount());
  }
  if (object_count == 0.0) throw Error(map_file, "approach", expected, "no object in the map");

  const LabelOcTree& tree = map.tree();
  Eigen::Vector3d free_sum = Eigen::Vector3d::Zero();
  double free_volume = 0.0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (tree.isNodeOccupied(*it)) continue;
    const double size = it.getSize();
    const double volume = size * size * size;
    const octomap::point3d c = it.getCoordinate();
    free_sum += volume * Eigen::Vector3d(c.x(), c.y(), c.z());
    free_volume += volume;
  }
  if (free_volume == 0.0) throw Error(map_file, "approach", expected, "no free voxel in the map");
  const Eigen::Vector3d direction = object_sum / object_count - free_sum / free_volume;
  if (!(direction.norm() > 1e-9))
    throw Error(map_file, "approach", expected, "free space centred on the objects (no direction)");
  return direction.normalized();
}

bool boxesOverlapAcross(const OrientedBox& a, const OrientedBox& b, const Eigen::Vector3d& direction,
                        double margin) {
  const Eigen::Vector3d d = direction.normalized();
  const Eigen::Matrix3d axes_a = axesOf(a);
  const Eigen::Matrix3d axes_b = axesOf(b);
  // The projections are zonogons whose edges are the projected box axes, so the
  // candidate separating lines in the plane are perpendicular to those: d x axis.
  for (const Eigen::Matrix3d* axes : {&axes_a, &axes_b}) {
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d n = d.cross(axes->col(k));
      if (n.norm() < 1e-9) continue;  // this axis is along d: its faces project to nothing
      n.normalize();
      const auto [low_a, high_a] = interval(a, axes_a, n);
      const auto [low_b, high_b] = interval(b, axes_b, n);
      if (std::min(high_a, high_b) - std::max(low_a, low_b) <= margin) return false;
    }
  }
  return true;
}

bool boxInPathOf(const OrientedBox& object, const OrientedBox& target,
                 const Eigen::Vector3d& direction, double margin) {
  const Eigen::Vector3d d = direction.normalized();
  const Eigen::Matrix3d axes_o = axesOf(object);
  const Eigen::Matrix3d axes_t = axesOf(target);
  // In front: the object reaches nearer the camera than the target does.
  if (!(interval(object, axes_o, d).first < interval(target, axes_t, d).first)) return false;
  // The path: the target's box moved back along d towards the camera, far
  // beyond any map. It and the object's box are convex; they meet unless one
  // of the separating axes of a box and a box swept along d parts them: the
  // faces' normals (the object's axes, the target's axes, d x the target's
  // axes) and the edges' cross products (the object's axes x the target's
  // axes and x d).
  constexpr double kPathLength = 1e3;
  std::vector<Eigen::Vector3d> normals;
  for (int k = 0; k < 3; ++k) {
    normals.push_back(axes_o.col(k));
    normals.push_back(axes_t.col(k));
    normals.push_back(d.cross(axes_t.col(k)));
    normals.push_back(d.cross(axes_o.col(k)));
    for (int j = 0; j < 3; ++j) normals.push_back(axes_o.col(k).cross(axes_t.col(j)));
  }
  for (Eigen::Vector3d n : normals) {
    if (n.norm() < 1e-9) continue;  // parallel edges: another axis covers it
    n.normalize();
    const auto [low_o, high_o] = interval(object, axes_o, n);
    auto [low_t, high_t] = interval(target, axes_t, n);
    const double swept = -kPathLength * d.dot(n);
    low_t += std::min(0.0, swept);
    high_t += std::max(0.0, swept);
    // The margin keeps neighbours that merely graze the path out; an object
    // thinner than twice the margin along n (a face one voxel deep, whatever
    // the approach) is in the way once more than half of it is in the path.
    const double overlap = std::min(high_o, high_t) - std::max(low_o, low_t);
    if (overlap <= std::min(margin, 0.5 * (high_o - low_o))) return false;
  }
  return true;
}

void orderForRemoval(std::vector<size_t>& removals, const std::vector<ObjectInstance>& objects,
                     const Eigen::Vector3d& approach, double margin) {
  const Eigen::Vector3d d = approach.normalized();
  sortFrontToBack(removals, objects, d);
  // blockers[k]: how many removals still in the path of removals[k]. The
  // centroids alone put a flat object before a tall one beside it whose near
  // edge is in its path.
  const size_t n = removals.size();
  std::vector<std::vector<size_t>> blocks(n);  // blocks[j]: the k that j is in the path of
  std::vector<size_t> blockers(n, 0);
  for (size_t j = 0; j < n; ++j)
    for (size_t k = 0; k < n; ++k)
      if (j != k && boxInPathOf(objects[removals[j]].box, objects[removals[k]].box, d, margin)) {
        blocks[j].push_back(k);
        ++blockers[k];
      }
  std::vector<size_t> ordered;
  std::vector<bool> taken(n, false);
  while (ordered.size() < n) {
    // The front-most removal with nothing left in its path; when each has
    // one (objects in each other's paths), the front-most of all.
    size_t next = n;
    for (size_t k = 0; k < n && next == n; ++k)
      if (!taken[k] && blockers[k] == 0) next = k;
    for (size_t k = 0; k < n && next == n; ++k)
      if (!taken[k]) next = k;
    taken[next] = true;
    ordered.push_back(removals[next]);
    for (size_t k : blocks[next])
      if (blockers[k] > 0) --blockers[k];
  }
  removals = std::move(ordered);
}

std::vector<size_t> findOccluders(const std::vector<ObjectInstance>& objects, size_t target,
                                  const Eigen::Vector3d& approach, double margin,
                                  OccluderRule rule) {
  const Eigen::Vector3d d = approach.normalized();
  const double target_depth = objects[target].centroid.dot(d);
  std::vector<size_t> occluders;
  for (size_t i = 0; i < objects.size(); ++i) {
    if (i == target) continue;
    const bool in_the_way = rule == OccluderRule::Centroid
                                ? objects[i].centroid.dot(d) < target_depth
                                : boxInPathOf(objects[i].box, objects[target].box, d, margin);
    if (in_the_way) occluders.push_back(i);
  }
  orderForRemoval(occluders, objects, d, margin);
  return occluders;
}

Grasp graspFor(const ObjectInstance& object, const Eigen::Vector3d& approach) {
  Grasp grasp;
  grasp.approach = approach.normalized();
  grasp.axes = axesOf(object.box);
  grasp.size = object.box.size;
  // The face that shows the most area along the approach (its area times
  // |cos| of its normal to it): the front of a cube, but the broad top of a
  // flat envelope seen from above at a slant, not its edge, which no gripper
  // takes and which faces the approach more squarely.
  const auto shown = [&](int k) {
    return std::abs(grasp.axes.col(k).dot(grasp.approach)) * grasp.size[(k + 1) % 3] *
           grasp.size[(k + 2) % 3];
  };
  int best = 0;
  for (int k = 1; k < 3; ++k)
    if (shown(k) > shown(best)) best = k;
  grasp.face_axis = best;
  const double sign = grasp.axes.col(best).dot(grasp.approach) > 0.0 ? -1.0 : 1.0;
  grasp.face_normal = sign * grasp.axes.col(best);
  // The centroid in box coordinates, moved onto the front face (and kept on it).
  Eigen::Vector3d local = grasp.axes.transpose() * (object.centroid - object.box.center);
  const Eigen::Vector3d half = 0.5 * object.box.size;
  local = local.cwiseMax(-half).cwiseMin(half);
  local[best] = sign * half[best];
  grasp.position = object.box.center + grasp.axes * local;
  return grasp;
}

std::string binContentsWarning(const LabelMap& map, const OrientedBox& bin,
                               const std::string& map_file) {
  const double resolution = map.parameters().resolution;
  std::map<int, double> voxels;  // per label, in voxels of the map's resolution
  map.forEachOccupied([&](const OccupiedVoxel& voxel) {
    if (voxel.label == 0 || !bin.contains(voxel.center)) return;
    voxels[voxel.label] += std::pow(voxel.size / resolution, 3.0);
  });
  if (voxels.empty()) return {};
  double total = 0.0;
  std::string list;
  size_t named = 0;
  for (const auto& [label, count] : voxels) {
    total += count;
    if (named++ < 10)
      list += (list.empty() ? "" : ", ") + labelText(map.labels(), label) + ": " +
              std::to_string(static_cast<long long>(std::llround(count)));
  }
  if (voxels.size() > 10) list += " and " + std::to_string(voxels.size() - 10) + " more labels";
  return "--empty-bin " + vectorText(bin.center) + "," + vectorText(bin.size) + " holds " +
         std::to_string(static_cast<long long>(std::llround(total))) +
         " occupied voxels of objects in " + map_file + " (" + list +
         "): it is not empty there, and the placements do not look at the map, so objects "
         "placed in it may collide with them. Is the bin given in the map's coordinates "
         "(metres, the map's frame)?";
}

std::vector<Placement> placeInBin(const std::vector<OrientedBox>& boxes, const std::optional<OrientedBox>& bin,
                                  double gap) {
  std::vector<Placement> placements(boxes.size());
  if (!bin) return placements;
  const Eigen::Vector3d low = bin->center - 0.5 * bin->size;
  const int along = bin->size.y() > bin->size.x() ? 1 : 0;
  const int across = 1 - along;
  double cursor = gap;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Eigen::Vector3d extent = axesOf(boxes[i]).cwiseAbs() * boxes[i].size;  // world-aligned extent
    const bool fits = cursor + extent[along] + gap <= bin->size[along] &&
                      extent[across] + 2.0 * gap <= bin->size[across] && extent.z() <= bin->size.z();
    if (!fits) continue;
    Placement& placement = placements[i];
    placement.in_bin = true;
    placement.position[along] = low[along] + cursor + 0.5 * extent[along];
    placement.position[across] = bin->center[across];
    placement.position.z() = low.z() + 0.5 * extent.z();
    cursor += extent[along] + gap;
  }
  return placements;
}

PickPlan planPick(const std::vector<ObjectInstance>& objects, const LabelSet& labels, int target_label,
                  const Eigen::Vector3d& approach, const PlanOptions& options, double resolution) {
  const std::string& file = options.objects.map_file;
  if (!labels.contains(target_label) || target_label == 0)
    throw Error(file, "target", "an object label (1.." + std::to_string(labels.size() - 1) + ")",
                labelText(labels, target_label));
  if (!(options.overlap_margin_voxels >= 0.0) || !std::isfinite(options.overlap_margin_voxels))
    throw Error(file, "overlap_margin_voxels", "a finite number >= 0", std::to_string(options.overlap_margin_voxels));
  if (!(options.placement_gap >= 0.0) || !std::isfinite(options.placement_gap))
    throw Error(file, "placement_gap", "a finite number of metres >= 0", std::to_string(options.placement_gap));
  if (options.empty_bin && !((options.empty_bin->size.array() > 0.0).all() && options.empty_bin->size.allFinite() &&
                             options.empty_bin->center.allFinite()))
    throw Error(file, "empty_bin", "a finite box with all sizes > 0",
                vectorText(options.empty_bin->center) + "," + vectorText(options.empty_bin->size));

  PickPlan plan;
  plan.target_label = target_label;
  plan.target_name = labels.at(target_label).name;
  plan.resolution = resolution;
  plan.approach = normalizedApproach(approach, file);
  plan.approach_source = options.approach_source;
  plan.objects = objects;
  plan.empty_bin = options.empty_bin;
  plan.options = options;

  const auto target = std::find_if(plan.objects.begin(), plan.objects.end(), [&](const ObjectInstance& o) {
    return o.label == target_label && o.instance == 0;
  });
  if (target == plan.objects.end())
    throw Error(file, "target", "a label with occupied voxels in the map",
                "label " + labelText(labels, target_label) + ", which has no occupied voxel" +
                    (options.objects.min_cluster_voxels > 1
                         ? " in a cluster of at least " + std::to_string(options.objects.min_cluster_voxels) +
                               " voxels"
                         : std::string()));
  plan.target = static_cast<size_t>(target - plan.objects.begin());

  const double margin = options.overlap_margin_voxels * resolution;
  plan.occluders =
      findOccluders(plan.objects, plan.target, plan.approach, margin, options.occluder_rule);
  if (options.transitive) {
    std::set<size_t> chosen(plan.occluders.begin(), plan.occluders.end());
    std::vector<size_t> pending = plan.occluders;
    while (!pending.empty()) {
      const size_t blocked = pending.back();
      pending.pop_back();
      for (size_t i :
           findOccluders(plan.objects, blocked, plan.approach, margin, options.occluder_rule))
        if (i != plan.target && chosen.insert(i).second) pending.push_back(i);
    }
    plan.occluders.assign(chosen.begin(), chosen.end());
    orderForRemoval(plan.occluders, plan.objects, plan.approach, margin);
  }

  const double target_depth = plan.objects[plan.target].centroid.dot(plan.approach);
  plan.roles.assign(plan.objects.size(), ObjectRole::Other);
  plan.depth.resize(plan.objects.size());
  for (size_t i = 0; i < plan.objects.size(); ++i)
    plan.depth[i] = plan.objects[i].centroid.dot(plan.approach) - target_depth;
  plan.roles[plan.target] = ObjectRole::Target;
  for (size_t i : plan.occluders) plan.roles[i] = ObjectRole::Occluder;

  std::vector<OrientedBox> removed;
  for (size_t i : plan.occluders) removed.push_back(plan.objects[i].box);
  const std::vector<Placement> placements = placeInBin(removed, options.empty_bin, options.placement_gap);
  for (size_t k = 0; k < plan.occluders.size(); ++k) {
    PlanStep step;
    step.action = StepAction::Remove;
    step.object = plan.occluders[k];
    step.grasp = graspFor(plan.objects[step.object], plan.approach);
    step.placement = placements[k];
    plan.steps.push_back(std::move(step));
  }
  PlanStep pick;
  pick.action = StepAction::Pick;
  pick.object = plan.target;
  pick.grasp = graspFor(plan.objects[plan.target], plan.approach);
  plan.steps.push_back(std::move(pick));
  return plan;
}

PickPlan planPick(const LabelMap& map, int target_label, const PlanOptions& options) {
  const std::string& file = options.objects.map_file;
  if (!map.labels().contains(target_label) || target_label == 0)
    throw Error(file, "target", "an object label (1.." + std::to_string(map.numLabels() - 1) + ")",
                labelText(map.labels(), target_label));
  PlanOptions effective = options;
  if (effective.objects.labels) {
    auto& labels = *effective.objects.labels;
    if (std::find(labels.begin(), labels.end(), target_label) == labels.end()) {
      labels.push_back(target_label);
      std::sort(labels.begin(), labels.end());  // the plan lists them in ascending order
    }
  }
  const std::vector<ObjectInstance> objects = extractObjects(map, effective.objects);
  Eigen::Vector3d approach;
  if (effective.approach) {
    approach = *effective.approach;
  } else if (const auto viewing = map.meanViewingDirection()) {
    approach = *viewing;
    effective.approach_source = ApproachSource::MapCameras;
  } else {
    // Without the target there is nothing to plan; say so before blaming the approach.
    const bool has_target = std::any_of(objects.begin(), objects.end(),
                                        [&](const ObjectInstance& o) { return o.label == target_label; });
    approach = has_target ? approachFromFreeSpace(map, objects, file) : Eigen::Vector3d::UnitX();
    effective.approach_source = ApproachSource::FreeSpace;
  }
  PickPlan plan = planPick(objects, map.labels(), target_label, approach, effective,
                           map.parameters().resolution);
  plan.occupancy_threshold = map.parameters().occupancy_threshold;
  return plan;
}

}  // namespace lom
