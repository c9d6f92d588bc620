// report.json and aggregate.json; the field list is documented in docs/evaluation.md.
#include <algorithm>

#include <nlohmann/json.hpp>

#include "lom/report.hpp"

namespace lom {

namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kReportFormat = "labeloctomap-score-report";
constexpr const char* kAggregateFormat = "labeloctomap-score-aggregate";
constexpr int kVersion = 1;

Json scoresJson(const MethodScores& scores) {
  return Json{{"projection_mean", scores.projection_mean},
              {"projection_max", scores.projection_max},
              {"labeloctomap", scores.labeloctomap}};
}

Json volumesJson(const IouVolumes& volumes) {
  return Json{{"true_positive", volumes.true_positive},
              {"false_positive", volumes.falsePositive()},
              {"false_negative", volumes.falseNegative()}};
}

Json boxJson(const OrientedBox& box) {
  const auto& q = box.rotation;
  return Json{{"center", {box.center.x(), box.center.y(), box.center.z()}},
              {"size", {box.size.x(), box.size.y(), box.size.z()}},
              {"rotation", {q.x(), q.y(), q.z(), q.w()}}};
}

Json summaryJson(const ScoreSummary& summary) {
  return Json{{"objects", summary.objects},
              {"iou_3d", scoresJson(summary.iou_3d)},
              {"box_iou", scoresJson(summary.box_iou)},
              {"labeloctomap_beats_projection_max", summary.labeloctomap_beats_projection_max}};
}

Json metricsJson(const Metrics2d& metrics) {
  return Json{{"pixel_accuracy", metrics.pixel_accuracy},
              {"mean_accuracy", metrics.mean_accuracy},
              {"mean_iu", metrics.mean_iu},
              {"fw_iu", metrics.fw_iu},
              {"pixels", metrics.pixels},
              {"classes", metrics.classes}};
}

// Names from the file system (the sequence folder, the map file) may hold
// bytes that are not UTF-8: they become U+FFFD instead of failing the report.
std::string dumped(const Json& value) {
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// Like dump(2), but arrays of numbers stay on one line, so that a box or the
// per-view scores read at a glance.
void writeJson(const Json& value, int indent, std::string& out) {
  const std::string pad(static_cast<size_t>(indent), ' ');
  const std::string inner(static_cast<size_t>(indent + 2), ' ');
  if (value.is_object() && !value.empty()) {
    out += "{\n";
    bool first = true;
    for (auto it = value.begin(); it != value.end(); ++it) {
      out += (first ? "" : ",\n") + inner + dumped(Json(it.key())) + ": ";
      writeJson(it.value(), indent + 2, out);
      first = false;
    }
    out += "\n" + pad + "}";
  } else if (value.is_array() && !value.empty() &&
             std::all_of(value.begin(), value.end(), [](const Json& v) { return v.is_primitive(); })) {
    out += "[";
    for (size_t i = 0; i < value.size(); ++i) out += (i ? ", " : "") + dumped(value[i]);
    out += "]";
  } else if (value.is_array() && !value.empty()) {
    out += "[\n";
    for (size_t i = 0; i < value.size(); ++i) {
      out += (i ? ",\n" : "") + inner;
      writeJson(value[i], indent + 2, out);
    }
    out += "\n" + pad + "]";
  } else {
    out += dumped(value);
  }
}

std::string pretty(const Json& value) {
  std::string out;
  writeJson(value, 0, out);
  return out + "\n";
}

}  // namespace

std::string reportJson(const EvaluationReport& report) {
  Json objects = Json::array();
  for (const auto& o : report.objects) {
    objects.push_back(Json{{"label", o.label},
                           {"name", o.name},
                           {"voxels", o.voxels},
                           {"iou_3d", scoresJson(o.iou_3d)},
                           {"labeloctomap_volumes", volumesJson(o.labeloctomap_volumes)},
                           {"per_view", o.per_view},
                           {"box_iou", scoresJson(o.box_iou)},
                           {"per_view_box_iou", o.per_view_box_iou},
                           {"box", boxJson(o.ground_truth)},
                           {"fitted_box", o.fitted_box ? boxJson(*o.fitted_box) : Json(nullptr)}});
  }
  Json root{{"format", kReportFormat},
            {"version", kVersion},
            {"sequence", report.sequence},
            {"resolution", report.resolution},
            {"max_range", report.max_range},
            {"occupancy_threshold", report.occupancy_threshold},
            {"p_miss", report.p_miss},
            {"frames", report.fused_frames
                           ? Json::array({report.fused_frames->first, report.fused_frames->second})
                           : Json(nullptr)},
            {"segmenter", report.segmenter.empty() ? Json(nullptr) : Json(report.segmenter)},
            {"iou_mode", iouModeName(report.iou_mode)},
            {"candidates", report.candidates ? Json(*report.candidates) : Json(nullptr)},
            {"map", report.map_file.empty() ? Json(nullptr) : Json(report.map_file)},
            {"warnings", report.warnings},
            {"views", report.views},
            {"objects", std::move(objects)},
            {"summary", summaryJson(report.summary)}};
  if (report.metrics_2d) root["metrics_2d"] = metricsJson(*report.metrics_2d);
  if (report.metrics_2d_candidates) root["metrics_2d_candidates"] = metricsJson(*report.metrics_2d_candidates);
  if (!report.metrics_2d_excluded_frames.empty())
    root["metrics_2d_excluded_frames"] = report.metrics_2d_excluded_frames;
  if (!report.metrics_2d_not_scored.empty())
    root["metrics_2d_not_scored"] = report.metrics_2d_not_scored;
  return pretty(root);
}

std::string aggregateJson(const std::vector<EvaluationReport>& reports) {
  Json sequences = Json::array();
  for (const auto& report : reports) {
    Json entry{{"sequence", report.sequence}, {"report", report.sequence + "/report.json"}};
    const Json summary = summaryJson(report.summary);
    for (auto it = summary.begin(); it != summary.end(); ++it) entry[it.key()] = it.value();
    // The settings its scores depend on, as its report.json has them.
    entry["resolution"] = report.resolution;
    entry["max_range"] = report.max_range;
    entry["occupancy_threshold"] = report.occupancy_threshold;
    entry["p_miss"] = report.p_miss;
    entry["iou_mode"] = iouModeName(report.iou_mode);
    entry["warnings"] = report.warnings;  // what makes its numbers doubtful, as its report says
    sequences.push_back(std::move(entry));
  }
  const Json root{{"format", kAggregateFormat},
                  {"version", kVersion},
                  {"warnings", mixedSettingsWarnings(reports)},
                  {"sequences", std::move(sequences)},
                  {"summary", summaryJson(summarizeAll(reports))}};
  return pretty(root);
}

}  // namespace lom
