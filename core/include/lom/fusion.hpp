#pragma once
// Fusion of RGB-D frames with per-pixel label probabilities into a LabelMap,
// following the paper (sections III-IV). Semantics: docs/fusion.md.
#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lom/camera.hpp"
#include "lom/error.hpp"
#include "lom/images.hpp"
#include "lom/label_map.hpp"
#include "lom/sequence.hpp"

namespace lom {

class Segmenter;  // lom/segmenter.hpp

// Probabilities are clamped to [kProbabilityEpsilon, 1 - kProbabilityEpsilon]
// before logit so that no log-odds value is ever infinite.
inline constexpr double kProbabilityEpsilon = 1e-6;

// Per-pixel label evidence of one frame: log-odds logit(p_k) of every label k,
// from a probability image or a label image (one-hot with `label_confidence`),
// after restricting to class candidates when given.
class FrameEvidence {
 public:
  // Exactly one of proba / label must be set. Throws lom::Error on size mismatches.
  FrameEvidence(int num_labels, const ProbabilityImage* proba, const LabelImage* label,
                const std::optional<std::vector<int>>& candidates, double label_confidence);
  [[nodiscard]] int numLabels() const { return num_labels_; }
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  // Probabilities of pixel (u, v) after candidates and renormalisation (not
  // clamped). A pixel that gives no probability to any candidate gets the
  // same probability for each of them; false is returned for it (true for
  // every other pixel).
  bool probabilities(int u, int v, float* out) const;
  // logit of the clamped probabilities.
  void logOdds(int u, int v, float* out) const;
  // Argmax label of pixel (u, v) (ties to the lower id); -1 for a pixel that
  // gives no probability to any candidate (it has no label to project).
  [[nodiscard]] int argmax(int u, int v) const;

  // For fast paths: the probability image when it is used as is (no candidates),
  // so that only its channels need a logit per pixel; nullptr otherwise.
  [[nodiscard]] const ProbabilityImage* directProbabilities() const;
  // The class candidates given (nullopt: every label).
  [[nodiscard]] const std::optional<std::vector<int>>& candidates() const { return candidates_; }

 private:
  int num_labels_;
  int width_ = 0, height_ = 0;
  const ProbabilityImage* proba_;
  const LabelImage* label_;
  std::vector<char> allowed_;  // per label: 1 if candidate (or no candidates given)
  bool restricted_ = false;    // some label is not a candidate: renormalise each pixel
  std::optional<std::vector<int>> candidates_;
  double label_confidence_;
  std::vector<int> channel_of_label_;  // -1 when the label has no channel
};

struct FrameStats {
  size_t valid_pixels = 0;
  // Valid pixels farther from the camera than max range: their rays only
  // clear free space up to max range and add no hit. Counted by fuseSequence
  // (countDepthRanges), outside the integration; integrateFrame leaves it 0.
  size_t beyond_range_pixels = 0;
  // The largest distance from the camera of a measured pixel, in metres (fuseSequence).
  double farthest_range = 0.0;
  // Measured pixels (finite depth > 0) whose point lies outside the map's
  // extent (mapExtent): the map cannot hold them, so they add neither a hit
  // nor free space, and are not among valid_pixels. Counted by fuseSequence
  // (noteDepthRanges: measured pixels less valid ones), outside the
  // integration; integrateFrame leaves it 0.
  size_t outside_map_pixels = 0;
  size_t hit_voxels = 0;
  size_t miss_voxels = 0;
  double seconds = 0.0;
};

enum class IntegrationPath {
  Fast,       // pixels grouped by end voxel, one ray per end voxel, both cores, sorted tree pass
  Reference,  // every pixel casts its own ray into a hash set; straightforward and slow
};

enum class VectorKernels {
  Best,         // AVX-512 (with byte permutes, VBMI) or AVX2 kernels where the processor has them
  UpToAvx512F,  // AVX-512 foundation at most: no byte permutes
  UpToAvx2,     // AVX2 at most
  Baseline,  // the baseline x86-64 instructions only
};

// Voxel sizes that the command line and the studio fuse with, in metres, and
// the longest ray, in voxels (max range / resolution), that they accept: both
// bound the memory a frame needs (docs/fusion.md, "Limits of the command line").
inline constexpr double kMinFusionResolution = 0.002;
inline constexpr double kMaxFusionResolution = 1.0;
inline constexpr double kMaxFusionVoxelsPerRay = 1000.0;
// What fusing a frame takes per voxel its rays cross, at most, in bytes: the
// voxel's place in the frame's update streams and, for a voxel new to the map,
// its nodes (measured in docs/fusion.md, "Limits of the command line").
inline constexpr double kFusionBytesPerCrossedVoxel = 120.0;
// Of those, what a voxel the map already holds takes: its place in the miss
// stream and in the sort's spare buffer (two 24-byte updates).
inline constexpr double kFusionStreamBytesPerCrossedVoxel = 48.0;

struct IntegrationOptions {
  IntegrationPath path = IntegrationPath::Fast;
  // With an unlimited max range (<= 0) the farthest depth sets how long the
  // rays are, and with them the memory a frame needs: a frame with a depth
  // farther than this many voxels from the camera is refused (lom::Error,
  // field "depth") before it is integrated. 0 = no limit.
  double max_voxels_per_ray = kMaxFusionVoxelsPerRay;
  // A frame whose rays cross so many voxels that fusing it would take more
  // than this many bytes (kFusionBytesPerCrossedVoxel per voxel) is refused
  // (lom::Error, field "depth") before it changes the map. 0 = the memory
  // the system has available when the frame is fused (availableMemoryBytes);
  // a frame that could take more than 256 MiB is checked against it. Only
  // the fast path checks: the reference path is for tests and benchmarks.
  double frame_memory_limit_bytes = 0.0;
  int threads = 0;  // fast path worker threads; 0 = one per core
  // Fast path: which vector kernels may run (where the processor has them).
  // Every choice gives the same map to the last bit; the others are for checks.
  VectorKernels kernels = VectorKernels::Best;
  // Fast path: asked before the frame and between its phases (rays, memory
  // check, update streams, their merge); once it says true, the frame is
  // abandoned with FrameCancelled before the tree pass, leaving the map as it
  // was. The tree pass itself (about half of a fine room-scale frame) runs to
  // its end. Empty: never cancelled.
  std::function<bool()> cancelled;
};

// Thrown by integrateFrame when IntegrationOptions::cancel was set: the frame
// was not fused and the map is unchanged.
struct FrameCancelled : std::runtime_error {
  FrameCancelled() : std::runtime_error("the frame's fusion was cancelled") {}
};

// The memory this process can still take, in bytes: MemAvailable of
// /proc/meminfo and, under a limit on the address space (`ulimit -v`), no more
// than the limit leaves. nullopt when neither can be read.
[[nodiscard]] std::optional<double> availableMemoryBytes();

// Distances of a depth image's measured pixels from the camera, as fusion
// measures them against max range: pixel (u, v) at depth z is the point
// ((u - cx) z / fx, (v - cy) z / fy, z), at distance z sqrt(x^2 + y^2 + 1).
struct DepthRanges {
  size_t measured = 0;  // pixels with a finite depth > 0
  size_t beyond = 0;    // ... farther than max range (none when max range <= 0, unlimited)
  double farthest = 0.0;
};
[[nodiscard]] DepthRanges countDepthRanges(const CameraIntrinsics& camera, const DepthImage& depth,
                                           double max_range);

// The finest voxel size worth suggesting for rays of `max_range` metres: at
// least `resolution`, and coarse enough for a ray to cross at most 250 voxels
// (in steps of 5 mm). A map's memory grows with the free voxels its rays cross:
// a room fused at 1 cm up to 10 m takes gigabytes, at 4 cm tens of megabytes.
[[nodiscard]] double suggestedResolutionForRange(double max_range, double resolution);

// A fused frame's stats completed with its depths beyond max range, its
// farthest range (countDepthRanges) and its pixels outside the map's extent
// (from `stats.valid_pixels`, which integrateFrame set), as fuseSequence
// reports each frame.
void noteDepthRanges(FrameStats& stats, const CameraIntrinsics& camera, const DepthImage& depth,
                     double max_range);
// Adds a frame's stats to the totals of a fusion: counts and seconds summed,
// farthest_range the maximum.
void addFrameStats(FrameStats& totals, const FrameStats& frame);
// The fused frames' measured depths: those the map holds (valid_pixels) and
// those outside its extent.
[[nodiscard]] size_t measuredPixels(const FrameStats& totals);

// Whether max range (when limited) took more than half of the fused frames'
// measured depths: they mapped nothing, at most cleared free space, which the
// CLI and the studio say. (Against measured, not valid, depths: a depth
// beyond max range may also lie outside the map's extent.)
[[nodiscard]] bool mostDepthsBeyondMaxRange(const FrameStats& totals, double max_range);

// What the CLI and the studio say when even the farthest depth of the frames
// first..last-1 fused (`totals`) is nearer than depth cameras measure
// (kMinPlausibleMedianDepth): a wrong camera.depth_scale, or .npy depths not
// in metres, shrinks the map by that factor without any other sign. The
// warning (naming sequence.json and the field) without a prefix, or empty.
[[nodiscard]] std::string nearDepthWarning(const Sequence& sequence, size_t first, size_t last,
                                           const FrameStats& totals);

// The map's extent: OctoMap's 16-level keys reach kMapExtentVoxels voxels on
// either side of the origin on each axis, so a map holds the points whose every
// coordinate c satisfies -extent <= c < extent, extent = kMapExtentVoxels x
// resolution (327.68 m at 1 cm, 65.536 m at 2 mm). Sequences in a site or
// georeferenced frame can lie farther out: docs/fusion.md, "The map's extent".
inline constexpr double kMapExtentVoxels = 32768.0;
[[nodiscard]] inline double mapExtent(double resolution) { return kMapExtentVoxels * resolution; }
// Whether a map of `resolution` holds `point`: the very test that fusion makes
// on every point and camera centre.
[[nodiscard]] bool insideMapExtent(const Eigen::Vector3d& point, double resolution);
// "327.68 m either side of the origin on each axis at 0.01 m voxels", for messages.
[[nodiscard]] std::string describeMapExtent(double resolution);
// The finest voxel size, in whole millimetres, whose extent holds every
// coordinate up to `reach` metres from the origin.
[[nodiscard]] double resolutionForReach(double reach);
// Throws lom::Error naming sequence.json and frames[i].pose when the camera of
// a frame in [first, last) lies outside the extent of a map of `resolution`:
// such a frame cannot be fused (its rays would start outside the map).
void checkCamerasInsideMap(const Sequence& sequence, double resolution, size_t first = 0,
                           size_t last = static_cast<size_t>(-1));

// For a sequence before any voxel size is chosen (labeloctomap validate):
// cameras outside the extent at the coarsest voxel fusion takes
// (kMaxFusionResolution) can never be fused, a problem each; cameras outside
// the extent at the finest (kMinFusionResolution) need coarser voxels, which
// `warning` says (empty when all are inside).
struct CameraExtentCheck {
  std::vector<Problem> problems;
  std::string warning;
};
[[nodiscard]] CameraExtentCheck checkCameraExtents(const Sequence& sequence);

// Integrates one frame into `map` with the paper's rule (docs/fusion.md). Both
// paths give the same map (the fast one may differ in the last float bits of
// summed log-odds). Throws lom::Error (field "pose") when the camera lies
// outside the map's extent.
FrameStats integrateFrame(LabelMap& map, const CameraIntrinsics& camera,
                          const Eigen::Isometry3d& T_world_camera, const DepthImage& depth,
                          const FrameEvidence& evidence, const IntegrationOptions& integration = {});

// The checks of fusion settings that the command line and the studio share:
// each returns what is wrong (nothing when all is well), which the command
// line words for its options and the studio's Fusion panel for its fields.

// Rays longer than the limit: with a limited max range (> 0), max range /
// resolution voxels. An unlimited range (<= 0) is left to the depths.
struct RayLengthProblem {
  double voxels = 0.0;  // max range / resolution, rounded up
  double limit = kMaxFusionVoxelsPerRay;
};
[[nodiscard]] std::optional<RayLengthProblem> checkRayLength(double max_range, double resolution);

// A class candidate that is not a label of the sequence (0 to label_count - 1):
// the first such, in the order given. None when no candidates are given.
struct CandidateProblem {
  int label = 0;
  int label_count = 0;
};
[[nodiscard]] std::optional<CandidateProblem> checkCandidates(
    const std::optional<std::vector<int>>& candidates, const LabelSet& labels);

struct FusionOptions {
  MapParameters map;
  std::optional<std::vector<int>> candidates;  // labels known to be present
  double label_confidence = 0.9;  // one-hot confidence when a frame has only a label image
  IntegrationOptions integration;
  size_t first_frame = 0;
  size_t last_frame = static_cast<size_t>(-1);  // exclusive; clipped to the sequence
  // Runs on the colour image of every frame without a proba (docs/segmenter.md).
  std::shared_ptr<const Segmenter> segmenter;
};

struct FusionProgress {
  size_t frame_index = 0;  // index in the sequence of the frame just fused
  size_t done = 0;
  size_t total = 0;
  FrameStats stats;
  // The frames fused so far: counts and seconds summed, farthest_range their maximum.
  FrameStats totals;
};

// The images fusion reads of frame `index` besides its depth image: the proba
// image when it is fused as it is (an 8-bit one as its codes only), else the
// colour image when `segmenter` (may be null) runs on it
// (loadFrameWithSegmenter's rule), else the label image. The frame's other
// images are not opened: reading all of a 640x480 frame takes twice as long
// (docs/performance.md, "Reading frames").
[[nodiscard]] FrameParts fusionPartsOf(const Sequence& sequence, size_t index,
                                       const Segmenter* segmenter);

// Frame `index` as fusion reads it (fusionPartsOf), with the segmenter's
// probabilities where it runs. Throws lom::Error naming the file and field.
[[nodiscard]] FrameData loadFusionFrame(const Sequence& sequence, size_t index,
                                        const Segmenter* segmenter);

// Builds the evidence of a loaded frame (proba if present, else label image).
// Throws lom::Error naming the frame when it has neither.
[[nodiscard]] FrameEvidence makeEvidence(const Sequence& sequence, size_t index,
                                         const FrameData& frame, const FusionOptions& options);

// Fuses frames [first_frame, last_frame) of the sequence into a new map.
// `progress` (optional) is called after each frame; returning false cancels.
[[nodiscard]] LabelMap fuseSequence(const Sequence& sequence, const FusionOptions& options,
                                    const std::function<bool(const FusionProgress&)>& progress = {});
// The same into `map` (fused earlier, e.g. from another recording of the
// scene with the same labels), with the map's own parameters: options.map is
// not used. Fusing frames A then B this way gives the map of A and B fused at
// once. The caller checks that the labels and the world frame agree
// (lom::checkMapMatchesSequence).
void fuseSequenceInto(LabelMap& map, const Sequence& sequence, const FusionOptions& options,
                      const std::function<bool(const FusionProgress&)>& progress = {});
// The camera views fusing frames [first, last) of `sequence` records in a map
// (last is clipped to the sequence), to tell whether a map was fused from
// those frames (sameCameraViews).
[[nodiscard]] CameraViewRecord cameraViewsOf(const Sequence& sequence, size_t first = 0,
                                             size_t last = static_cast<size_t>(-1));
// Records the sequence's world frame (frame_id) in `map` before its frames
// are fused (LabelMap::noteWorldFrame); throws lom::Error naming
// sequence.json's frame_id when the map records another.
void noteSequenceWorldFrame(LabelMap& map, const Sequence& sequence);
// Where frame `index`'s probabilities come from when it is fused with
// `segmenter` (which may be null): the model's file name where it runs
// (segmenterRunsOn), "" for the frame's own; LabelMap::noteFusedEvidence
// records it.
[[nodiscard]] std::string evidenceSourceOf(const Sequence& sequence, size_t index,
                                           const Segmenter* segmenter);
// The record fusing frames [first, last) with `segmenter` makes
// (FusedEvidence): what the projection baselines of a score of those frames
// read, to compare with a map's.
[[nodiscard]] FusedEvidence evidenceOf(const Sequence& sequence, size_t first, size_t last,
                                       const Segmenter* segmenter);
// The mean up of the sequence's cameras (meanCameraUp of lom/level_plane.hpp):
// the stand-in for the up of a map fused from it that records no camera.
[[nodiscard]] std::optional<Eigen::Vector3d> camerasUpOf(const Sequence& sequence);

}  // namespace lom
