#pragma once
// Scoring a labelled map against ground-truth boxes (the paper's section V.B):
// per-object IU_3d and box IU of LabelOctoMap and of the single-view projection
// baseline, plus the 2D metrics of section V.A. Definitions: docs/evaluation.md.
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lom/annotations.hpp"
#include "lom/error.hpp"
#include "lom/fusion.hpp"
#include "lom/geometry.hpp"
#include "lom/label_map.hpp"
#include "lom/metrics_2d.hpp"
#include "lom/sequence.hpp"

namespace lom {

enum class IouMode {
  Exact,   // each voxel counts with the exact volume of its cube inside the box
  Center,  // each voxel counts with its full volume when its centre is inside the box
};
[[nodiscard]] const char* iouModeName(IouMode mode);  // "exact" | "center"
[[nodiscard]] std::optional<IouMode> parseIouMode(const std::string& name);

struct EvaluationOptions {
  // Candidates and frame range apply to fusion, the projection baseline and the
  // 2D metrics alike; the map parameters are used when the map is fused here.
  FusionOptions fusion;
  IouMode iou_mode = IouMode::Exact;
  // Box fit: voxels whose centres are at most this many voxel edges apart are
  // in the same cluster; only the largest cluster is boxed.
  double cluster_tolerance_voxels = 2.0;
  // Scoring a map fused earlier (ScoreInputs::map) whose file records the
  // candidates it was fused with (FusedCandidates): use those for the
  // projection baselines and the 2D metrics instead of fusion.candidates, so
  // that both sides of the comparison saw the same labels.
  bool candidates_from_map = false;
  // Only for error messages.
  std::string annotations_file;
  std::string map_file;
};

// The volumes behind a voxel set's IU_3d against a box, in cubic metres.
struct IouVolumes {
  double predicted = 0.0;      // v_pred: the voxels' volume
  double ground_truth = 0.0;   // v_gt: the box's volume
  double true_positive = 0.0;  // v_tp: the voxels' volume inside the box, as `mode` counts it
  [[nodiscard]] double falsePositive() const { return predicted - true_positive; }     // v_fp
  [[nodiscard]] double falseNegative() const { return ground_truth - true_positive; }  // v_fn
  // v_tp / (v_tp + v_fp + v_fn), in [0, 1]; 0 for no voxels.
  [[nodiscard]] double iou() const;
};
struct MethodScores {
  double projection_mean = 0.0;
  double projection_max = 0.0;
  double labeloctomap = 0.0;
};

struct ObjectScore {
  int label = 0;
  std::string name;
  size_t voxels = 0;              // LabelOctoMap voxels of the label (finest resolution)
  MethodScores iou_3d;
  IouVolumes labeloctomap_volumes;  // the terms of LabelOctoMap's IU_3d
  std::vector<double> per_view;   // projection IU_3d of each view, in view order
  MethodScores box_iou;
  std::vector<double> per_view_box_iou;
  OrientedBox ground_truth;
  std::optional<OrientedBox> fitted_box;  // fitted to the LabelOctoMap voxels (none when empty)
};

struct ScoreSummary {
  size_t objects = 0;
  MethodScores iou_3d;   // means over the objects
  MethodScores box_iou;
  size_t labeloctomap_beats_projection_max = 0;  // objects with LabelOctoMap IU_3d > Projection (Max)
};
[[nodiscard]] ScoreSummary summarize(const std::vector<ObjectScore>& objects);

// How well a map fits a sequence's depths: of the valid depths of the sampled
// frames (every `stride`-th pixel of every `stride`-th row) that lie within
// the map's max range, how many fall on an occupied voxel of the map. A map
// fused from the sequence scores high (its surfaces are where the depths
// are); a map of another scene, or of the same scene in another world frame,
// scores near zero.
struct MapFit {
  size_t depths = 0;    // valid depths within the map's max range, sampled
  size_t occupied = 0;  // ... that fall on an occupied voxel
  [[nodiscard]] double fraction() const {
    return depths ? static_cast<double>(occupied) / static_cast<double>(depths) : 0.0;
  }
};

struct EvaluationReport {
  std::string sequence;          // the sequence folder's name
  double resolution = 0.0;       // of the map; also used by the projection baseline
  double max_range = 0.0;
  double occupancy_threshold = 0.0;
  double p_miss = 0.0;  // of the map
  // The first and last (inclusive) frames fused into the map when it was
  // fused from the sequence (score without --map, the studio's own fusion).
  std::optional<std::pair<size_t, size_t>> fused_frames;
  // The segmenter model those frames ran through when they had no proba
  // image (--segmenter); empty when none.
  std::string segmenter;
  IouMode iou_mode = IouMode::Exact;
  std::optional<std::vector<int>> candidates;
  std::vector<size_t> views;     // frame indices of the views (frames with view: true)
  std::vector<ObjectScore> objects;  // by ascending label
  ScoreSummary summary;
  // Over all frames with both a ground-truth label image and a proba image,
  // except those whose proba was made from that label image.
  std::optional<Metrics2d> metrics_2d;             // argmax of the probabilities
  std::optional<Metrics2d> metrics_2d_candidates;  // argmax after candidates (when given)
  // Frames with both images left out of the 2D metrics because their proba was
  // made from their own label image (proba_from_label): the argmax would
  // reproduce the ground truth and score 100 %.
  std::vector<size_t> metrics_2d_excluded_frames;
  // Why the 2D metrics are absent although frames have both images (every one
  // was left out); empty otherwise. One sentence, for reports and the terminal.
  std::string metrics_2d_not_scored;
  // When scoreSequence fused the map (no map given): the fused frames' stats
  // summed, and the frames with depth points outside the map's extent
  // (FrameStats::outside_map_pixels), which the map left out.
  FrameStats fusion_totals;
  std::vector<size_t> frames_outside_map;
  // Scored with a map from a file (score --map): how well it fits the
  // sequence's depths (mapFitOf); poor fits are warned about.
  std::optional<MapFit> map_fit;
  // ... and how its candidates compare with the baselines' (one sentence
  // each, empty when there is nothing to say): a warning when the baselines
  // used other candidates than the map was fused with (its file records
  // them), a note when they took the map's (candidates_from_map).
  std::string map_candidates_warning;
  std::string map_candidates_note;
  // Boxes whose name in the annotations file is not the name of their label
  // in the sequence (boxes drawn for another label numbering?), one sentence
  // each. Objects are scored, and named in the report, by the sequence's label.
  std::vector<std::string> box_name_warnings;
  // The map file scored (score --map); empty when the map was fused from the
  // sequence with the report's settings.
  std::string map_file;
  // Everything that bears on reading the scores, one sentence each, written
  // into the reports (report.json "warnings", report.md) and said by `score`:
  // the box name warnings, a map fused with other candidates than the
  // baselines use, boxes whose label is not among the candidates (they can
  // only score 0), a map that does not fit the sequence's depths, and what
  // the caller adds (score: depths outside the map or beyond max range).
  std::vector<std::string> warnings;
};

// The summary over all objects of several reports (a batch).
[[nodiscard]] ScoreSummary summarizeAll(const std::vector<EvaluationReport>& reports);

struct EvaluationProgress {
  std::string stage;  // "fusing", "projecting", "scoring"
  size_t done = 0;
  size_t total = 0;
};
// Returning false cancels: the evaluation throws EvaluationCancelled.
using EvaluationProgressFn = std::function<bool(const EvaluationProgress&)>;

class EvaluationCancelled : public std::runtime_error {
 public:
  EvaluationCancelled() : std::runtime_error("evaluation cancelled") {}
};

// A box that cannot be scored against a sequence with `label_count` labels:
// its label is not an object label (1..label_count-1), or an earlier box
// (`boxed_before`) has it already. In box order.
struct UnscorableBox {
  size_t index = 0;
  int label = 0;
  std::optional<size_t> boxed_before;
};
[[nodiscard]] std::vector<UnscorableBox> unscorableBoxes(const Annotations& annotations,
                                                         int label_count);

// The annotations' frame_id when it is not the sequence's (score refuses
// such boxes), naming `annotations_file` and the sequence's sequence.json.
[[nodiscard]] std::optional<Problem> frameIdProblem(const Sequence& sequence,
                                                    const Annotations& annotations,
                                                    const std::string& annotations_file);

// One problem per box that cannot be scored against labels 0..label_count-1
// of `labelled` ("the sequence", "the map", a file): its label is not an
// object label, or an earlier box has it. In box order; empty when every box
// can be scored (the want of any box is not among them).
[[nodiscard]] std::vector<Problem> boxLabelProblems(const Annotations& annotations, int label_count,
                                                    const std::string& annotations_file,
                                                    const std::string& labelled);

// Throws lom::Error (naming options.annotations_file and the field) when the
// annotations' frame_id differs from the sequence's or a box's label is not an
// object label of the sequence.
void checkAnnotationsForSequence(const Sequence& sequence, const Annotations& annotations,
                                 const std::string& annotations_file);

// One sentence per box whose name in `annotations_file` is not the name of
// its label in `labels` (read from `labels_file`): boxes drawn for another
// label numbering? The box is scored, and named, as its label. Boxes that
// cannot be scored (unscorableBoxes) are not scored: they get no sentence.
[[nodiscard]] std::vector<std::string> boxNameWarnings(const Annotations& annotations,
                                                       const LabelSet& labels,
                                                       const std::string& annotations_file,
                                                       const std::string& labels_file);

// Throws lom::Error (naming the file and the field) when there is no box, or
// for the first of boxLabelProblems.
void checkBoxLabels(const Annotations& annotations, int label_count,
                    const std::string& annotations_file, const std::string& labelled);
// Throws lom::Error naming `map_file` and the field "labels" (or "labels[k]")
// unless the map has the sequence's labels, with the same names in the same
// order (a map fused from another sequence's label set), or the field "world
// frame" when the map records fused poses of another world frame than the
// sequence's frame_id.
void checkMapMatchesSequence(const LabelMap& map, const Sequence& sequence,
                             const std::string& map_file);

// Samples the sequence's first, middle and last frames (unreadable depth
// images are left out). Below kPoorMapFit, `score --map` and the studio warn
// that the map may not be of the sequence.
[[nodiscard]] MapFit mapFitOf(const LabelMap& map, const Sequence& sequence, int stride = 8);
inline constexpr double kPoorMapFit = 0.2;
// The warning for a fit below kPoorMapFit, naming `map_file` (one sentence,
// to which callers add what it means for them); empty when the fit is good
// or no depth could be sampled.
[[nodiscard]] std::string poorMapFitWarning(const MapFit& fit, const std::string& map_file);

// What a report of a map read from `map_file` says about that file, as
// `score --map` reports it: its name (report.map_file), how well it fits the
// sequence's depths (report.map_fit; a warning when poorly), and its fusion
// candidates against the baselines' (a warning when they differ, a note when
// the baselines took the map's: `candidates_from_map`), and a warning when
// the map records another number of fused frames than the frames scored,
// [first_frame, last_frame) clipped to the sequence (a map fused from some of
// them, or continued over them twice: the comparison is not matched), and
// when the map's probabilities came from elsewhere than those the baselines
// read with `segmenter` (FusedEvidence: a map fused with a segmenter, scored
// against the frames' own probabilities).
void describeMapFile(EvaluationReport& report, const LabelMap& map, const Sequence& sequence,
                     const std::string& map_file, bool candidates_from_map, size_t first_frame = 0,
                     size_t last_frame = static_cast<size_t>(-1),
                     const Segmenter* segmenter = nullptr);

// Scores every annotated object. Resolution and max range come from `map`.
// Throws lom::Error for unusable inputs (see checkAnnotationsForSequence; a map
// with another label set or no occupied voxel; no view among the frames).
[[nodiscard]] EvaluationReport evaluate(const Sequence& sequence, const Annotations& annotations,
                                        const LabelMap& map, const EvaluationOptions& options,
                                        const EvaluationProgressFn& progress = {});

[[nodiscard]] IouVolumes voxelIouVolumes(const std::vector<VoxelKey>& voxels, double resolution,
                                         const OrientedBox& box, IouMode mode);
// The volumes of `voxels` voxels of edge `resolution` whose shares inside the
// box (voxelSharesInBox) sum to `share_sum`. v_gt as `mode` counts it: exact,
// the box's volume; center, the volume of the grid voxels whose centres are
// inside the box, so that both sides count whole voxels by one test and v_tp
// never exceeds v_gt. v_tp is at most each volume (the shares' sum may pass
// them in the last bits).
[[nodiscard]] IouVolumes iouVolumesOf(double share_sum, size_t voxels, double resolution,
                                      const OrientedBox& box, IouMode mode);
// IU_3d of a voxel set against a box (the paper's equation; 0 for no voxels).
[[nodiscard]] double voxelIou(const std::vector<VoxelKey>& voxels, double resolution,
                              const OrientedBox& box, IouMode mode);
// The share of each voxel (a cube of edge `resolution` centred at each of
// `centres`) that IU_3d counts inside the box: exact, the share of its volume
// inside; center, 1 when its centre is inside, else 0. In the centres' order.
[[nodiscard]] std::vector<double> voxelSharesInBox(const std::vector<Eigen::Vector3d>& centres,
                                                   double resolution, const OrientedBox& box,
                                                   IouMode mode);

struct ScoreInputs {
  std::filesystem::path sequence;     // folder or sequence.json
  std::filesystem::path annotations;  // annotations.json
  std::optional<std::filesystem::path> map;  // a fused .ot; fused from the sequence when absent
  std::optional<double> occupancy_threshold;  // re-thresholds a loaded map
};

// Loads the sequence and the annotations of `inputs` and checks them against
// each other (checkAnnotationsForSequence) as scoreSequence does before its
// fusion; throws lom::Error naming the annotations file and the field.
void checkAnnotationsFor(const ScoreInputs& inputs);

// Loads the inputs, fuses (or loads) the map and evaluates. Annotations are
// checked against the sequence before the fusion starts.
[[nodiscard]] EvaluationReport scoreSequence(const ScoreInputs& inputs, const EvaluationOptions& options,
                                             const EvaluationProgressFn& progress = {});

// A batch list: one sequence per line, "SEQ ANNOTATIONS [MAP.ot]", paths
// relative to the list's folder, double quotes around paths with spaces,
// blank lines and lines starting with # ignored.
struct BatchEntry {
  ScoreInputs inputs;
  std::string name;  // the sequence folder's name: its report goes to DIR/<name>/
  size_t line = 0;
};
// Throws lom::Error naming the list file and the line for malformed lines,
// missing files and two sequences with the same folder name.
[[nodiscard]] std::vector<BatchEntry> readBatchList(const std::filesystem::path& list);

// The name under which a sequence folder is reported.
[[nodiscard]] std::string sequenceName(const std::filesystem::path& sequence_folder_or_json);

}  // namespace lom
