#include "evaluation_frames.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_set>

#include "lom/segmenter.hpp"
#include "lom/error.hpp"

namespace lom::detail {

namespace {

std::uint64_t pack(const VoxelKey& key) {
  return (static_cast<std::uint64_t>(key.x) << 32) | (static_cast<std::uint64_t>(key.y) << 16) | key.z;
}

VoxelKey unpack(std::uint64_t packed) {
  return {static_cast<std::uint16_t>(packed >> 32), static_cast<std::uint16_t>(packed >> 16),
          static_cast<std::uint16_t>(packed)};
}

// The argmax for the 2D metrics: a pixel that gives no probability to any
// candidate gets the lowest candidate (the argmax of the equal probabilities
// the fusion gives it), so that it still counts, as a mistake unless that is
// its true label. Projections use FrameEvidence::argmax, which gives it none.
class ArgmaxOf {
 public:
  explicit ArgmaxOf(const FrameEvidence& evidence)
      : evidence_(evidence), buffer_(static_cast<size_t>(evidence.numLabels())) {}
  int operator()(int u, int v) {
    evidence_.probabilities(u, v, buffer_.data());
    return static_cast<int>(std::max_element(buffer_.begin(), buffer_.end()) - buffer_.begin());
  }

 private:
  const FrameEvidence& evidence_;
  std::vector<float> buffer_;
};

// Background voxels of the views enough to level the baselines' boxes by
// (findLevelPlane asks for at least 200 on its plane).
constexpr size_t kMinLevelVoxels = 400;

// The voxels each scored label occupies when only this frame's argmax labels
// are projected: the hits of the fusion (same range rule, same keys), one label each.
std::map<int, std::vector<VoxelKey>> projectView(
    const Sequence& sequence, size_t index, const FrameData& frame, const LabelMap& map,
    const std::vector<int>& slot_of_label, const std::vector<int>& scored_labels,
    const EvaluationOptions& options, std::unordered_set<std::uint64_t>& seen,
    std::unordered_set<std::uint64_t>& seen_background, std::vector<char>& label_seen) {
  const FrameEvidence evidence = makeEvidence(sequence, index, frame, options.fusion);
  const CameraIntrinsics& camera = sequence.cameraOf(index);
  const Eigen::Isometry3d& T_world_camera = sequence.frames[index].T_world_camera;
  const Eigen::Vector3d origin = T_world_camera.translation();
  const double max_range = map.parameters().max_range;
  const DepthImage& depth = frame.depth;
  if (evidence.width() != depth.width || evidence.height() != depth.height)
    throw Error((sequence.root / "sequence.json").string(), "frames[" + std::to_string(index) + "]",
                "label evidence of the depth image's size " + std::to_string(depth.width) + "x" +
                    std::to_string(depth.height),
                std::to_string(evidence.width()) + "x" + std::to_string(evidence.height()));

  std::vector<std::unordered_set<std::uint64_t>> keys(scored_labels.size());
  size_t unseen = static_cast<size_t>(std::count(label_seen.begin(), label_seen.end(), 0));
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const float z = depth.at(u, v);
      const bool measured = z > 0.f && std::isfinite(z);
      // A pixel without depth still tells which labels the view holds, as long
      // as some scored label has not been seen yet.
      if (!measured && unseen == 0) continue;
      const int label = evidence.argmax(u, v);
      if (label < 0) continue;  // no probability for any candidate
      const int slot = slot_of_label[static_cast<size_t>(label)];
      if (slot >= 0 && !label_seen[static_cast<size_t>(slot)]) {
        label_seen[static_cast<size_t>(slot)] = 1;
        --unseen;
      }
      if (!measured) continue;
      const Eigen::Vector3d point = T_world_camera * camera.backProject(u, v, z);
      if (max_range > 0.0 && (point - origin).norm() > max_range) continue;
      try {
        const std::uint64_t key = pack(map.keyOf(point));
        seen.insert(key);
        if (label == 0) seen_background.insert(key);
        if (slot >= 0) keys[static_cast<size_t>(slot)].insert(key);
      } catch (const Error&) {
        // Outside the octree's extent: the fusion drops such points too.
      }
    }
  }
  std::map<int, std::vector<VoxelKey>> voxels;
  for (size_t s = 0; s < scored_labels.size(); ++s) {
    std::vector<VoxelKey>& list = voxels[scored_labels[s]];
    list.reserve(keys[s].size());
    for (std::uint64_t packed : keys[s]) list.push_back(unpack(packed));
    std::sort(list.begin(), list.end());
  }
  return voxels;
}

void addToConfusion(const Sequence& sequence, size_t index, const FrameData& frame,
                    const FusionOptions& fusion, ConfusionMatrix& confusion) {
  const FrameEvidence evidence = makeEvidence(sequence, index, frame, fusion);
  const LabelImage& truth = *frame.label;
  if (evidence.width() != truth.width || evidence.height() != truth.height)
    throw Error((sequence.root / "sequence.json").string(),
                "frames[" + std::to_string(index) + "].label",
                "a label image of the proba image's size " + std::to_string(evidence.width()) + "x" +
                    std::to_string(evidence.height()),
                std::to_string(truth.width) + "x" + std::to_string(truth.height));
  ArgmaxOf argmax(evidence);
  for (int v = 0; v < truth.height; ++v)
    for (int u = 0; u < truth.width; ++u) confusion.add(truth.at(u, v), argmax(u, v));
}

}  // namespace

FrameScan scanFrames(const Sequence& sequence, const LabelMap& map,
                     const std::vector<int>& scored_labels, const EvaluationOptions& options,
                     const EvaluationProgressFn& progress) {
  const size_t first = std::min(options.fusion.first_frame, sequence.frames.size());
  const size_t last = std::min(options.fusion.last_frame, sequence.frames.size());
  std::vector<int> slot_of_label(static_cast<size_t>(sequence.labels.size()), -1);
  for (size_t s = 0; s < scored_labels.size(); ++s)
    slot_of_label[static_cast<size_t>(scored_labels[s])] = static_cast<int>(s);

  FusionOptions without_candidates = options.fusion;
  without_candidates.candidates.reset();

  FrameScan scan;
  std::vector<size_t> to_load;
  // A proba made from the frame's own label image would score 100 % against it.
  // (A segmenter replaces such a proba with its own: then the frame is scored.)
  const auto ownLabelsProba = [&](const FrameRecord& record) {
    return record.proba_from_label && !record.proba.empty() && !options.fusion.segmenter;
  };
  std::vector<char> scores_2d(last, 0);  // frames whose images the 2D metrics compare
  for (size_t i = first; i < last; ++i) {
    const FrameRecord& record = sequence.frames[i];
    const bool has_proba = !record.proba.empty() || options.fusion.segmenter;
    // A placeholder label image (an import without labels) is no ground truth.
    const bool scored_2d = !record.label.empty() && !record.label_placeholder && has_proba;
    if (has_proba && !record.label.empty() && record.label_placeholder)
      ++scan.placeholder_labels_2d;
    if (scored_2d && ownLabelsProba(record)) {
      scan.excluded_2d.push_back(i);
      if (record.view) to_load.push_back(i);
      continue;
    }
    scores_2d[i] = scored_2d;
    if (record.view || scored_2d) to_load.push_back(i);
  }
  std::unordered_set<std::uint64_t> seen;  // every view's voxels, any label
  std::unordered_set<std::uint64_t> seen_background;  // those of the background's pixels
  std::vector<char> label_seen(scored_labels.size(), 0);
  EvaluationProgress report{"projecting", 0, to_load.size()};
  for (size_t i : to_load) {
    const FrameRecord& record = sequence.frames[i];
    const FrameData frame = loadFrameWithSegmenter(sequence, i, options.fusion.segmenter.get());
    if (record.view) {
      scan.views.push_back(i);
      scan.view_voxels.push_back(projectView(sequence, i, frame, map, slot_of_label, scored_labels,
                                             options, seen, seen_background, label_seen));
    }
    if (scores_2d[i] && frame.label && frame.proba) {
      if (!scan.confusion) scan.confusion.emplace(sequence.labels.size());
      addToConfusion(sequence, i, frame, without_candidates, *scan.confusion);
      if (options.fusion.candidates) {
        if (!scan.confusion_candidates) scan.confusion_candidates.emplace(sequence.labels.size());
        addToConfusion(sequence, i, frame, options.fusion, *scan.confusion_candidates);
      }
    }
    ++report.done;
    if (progress && !progress(report)) throw EvaluationCancelled();
  }
  for (size_t s = 0; s < scored_labels.size(); ++s)
    if (label_seen[s]) scan.labels_in_views.insert(scored_labels[s]);
  // The level of the baselines' boxes is the plane the objects rest on,
  // which is background: where the objects hide much of the floor (three
  // views), a plane across their tops held more voxels than the floor (synth
  // seed 7: 1832 against 1437) and cut every box short. Every label's voxels
  // when the views hold hardly any background.
  const std::unordered_set<std::uint64_t>& level_voxels =
      seen_background.size() >= kMinLevelVoxels ? seen_background : seen;
  std::vector<std::uint64_t> ordered(level_voxels.begin(), level_voxels.end());
  std::sort(ordered.begin(), ordered.end());  // the same scene gives the same level
  scan.view_centres.reserve(ordered.size());
  for (const std::uint64_t key : ordered) scan.view_centres.push_back(map.centerOf(unpack(key)));
  return scan;
}

}  // namespace lom::detail
