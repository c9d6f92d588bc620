// plan.json and the plan table; the fields are documented in docs/planning.md.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "lom/atomic_file.hpp"
#include "lom/planning.hpp"
#include "lom/text_columns.hpp"

namespace lom {

namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kPlanFormat = "labeloctomap-plan";
constexpr int kPlanVersion = 1;

Json vec(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json axesJson(const Eigen::Matrix3d& axes) {
  return Json::array({vec(axes.col(0)), vec(axes.col(1)), vec(axes.col(2))});
}

Json boxJson(const OrientedBox& box) {
  const Eigen::Quaterniond q = box.rotation.normalized();
  return Json{{"center", vec(box.center)},
              {"size", vec(box.size)},
              {"rotation", {q.x(), q.y(), q.z(), q.w()}},
              {"axes", axesJson(q.toRotationMatrix())}};
}

Json graspJson(const Grasp& grasp) {
  return Json{{"position", vec(grasp.position)}, {"approach", vec(grasp.approach)},
              {"face_normal", vec(grasp.face_normal)}, {"face_axis", grasp.face_axis},
              {"axes", axesJson(grasp.axes)},           {"size", vec(grasp.size)}};
}

Json placementJson(const std::optional<Placement>& placement) {
  if (!placement) return Json(nullptr);
  if (!placement->in_bin) return Json{{"where", "outside"}};
  return Json{{"where", "bin"}, {"position", vec(placement->position)}};
}

std::string fixed(double value, int decimals = 3) {
  if (std::abs(value) < 0.5 * std::pow(10.0, -decimals)) value = 0.0;  // no "-0.000"
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string triple(const Eigen::Vector3d& v, int decimals = 3) {
  return fixed(v.x(), decimals) + " " + fixed(v.y(), decimals) + " " + fixed(v.z(), decimals);
}

// Left-aligned in `width` columns, always followed by at least one space (long text is cut with "~").
std::string pad(const std::string& text, size_t width) {
  return padRight(cutToColumns(text, width - 1), width);
}

std::string objectName(const ObjectInstance& object) {
  return object.id() + (object.name.empty() ? "" : " " + object.name);
}

const char* approachExplanation(ApproachSource source) {
  switch (source) {
    case ApproachSource::Given: return "given";
    case ApproachSource::Sequence: return "mean viewing direction of the sequence";
    case ApproachSource::MapCameras:
      return "mean viewing direction of the map's cameras";
    case ApproachSource::FreeSpace: return "from the map's free space toward the objects";
  }
  return "given";
}

}  // namespace

std::string planJson(const PickPlan& plan, const std::string& map_file) {
  Json objects = Json::array();
  for (size_t i = 0; i < plan.objects.size(); ++i) {
    const ObjectInstance& o = plan.objects[i];
    objects.push_back(Json{{"id", o.id()},
                           {"label", o.label},
                           {"name", o.name},
                           {"instance", o.instance},
                           {"role", objectRoleName(plan.roles[i])},
                           {"voxels", o.voxelCount()},
                           {"cluster_voxels", o.voxelCount()},  // as objects.json names them
                           {"label_voxels", o.label_voxels},
                           {"label_clusters", o.label_clusters},
                           {"mean_probability", o.mean_probability},
                           {"centroid", vec(o.centroid)},
                           {"depth", plan.depth[i]},
                           {"box", boxJson(o.box)}});
  }
  Json occluders = Json::array();
  for (size_t i : plan.occluders) occluders.push_back(plan.objects[i].id());
  Json steps = Json::array();
  for (size_t k = 0; k < plan.steps.size(); ++k) {
    const PlanStep& step = plan.steps[k];
    const ObjectInstance& o = plan.objects[step.object];
    steps.push_back(Json{{"step", k + 1},
                         {"action", stepActionName(step.action)},
                         {"object", o.id()},
                         {"label", o.label},
                         {"name", o.name},
                         {"grasp", graspJson(step.grasp)},
                         {"placement", placementJson(step.placement)}});
  }
  const PlanOptions& options = plan.options;
  Json root{{"format", kPlanFormat},
            {"version", kPlanVersion},
            {"map", map_file},
            {"resolution", plan.resolution},
            {"occupancy_threshold",
             plan.occupancy_threshold ? Json(*plan.occupancy_threshold) : Json(nullptr)},
            {"target", Json{{"label", plan.target_label},
                            {"name", plan.target_name},
                            {"object", plan.objects[plan.target].id()}}},
            {"approach", Json{{"direction", vec(plan.approach)},
                              {"source", approachSourceName(plan.approach_source)}}},
            {"options", Json{{"candidates", options.objects.labels ? Json(*options.objects.labels)
                                                                   : Json(nullptr)},
                             {"all_clusters", options.objects.all_clusters},
                             {"cluster_tolerance_voxels", options.objects.cluster_tolerance_voxels},
                             {"min_cluster_voxels", options.objects.min_cluster_voxels},
                             {"occluder_rule", occluderRuleName(options.occluder_rule)},
                             {"overlap_margin_voxels", options.overlap_margin_voxels},
                             {"transitive", options.transitive},
                             {"placement_gap", options.placement_gap}}},
            {"empty_bin", plan.empty_bin ? Json{{"center", vec(plan.empty_bin->center)},
                                                {"size", vec(plan.empty_bin->size)}}
                                         : Json(nullptr)},
            {"objects", std::move(objects)},
            {"occluders", std::move(occluders)},
            {"steps", std::move(steps)}};
  // A map path from the file system may hold bytes that are not UTF-8.
  return root.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string planTable(const PickPlan& plan) {
  std::ostringstream out;
  const ObjectInstance& target = plan.objects[plan.target];
  out << "target    " << objectName(target) << " (" << target.voxelCount() << " voxels, centroid "
      << triple(target.centroid) << " m)\n";
  out << "approach  " << triple(plan.approach) << " (" << approachExplanation(plan.approach_source) << ")\n";
  // The rule that chose them: the words a reader checks the removals by.
  const bool by_centroid = plan.options.occluder_rule == OccluderRule::Centroid;
  out << "objects   " << plan.objects.size() << ", " << plan.occluders.size() << " in the way ("
      << (by_centroid ? "centroid nearer the cameras than the target's, the paper's rule"
                      : "in the target's path along the approach")
      << (plan.options.transitive && !by_centroid ? ", and in the paths of those (--transitive)"
                                                  : "")
      << ")";
  if (plan.empty_bin)
    out << "; empty bin at " << triple(plan.empty_bin->center) << ", size " << triple(plan.empty_bin->size) << "\n";
  else
    out << "; no empty bin: removed objects go outside\n";

  out << "\n" << pad("object", 32) << padLeft("voxels", 7) << padLeft("mean p", 8) << padLeft("front (m)", 11)
      << "  " << pad("box size (m)", 20) << "role\n";
  for (size_t i = 0; i < plan.objects.size(); ++i) {
    const ObjectInstance& o = plan.objects[i];
    out << pad(objectName(o), 32) << padLeft(std::to_string(o.voxelCount()), 7)
        << padLeft(fixed(o.mean_probability, 2), 8) << padLeft(fixed(-plan.depth[i]), 11) << "  "
        << pad(triple(o.box.size), 20) << objectRoleName(plan.roles[i]) << "\n";
  }

  out << "\n" << padLeft("step", 4) << "  " << pad("action", 8) << pad("object", 32) << pad("grasp position (m)", 22)
      << "place\n";
  for (size_t k = 0; k < plan.steps.size(); ++k) {
    const PlanStep& step = plan.steps[k];
    std::string place = "-";
    if (step.placement) place = step.placement->in_bin ? "bin " + triple(step.placement->position) : "outside";
    out << padLeft(std::to_string(k + 1), 4) << "  " << pad(stepActionName(step.action), 8)
        << pad(objectName(plan.objects[step.object]), 32) << pad(triple(step.grasp.position), 22) << place << "\n";
  }
  return out.str();
}

void writePlanJson(const PickPlan& plan, const std::filesystem::path& path, const std::string& map_file) {
  writeTextFileAtomically(path, planJson(plan, map_file));
}

}  // namespace lom
