#include "lom/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <set>

#include "evaluation_frames.hpp"
#include "lom/box_fit.hpp"
#include "lom/error.hpp"
#include "lom/iou.hpp"
#include "lom/level_plane.hpp"

namespace lom {

namespace {

constexpr const char* kMetrics2dFromLabels =
    "the probabilities were made from the label images, which are not an independent ground "
    "truth";

constexpr const char* kMetrics2dPlaceholders =
    "the label images are placeholders written by an import of colour and depth only, so "
    "there is no ground truth to compare the probabilities with";

std::string orDefault(const std::string& text, const char* fallback) {
  return text.empty() ? fallback : text;
}

std::string formatPoint(const Eigen::Vector3d& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.3f, %.3f, %.3f)", p.x(), p.y(), p.z());
  return text;
}

// Boxes in which the map has no occupied voxel of any label, said in at most
// two sentences (those outside everything the map observed, and the others):
// LabelOctoMap scores 0 there whatever it mapped, and a box given in other
// units or another frame (millimetres for metres) looks just like that. A
// third names boxes far larger than the map (millimetres again), which hold
// voxels but score about 0. Each names its first ten boxes and counts the rest.
// Many boxes are named up to ten, then counted: a sentence, not a page.
std::string listed(const std::vector<std::string>& names) {
  constexpr size_t kNamed = 10;
  std::string text;
  for (size_t i = 0; i < std::min(names.size(), kNamed); ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > kNamed) text += " and " + std::to_string(names.size() - kNamed) + " more";
  return text;
}

std::vector<std::string> emptyBoxWarnings(const Annotations& annotations, const LabelSet& labels,
                                          const LabelMap& map, const std::string& file) {
  std::vector<std::string> warnings;
  const std::vector<GroundTruthBox>& boxes = annotations.boxes;
  if (boxes.empty()) return warnings;
  // A voxel counts when any part of it is in the box: its centre within half
  // its own edge of the box (a pruned leaf stands for many voxels; corners
  // aside, which a box of an object never holds alone).
  std::vector<Eigen::AlignedBox3d> reach;
  for (const GroundTruthBox& box : boxes) {
    const Eigen::Vector3d half =
        box.box.rotation.toRotationMatrix().cwiseAbs() * (0.5 * box.box.size);
    reach.emplace_back(box.box.center - half, box.box.center + half);
  }
  std::vector<bool> holds(boxes.size(), false);
  size_t left = boxes.size();
  map.forEachOccupied([&](const OccupiedVoxel& voxel) {
    if (left == 0) return;
    const double margin = 0.5 * voxel.size;
    const Eigen::Vector3d grow = Eigen::Vector3d::Constant(margin);
    for (size_t i = 0; i < boxes.size(); ++i)
      if (!holds[i] &&
          Eigen::AlignedBox3d(reach[i].min() - grow, reach[i].max() + grow)
              .contains(voxel.center) &&
          boxes[i].box.contains(voxel.center, margin)) {
        holds[i] = true;
        --left;
      }
  });
  const auto bounds = map.bounds();
  const bool mapped = bounds.has_value();
  Eigen::AlignedBox3d observed;
  observed.setEmpty();
  if (mapped) observed = Eigen::AlignedBox3d(bounds->first, bounds->second);
  const std::string span = mapped ? " (its known voxels span " + formatPoint(observed.min()) +
                                        " to " + formatPoint(observed.max()) + " m)"
                                  : std::string(" (the map is empty)");
  std::vector<std::string> outside, empty, huge;
  bool far = false;
  const double across = mapped ? observed.diagonal().norm() : 0.0;
  for (size_t i = 0; i < boxes.size(); ++i) {
    // Named only for a box that is warned about (most are not).
    const auto which = [&] {
      const int label = boxes[i].label;
      return "boxes[" + std::to_string(i) + "] (label " + std::to_string(label) + ", " +
             (labels.contains(label) ? labels.at(label).name : "?") + ")";
    };
    const bool outside_map = !mapped || !reach[i].intersects(observed);  // bounds hold whole voxels
    // Far larger than all the map saw: it may hold voxels, yet scores about 0
    // (one outside the map is said to be there).
    if (!outside_map && boxes[i].box.size.maxCoeff() > 3.0 * across) {
      char size[96];
      std::snprintf(size, sizeof size, " is %.3g x %.3g x %.3g m", boxes[i].box.size.x(),
                    boxes[i].box.size.y(), boxes[i].box.size.z());
      huge.push_back(which() + size);
    }
    if (holds[i]) continue;
    if (outside_map) {
      outside.push_back(which());
      // Farther from the map than the map is across: not a near miss.
      far = far || !mapped || observed.exteriorDistance(boxes[i].box.center) > across;
    } else {
      empty.push_back(which());
    }
  }
  if (!outside.empty())
    warnings.push_back(file + ": " + listed(outside) + (outside.size() == 1 ? " lies" : " lie") +
                       " outside everything the map observed" + span +
                       ": nothing was mapped there, so " +
                       (outside.size() == 1 ? "it scores" : "they score") + " 0 in every column." +
                       (far ? " A box this far from the map is often given in other units or "
                              "another frame."
                            : ""));
  if (!empty.empty())
    warnings.push_back(file + ": " + listed(empty) + (empty.size() == 1 ? " holds" : " hold") +
                       " no occupied voxel of any label: nothing was mapped inside " +
                       (empty.size() == 1 ? "it" : "them") + ", so LabelOctoMap scores 0 there.");
  if (!huge.empty())
    warnings.push_back(
        file + ": " + listed(huge) +
        (huge.size() == 1 ? ", more than three times" : ", each more than three times") +
        " as large as everything the map observed" + span +
        ": an object's voxels fill almost none of " + (huge.size() == 1 ? "it" : "them") +
        ", so its IU is about 0 in every column. A box this large is often "
        "given in millimetres for metres.");
  return warnings;
}

void checkMapAgainstSequence(const LabelMap& map, const Sequence& sequence, const std::string& map_file) {
  const std::string file = orDefault(map_file, "(map)");
  checkMapMatchesSequence(map, sequence, file);
  if (map.occupiedCountPerLabel().empty())
    throw Error(file, "map", "at least one occupied voxel", "an empty map");
}

// Box IU of the largest cluster's fitted box, level with the scene (0 and no
// box when there are no voxels).
double fittedBoxIou(const std::vector<VoxelKey>& voxels, double resolution,
                    const OrientedBox& truth, double tolerance_voxels, const SceneLevel& level,
                    std::optional<OrientedBox>* fitted = nullptr) {
  if (voxels.empty()) return 0.0;
  const OrientedBox box =
      fitOrientedBox(largestCluster(voxels, tolerance_voxels), resolution, level.up, level.plane);
  if (fitted) *fitted = box;
  return boxIoU(box, truth);
}

void meanAndMax(const std::vector<double>& values, double& mean, double& max) {
  mean = values.empty() ? 0.0 : std::accumulate(values.begin(), values.end(), 0.0) / values.size();
  max = values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

}  // namespace

const char* iouModeName(IouMode mode) { return mode == IouMode::Exact ? "exact" : "center"; }

std::optional<IouMode> parseIouMode(const std::string& name) {
  if (name == "exact") return IouMode::Exact;
  if (name == "center") return IouMode::Center;
  return std::nullopt;
}

std::optional<Problem> frameIdProblem(const Sequence& sequence, const Annotations& annotations,
                                      const std::string& annotations_file) {
  if (annotations.frame_id == sequence.frame_id) return std::nullopt;
  return Problem{orDefault(annotations_file, "(annotations)"), "frame_id",
                 "the sequence's frame \"" + sequence.frame_id + "\" (" +
                     (sequence.root / "sequence.json").string() + ")",
                 "\"" + annotations.frame_id + "\""};
}

void checkAnnotationsForSequence(const Sequence& sequence, const Annotations& annotations,
                                 const std::string& annotations_file) {
  if (auto problem = frameIdProblem(sequence, annotations, annotations_file))
    throw Error(std::move(*problem));
  checkBoxLabels(annotations, sequence.labels.size(), orDefault(annotations_file, "(annotations)"),
                 "the sequence");
}

std::vector<std::string> boxNameWarnings(const Annotations& annotations, const LabelSet& labels,
                                         const std::string& annotations_file,
                                         const std::string& labels_file) {
  std::vector<bool> scored(annotations.boxes.size(), true);
  for (const UnscorableBox& box : unscorableBoxes(annotations, labels.size()))
    scored[box.index] = false;
  std::vector<std::string> warnings;
  for (size_t i = 0; i < annotations.boxes.size(); ++i) {
    const GroundTruthBox& box = annotations.boxes[i];
    if (!scored[i] || !labels.contains(box.label)) continue;
    const std::string& name = labels.at(box.label).name;
    if (box.name.empty() || box.name == name) continue;
    warnings.push_back(annotations_file + ": boxes[" + std::to_string(i) + "].name is '" +
                       box.name + "', but label " + std::to_string(box.label) + " of " +
                       labels_file + " is '" + name + "': the box is scored, and named, as label " +
                       std::to_string(box.label) +
                       " (were the boxes drawn for another label numbering?)");
  }
  return warnings;
}

std::vector<Problem> boxLabelProblems(const Annotations& annotations, int label_count,
                                      const std::string& annotations_file,
                                      const std::string& labelled) {
  const std::string file = orDefault(annotations_file, "(annotations)");
  const int n = label_count;
  std::vector<Problem> problems;
  for (const UnscorableBox& box : unscorableBoxes(annotations, n)) {
    // A YAML box file names its boxes' labels in `name` (object_12): it has no `label`.
    const std::string field =
        "boxes[" + std::to_string(box.index) + "]." + (isYamlBoxesPath(file) ? "name" : "label");
    if (box.boxed_before)
      problems.push_back({file, field, "each label in at most one box",
                          "label " + std::to_string(box.label) + " again (also boxes[" +
                              std::to_string(*box.boxed_before) + "])"});
    else
      problems.push_back(
          {file, field,
           n > 1 ? "an object label of " + labelled + " (1.." + std::to_string(n - 1) +
                       "; 0 is the background)"
                 : "an object label, but " + labelled +
                       " has none (only the background, 0: it was recorded without label images)",
           std::to_string(box.label)});
  }
  return problems;
}

void checkBoxLabels(const Annotations& annotations, int label_count,
                    const std::string& annotations_file, const std::string& labelled) {
  const std::string file = orDefault(annotations_file, "(annotations)");
  if (annotations.boxes.empty()) throw Error(file, "boxes", "at least one box to score", "none");
  std::vector<Problem> problems = boxLabelProblems(annotations, label_count, file, labelled);
  if (!problems.empty()) throw Error(std::move(problems.front()));
}

std::vector<UnscorableBox> unscorableBoxes(const Annotations& annotations, int label_count) {
  std::vector<UnscorableBox> unscorable;
  std::vector<std::optional<size_t>> box_of_label(static_cast<size_t>(std::max(label_count, 0)));
  for (size_t i = 0; i < annotations.boxes.size(); ++i) {
    const int label = annotations.boxes[i].label;
    if (label <= 0 || label >= label_count) {
      unscorable.push_back({i, label, std::nullopt});
      continue;
    }
    std::optional<size_t>& first = box_of_label[static_cast<size_t>(label)];
    if (first)
      unscorable.push_back({i, label, first});
    else
      first = i;
  }
  return unscorable;
}

double IouVolumes::iou() const {
  if (predicted <= 0.0) return 0.0;
  // v_tp + v_fp + v_fn = v_pred + v_gt - v_tp
  const double denominator = predicted + ground_truth - true_positive;
  return denominator > 0.0 ? std::clamp(true_positive / denominator, 0.0, 1.0) : 0.0;
}

namespace {

// The share of a voxel centred at `center` that IU_3d counts inside the box.
double shareCounted(const VoxelBoxIntersector& intersector, const Eigen::Vector3d& center,
                    double voxel_volume, IouMode mode) {
  if (mode == IouMode::Center) return intersector.centerInside(center) ? 1.0 : 0.0;
  return std::clamp(intersector.volume(center) / voxel_volume, 0.0, 1.0);
}

}  // namespace

IouVolumes iouVolumesOf(double share_sum, size_t voxels, double resolution, const OrientedBox& box,
                        IouMode mode) {
  const double voxel_volume = resolution * resolution * resolution;
  IouVolumes volumes;
  volumes.ground_truth = mode == IouMode::Exact
                             ? box.volume()
                             : VoxelBoxIntersector(box, resolution).centresInside() * voxel_volume;
  volumes.predicted = voxel_volume * static_cast<double>(voxels);
  // A voxel wholly inside adds 1.0000000000000002 of itself: the overlap is
  // at most each volume, so v_fp and v_fn are never negative.
  volumes.true_positive =
      std::min({share_sum * voxel_volume, volumes.predicted, volumes.ground_truth});
  return volumes;
}

IouVolumes voxelIouVolumes(const std::vector<VoxelKey>& voxels, double resolution,
                           const OrientedBox& box, IouMode mode) {
  const VoxelBoxIntersector intersector(box, resolution);
  const double voxel_volume = resolution * resolution * resolution;
  double share_sum = 0.0;
  for (const auto& key : voxels)
    share_sum += shareCounted(intersector, voxelCenter(key, resolution), voxel_volume, mode);
  return iouVolumesOf(share_sum, voxels.size(), resolution, box, mode);
}

double voxelIou(const std::vector<VoxelKey>& voxels, double resolution, const OrientedBox& box,
                IouMode mode) {
  return voxelIouVolumes(voxels, resolution, box, mode).iou();
}

std::vector<double> voxelSharesInBox(const std::vector<Eigen::Vector3d>& centres, double resolution,
                                     const OrientedBox& box, IouMode mode) {
  const VoxelBoxIntersector intersector(box, resolution);
  const double voxel_volume = resolution * resolution * resolution;
  std::vector<double> shares;
  shares.reserve(centres.size());
  for (const Eigen::Vector3d& centre : centres)
    shares.push_back(shareCounted(intersector, centre, voxel_volume, mode));
  return shares;
}

ScoreSummary summarize(const std::vector<ObjectScore>& objects) {
  ScoreSummary summary;
  summary.objects = objects.size();
  if (objects.empty()) return summary;
  auto mean = [&](auto member) {
    double sum = 0.0;
    for (const auto& o : objects) sum += member(o);
    return sum / static_cast<double>(objects.size());
  };
  summary.iou_3d.projection_mean = mean([](const ObjectScore& o) { return o.iou_3d.projection_mean; });
  summary.iou_3d.projection_max = mean([](const ObjectScore& o) { return o.iou_3d.projection_max; });
  summary.iou_3d.labeloctomap = mean([](const ObjectScore& o) { return o.iou_3d.labeloctomap; });
  summary.box_iou.projection_mean = mean([](const ObjectScore& o) { return o.box_iou.projection_mean; });
  summary.box_iou.projection_max = mean([](const ObjectScore& o) { return o.box_iou.projection_max; });
  summary.box_iou.labeloctomap = mean([](const ObjectScore& o) { return o.box_iou.labeloctomap; });
  for (const auto& o : objects)
    if (o.iou_3d.labeloctomap > o.iou_3d.projection_max) ++summary.labeloctomap_beats_projection_max;
  return summary;
}

ScoreSummary summarizeAll(const std::vector<EvaluationReport>& reports) {
  std::vector<ObjectScore> objects;
  for (const auto& report : reports) objects.insert(objects.end(), report.objects.begin(), report.objects.end());
  return summarize(objects);
}

void checkMapMatchesSequence(const LabelMap& map, const Sequence& sequence,
                             const std::string& map_file) {
  const std::string file = orDefault(map_file, "(map)");
  if (map.numLabels() != sequence.labels.size())
    throw Error(file, "labels",
                std::to_string(sequence.labels.size()) +
                    (sequence.labels.size() == 1 ? " label" : " labels") + " (the sequence's)",
                std::to_string(map.numLabels()) + (map.numLabels() == 1 ? " label" : " labels"));
  for (int k = 0; k < map.numLabels(); ++k)
    if (map.labels().at(k).name != sequence.labels.at(k).name)
      throw Error(file, "labels[" + std::to_string(k) + "]",
                  "the sequence's label \"" + sequence.labels.at(k).name + "\"",
                  "\"" + map.labels().at(k).name + "\"");
  // Poses and boxes in another world frame place the map elsewhere (an
  // "odom" map scored against boxes in "map"); a map of before the record,
  // or with no frame fused yet, cannot tell.
  const WorldFrameRecord& world = map.worldFrame();
  if (world.recorded && !world.frame_id.empty() && world.frame_id != sequence.frame_id)
    throw Error(file, "world frame",
                "the sequence's frame_id \"" + sequence.frame_id + "\" (" +
                    (sequence.root / "sequence.json").string() +
                    "): poses in one world frame are not coordinates of another",
                "\"" + world.frame_id + "\", the frame the map's fused poses were in");
}

MapFit mapFitOf(const LabelMap& map, const Sequence& sequence, int stride) {
  MapFit fit;
  if (sequence.frames.empty() || stride < 1) return fit;
  const size_t last = sequence.frames.size() - 1;
  std::vector<size_t> frames = {0, last / 2, last};
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  const double max_range = map.parameters().max_range;
  for (const size_t index : frames) {
    const FrameRecord& record = sequence.frames[index];
    const CameraIntrinsics& camera = sequence.cameraOf(index);
    DepthImage depth;
    try {
      depth = readDepthImage(sequence.pathOf(record.depth), camera.depth_scale);
    } catch (const std::exception&) {
      continue;  // validate and fusion name it; the other frames still tell
    }
    for (int v = stride / 2; v < depth.height; v += stride)
      for (int u = stride / 2; u < depth.width; u += stride) {
        const float z = depth.at(u, v);
        if (!(z > 0.f) || !std::isfinite(z)) continue;
        const Eigen::Vector3d in_camera = camera.backProject(u, v, z);
        if (max_range > 0.0 && in_camera.norm() > max_range) continue;
        ++fit.depths;
        if (map.voxelAt(record.T_world_camera * in_camera).occupied) ++fit.occupied;
      }
  }
  return fit;
}

std::string poorMapFitWarning(const MapFit& fit, const std::string& map_file) {
  if (fit.depths == 0 || fit.fraction() >= kPoorMapFit) return {};
  return map_file + ": only " +
         std::to_string(static_cast<int>(std::round(100.0 * fit.fraction()))) +
         "% of the sequence's depths (" + std::to_string(fit.depths) +
         " sampled in its first, middle and last frames) fall on occupied voxels of the map: "
         "was it fused from another sequence, or with other poses?";
}

EvaluationReport evaluate(const Sequence& sequence, const Annotations& annotations, const LabelMap& map,
                          const EvaluationOptions& options, const EvaluationProgressFn& progress) {
  checkAnnotationsForSequence(sequence, annotations, options.annotations_file);
  checkMapAgainstSequence(map, sequence, options.map_file);

  std::vector<GroundTruthBox> boxes = annotations.boxes;
  std::sort(boxes.begin(), boxes.end(),
            [](const GroundTruthBox& a, const GroundTruthBox& b) { return a.label < b.label; });
  std::vector<int> labels;
  for (const auto& box : boxes) labels.push_back(box.label);

  EvaluationReport report;
  report.sequence = sequenceName(sequence.root);
  report.resolution = map.parameters().resolution;
  report.max_range = map.parameters().max_range;
  report.occupancy_threshold = map.parameters().occupancy_threshold;
  report.p_miss = map.parameters().p_miss;
  report.iou_mode = options.iou_mode;
  report.candidates = options.fusion.candidates;
  if (report.candidates) {  // as a set: ascending, once each
    std::sort(report.candidates->begin(), report.candidates->end());
    report.candidates->erase(std::unique(report.candidates->begin(), report.candidates->end()),
                             report.candidates->end());
  }
  report.box_name_warnings = boxNameWarnings(annotations, sequence.labels,
                                             orDefault(options.annotations_file, "(annotations)"),
                                             (sequence.root / "sequence.json").string());
  report.warnings.insert(report.warnings.end(), report.box_name_warnings.begin(),
                         report.box_name_warnings.end());
  if (report.candidates) {
    std::string list;
    for (const int c : *report.candidates) list += (list.empty() ? "" : ",") + std::to_string(c);
    for (size_t i = 0; i < annotations.boxes.size(); ++i) {
      const int label = annotations.boxes[i].label;
      if (std::binary_search(report.candidates->begin(), report.candidates->end(), label)) continue;
      // A map fused earlier with other candidates (score --map --candidates)
      // may hold the label: only the baselines cannot.
      const FusedCandidates& fused = map.fusedCandidates();
      const bool map_may_hold =
          !fused.recorded || !fused.labels ||
          std::binary_search(fused.labels->begin(), fused.labels->end(), label);
      const std::string box = orDefault(options.annotations_file, "(annotations)") + ": boxes[" +
                              std::to_string(i) + "] is of label " + std::to_string(label) + " (" +
                              sequence.labels.at(label).name +
                              "), which is not among the candidates " + list;
      report.warnings.push_back(
          map_may_hold
              ? box +
                    ": no pixel of the projection baselines and the 2D metrics can take that "
                    "label, so they score 0 for it, while " +
                    orDefault(options.map_file, "the map") +
                    (fused.recorded ? " was fused with it"
                                    : " may hold it (it does not record its candidates)") +
                    ": the comparison is not matched (leave out --candidates to use the map's)"
              : box +
                    ": no voxel or pixel can take that label, so it scores 0 in every column "
                    "and pulls the means down");
    }
  }

  for (std::string& warning : emptyBoxWarnings(
           annotations, sequence.labels, map, orDefault(options.annotations_file, "(annotations)")))
    report.warnings.push_back(std::move(warning));

  detail::FrameScan scan = detail::scanFrames(sequence, map, labels, options, progress);
  if (scan.views.empty())
    throw Error((sequence.root / "sequence.json").string(), "frames[].view",
                "at least one frame with view: true among the frames scored", "none");
  report.views = scan.views;

  const double resolution = report.resolution;
  // Boxes are fitted level with the scene, as the studio fits them: a world
  // that is the first camera's frame would otherwise tilt every box by its
  // pitch. The sequence's poses stand in for a map that records no camera.
  const SceneLevel level = sceneLevelOf(map, camerasUpOf(sequence));
  // The projection baselines' boxes are levelled by what the views see (the
  // same up, levelled by the largest plane of every view's points), not by
  // the map scored: its voxels change with its threshold, p_miss or frames,
  // and the baselines of one sequence must not change with them.
  const SceneLevel views_level = sceneLevel(scan.view_centres, camerasUpOf(sequence), resolution);
  EvaluationProgress step{"scoring", 0, boxes.size()};
  for (const auto& box : boxes) {
    ObjectScore object;
    object.label = box.label;
    object.name = sequence.labels.at(box.label).name;
    object.ground_truth = box.box;

    const std::vector<VoxelKey> mapped = map.voxelsOfLabel(box.label);
    object.voxels = mapped.size();
    object.labeloctomap_volumes = voxelIouVolumes(mapped, resolution, box.box, options.iou_mode);
    object.iou_3d.labeloctomap = object.labeloctomap_volumes.iou();
    object.box_iou.labeloctomap = fittedBoxIou(
        mapped, resolution, box.box, options.cluster_tolerance_voxels, level, &object.fitted_box);
    for (const auto& view : scan.view_voxels) {
      const std::vector<VoxelKey>& projected = view.at(box.label);
      object.per_view.push_back(voxelIou(projected, resolution, box.box, options.iou_mode));
      object.per_view_box_iou.push_back(fittedBoxIou(
          projected, resolution, box.box, options.cluster_tolerance_voxels, views_level));
    }
    meanAndMax(object.per_view, object.iou_3d.projection_mean, object.iou_3d.projection_max);
    meanAndMax(object.per_view_box_iou, object.box_iou.projection_mean, object.box_iou.projection_max);
    report.objects.push_back(std::move(object));
    ++step.done;
    if (progress && !progress(step)) throw EvaluationCancelled();
  }
  // A box whose label neither the map nor any view holds scores 0 in every
  // column, whatever the methods: boxes of another scene, or a label the
  // segmentation never gives. (An object without depth, a transparent one,
  // still has its pixels; a label left out by the candidates is said above.)
  {
    std::set<int> mapped_labels;
    for (const ObjectScore& object : report.objects)
      if (object.voxels > 0) mapped_labels.insert(object.label);
    std::vector<std::string> nowhere;
    for (size_t i = 0; i < annotations.boxes.size(); ++i) {  // in the file's order
      const int label = annotations.boxes[i].label;
      if (mapped_labels.count(label) || scan.labels_in_views.count(label)) continue;
      if (report.candidates &&
          !std::binary_search(report.candidates->begin(), report.candidates->end(), label))
        continue;
      nowhere.push_back("boxes[" + std::to_string(i) + "] (label " + std::to_string(label) + ", " +
                        sequence.labels.at(label).name + ")");
    }
    if (!nowhere.empty()) {
      const std::string list = listed(nowhere);
      const bool one = nowhere.size() == 1;
      report.warnings.push_back(
          orDefault(options.annotations_file, "(annotations)") + ": " + list + ": no voxel of " +
          orDefault(options.map_file, "the map") + " and no pixel of the views scored has " +
          (one ? "its label" : "their labels") + ", so " + (one ? "it scores" : "they score") +
          " 0 in every column. Are the boxes of another scene, or is the label one the "
          "segmentation never gives?");
    }
  }
  report.summary = summarize(report.objects);
  if (scan.confusion && scan.confusion->total() > 0) report.metrics_2d = scan.confusion->metrics();
  if (scan.confusion_candidates && scan.confusion_candidates->total() > 0)
    report.metrics_2d_candidates = scan.confusion_candidates->metrics();
  report.metrics_2d_excluded_frames = scan.excluded_2d;
  if (!report.metrics_2d && !scan.excluded_2d.empty())
    report.metrics_2d_not_scored = kMetrics2dFromLabels;
  else if (!report.metrics_2d && scan.placeholder_labels_2d > 0)
    report.metrics_2d_not_scored = kMetrics2dPlaceholders;
  return report;
}

}  // namespace lom
