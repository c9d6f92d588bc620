// The sequence writer every importer feeds: pose checks, depth filtering,
// resampling of colour and label evidence to the depth camera, label images to
// one-hot probabilities, frame files and, last, sequence.json.

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "import_internal.hpp"
#include "lom/atomic_file.hpp"
#include "lom/npy.hpp"
#include "lom/sequence.hpp"

namespace lom::import_detail {

namespace {

constexpr double kAspectTolerance = 0.01;
// Poses read from text with a few digits are re-orthonormalised; farther from a
// rotation than this they are rejected.
constexpr double kRotationTolerance = 1e-2;

std::string sizeText(int width, int height) {
  return std::to_string(width) + " x " + std::to_string(height);
}

bool sameAspect(int w1, int h1, int w2, int h2) {
  const double a = static_cast<double>(w1) / h1;
  const double b = static_cast<double>(w2) / h2;
  return std::abs(a - b) <= kAspectTolerance * b;
}

// The intrinsics of `camera` for an image of another size covering the same view.
CameraIntrinsics scaledCamera(const CameraIntrinsics& camera, int width, int height) {
  CameraIntrinsics scaled = camera;
  const double sx = static_cast<double>(width) / camera.width;
  const double sy = static_cast<double>(height) / camera.height;
  scaled.width = width;
  scaled.height = height;
  scaled.fx = camera.fx * sx;
  scaled.fy = camera.fy * sy;
  scaled.cx = (camera.cx + 0.5) * sx - 0.5;
  scaled.cy = (camera.cy + 0.5) * sy - 0.5;
  return scaled;
}

// For each pixel of `to`, the (sub)pixel of `from` seeing the same direction
// (both cameras share their optical centre).
struct PixelMap {
  int width = 0, height = 0;
  std::vector<float> x, y;
  [[nodiscard]] bool inside(size_t i, int from_w, int from_h) const {
    return x[i] > -0.5f && y[i] > -0.5f && x[i] < from_w - 0.5f && y[i] < from_h - 0.5f;
  }
};

PixelMap makePixelMap(const CameraIntrinsics& from, const CameraIntrinsics& to) {
  PixelMap map;
  map.width = to.width;
  map.height = to.height;
  const size_t n = static_cast<size_t>(to.width) * static_cast<size_t>(to.height);
  map.x.resize(n);
  map.y.resize(n);
  for (int v = 0; v < to.height; ++v)
    for (int u = 0; u < to.width; ++u) {
      const size_t i = static_cast<size_t>(v) * static_cast<size_t>(to.width) + u;
      map.x[i] = static_cast<float>(from.fx * (u - to.cx) / to.fx + from.cx);
      map.y[i] = static_cast<float>(from.fy * (v - to.cy) / to.fy + from.cy);
    }
  return map;
}

// Bilinear sample of an interleaved float/uint8 image with `channels` channels.
template <typename T>
void bilinear(const T* data, int width, int height, int channels, float x, float y, float* out) {
  x = std::clamp(x, 0.0f, static_cast<float>(width - 1));
  y = std::clamp(y, 0.0f, static_cast<float>(height - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const float fx = x - x0, fy = y - y0;
  const auto at = [&](int xx, int yy, int c) {
    return static_cast<float>(
        data[(static_cast<size_t>(yy) * static_cast<size_t>(width) + xx) * channels + c]);
  };
  for (int c = 0; c < channels; ++c)
    out[c] = (1 - fy) * ((1 - fx) * at(x0, y0, c) + fx * at(x1, y0, c)) +
             fy * ((1 - fx) * at(x0, y1, c) + fx * at(x1, y1, c));
}

ColorImage resampleColor(const ColorImage& in, const PixelMap& map) {
  ColorImage out;
  out.width = map.width;
  out.height = map.height;
  out.rgb.assign(static_cast<size_t>(map.width) * map.height * 3, 0);
  float rgb[3];
  for (size_t i = 0; i < map.x.size(); ++i) {
    if (!map.inside(i, in.width, in.height)) continue;
    bilinear(in.rgb.data(), in.width, in.height, 3, map.x[i], map.y[i], rgb);
    for (int c = 0; c < 3; ++c)
      out.rgb[i * 3 + c] = static_cast<std::uint8_t>(std::clamp(std::lround(rgb[c]), 0L, 255L));
  }
  return out;
}

LabelImage resampleLabel(const LabelImage& in, const PixelMap& map) {
  LabelImage out;
  out.width = map.width;
  out.height = map.height;
  out.ids.assign(static_cast<size_t>(map.width) * map.height, 0);
  for (size_t i = 0; i < map.x.size(); ++i) {
    if (!map.inside(i, in.width, in.height)) continue;
    const int x = std::clamp(static_cast<int>(std::lround(map.x[i])), 0, in.width - 1);
    const int y = std::clamp(static_cast<int>(std::lround(map.y[i])), 0, in.height - 1);
    out.ids[i] = in.ids[static_cast<size_t>(y) * static_cast<size_t>(in.width) + x];
  }
  return out;
}

ProbabilityImage resampleProba(const ProbabilityImage& in, const PixelMap& map) {
  ProbabilityImage out;
  out.width = map.width;
  out.height = map.height;
  out.channels = in.channels;
  out.channel_labels = in.channel_labels;
  out.values.assign(static_cast<size_t>(map.width) * map.height * in.channels, 0.0f);
  for (size_t i = 0; i < map.x.size(); ++i) {
    if (!map.inside(i, in.width, in.height)) continue;
    bilinear(in.values.data(), in.width, in.height, in.channels, map.x[i], map.y[i],
             out.values.data() + i * in.channels);
  }
  return out;
}

// IEEE 754 binary16, round to nearest even.
std::uint16_t floatToHalf(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  const std::uint16_t sign = static_cast<std::uint16_t>((bits >> 16) & 0x8000u);
  const std::uint32_t abs = bits & 0x7fffffffu;
  if (abs >= 0x7f800000u)  // inf or NaN
    return static_cast<std::uint16_t>(sign | 0x7c00u | (abs > 0x7f800000u ? 0x200u : 0u));
  if (abs >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // overflow
  if (abs < 0x38800000u) {  // subnormal or zero in half precision
    if (abs < 0x33000000u) return sign;
    const std::uint32_t mantissa = (abs & 0x7fffffu) | 0x800000u;
    const int shift = 126 - static_cast<int>(abs >> 23);  // value * 2^24 = mantissa >> shift
    const std::uint32_t half_mantissa = mantissa >> shift;
    const std::uint32_t remainder = mantissa & ((1u << shift) - 1);
    const std::uint32_t halfway = 1u << (shift - 1);
    std::uint32_t result = half_mantissa;
    if (remainder > halfway || (remainder == halfway && (half_mantissa & 1u))) ++result;
    return static_cast<std::uint16_t>(sign | result);
  }
  std::uint32_t result = ((abs >> 13) - (112u << 10));
  const std::uint32_t remainder = abs & 0x1fffu;
  if (remainder > 0x1000u || (remainder == 0x1000u && (result & 1u))) ++result;
  return static_cast<std::uint16_t>(sign | result);
}

void writeProbabilityNpy(const fs::path& path, const ProbabilityImage& proba) {
  NpyArray array;
  array.type = NpyType::Float16;
  array.shape = {static_cast<size_t>(proba.height), static_cast<size_t>(proba.width),
                 static_cast<size_t>(proba.channels)};
  array.bytes.resize(proba.values.size() * 2);
  for (size_t i = 0; i < proba.values.size(); ++i) {
    const std::uint16_t h = floatToHalf(std::clamp(proba.values[i], 0.0f, 1.0f));
    std::memcpy(array.bytes.data() + 2 * i, &h, 2);
  }
  writeNpy(path, array);
}

// One-hot probabilities over the labels present in the image.
ProbabilityImage oneHot(const LabelImage& label, double confidence) {
  std::vector<int> present(label.ids.begin(), label.ids.end());
  std::sort(present.begin(), present.end());
  present.erase(std::unique(present.begin(), present.end()), present.end());
  ProbabilityImage proba;
  proba.width = label.width;
  proba.height = label.height;
  proba.channels = static_cast<int>(present.size());
  proba.channel_labels = present;
  const size_t k = present.size();
  const float other = k > 1 ? static_cast<float>((1.0 - confidence) / static_cast<double>(k - 1))
                            : 0.0f;
  proba.values.assign(label.ids.size() * k, other);
  std::vector<int> channel_of(static_cast<size_t>(present.back()) + 1, 0);
  for (size_t c = 0; c < k; ++c) channel_of[static_cast<size_t>(present[c])] = static_cast<int>(c);
  for (size_t i = 0; i < label.ids.size(); ++i)
    proba.values[i * k + static_cast<size_t>(channel_of[label.ids[i]])] =
        static_cast<float>(confidence);
  return proba;
}

std::string indexName(size_t index) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "%06zu", index);
  return buffer;
}

}  // namespace

SequenceWriter::SequenceWriter(const fs::path& out_folder, const ImportOptions& options,
                               ImportReport& report, const ImportProgressCallback& progress)
    : out_(out_folder), options_(options), report_(report), progress_(progress) {
  labels_ = backgroundOnlyLabels();
  std::error_code ec;
  if (fs::exists(out_, ec) && !fs::is_directory(out_, ec))
    throw Error(out_.string(), "output", "a folder (new or empty) for the sequence",
                "a file of that name");
  if (!options_.overwrite && fs::is_directory(out_, ec)) {
    if (fs::exists(out_ / "sequence.json", ec))
      throw Error(out_.string(), "output",
                  "a new or empty folder (or the overwrite option to replace the sequence)",
                  "a folder that already holds sequence.json");
    for (const char* sub : {"depth", "color", "proba", "label"})
      if (fs::is_directory(out_ / sub, ec) && !fs::is_empty(out_ / sub, ec))
        throw Error(out_.string(), "output",
                    "a new or empty folder (or the overwrite option to replace its frames)",
                    std::string("a folder with files in ") + sub + "/");
  }
}

SequenceWriter::~SequenceWriter() {
  if (!finished_) cleanUp();
}

void SequenceWriter::prepareFolder() {
  if (prepared_) return;
  std::error_code ec;
  if (!fs::exists(out_, ec)) {
    // The folders of the path that are missing go again when the import
    // fails or is cancelled (out/new/seq leaves no empty out/new behind).
    new_folders_.emplace(out_);
    fs::create_directories(out_, ec);
    if (ec)
      throw Error(out_.string(), "output", "a folder that can be created", ec.message());
    // Removed whole on failure, as the kernel resolved it now that it exists.
    created_folder_ = fs::canonical(out_, ec);
    if (ec) created_folder_ = fs::absolute(out_);
    pending_ = PendingOutput(created_folder_, PendingOutput::Kind::Tree);
  } else {
    // An existing folder (empty frame folders, or --overwrite) gets the
    // frames only once they are all written: a failed or cancelled import
    // leaves it as it was.
    staging_ = createStagingFolder(out_, "import", pending_);
  }
  prepared_ = true;
}

void SequenceWriter::commitSequence(const std::string& json) {
  if (staging_.empty()) {  // a new folder: removed whole if this fails
    writeTextFileAtomically(out_ / "sequence.json", json);
    pending_.release();
    new_folders_->keep();
    return;
  }
  // The new sequence file first, complete, beside the new frames: a write
  // that fails (a full disk) leaves the old sequence untouched.
  try {
    writeTextFileAtomically(staging_ / "sequence.json", json);
  } catch (const Error& e) {  // named where it goes, not by the hidden staging folder
    throw Error((out_ / "sequence.json").string(), e.problem().field, e.problem().expected,
                e.problem().found + " (the sequence there is left as it was)");
  }
  // Then the old files aside and the new ones in, by renames within the
  // folder; any rename that fails puts everything back. The staging folder
  // then holds the old sequence: a signal no longer removes it.
  pending_.release();
  const fs::path old = staging_ / ".replaced";
  std::error_code ec;
  fs::create_directories(old, ec);
  if (ec) throw Error(old.string(), "output", "a folder for the replaced files", ec.message());
  const char* const kParts[] = {"sequence.json", "depth", "color", "proba", "label"};
  std::vector<std::string> set_aside, moved_in;
  auto rollBack = [&] {
    std::error_code ignored;
    for (auto it = moved_in.rbegin(); it != moved_in.rend(); ++it)
      fs::rename(out_ / *it, staging_ / *it, ignored);
    for (auto it = set_aside.rbegin(); it != set_aside.rend(); ++it)
      fs::rename(old / *it, out_ / *it, ignored);
  };
  auto move = [&](const fs::path& from, const fs::path& to, std::vector<std::string>& done,
                  const char* name) {
    fs::rename(from, to, ec);
    if (ec) {
      const std::string why = ec.message();
      rollBack();
      throw Error((out_ / name).string(), "output", "a file or folder the import can replace",
                  "rename failed: " + why + " (the sequence there is left as it was)");
    }
    done.emplace_back(name);
  };
  // The old sequence file goes first: a half-replaced folder is never a sequence.
  for (const char* part : kParts)
    if (fs::symlink_status(out_ / part, ec).type() != fs::file_type::not_found)
      move(out_ / part, old / part, set_aside, part);
  // The new one comes last, for the same reason.
  for (const char* part : {"depth", "color", "proba", "label", "sequence.json"})
    if (fs::symlink_status(staging_ / part, ec).type() != fs::file_type::not_found)
      move(staging_ / part, out_ / part, moved_in, part);
  fs::remove_all(staging_, ec);  // the replaced files with it
  staging_.clear();
}

fs::path SequenceWriter::fileIn(const char* sub, const std::string& name) {
  prepareFolder();
  const fs::path dir = (staging_.empty() ? out_ : staging_) / sub;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    fs::create_directories(dir, ec);
    if (ec) throw Error(dir.string(), "output", "a writable folder", ec.message());
  }
  return dir / name;
}

void SequenceWriter::cleanUp() noexcept {
  std::error_code ec;
  if (!staging_.empty()) fs::remove_all(staging_, ec);
  // A new output goes whole; an existing one was written only through the
  // staging folder, removed above.
  if (!created_folder_.empty()) fs::remove_all(created_folder_, ec);
  new_folders_.reset();  // the folders above it, while empty
}

void SequenceWriter::note(const std::string& text) {
  if (note_counts_[text]++ == 0) note_order_.push_back(text);
}

bool SequenceWriter::advance() {
  ++done_;
  if (!progress_) return true;
  if (!progress_(ImportProgress{done_, std::max(total_, done_)})) {
    report_.cancelled = true;
    return false;
  }
  return true;
}

bool SequenceWriter::reading(std::uint64_t read, std::uint64_t read_total) {
  if (!progress_ || read_total == 0) return true;
  // A thousandth at a time: a bag's records come in thousands, and the
  // command line prints each report.
  const std::uint64_t step = std::min(read, read_total) * 1000 / read_total + 1;
  if (step == reading_reported_) return true;
  reading_reported_ = step;
  if (!progress_(ImportProgress{0, 0, read, read_total})) {
    report_.cancelled = true;
    return false;
  }
  return true;
}

bool SequenceWriter::skip(const std::string& frame, const std::string& reason) {
  report_.skipped.push_back({frame, reason});
  return advance();
}

bool SequenceWriter::add(SourceFrame frame) {
  FrameRecord record;
  if (auto reason = convert(frame, record)) return skip(frame.name, *reason);
  records_.push_back(std::move(record));
  return advance();
}

std::optional<std::string> SequenceWriter::convert(SourceFrame& frame, FrameRecord& record) {
  if (auto reason = convertPose(frame, record)) return reason;
  record.stamp = frame.stamp;
  CameraIntrinsics camera;
  DepthFilterStats stats;
  if (auto reason = convertDepth(frame, record, camera, stats)) return reason;
  convertColor(frame, camera);
  if (auto reason = convertEvidence(frame, record, camera)) return reason;
  size_t valid = 0;
  for (float z : frame.depth.metres) valid += z > 0.0f;
  if (valid == 0)
    return "no valid depth (" + std::to_string(stats.invalid) + " invalid, " +
           std::to_string(stats.out_of_range) + " out of range, " + std::to_string(stats.flying) +
           " flying pixels removed)";
  if (camera_.width <= 0 || camera_.height <= 0) {  // the first frame written
    camera_.width = camera.width;
    camera_.height = camera.height;
  }
  writeFrameFiles(frame, record);
  return std::nullopt;
}

// Pose: finite, rigid (re-orthonormalised when read from text with few digits).
std::optional<std::string> SequenceWriter::convertPose(const SourceFrame& frame,
                                                       FrameRecord& record) {
  const Eigen::Matrix4d& P = frame.pose;
  if (!P.allFinite()) return std::string("no valid pose (the pose holds inf or NaN)");
  const Eigen::Matrix3d R = P.topLeftCorner<3, 3>();
  const double orthonormality = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const double det = R.determinant();
  const double last_row = (P.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff();
  if (orthonormality > kRotationTolerance || det <= 0.0 || last_row > 1e-4)
    return "the pose is not a rigid transform (det R = " + formatNumber(det) +
           ", max |R^T R - I| = " + formatNumber(orthonormality) + ", last row " +
           formatNumber(P(3, 0)) + " " + formatNumber(P(3, 1)) + " " + formatNumber(P(3, 2)) + " " +
           formatNumber(P(3, 3)) + ")";
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d rotation = svd.matrixU() * svd.matrixV().transpose();
  if (orthonormality > 1e-12) {
    const Eigen::Quaterniond q(rotation);
    rotation = q.normalized().toRotationMatrix();
  } else {
    rotation = R;
  }
  record.T_world_camera.linear() = rotation;
  record.T_world_camera.translation() = P.topRightCorner<3, 1>();
  return std::nullopt;
}

// Depth and camera: the depth filtered, depths the 16-bit PNG cannot hold dropped.
std::optional<std::string> SequenceWriter::convertDepth(SourceFrame& frame, FrameRecord& record,
                                                        CameraIntrinsics& camera,
                                                        DepthFilterStats& stats) {
  DepthImage& depth = frame.depth;
  if (depth.width <= 0 || depth.height <= 0 || depth.metres.empty())
    return std::string("empty depth image");
  // Intrinsics without an image size (a bare camera matrix) take the size of
  // the first frame written (convert), not of a frame that is then skipped.
  CameraIntrinsics reference = camera_;
  if (reference.width <= 0 || reference.height <= 0) {
    reference.width = depth.width;
    reference.height = depth.height;
  }
  camera = reference;
  camera.depth_scale = depth_scale_;
  if (depth.width != reference.width || depth.height != reference.height) {
    if (!sameAspect(depth.width, depth.height, reference.width, reference.height))
      return "the depth image is " + sizeText(depth.width, depth.height) + ", the camera " +
             sizeText(reference.width, reference.height) + " (another aspect ratio)";
    camera = scaledCamera(camera, depth.width, depth.height);
    record.camera = camera;
    note("depth images of " + sizeText(depth.width, depth.height) + " instead of " +
         sizeText(reference.width, reference.height) + ": intrinsics scaled for those frames");
  }

  stats = filterDepth(depth, options_.depth_filter);
  filter_totals_.invalid += stats.invalid;
  filter_totals_.out_of_range += stats.out_of_range;
  filter_totals_.flying += stats.flying;
  filter_totals_.kept += stats.kept;
  if (stats.invalid > 0) note("NaN, infinite or negative depths were treated as holes");
  const double max_storable = 65535.0 * depth_scale_;
  size_t too_far = 0;
  for (float& z : depth.metres)
    if (z > max_storable) {
      z = 0.0f;
      ++too_far;
    }
  if (too_far > 0)
    note("depths beyond " + formatNumber(max_storable, 4) +
         " m (65535 x the depth unit) were dropped");
  return std::nullopt;
}

// Colour: display only; resampled to the depth camera when it has another size.
void SequenceWriter::convertColor(SourceFrame& frame, const CameraIntrinsics& camera) {
  if (frame.color && options_.write_color) {
    ColorImage& color = *frame.color;
    if (color.width != frame.depth.width || color.height != frame.depth.height) {
      std::optional<CameraIntrinsics> from = frame.color_camera;
      if (!from && sameAspect(color.width, color.height, frame.depth.width, frame.depth.height))
        from = scaledCamera(camera, color.width, color.height);
      if (from) {
        CameraIntrinsics from_sized = *from;
        from_sized.width = color.width;
        from_sized.height = color.height;
        note("colour images of " + sizeText(color.width, color.height) +
             " resampled to the depth camera");
        color = resampleColor(color, makePixelMap(from_sized, camera));
      } else {
        note("colour images of another aspect ratio than the depth images were left out");
        frame.color.reset();
      }
    }
  } else {
    frame.color.reset();
  }
}

// Label evidence: resampled to the depth camera; depth outside its view is
// dropped. Label images alone become one-hot probabilities.
std::optional<std::string> SequenceWriter::convertEvidence(SourceFrame& frame, FrameRecord& record,
                                                           const CameraIntrinsics& camera) {
  DepthImage& depth = frame.depth;
  const bool has_proba = frame.proba.has_value();
  const bool has_label = frame.label.has_value();
  auto evidenceSize = [&]() -> std::pair<int, int> {
    return has_proba ? std::pair{frame.proba->width, frame.proba->height}
                     : std::pair{frame.label->width, frame.label->height};
  };
  if (has_proba || has_label) {
    const auto [ew, eh] = evidenceSize();
    if (has_proba && has_label &&
        (frame.label->width != ew || frame.label->height != eh))
      return "the label image is " + sizeText(frame.label->width, frame.label->height) +
             ", the probability image " + sizeText(ew, eh);
    if (ew != depth.width || eh != depth.height) {
      std::optional<CameraIntrinsics> from = frame.evidence_camera;
      if (!from && sameAspect(ew, eh, depth.width, depth.height))
        from = scaledCamera(camera, ew, eh);
      if (!from)
        return std::string(has_proba ? "the probability" : "the label") + " image is " +
               sizeText(ew, eh) + ", the depth image " + sizeText(depth.width, depth.height) +
               " (another aspect ratio; give the cameras of both to resample)";
      CameraIntrinsics from_sized = *from;
      from_sized.width = ew;
      from_sized.height = eh;
      const PixelMap map = makePixelMap(from_sized, camera);
      if (has_proba) frame.proba = resampleProba(*frame.proba, map);
      if (has_label) frame.label = resampleLabel(*frame.label, map);
      size_t outside = 0;
      for (size_t i = 0; i < map.x.size(); ++i)
        if (!map.inside(i, ew, eh) && depth.metres[i] > 0.0f) {
          depth.metres[i] = 0.0f;
          ++outside;
        }
      note(std::string(has_proba ? "probability" : "label") + " images of " + sizeText(ew, eh) +
           " resampled to the depth camera" +
           (outside ? " (depth outside their view dropped)" : ""));
    }
  }
  if (has_label) {
    for (std::uint16_t id : frame.label->ids)
      if (!labels_.contains(id))
        return "label id " + std::to_string(id) + " is not one of the " +
               std::to_string(labels_.size()) + " labels";
  }
  if (has_proba) {
    for (int id : frame.proba->channel_labels)
      if (!labels_.contains(id))
        return "probability channel of label " + std::to_string(id) + " is not one of the " +
               std::to_string(labels_.size()) + " labels";
  }
  if (!has_proba && has_label) {
    frame.proba = oneHot(*frame.label, options_.label_confidence);
    record.proba_from_label = true;
  }
  if (!has_proba && !has_label && !labelless_)
    return std::string("no probability or label image for this frame");
  return std::nullopt;
}

void SequenceWriter::writeFrameFiles(const SourceFrame& frame, FrameRecord& record) {
  const DepthImage& depth = frame.depth;
  const std::string name = indexName(records_.size());
  record.depth = "depth/" + name + ".png";
  writeDepthPng(fileIn("depth", name + ".png"), depth, depth_scale_);
  if (frame.color) {
    record.color = "color/" + name + ".png";
    writeColorPng(fileIn("color", name + ".png"), *frame.color);
  }
  if (frame.proba) {
    record.proba = "proba/" + name + ".npy";
    writeProbabilityNpy(fileIn("proba", name + ".npy"), *frame.proba);
    record.proba_labels = frame.proba->channel_labels;
  }
  if (frame.label) {
    record.label = "label/" + name + ".png";
    writeLabelPng(fileIn("label", name + ".png"), *frame.label);
  } else if (labelless_ && !frame.proba) {
    LabelImage background;
    background.width = depth.width;
    background.height = depth.height;
    background.ids.assign(depth.metres.size(), 0);
    record.label = "label/" + name + ".png";
    record.label_placeholder = true;  // all background, for want of labels: no ground truth
    writeLabelPng(fileIn("label", name + ".png"), background);
  }
}

void SequenceWriter::finish(const std::string& source_description) {
  if (!records_.empty()) {
    const auto& t = filter_totals_;
    const double measured = static_cast<double>(t.kept + t.flying + t.out_of_range);
    auto percent = [&](size_t n) {
      return measured > 0 ? " (" + formatNumber(100.0 * static_cast<double>(n) / measured, 3) + "%)"
                          : std::string();
    };
    note("depth filter: " + std::to_string(t.kept) + " depths kept; dropped " +
         std::to_string(t.out_of_range) + " out of range" + percent(t.out_of_range) + ", " +
         std::to_string(t.flying) + " flying pixels" + percent(t.flying) +
         (t.invalid ? ", " + std::to_string(t.invalid) + " NaN/negative" : std::string()));
  }
  // A label list that names nothing of this source would otherwise vanish without a word.
  if (options_.labels && labelless_)
    note(
        "the source has no label or probability images: the given labels are the sequence's, "
        "for a segmenter's probabilities (labeloctomap segment); each frame's label image is "
        "a placeholder, all background, which scoring does not use as ground truth");
  else if (options_.labels && !(labels_ == *options_.labels))
    note("the given label list was not used: this source names its own labels");
  for (const auto& text : note_order_) {
    const size_t count = note_counts_[text];
    report_.notes.push_back(count > 1 ? text + " (" + std::to_string(count) + " times)" : text);
  }
  report_.frames_written = records_.size();
  if (report_.cancelled) return;
  if (records_.empty()) {
    std::string found = "none";
    if (report_.skipped.empty() && report_.frames_found > 0 &&
        options_.first_frame >= report_.frames_found)
      found = "none: --first " + std::to_string(options_.first_frame) +
              " is past the last of the " + std::to_string(report_.frames_found) +
              " frames found (--first counts from 0)";
    else if (!report_.skipped.empty())
      found = "none of " + std::to_string(report_.skipped.size()) + " frames; the first, " +
              report_.skipped.front().frame + ", because " + report_.skipped.front().reason;
    throw Error(source_description, "frames", "at least one frame that can be imported", found);
  }
  Sequence sequence;
  sequence.root = out_;
  sequence.frame_id = frame_id_;
  sequence.labels = labels_;
  sequence.camera = camera_;
  sequence.camera.depth_scale = depth_scale_;
  sequence.frames = std::move(records_);
  const std::string json = sequenceJsonText(sequence, out_);  // checked before anything moves
  commitSequence(json);
  finished_ = true;
}

std::vector<size_t> selectFrames(size_t count, const ImportOptions& options) {
  std::vector<size_t> selected;
  const size_t step = std::max<size_t>(options.frame_step, 1);
  for (size_t i = options.first_frame; i < count; i += step) {
    if (options.max_frames && selected.size() >= options.max_frames) break;
    selected.push_back(i);
  }
  return selected;
}

}  // namespace lom::import_detail
