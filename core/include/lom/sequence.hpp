#pragma once
// Recorded frame sequences, format "labeloctomap-sequence" version 1
// (docs/sequence-format.md).
#include <Eigen/Geometry>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "lom/camera.hpp"
#include "lom/error.hpp"
#include "lom/images.hpp"
#include "lom/labels.hpp"

namespace lom {

struct FrameRecord {
  // Seconds; absent when the source recorded no time (a frame number is not a time).
  std::optional<double> stamp;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  std::string depth;                // relative path; .png (16-bit) or .npy (float32 metres)
  std::string color;                // optional
  std::string proba;                // optional .npy H x W x C
  std::vector<int> proba_labels;    // label of each proba channel; empty = all labels in order
  // The proba was made from this frame's own label image (one-hot): comparing
  // the two says nothing, so the 2D metrics leave the frame out.
  bool proba_from_label = false;
  std::string label;                // optional 8/16-bit PNG of label ids
  // The label image stands in for labels the source did not have (an import of
  // colour and depth only writes one all background): no ground truth, so the
  // 2D metrics leave the frame out. Only together with `label`.
  bool label_placeholder = false;
  bool view = true;                 // counts as a separate viewpoint for the projection baseline
  std::optional<CameraIntrinsics> camera;  // overrides the sequence camera
};

struct Sequence {
  std::filesystem::path root;  // folder holding sequence.json
  std::string frame_id = "world";
  LabelSet labels;
  CameraIntrinsics camera;
  std::vector<FrameRecord> frames;

  [[nodiscard]] const CameraIntrinsics& cameraOf(size_t frame) const {
    return frames[frame].camera ? *frames[frame].camera : camera;
  }
  [[nodiscard]] std::filesystem::path pathOf(const std::string& relative) const {
    return root / relative;
  }
};

// Everything one frame holds, loaded from disk.
struct FrameData {
  DepthImage depth;
  std::optional<ColorImage> color;
  std::optional<ProbabilityImage> proba;
  std::optional<LabelImage> label;
};

// Reads `folder/sequence.json` (or a path to the json itself). Checks the JSON
// structure (types, required fields, rigid poses, label ids) and throws
// lom::Error naming the file and the field on the first problem. Does not open
// the frame files: see validateSequence / loadFrame.
[[nodiscard]] Sequence loadSequence(const std::filesystem::path& folder_or_json);

// Every frame file the sequence names (depth, colour, proba, label), resolved
// against its folder: what commands and the studio must never write over.
[[nodiscard]] std::vector<std::filesystem::path> frameFilesOf(const Sequence& sequence);

// Writes `folder/sequence.json` atomically (frame files are written by the caller).
void saveSequence(const Sequence& sequence, const std::filesystem::path& folder);

// The text saveSequence writes to `folder/sequence.json`, checked the same way
// (for callers that stage it with other files and rename them together).
[[nodiscard]] std::string sequenceJsonText(const Sequence& sequence,
                                           const std::filesystem::path& folder);

// Opens every file of every frame and checks existence, image size, bit depth,
// channel count, proba dtype, label ids. Returns all problems found (empty = valid).
// (checkSequence's problems.)
[[nodiscard]] std::vector<Problem> validateSequence(const Sequence& sequence);

// `value` with at most `decimals` decimals, every digit before the point
// (epoch stamps, site coordinates), trailing zeros dropped ("-0" is "0").
[[nodiscard]] std::string fixedDigits(double value, int decimals);

// The measured depths of a depth image: the pixels whose depth is finite and
// > 0, and their nearest, median and farthest depth in metres (0 when none).
struct DepthFigures {
  size_t pixels = 0;
  size_t valid = 0;
  double min = 0.0;
  double median = 0.0;
  double max = 0.0;
  [[nodiscard]] double validFraction() const {
    return pixels ? static_cast<double>(valid) / static_cast<double>(pixels) : 0.0;
  }
};
[[nodiscard]] DepthFigures depthFigures(const DepthImage& depth);

// What validateSequence finds, and what it saw on the way.
struct SequenceCheck {
  std::vector<Problem> problems;
  // Worth a look, but no failure (the values are valid): depths whose median
  // no depth camera measures (a wrong depth_scale; implausibleDepthWarning),
  // a frame listed twice, a depth file shared by frames with different poses,
  // stamps that go back. Each names sequence.json and the frames.
  std::vector<std::string> warnings;
  // Per frame, the figures of its depth image; none when it could not be
  // read (a problem says why), whatever the frame's other images.
  std::vector<std::optional<DepthFigures>> frame_depths;
  // Over every valid depth of the frames read. The median is taken from a
  // histogram of the depths (bins 0.1 % wide): a whole recording's depths
  // would not fit in memory.
  DepthFigures depths;
};
[[nodiscard]] SequenceCheck checkSequence(const Sequence& sequence);

// A median valid depth outside these bounds is no scene a depth camera
// measures: they see from about 0.1-0.5 m to 10-20 m. Such depths mean a
// wrong camera.depth_scale (or .npy depths not in metres): fused, the map is
// shrunk or stretched by that factor without any other sign.
inline constexpr double kMinPlausibleMedianDepth = 0.1;
inline constexpr double kMaxPlausibleMedianDepth = 20.0;
// "" when `figures.median` is within those bounds (or nothing was measured);
// else a warning naming sequence.json and the depth_scale field (or the .npy
// depths) of `frames`, the frames whose depths `figures` describe ("the 3
// frames sampled" when `sampled`), what was found and the depth_scale that
// would give a plausible median.
[[nodiscard]] std::string implausibleDepthWarning(const Sequence& sequence,
                                                  const std::vector<size_t>& frames,
                                                  const DepthFigures& figures,
                                                  bool sampled = false);

// A camera that moves farther between two consecutive frames than
// `limit_metres` (10 m by default: farther than a depth camera sees, so a
// wrong pose rather than motion). Fusion would spread the map over that
// distance, and a view that fits all of it shows the voxels smaller than a
// pixel. Each message: "frames[i].pose: the camera is 300 m from
// where it was in frames[i-1] (a wrong pose?)". Cameras outside the extent
// of every map fusion can make (lom::checkCameraExtents) are left out: each
// step is measured from the camera before it that lies inside. Only the
// frames first..last-1 (fuse --frames) are looked at.
[[nodiscard]] std::vector<std::string> cameraJumps(const Sequence& sequence,
                                                   double limit_metres = 10.0, size_t first = 0,
                                                   size_t last = static_cast<size_t>(-1));

// Intrinsics whose field of view no depth camera has: wider than
// kMaxPlausibleFieldOfView degrees on either image axis. Such a camera matrix
// has focal lengths in millimetres or metres instead of pixels, or belongs to
// much smaller images; fused, its depths land metres to kilometres from where
// they were measured. (Narrow views are not flagged: small test images keep a
// real camera's focal lengths.) One message for the
// sequence's camera (when a frame uses it) and one for the first frame with a
// camera of its own that is implausible, "camera: fx = ..., fy = ... give a
// field of view of 179.4 x 179.1 degrees at 640 x 480 pixels; ...". A warning:
// the values are valid numbers, and a lens may be unusual. Only the cameras of
// frames [first_frame, last_frame) count (those a fusion of them uses).
// A principal point outside the middle half of the image on either axis
// (cx < 0.25 width, ...) is named too: the camera matrix of images of
// another size ("camera: the principal point cx = 74.6, cy = 61.9 lies at
// 12 % and 13 % of the 640 x 480 pixels' ...").
inline constexpr double kMaxPlausibleFieldOfView = 150.0;
inline constexpr double kMinPrincipalPointFraction = 0.25;
[[nodiscard]] std::vector<std::string> implausibleIntrinsics(
    const Sequence& sequence, size_t first_frame = 0,
    size_t last_frame = std::numeric_limits<size_t>::max());

// Which of a frame's images loadFrame reads besides its depth image: a part
// left out stays empty in FrameData and its file is not opened.
struct FrameParts {
  bool color = true;
  bool proba = true;
  bool label = true;
  // False: an 8-bit proba image keeps only its codes, without the float copy
  // of every value (15 MB for a 640x480 image of 12 channels); fusion
  // (FrameEvidence, integrateFrame) reads either.
  bool proba_floats = true;
};

// Loads one frame's images (those `parts` asks for). Throws lom::Error naming
// the file and field.
[[nodiscard]] FrameData loadFrame(const Sequence& sequence, size_t index, FrameParts parts = {});

// Image file helpers (OpenCV behind the scenes). All throw lom::Error naming the file.
[[nodiscard]] DepthImage readDepthImage(const std::filesystem::path& path, double depth_scale);
[[nodiscard]] ColorImage readColorImage(const std::filesystem::path& path);
[[nodiscard]] LabelImage readLabelImage(const std::filesystem::path& path);
// With `floats_of_codes` false, an 8-bit image keeps only its codes (`values`
// stays empty; see ProbabilityImage).
[[nodiscard]] ProbabilityImage readProbabilityImage(const std::filesystem::path& path,
                                                    const std::vector<int>& channel_labels,
                                                    int num_labels, bool floats_of_codes = true);
// 16-bit PNG with value = round(metres / depth_scale), 0 for no measurement.
void writeDepthPng(const std::filesystem::path& path, const DepthImage& depth, double depth_scale);
void writeColorPng(const std::filesystem::path& path, const ColorImage& color);
void writeLabelPng(const std::filesystem::path& path, const LabelImage& label);

}  // namespace lom
