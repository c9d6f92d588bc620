#include "lom/fusion.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "fusion_internal.hpp"
#include "lom/error.hpp"
#include "lom/level_plane.hpp"
#include "lom/octree/label_octree.hpp"
#include "lom/segmenter.hpp"

namespace lom {

// ---------------------------------------------------------------------------
// FrameEvidence

FrameEvidence::FrameEvidence(int num_labels, const ProbabilityImage* proba, const LabelImage* label,
                             const std::optional<std::vector<int>>& candidates,
                             double label_confidence)
    : num_labels_(num_labels),
      proba_(proba),
      label_(proba ? nullptr : label),
      label_confidence_(label_confidence) {
  if (!proba_ && !label_)
    throw Error("", "frame", "a probability image or a label image", "neither");
  if (num_labels < 1 || num_labels > 256)
    throw Error("", "labels", "between 1 and 256 labels", std::to_string(num_labels));
  if (!(label_confidence > 0.0 && label_confidence < 1.0))
    throw Error("", "label_confidence", "a probability strictly between 0 and 1",
                std::to_string(label_confidence));
  allowed_.assign(static_cast<size_t>(num_labels), candidates ? 0 : 1);
  if (candidates) {
    for (int id : *candidates) {
      if (id < 0 || id >= num_labels)
        throw Error("", "candidates", "label ids between 0 and " + std::to_string(num_labels - 1),
                    std::to_string(id));
      allowed_[static_cast<size_t>(id)] = 1;
    }
    if (candidates->empty())
      throw Error("", "candidates", "at least one candidate label", "an empty list");
    restricted_ = std::find(allowed_.begin(), allowed_.end(), 0) != allowed_.end();
    // Every label listed is no restriction at all.
    if (restricted_) candidates_ = candidates;
  }
  if (proba_) {
    width_ = proba_->width;
    height_ = proba_->height;
    if (static_cast<int>(proba_->channel_labels.size()) != proba_->channels)
      throw Error("", "proba_labels", std::to_string(proba_->channels) + " channel labels",
                  std::to_string(proba_->channel_labels.size()));
    channel_of_label_.assign(static_cast<size_t>(num_labels), -1);
    for (int c = 0; c < proba_->channels; ++c) {
      const int id = proba_->channel_labels[static_cast<size_t>(c)];
      if (id < 0 || id >= num_labels)
        throw Error("", "proba_labels", "label ids between 0 and " + std::to_string(num_labels - 1),
                    std::to_string(id));
      channel_of_label_[static_cast<size_t>(id)] = c;
    }
  } else {
    width_ = label_->width;
    height_ = label_->height;
  }
}

bool FrameEvidence::probabilities(int u, int v, float* out) const {
  std::fill(out, out + num_labels_, 0.f);
  if (proba_) {
    const size_t first =
        (static_cast<size_t>(v) * static_cast<size_t>(proba_->width) + static_cast<size_t>(u)) *
        static_cast<size_t>(proba_->channels);
    for (int c = 0; c < proba_->channels; ++c)
      out[proba_->channel_labels[static_cast<size_t>(c)]] +=
          proba_->probability(first + static_cast<size_t>(c));
  } else {
    const int id = label_->at(u, v);
    if (num_labels_ == 1) {
      out[0] = static_cast<float>(label_confidence_);
    } else {
      std::fill(out, out + num_labels_,
                static_cast<float>((1.0 - label_confidence_) / (num_labels_ - 1)));
      if (id >= 0 && id < num_labels_) out[id] = static_cast<float>(label_confidence_);
    }
  }
  if (!restricted_) return true;
  // Class candidates: drop the other labels and renormalise over the candidates.
  double sum = 0.0;
  int allowed_count = 0;
  for (int k = 0; k < num_labels_; ++k) {
    if (!allowed_[static_cast<size_t>(k)]) out[k] = 0.f;
    sum += out[k];
    allowed_count += allowed_[static_cast<size_t>(k)];
  }
  for (int k = 0; k < num_labels_; ++k) {
    if (!allowed_[static_cast<size_t>(k)]) continue;
    out[k] = sum > 0.0 ? static_cast<float>(out[k] / sum) : 1.f / static_cast<float>(allowed_count);
  }
  return sum > 0.0;
}

float clampedLogit(float p) {
  return logit(std::clamp(static_cast<double>(p), kProbabilityEpsilon, 1.0 - kProbabilityEpsilon));
}

void FrameEvidence::logOdds(int u, int v, float* out) const {
  probabilities(u, v, out);
  for (int k = 0; k < num_labels_; ++k) out[k] = clampedLogit(out[k]);
}

const ProbabilityImage* FrameEvidence::directProbabilities() const {
  return restricted_ ? nullptr : proba_;
}

int FrameEvidence::argmax(int u, int v) const {
  float p[256];  // a map has at most 256 labels; no allocation per pixel
  if (!probabilities(u, v, p)) return -1;
  return static_cast<int>(std::max_element(p, p + num_labels_) - p);
}

// ---------------------------------------------------------------------------
// Reference integration: every pixel casts its own ray.

void checkFrameInputs(const LabelMap& map, const CameraIntrinsics& camera, const DepthImage& depth,
                      const FrameEvidence& evidence) {
  if (depth.width != camera.width || depth.height != camera.height)
    throw Error("", "depth", "an image of the camera's size " + std::to_string(camera.width) + "x" +
                                 std::to_string(camera.height),
                std::to_string(depth.width) + "x" + std::to_string(depth.height));
  if (evidence.width() != depth.width || evidence.height() != depth.height)
    throw Error("", "proba", "label evidence of the depth image's size",
                std::to_string(evidence.width()) + "x" + std::to_string(evidence.height()));
  if (evidence.numLabels() != map.numLabels())
    throw Error("", "labels", std::to_string(map.numLabels()) + " labels (the map's)",
                std::to_string(evidence.numLabels()));
}

Eigen::Vector3d rayEnd(const grid::Grid& g, const Eigen::Vector3d& origin, const grid::Key& end_key,
                       bool beyond_range, double max_range) {
  const Eigen::Vector3d target = g.centerOf(end_key);
  if (!beyond_range) return target;
  return origin + (target - origin).normalized() * max_range;
}

FrameStats integrateFrameReference(LabelMap& map, const CameraIntrinsics& camera,
                                   const Eigen::Isometry3d& T_world_camera,
                                   const DepthImage& depth, const FrameEvidence& evidence) {
  const auto start = std::chrono::steady_clock::now();
  checkFrameInputs(map, camera, depth, evidence);
  LabelOcTree& tree = map.tree();
  const int n = map.numLabels();
  const double max_range = map.parameters().max_range;
  const grid::Grid g(map.parameters().resolution);
  const Eigen::Vector3d origin = T_world_camera.translation();

  std::unordered_map<octomap::OcTreeKey, std::vector<float>, octomap::OcTreeKey::KeyHash> hits;
  octomap::KeySet misses;
  std::vector<float> pixel_log_odds(static_cast<size_t>(n));
  FrameStats stats;
  const PixelProjector projector(g, camera, T_world_camera, max_range);

  std::vector<std::uint64_t> row(static_cast<size_t>(depth.width));
  for (int v = 0; v < depth.height; ++v) {
    projector.projectRow(v, depth.metres.data() + static_cast<size_t>(v) * depth.width, depth.width,
                         row.data());
    for (int u = 0; u < depth.width; ++u) {
      if (row[static_cast<size_t>(u)] == kNoVoxel) continue;
      const PixelRay ray = unpackVoxel(row[static_cast<size_t>(u)]);
      ++stats.valid_pixels;
      const Eigen::Vector3d end = rayEnd(g, origin, ray.end_key, ray.beyond_range, max_range);
      grid::traverseRay(g, origin, end, [&](std::uint16_t x, std::uint16_t y, std::uint16_t z) {
        misses.insert(octomap::OcTreeKey(x, y, z));
      });
      if (ray.beyond_range) continue;
      evidence.logOdds(u, v, pixel_log_odds.data());
      const octomap::OcTreeKey key(ray.end_key[0], ray.end_key[1], ray.end_key[2]);
      auto [it, inserted] = hits.try_emplace(key);
      if (inserted) {
        it->second = pixel_log_odds;
      } else {
        for (int k = 0; k < n; ++k)
          it->second[static_cast<size_t>(k)] += pixel_log_odds[static_cast<size_t>(k)];
      }
    }
  }

  std::vector<octomap::OcTreeKey> touched;
  touched.reserve(hits.size() + misses.size());
  for (const auto& key : misses) {
    if (hits.count(key)) continue;  // a voxel hit in this frame is never also missed
    tree.applyMiss(key);
    touched.push_back(key);
    ++stats.miss_voxels;
  }
  for (const auto& [key, sum] : hits) {
    tree.applyHit(key, sum.data());
    touched.push_back(key);
  }
  stats.hit_voxels = hits.size();
  tree.refreshAncestors(std::move(touched));
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

// ---------------------------------------------------------------------------
// The map's extent

bool insideMapExtent(const Eigen::Vector3d& point, double resolution) {
  grid::Key key;
  return grid::Grid(resolution).keyOf(point, key);
}

namespace {

std::string formatMetres(double value) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

std::string formatPosition(const Eigen::Vector3d& p) {
  return "(" + formatMetres(p.x()) + ", " + formatMetres(p.y()) + ", " + formatMetres(p.z()) +
         ") m";
}

// Why a camera outside the extent cannot be fused, and what voxel size would hold it.
std::string cameraExtentExpected(const Eigen::Vector3d& camera, double resolution) {
  std::string text = "a camera position inside the map's extent, " + describeMapExtent(resolution);
  const double needed = resolutionForReach(camera.cwiseAbs().maxCoeff());
  if (std::isfinite(needed) && needed <= kMaxFusionResolution)
    text += " (voxels of " + formatMetres(needed) + " m or more hold this one)";
  else
    text += " (no voxel size fusion takes, up to " + formatMetres(kMaxFusionResolution) +
            " m, holds this one: a wrong pose?)";
  return text;
}

}  // namespace

std::string describeMapExtent(double resolution) {
  return formatMetres(mapExtent(resolution)) + " m either side of the origin on each axis at " +
         formatMetres(resolution) + " m voxels";
}

double resolutionForReach(double reach) {
  // A coordinate c is inside when |c| / resolution < kMapExtentVoxels (and -c
  // may reach it exactly): the next whole millimetre past reach / 32768.
  double millimetres = std::floor(reach / kMapExtentVoxels * 1000.0) + 1.0;
  // Far past any voxel size (a wrong pose): whole millimetres no longer count.
  if (!(millimetres < 1e9)) return std::numeric_limits<double>::infinity();
  for (int step = 0; step < 4 && !(reach / (millimetres / 1000.0) < kMapExtentVoxels); ++step)
    millimetres += 1.0;  // a division that rounded up
  return millimetres / 1000.0;
}

void checkCamerasInsideMap(const Sequence& sequence, double resolution, size_t first, size_t last) {
  last = std::min(last, sequence.frames.size());
  for (size_t i = first; i < last; ++i) {
    const Eigen::Vector3d camera = sequence.frames[i].T_world_camera.translation();
    if (insideMapExtent(camera, resolution)) continue;
    throw Error((sequence.root / "sequence.json").string(),
                "frames[" + std::to_string(i) + "].pose", cameraExtentExpected(camera, resolution),
                "the camera at " + formatPosition(camera));
  }
}

CameraExtentCheck checkCameraExtents(const Sequence& sequence) {
  CameraExtentCheck check;
  const std::string file = (sequence.root / "sequence.json").string();
  size_t outside_finest = 0, first_outside = 0, farthest_frame = 0;
  double farthest = 0.0;
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    const Eigen::Vector3d camera = sequence.frames[i].T_world_camera.translation();
    if (!insideMapExtent(camera, kMaxFusionResolution)) {
      check.problems.push_back({file, "frames[" + std::to_string(i) + "].pose",
                                cameraExtentExpected(camera, kMaxFusionResolution),
                                "the camera at " + formatPosition(camera)});
      continue;
    }
    if (insideMapExtent(camera, kMinFusionResolution)) continue;
    if (outside_finest++ == 0) first_outside = i;
    const double reach = camera.cwiseAbs().maxCoeff();
    if (reach > farthest) {
      farthest = reach;
      farthest_frame = i;
    }
  }
  if (outside_finest == 0) return check;
  const std::string frames =
      "frames[" + std::to_string(first_outside) + "].pose" +
      (outside_finest > 1 ? " and " + std::to_string(outside_finest - 1) + " other frame" +
                                (outside_finest > 2 ? "s" : "")
                          : std::string());
  check.warning = frames + ": " + (outside_finest > 1 ? "cameras lie" : "the camera lies") +
                  " outside the extent of a map with the finest voxels fusion takes, " +
                  describeMapExtent(kMinFusionResolution) + " (frames[" +
                  std::to_string(farthest_frame) + "] " + formatMetres(farthest) +
                  " m out on an axis): fusing needs voxels of " +
                  formatMetres(resolutionForReach(farthest)) +
                  " m or more, and coarser still for depths that reach farther out";
  return check;
}

namespace {

// IntegrationOptions::max_voxels_per_ray: with an unlimited range, the
// farthest depth must lie within the limit.
void checkUnlimitedRays(const MapParameters& parameters, const CameraIntrinsics& camera,
                        const DepthImage& depth, double max_voxels_per_ray) {
  if (parameters.max_range > 0.0 || !(max_voxels_per_ray > 0.0)) return;
  const double farthest = countDepthRanges(camera, depth, 0.0).farthest;
  const double voxels = farthest / parameters.resolution;
  if (!(voxels > max_voxels_per_ray + 1e-9)) return;
  char found[96];
  std::snprintf(found, sizeof found, "a depth %.2f m from the camera (%.0f voxels)", farthest,
                voxels);
  throw Error("", "depth",
              "depths within " + formatMetres(max_voxels_per_ray * parameters.resolution) +
                  " m of the camera (" + formatMetres(max_voxels_per_ray) + " voxels of " +
                  formatMetres(parameters.resolution) +
                  " m) with an unlimited max range: longer rays take gigabytes; set a max range "
                  "(depths beyond it only clear free space) or coarser voxels",
              found);
}

// A number of the first line of `file` that starts with `key` (its first
// number when `key` is empty), or nullopt.
std::optional<double> readNumber(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, key.size(), key) != 0) continue;
    char* end = nullptr;
    const double value = std::strtod(line.c_str() + key.size(), &end);
    if (end == line.c_str() + key.size()) return std::nullopt;
    return value;
  }
  return std::nullopt;
}

std::string formatBytes(double bytes) {
  char text[32];
  if (bytes >= 1024.0 * 1024.0 * 1024.0)
    std::snprintf(text, sizeof text, "%.1f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
  else if (bytes >= 1024.0 * 1024.0)
    std::snprintf(text, sizeof text, "%.0f MiB", bytes / (1024.0 * 1024.0));
  else
    std::snprintf(text, sizeof text, "%.0f bytes", bytes);
  return text;
}

std::string countOf(double count) {
  char text[32];
  if (count < 1e5)
    std::snprintf(text, sizeof text, "%.0f", count);
  else
    std::snprintf(text, sizeof text, count < 1e7 ? "%.1f million" : "%.0f million", count / 1e6);
  return text;
}

}  // namespace

std::optional<double> availableMemoryBytes() {
  std::optional<double> available;
  auto atMost = [&](double bytes) { available = available ? std::min(*available, bytes) : bytes; };
  if (const auto kib = readNumber("/proc/meminfo", "MemAvailable:")) atMost(*kib * 1024.0);
  // A container's memory limit (cgroup v2): "max" reads as no number.
  if (const auto limit = readNumber("/sys/fs/cgroup/memory.max", ""))
    if (const auto used = readNumber("/sys/fs/cgroup/memory.current", ""))
      atMost(std::max(0.0, *limit - *used));
  rlimit address_space{};
  if (getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY)
    if (const auto pages = readNumber("/proc/self/statm", "")) {
      const double used = *pages * static_cast<double>(sysconf(_SC_PAGESIZE));
      atMost(std::max(0.0, static_cast<double>(address_space.rlim_cur) - used));
    }
  return available;
}

bool frameMemoryNeedsCheck(size_t most_crossed, double limit_bytes) {
  constexpr double kCheckFrom = 256.0 * 1024 * 1024;  // no smaller frame reads the system's memory
  return limit_bytes > 0.0 ||
         static_cast<double>(most_crossed) * kFusionBytesPerCrossedVoxel > kCheckFrom;
}

void checkFrameMemory(size_t crossed, double limit_bytes, double resolution,
                      const std::function<size_t()>& count_new_voxels,
                      double reusable_stream_bytes) {
  double needed = static_cast<double>(crossed) * kFusionBytesPerCrossedVoxel;
  const bool given = limit_bytes > 0.0;
  double room = limit_bytes;
  if (!given) {
    const std::optional<double> available = availableMemoryBytes();
    if (!available) return;  // nothing to check against
    room = *available;
  }
  if (needed <= room) return;
  // A voxel the map already holds takes only its place in the streams.
  std::string new_voxels;
  if (count_new_voxels) {
    const size_t fresh = std::min(count_new_voxels(), crossed);
    needed = std::max(0.0, static_cast<double>(crossed) * kFusionStreamBytesPerCrossedVoxel -
                               reusable_stream_bytes) +
             static_cast<double>(fresh) *
                 (kFusionBytesPerCrossedVoxel - kFusionStreamBytesPerCrossedVoxel);
    if (needed <= room) return;
    new_voxels = ", " + countOf(static_cast<double>(fresh)) + " of them new to the map";
  }
  throw Error("", "depth",
              "rays that cross few enough voxels to fuse in the " + formatBytes(room) +
                  " of memory " + (given ? "allowed per frame" : "available") + " (at most " +
                  countOf(room / kFusionBytesPerCrossedVoxel) + " new voxels of " +
                  formatMetres(resolution) + " m, about " +
                  formatMetres(kFusionBytesPerCrossedVoxel) + " bytes each, or " +
                  countOf(room / kFusionStreamBytesPerCrossedVoxel) +
                  " the map holds already); coarser voxels or a shorter max range cross fewer",
              "rays crossing " + countOf(static_cast<double>(crossed)) + " voxels" + new_voxels +
                  " (about " + formatBytes(needed) + ")");
}

FrameStats integrateFrame(LabelMap& map, const CameraIntrinsics& camera,
                          const Eigen::Isometry3d& T_world_camera, const DepthImage& depth,
                          const FrameEvidence& evidence, const IntegrationOptions& integration) {
  // Rays start at the camera: outside the map, none could be cast, and the
  // frame's hits would land without the free space in front of them.
  const double resolution = map.parameters().resolution;
  if (!insideMapExtent(T_world_camera.translation(), resolution))
    throw Error("", "pose", cameraExtentExpected(T_world_camera.translation(), resolution),
                "the camera at " + formatPosition(T_world_camera.translation()));
  checkUnlimitedRays(map.parameters(), camera, depth, integration.max_voxels_per_ray);
  const FrameStats stats =
      integration.path == IntegrationPath::Reference
          ? integrateFrameReference(map, camera, T_world_camera, depth, evidence)
          : integrateFrameFast(map, camera, T_world_camera, depth, evidence, integration.threads,
                               integration.kernels, integration.frame_memory_limit_bytes,
                               integration.cancelled);
  map.noteFusedCandidates(evidence.candidates());
  map.noteCameraView(T_world_camera.linear());
  return stats;
}

// ---------------------------------------------------------------------------
// Sequences

void noteDepthRanges(FrameStats& stats, const CameraIntrinsics& camera, const DepthImage& depth,
                     double max_range) {
  const DepthRanges ranges = countDepthRanges(camera, depth, max_range);
  stats.beyond_range_pixels = ranges.beyond;
  stats.farthest_range = ranges.farthest;
  // countDepthRanges counts a pixel as measured exactly when the
  // back-projection does; integration counts as valid those of them inside
  // the extent. The difference costs nothing in the integration's loops.
  stats.outside_map_pixels = ranges.measured - std::min(ranges.measured, stats.valid_pixels);
}

void addFrameStats(FrameStats& totals, const FrameStats& frame) {
  totals.valid_pixels += frame.valid_pixels;
  totals.beyond_range_pixels += frame.beyond_range_pixels;
  totals.outside_map_pixels += frame.outside_map_pixels;
  totals.farthest_range = std::max(totals.farthest_range, frame.farthest_range);
  totals.hit_voxels += frame.hit_voxels;
  totals.miss_voxels += frame.miss_voxels;
  totals.seconds += frame.seconds;
}

size_t measuredPixels(const FrameStats& totals) {
  return totals.valid_pixels + totals.outside_map_pixels;
}

bool mostDepthsBeyondMaxRange(const FrameStats& totals, double max_range) {
  return max_range > 0.0 && 2 * totals.beyond_range_pixels > measuredPixels(totals);
}

std::string nearDepthWarning(const Sequence& sequence, size_t first, size_t last,
                             const FrameStats& totals) {
  // Fusion keeps the farthest depth, not a median (that would take a sort of
  // every frame's depths): when even the farthest is this near, so is the median.
  if (measuredPixels(totals) == 0 || totals.farthest_range >= kMinPlausibleMedianDepth) return {};
  // 16-bit images hold units of depth_scale; .npy files hold metres.
  last = std::min(last, sequence.frames.size());
  size_t npy = 0, scaled = 0;
  for (size_t i = first; i < last; ++i) {
    std::string extension = std::filesystem::path(sequence.frames[i].depth).extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    ++(extension == ".npy" ? npy : scaled);
  }
  const size_t fused = last > first ? last - first : 0;
  char text[160];
  std::snprintf(text, sizeof text,
                "%.3g m from the camera, nearer than depth cameras measure (%g to %g m): ",
                totals.farthest_range, kMinPlausibleMedianDepth, kMaxPlausibleMedianDepth);
  char scale_value[32];
  std::snprintf(scale_value, sizeof scale_value, "%.6g", sequence.camera.depth_scale);
  const std::string scale = std::string("depth_scale ") + scale_value +
                            " (metres per unit of the depth images) is likely too small";
  const std::string unit = "the .npy depths are likely not in metres";
  return (sequence.root / "sequence.json").string() + ": " +
         (scaled && npy ? "camera.depth_scale, frames[].depth"
          : scaled      ? "camera.depth_scale"
                        : "frames[].depth") +
         ": the farthest measured point of the " + std::to_string(fused) +
         (fused == 1 ? " frame" : " frames") + " fused lies " + text +
         (scaled && npy ? scale + ", or " + unit
          : scaled      ? scale
                        : unit) +
         ", which shrinks the map by the same factor (labeloctomap validate gives the median "
         "depth and a scale that fits)";
}

std::optional<RayLengthProblem> checkRayLength(double max_range, double resolution) {
  // With a rounding tolerance: 9 m of 9 mm voxels is 1000.0000000000001.
  const double voxels = max_range / resolution;
  if (!(max_range > 0.0 && voxels > kMaxFusionVoxelsPerRay + 1e-9)) return std::nullopt;
  RayLengthProblem problem;
  problem.voxels = std::ceil(voxels - 1e-9);
  return problem;
}

std::optional<CandidateProblem> checkCandidates(const std::optional<std::vector<int>>& candidates,
                                                const LabelSet& labels) {
  if (candidates)
    for (int id : *candidates)
      if (!labels.contains(id)) return CandidateProblem{id, labels.size()};
  return std::nullopt;
}

double suggestedResolutionForRange(double max_range, double resolution) {
  constexpr double kMaxVoxelsPerRay = 250.0, kStep = 0.005;
  const double coarse = std::ceil(max_range / kMaxVoxelsPerRay / kStep - 1e-9) * kStep;
  // Never coarser than fusion takes (ranges past 250 m then get longer rays).
  return std::max(resolution, std::min(coarse, kMaxFusionResolution));
}

DepthRanges countDepthRanges(const CameraIntrinsics& camera, const DepthImage& depth,
                             double max_range) {
  DepthRanges ranges;
  if (depth.width <= 0 || depth.height <= 0) return ranges;
  // The same terms as the back-projection (PixelProjector), so that a pixel
  // counts as beyond exactly when fusion treats it so.
  const double inverse_fx = 1.0 / camera.fx;
  const double inverse_fy = 1.0 / camera.fy;
  const double limit =
      max_range > 0.0 ? max_range * max_range : std::numeric_limits<double>::infinity();
  std::vector<double> xx(static_cast<size_t>(depth.width));
  for (int u = 0; u < depth.width; ++u) {
    const double x = (u - camera.cx) * inverse_fx;
    xx[static_cast<size_t>(u)] = x * x;
  }
  double farthest_squared = 0.0;
  for (int v = 0; v < depth.height; ++v) {
    const double y = (v - camera.cy) * inverse_fy;
    const double yy_plus_one = y * y + 1.0;
    const float* row = depth.metres.data() + static_cast<size_t>(v) * depth.width;
    size_t measured = 0, beyond = 0;
    for (int u = 0; u < depth.width; ++u) {
      const float d = row[u];
      if (!(d > 0.f && d <= std::numeric_limits<float>::max())) continue;  // no NaN, no inf
      const double z = d;
      const double squared = z * z * (xx[static_cast<size_t>(u)] + yy_plus_one);
      ++measured;
      beyond += squared > limit ? 1 : 0;
      farthest_squared = std::max(farthest_squared, squared);
    }
    ranges.measured += measured;
    ranges.beyond += beyond;
  }
  ranges.farthest = std::sqrt(farthest_squared);
  return ranges;
}

FrameEvidence makeEvidence(const Sequence& sequence, size_t index, const FrameData& frame,
                           const FusionOptions& options) {
  const std::string frame_field = "frames[" + std::to_string(index) + "]";
  const std::string file = (sequence.root / "sequence.json").string();
  if (!frame.proba && !frame.label)
    throw Error(file, frame_field, "a proba or label image to fuse", "neither");
  try {
    return FrameEvidence(sequence.labels.size(), frame.proba ? &*frame.proba : nullptr,
                         frame.label ? &*frame.label : nullptr, options.candidates,
                         options.label_confidence);
  } catch (const Error& e) {
    Problem p = e.problem();
    p.file = file;
    p.field = frame_field + "." + p.field;
    throw Error(p);
  }
}

LabelMap fuseSequence(const Sequence& sequence, const FusionOptions& options,
                      const std::function<bool(const FusionProgress&)>& progress) {
  LabelMap map(sequence.labels, options.map);
  fuseSequenceInto(map, sequence, options, progress);
  return map;
}

void fuseSequenceInto(LabelMap& map, const Sequence& sequence, const FusionOptions& options,
                      const std::function<bool(const FusionProgress&)>& progress) {
  const size_t first = std::min(options.first_frame, sequence.frames.size());
  const size_t last = std::min(options.last_frame, sequence.frames.size());
  FusionProgress report;
  report.total = last > first ? last - first : 0;
  // Every camera before any frame: a pose far out fails at once, not after
  // the frames before it were fused.
  checkCamerasInsideMap(sequence, map.parameters().resolution, first, last);
  noteSequenceWorldFrame(map, sequence);
  for (size_t i = first; i < last; ++i) {
    const FrameData frame = loadFusionFrame(sequence, i, options.segmenter.get());
    const FrameEvidence evidence = makeEvidence(sequence, i, frame, options);
    try {
      report.stats = integrateFrame(map, sequence.cameraOf(i), sequence.frames[i].T_world_camera,
                                    frame.depth, evidence, options.integration);
    } catch (const Error& e) {
      Problem p = e.problem();
      p.file = (sequence.root / "sequence.json").string();
      p.field = "frames[" + std::to_string(i) + "]." + p.field;
      throw Error(p);
    }
    map.noteFusedEvidence(evidenceSourceOf(sequence, i, options.segmenter.get()));
    // How much of the frame max range cut off, for the caller to warn about
    // (counted apart from the integration, which keeps to its own work).
    noteDepthRanges(report.stats, sequence.cameraOf(i), frame.depth, map.parameters().max_range);
    addFrameStats(report.totals, report.stats);
    report.frame_index = i;
    ++report.done;
    if (progress && !progress(report)) break;
  }
  map.prune();  // merge every identical set of children once fusion is over
}

void noteSequenceWorldFrame(LabelMap& map, const Sequence& sequence) {
  try {
    map.noteWorldFrame(sequence.frame_id);
  } catch (const Error& e) {
    Problem p = e.problem();
    p.file = (sequence.root / "sequence.json").string();
    p.field = "frame_id";
    throw Error(p);
  }
}

std::string evidenceSourceOf(const Sequence& sequence, size_t index, const Segmenter* segmenter) {
  return segmenterRunsOn(sequence, index, segmenter) ? segmenter->modelPath().filename().string()
                                                     : std::string();
}

FusedEvidence evidenceOf(const Sequence& sequence, size_t first, size_t last,
                         const Segmenter* segmenter) {
  FusedEvidence evidence;
  std::set<std::string> models;  // ascending, each once, as the map records them
  const size_t end = std::min(last, sequence.frames.size());
  for (size_t i = first; i < end; ++i) {
    std::string source = evidenceSourceOf(sequence, i, segmenter);
    if (source.empty())
      evidence.own_probabilities = true;
    else
      models.insert(std::move(source));
  }
  evidence.models.assign(models.begin(), models.end());
  return evidence;
}

CameraViewRecord cameraViewsOf(const Sequence& sequence, size_t first, size_t last) {
  CameraViewRecord record;
  const size_t end = std::min(last, sequence.frames.size());
  for (size_t i = first; i < end; ++i)
    addCameraView(record, sequence.frames[i].T_world_camera.linear());
  return record;
}

std::optional<Eigen::Vector3d> camerasUpOf(const Sequence& sequence) {
  std::vector<Eigen::Matrix3d> rotations;
  rotations.reserve(sequence.frames.size());
  for (const FrameRecord& frame : sequence.frames)
    rotations.push_back(frame.T_world_camera.linear());
  return meanCameraUp(rotations);
}

}  // namespace lom
