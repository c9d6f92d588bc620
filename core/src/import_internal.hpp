#pragma once
// Pieces shared by the importers (import*.cpp): the sequence writer that every
// source feeds, text and matrix parsing, frame selection. Not a public API.
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "lom/atomic_file.hpp"
#include "lom/import.hpp"

namespace lom::import_detail {

namespace fs = std::filesystem;

// One frame as a source delivers it, before filtering and resampling.
struct SourceFrame {
  std::string name;  // for messages: file name, number or time stamp
  // Seconds; left empty when the source has no time (frame numbers are not times).
  std::optional<double> stamp;
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();  // camera-to-world, as read
  DepthImage depth;                                    // metres; 0 / NaN = no measurement
  std::optional<ColorImage> color;
  std::optional<ProbabilityImage> proba;  // channel_labels must be set
  std::optional<LabelImage> label;        // ground truth when proba is set, else the evidence
  // Cameras of the colour and of the label evidence (proba / label) images when
  // they are not the depth camera (ScanNet: colour at 1296 x 968). When absent,
  // an image of another size is assumed to cover the same field of view.
  std::optional<CameraIntrinsics> color_camera;
  std::optional<CameraIntrinsics> evidence_camera;
};

// Writes the converted frames and, last, sequence.json. On destruction without
// finish() (an exception, a cancel) it removes what it wrote; a sequence it
// replaces (the overwrite option) is removed only by finish(), once every new
// frame is written.
class SequenceWriter {
 public:
  SequenceWriter(const fs::path& out_folder, const ImportOptions& options, ImportReport& report,
                 const ImportProgressCallback& progress);
  ~SequenceWriter();
  SequenceWriter(const SequenceWriter&) = delete;
  SequenceWriter& operator=(const SequenceWriter&) = delete;

  // The depth camera; width/height <= 0 are taken from the first frame's depth.
  void setCamera(const CameraIntrinsics& camera) { camera_ = camera; }
  // Metres per unit of the written 16-bit depth PNGs.
  void setDepthScale(double scale) { depth_scale_ = scale; }
  void setLabels(LabelSet labels) { labels_ = std::move(labels); }
  // Frames without evidence get an all-background label image (single-label sequences).
  // A source without label or probability images: each frame gets an
  // all-background placeholder label image, and the sequence the labels given
  // with --labels (for a segmenter), else the background alone.
  void setLabelless(bool labelless) {
    labelless_ = labelless;
    if (labelless && options_.labels) labels_ = *options_.labels;
  }
  // The note saying a labelless source's sequence has only the background;
  // left out when --labels gave it labels (finish() notes those).
  void noteOnlyBackground(const std::string& text) {
    if (!options_.labels) note(text);
  }
  void setFrameId(std::string frame_id) { frame_id_ = std::move(frame_id); }
  void setTotal(size_t total) { total_ = total; }
  // Number of frames the source holds (before the frame subset).
  void setFound(size_t found) { report_.frames_found = found; }
  [[nodiscard]] const LabelSet& labels() const { return labels_; }

  // Converts and writes one frame; a frame that cannot be used is listed as
  // skipped. Returns false when the progress callback asked to cancel.
  bool add(SourceFrame frame);
  // Records a frame the source could not deliver; counts towards progress.
  bool skip(const std::string& frame, const std::string& reason);
  // How far the source has been read before its frames (ImportProgress::read):
  // reported when it has moved by a thousandth since the last report. Returns
  // false when the progress callback asked to cancel (the import then stops
  // without a frame, as cancelled).
  bool reading(std::uint64_t read, std::uint64_t read_total);
  // Adds a note once (repeated notes are counted instead).
  void note(const std::string& text);

  // Writes sequence.json. Throws lom::Error when no frame was written.
  void finish(const std::string& source_description);

 private:
  bool advance();
  void prepareFolder();
  // The subfolder `sub` of the output, created on its first file: a folder
  // that nothing goes into (proba/ of a geometry-only import) is not made.
  fs::path fileIn(const char* sub, const std::string& name);
  void cleanUp() noexcept;
  // Writes sequence.json and, for an existing folder, replaces the old
  // sequence (its sequence.json and frame folders) with the staged one, all
  // or nothing: a failure leaves the old sequence as it was.
  void commitSequence(const std::string& json);
  // The steps of convert(): each returns why the frame cannot be used, if it cannot.
  [[nodiscard]] std::optional<std::string> convert(SourceFrame& frame, FrameRecord& record);
  [[nodiscard]] std::optional<std::string> convertPose(const SourceFrame& frame,
                                                       FrameRecord& record);
  // The frame's camera: the depth camera, scaled to the frame's depth image.
  [[nodiscard]] std::optional<std::string> convertDepth(SourceFrame& frame, FrameRecord& record,
                                                        CameraIntrinsics& camera,
                                                        DepthFilterStats& stats);
  void convertColor(SourceFrame& frame, const CameraIntrinsics& camera);
  [[nodiscard]] std::optional<std::string> convertEvidence(SourceFrame& frame, FrameRecord& record,
                                                           const CameraIntrinsics& camera);
  void writeFrameFiles(const SourceFrame& frame, FrameRecord& record);

  fs::path out_;
  const ImportOptions& options_;
  ImportReport& report_;
  const ImportProgressCallback& progress_;
  CameraIntrinsics camera_;
  double depth_scale_ = 0.001;
  LabelSet labels_;
  bool labelless_ = false;
  std::string frame_id_ = "world";
  std::vector<FrameRecord> records_;
  size_t total_ = 0;
  size_t done_ = 0;
  std::uint64_t reading_reported_ = 0;  // thousandths of the reading last reported, plus 1
  bool finished_ = false;
  bool prepared_ = false;
  // The staging folder, or a new output folder, for a signal to remove.
  PendingOutput pending_;
  // The output folder this import made (as the kernel resolved it), removed
  // whole on failure, and the folders of its path that it made, removed
  // while empty (another import may have put its output beside it).
  fs::path created_folder_;
  std::optional<NewFolders> new_folders_;
  // With the overwrite option over an existing sequence: the folder inside the
  // output where the new frames are written until finish() swaps them in, so
  // that a failure or a cancel leaves the old sequence as it was.
  fs::path staging_;
  DepthFilterStats filter_totals_;
  std::map<std::string, size_t> note_counts_;
  std::vector<std::string> note_order_;
};

// Frame indices [0, count) kept by first_frame / frame_step / max_frames.
[[nodiscard]] std::vector<size_t> selectFrames(size_t count, const ImportOptions& options);

// --- text files --------------------------------------------------------------

// Whitespace- or comma-separated numbers (inf / nan accepted). Lines starting with
// '#' are skipped. Throws lom::Error naming the file and line for other tokens.
[[nodiscard]] std::vector<double> readNumbers(const fs::path& path);
[[nodiscard]] std::vector<double> parseNumbers(const std::string& text, const std::string& file,
                                               int line);
[[nodiscard]] std::string readText(const fs::path& path);
// Lines with their 1-based numbers, trailing '\r' removed.
[[nodiscard]] std::vector<std::pair<int, std::string>> readLines(const fs::path& path);

// Camera matrix from 4 numbers (fx fy cx cy), 9 (3x3) or 16 (4x4, top-left 3x3).
[[nodiscard]] CameraIntrinsics intrinsicsFromNumbers(const std::vector<double>& numbers,
                                                     const std::string& file);
// Camera-to-world from tx ty tz qx qy qz qw (quaternion normalised).
[[nodiscard]] Eigen::Matrix4d poseFromQuaternion(const double* tx_ty_tz_qx_qy_qz_qw);
[[nodiscard]] Eigen::Matrix4d matrixFromRowMajor(const double* values16);

// Numeric frame files: name -> number, e.g. "frame-000015.depth.png" -> 15.
struct NumberedFile {
  long number = 0;
  fs::path path;
};
// Files in `folder` whose name is prefix + digits + suffix, sorted by number.
[[nodiscard]] std::vector<NumberedFile> numberedFiles(const fs::path& folder,
                                                      const std::string& prefix,
                                                      const std::string& suffix);
// The name of a numbered file without `suffix` ("frame-15" of frame-15.depth.png):
// the files of the same frame are named from it, however its number is padded.
[[nodiscard]] inline std::string numberedStem(const NumberedFile& file, const std::string& suffix) {
  const std::string name = file.path.filename().string();
  return name.size() >= suffix.size() ? name.substr(0, name.size() - suffix.size()) : name;
}
// Same, with any of the suffixes (first match per number wins).
[[nodiscard]] std::vector<NumberedFile> numberedFiles(const fs::path& folder,
                                                      const std::string& prefix,
                                                      const std::vector<std::string>& suffixes);

// The camera to use: the override in options if any (noted), else `from_source`;
// throws a lom::Error naming `source` and `hint` when there is neither.
[[nodiscard]] CameraIntrinsics chooseCamera(const std::optional<CameraIntrinsics>& from_source,
                                            const std::string& from_source_description,
                                            const ImportOptions& options, SequenceWriter& writer,
                                            const fs::path& source, const std::string& hint);

// Raw 16-bit image values (no scaling), or an error naming the file.
[[nodiscard]] DepthImage readRaw16(const fs::path& path);
// Depth in metres from a 16-bit image, value * scale; `invalid_value` (if any) is 0.
[[nodiscard]] DepthImage readDepth16(const fs::path& path, double scale,
                                     std::optional<std::uint16_t> invalid_value = std::nullopt);
// Label ids through `map` (ids not in it are reported in `unknown` and become 0).
LabelImage remapLabels(const LabelImage& raw, const std::map<int, int>& map,
                       std::set<int>* unknown);

// A label set whose entry 0 is "__background__" and the others are `names`.
[[nodiscard]] LabelSet makeLabels(const std::vector<std::string>& names_after_background);
[[nodiscard]] LabelSet backgroundOnlyLabels();

// Importers; each fills the writer (or throws lom::Error for the source as a whole).
// How the note on a colour image left out begins (openSource lists those notes).
inline constexpr const char* kUnreadableColourNote =
    "a colour image that cannot be read was left out";
// How the notes that are warnings begin (ImportReport::warnings): those
// marked so, and the default intrinsics of a TUM folder, which the CLI has
// always printed as a plain note.
inline constexpr const char* kWarningNote = "warning: ";
inline constexpr const char* kDefaultTumIntrinsicsNote =
    "no freiburg1/2/3 in the folder name: the benchmark's default intrinsics";
// A frame's colour image, or nothing (and a note naming it) when it cannot be
// read: colour is shown, never fused, so the frame's depth is kept.
std::optional<ColorImage> readColorOrLeaveOut(const fs::path& path, SequenceWriter& writer);
void importFrames(const fs::path& source, const ImportOptions& options, SequenceWriter& writer);
void importTum(const fs::path& source, const ImportOptions& options, SequenceWriter& writer);
void importQuaternion(const fs::path& source, const ImportOptions& options,
                      SequenceWriter& writer);
void importScanNet(const fs::path& source, const ImportOptions& options, SequenceWriter& writer);
void importApcShelf(const fs::path& source, const ImportOptions& options, SequenceWriter& writer);
void importRosbag(const fs::path& source, const ImportOptions& options, SequenceWriter& writer);

// Pose of a time stamp from samples sorted by time: interpolated (linear
// translation, slerp) between the bracketing samples when both lie within
// `tolerance`, else the nearest sample within `tolerance`; nullopt otherwise.
struct TimedPose {
  double stamp = 0.0;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};
[[nodiscard]] std::optional<Eigen::Matrix4d> interpolatePose(const std::vector<TimedPose>& poses,
                                                             double stamp, double tolerance);
// Index of the stamp nearest to `stamp` within `tolerance` in a sorted list.
[[nodiscard]] std::optional<size_t> nearestStamp(const std::vector<double>& stamps, double stamp,
                                                 double tolerance);

[[nodiscard]] std::string formatNumber(double value, int precision = 6);

}  // namespace lom::import_detail
