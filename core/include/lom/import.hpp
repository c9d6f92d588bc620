#pragma once
// Importing recordings: ROS 1 bags and the RGB-D dataset layouts in common use
// are converted to v1 sequences (docs/import.md, docs/sequence-format.md).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "lom/camera.hpp"
#include "lom/images.hpp"
#include "lom/labels.hpp"
#include "lom/sequence.hpp"

namespace lom {

enum class SourceKind {
  Sequence,    // already a v1 sequence (folder holding sequence.json)
  RosBag,      // ROS 1 .bag file
  Frames,      // frame-NNNNNN.{color,depth}.png + frame-NNNNNN.pose.txt + a 3x3 intrinsics file
  Tum,         // TUM RGB-D benchmark folder: rgb.txt, depth.txt, groundtruth.txt
  Quaternion,  // color/N.png, depth/N.(png|pgm), pose.txt with "tx ty tz qx qy qz qw" lines
  ScanNet,     // ScanNet export: color/, depth/, pose/, intrinsic/ (and label-filt/)
  ApcShelf,    // Princeton Shelf & Tote (APC 2016) scene: cam.info.txt, frame-*, segm/, masks/
};

// "sequence", "rosbag", "frames", "tum", "quaternion", "scannet", "apc-shelf".
[[nodiscard]] std::string sourceKindName(SourceKind kind);
// The inverse of sourceKindName; nullopt for an unknown name (and for "auto").
[[nodiscard]] std::optional<SourceKind> sourceKindFromName(const std::string& name);
// All kinds an import can read (everything but Sequence), in the order above.
[[nodiscard]] std::vector<SourceKind> importableKinds();

struct SourceDetection {
  std::optional<SourceKind> kind;  // nullopt: not a layout this program knows
  std::string explanation;         // what was recognised, or what was looked for
};

// Looks at a file or folder (without reading images) and says which kind it is.
// Used by the studio's File > Open and by `labeloctomap import auto`.
[[nodiscard]] SourceDetection detectSource(const std::filesystem::path& path);
// False for a dataset folder of `kind` that holds no camera intrinsics (a
// frames or pose.txt folder without an intrinsics file): importing or opening
// it needs the intrinsics option. True otherwise.
[[nodiscard]] bool sourceStoresCamera(const std::filesystem::path& path, SourceKind kind);

// Depth clean-up applied to every imported frame, in this order: invalid values
// (NaN, infinite, <= 0) dropped, range limits, flying pixels, bilateral smoothing.
// A dropped pixel becomes 0 (no measurement).
struct DepthFilterOptions {
  double min_depth = 0.1;  // metres; nearer measurements are dropped
  double max_depth = 0.0;  // metres; farther ones are dropped; <= 0 = no limit
  // Flying pixels (mixtures of foreground and background at depth edges): a pixel
  // is dropped when a valid neighbour within `flying_pixel_radius` differs from
  // it by more than `flying_pixel_ratio` x its depth.
  bool flying_pixels = true;
  double flying_pixel_ratio = 0.05;
  int flying_pixel_radius = 1;
  // Edge-preserving smoothing of the remaining depths; 0 = off. Holes stay holes.
  int bilateral_radius = 0;
  double bilateral_sigma_space = 2.0;   // pixels
  double bilateral_sigma_depth = 0.01;  // relative to the pixel's depth
};

struct DepthFilterStats {
  size_t invalid = 0;        // NaN, infinite or negative values
  size_t out_of_range = 0;   // outside [min_depth, max_depth]
  size_t flying = 0;         // removed as flying pixels
  size_t kept = 0;           // valid pixels after filtering
};

// Applies the filters in place. Throws lom::Error for out-of-range options.
DepthFilterStats filterDepth(DepthImage& depth, const DepthFilterOptions& options);

// Topics of a ROS 1 bag; an empty string means detected automatically.
struct RosbagOptions {
  std::string depth_topic;        // sensor_msgs/Image 16UC1 (mm) or 32FC1 (m), or compressedDepth
  std::string color_topic;        // sensor_msgs/Image rgb8/bgr8/rgba8/bgra8/mono8 or CompressedImage
  std::string camera_info_topic;  // sensor_msgs/CameraInfo of the depth image
  std::string proba_topic;        // sensor_msgs/Image 32FC(N), 16UC(N) or 8UC(N): one channel per label
  std::string label_topic;        // sensor_msgs/Image mono8/8UC1/mono16/16UC1 label ids
  std::string fixed_frame;        // world frame; empty = root of the tf tree above the camera
  std::string camera_frame;       // optical frame; empty = the depth images' header.frame_id
  bool no_color = false;          // do not import colour even if a topic is found
  // Seconds (> 0, finite): a frame is skipped when, on a link of the camera's
  // chain that /tf moves, no sample lies within the time tolerance of its stamp
  // and the samples around it are farther apart than this (a pose interpolated
  // across a hole in the motion data is a guess). A large value allows any gap.
  double max_pose_gap = 0.5;
};

struct ImportOptions {
  RosbagOptions rosbag;
  // Images (bag topics, TUM lists) are matched to each depth image by the nearest
  // time stamp within this tolerance; poses too (bag: tf; TUM: groundtruth.txt).
  double time_tolerance = 0.02;  // seconds
  // Added to image time stamps before the pose is looked up (a clock offset
  // between the camera and the pose source, e.g. motion capture).
  double time_offset = 0.0;  // seconds
  DepthFilterOptions depth_filter;
  // Label images without probabilities become one-hot probabilities: the
  // pixel's label gets this confidence, the frame's other labels share the rest.
  double label_confidence = 0.9;
  // Camera override (fx, fy, cx, cy; width/height <= 0 = those of the depth images).
  std::optional<CameraIntrinsics> intrinsics;
  // Metres per unit of 16-bit depth images; default: the layout's own unit.
  std::optional<double> depth_scale;
  // Labels of probability channels / label ids where the source does not name
  // them (bag proba channels, label images of the frames layout).
  std::optional<LabelSet> labels;
  // Frame subset: every `frame_step`-th frame from `first_frame`, at most `max_frames`.
  size_t first_frame = 0;
  size_t frame_step = 1;
  size_t max_frames = 0;  // 0 = all
  bool write_color = true;
  // Replace an existing sequence in the output folder (only sequence.json and the
  // depth/, color/, proba/, label/ folders are removed; other files are kept).
  bool overwrite = false;
};

struct SkippedFrame {
  std::string frame;   // the source's name for it (file, number or time stamp)
  std::string reason;
};

struct ImportReport {
  SourceKind kind = SourceKind::Frames;
  std::filesystem::path source;
  std::filesystem::path output;
  size_t frames_found = 0;    // frames the source holds (before the frame subset)
  size_t frames_written = 0;
  std::vector<SkippedFrame> skipped;
  std::vector<std::string> notes;  // choices made and warnings (topics, intrinsics, resampling)
  bool cancelled = false;
  // Multi-line human summary: counts, then skipped frames, then notes.
  [[nodiscard]] std::string text(size_t max_skipped_listed = 20) const;
  // The notes that say the sequence may be wrong although no frame was
  // skipped (every frame at one pose, another camera's intrinsics, default
  // intrinsics): the studio shows them on every open of the recording.
  [[nodiscard]] std::vector<std::string> warnings() const;
};

// Whether a note of an import report is one of its warnings().
[[nodiscard]] bool isImportWarning(const std::string& note);

struct ImportProgress {
  size_t done = 0;   // frames converted or skipped
  size_t total = 0;  // frames to convert; 0 while the source is still being read
  // Before the frames, while the source is read through (a ROS bag: its
  // records checked, then its messages indexed, a pass over the file each):
  // bytes gone through of `read_total`, the passes' bytes together. A
  // compressed bag takes seconds to minutes there. Both 0 otherwise.
  std::uint64_t read = 0;
  std::uint64_t read_total = 0;
};
// Returning false cancels the import (nothing is left in the output folder);
// it is asked between frames and, while the source is read, every thousandth
// of the way.
using ImportProgressCallback = std::function<bool(const ImportProgress&)>;

// Converts `source` (of the given kind; nullopt = detect) into a v1 sequence in
// `out_folder`: frame files under depth/, color/, proba/, label/ and sequence.json
// written last, atomically. Frames that cannot be converted (missing pose, bad
// image) are skipped and listed in the report. Throws lom::Error naming the file
// and field when the source as a whole cannot be read, when no frame could be
// converted, or when out_folder holds a sequence and !options.overwrite.
ImportReport importSource(std::optional<SourceKind> kind, const std::filesystem::path& source,
                          const std::filesystem::path& out_folder, const ImportOptions& options = {},
                          const ImportProgressCallback& progress = {});

// "fx,fy,cx,cy" or a file holding 4 numbers (fx fy cx cy), a 3x3 matrix or a 4x4
// matrix whose top-left 3x3 is the camera matrix. Width/height are left at 0.
// Throws lom::Error naming the text or file.
[[nodiscard]] CameraIntrinsics parseIntrinsics(const std::string& text_or_file);

// True when this program was built with ROS 1 bag support.
[[nodiscard]] bool rosbagSupported();

// For the studio: opens anything detectSource recognises. A sequence is loaded
// as it is; any other source is imported into a cache folder under `cache_root`
// (one folder per source path, source modification times and options; reused
// while the source is unchanged) and that sequence is loaded.
struct OpenedSource {
  Sequence sequence;
  SourceKind kind = SourceKind::Sequence;
  std::filesystem::path folder;  // folder of the sequence (the source itself or the cache)
  bool converted = false;        // false when the source was a sequence
  bool reused_cache = false;     // true when an earlier conversion was reused
  ImportReport report;           // of the conversion (only when converted and not reused)
  // When the conversion left frames out (damaged images, missing poses): how
  // many and why, kept beside the cached sequence so that a reused
  // conversion says it too. Empty otherwise.
  std::string skipped_frames;
  // Likewise, frames kept without their colour image (which could not be
  // read): the files and why. Empty otherwise.
  std::string colour_left_out;
  // The conversion's notes (report.notes), and those of them that are
  // warnings (ImportReport::warnings), also for a reused conversion: they are
  // kept in the cache entry (kImportNotesFile) as the skipped frames are.
  std::vector<std::string> notes;
  std::vector<std::string> warnings;
};
// The file of a cache entry (OpenedSource::folder) with its notes, one a line.
inline constexpr const char* kImportNotesFile = "import-notes.txt";
[[nodiscard]] OpenedSource openSource(const std::filesystem::path& path,
                                      const ImportOptions& options = {},
                                      const std::filesystem::path& cache_root = {},
                                      const ImportProgressCallback& progress = {});
// $XDG_CACHE_HOME/labeloctomap/imports, else ~/.cache/labeloctomap/imports,
// else <temp>/labeloctomap-imports.
[[nodiscard]] std::filesystem::path defaultImportCacheRoot();

}  // namespace lom
