// Folder layouts: frames (TSDF-fusion tools, 7-Scenes), TUM RGB-D, the
// quaternion-pose layout, ScanNet exports.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "import_internal.hpp"
#include "lom/geometry.hpp"

namespace lom::import_detail {

namespace {

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// An intrinsics file in `folder`: a .txt whose name mentions intrinsics (or is
// K.txt / camera.txt / calib.txt), excluding `exclude_prefix` files.
std::optional<fs::path> findIntrinsicsFile(const fs::path& folder, const std::string& exclude_prefix) {
  std::vector<fs::path> candidates;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (!entry.is_regular_file(ec)) continue;
    const std::string name = lower(entry.path().filename().string());
    if (entry.path().extension() != ".txt") continue;
    if (!exclude_prefix.empty() && name.rfind(exclude_prefix, 0) == 0) continue;
    if (name.find("intrinsic") != std::string::npos || name == "k.txt" || name == "camera.txt" ||
        name == "calib.txt")
      candidates.push_back(entry.path());
  }
  std::sort(candidates.begin(), candidates.end());
  if (candidates.empty()) return std::nullopt;
  return candidates.front();
}

// Runs `read`; a lom::Error becomes the frame's skip reason.
template <typename Reader>
std::optional<std::string> tryRead(Reader&& read) {
  try {
    read();
    return std::nullopt;
  } catch (const Error& e) {
    return std::string(e.what());
  }
}

std::string frameName(long number) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "frame-%06ld", number);
  return buffer;
}

// "stamp value..." lines of a TUM list; '#' comments and blank lines skipped.
struct TumEntry {
  double stamp = 0.0;
  std::string file;
};
std::vector<TumEntry> readTumList(const fs::path& path) {
  std::vector<TumEntry> entries;
  for (const auto& [number, line] : readLines(path)) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream in(line);
    std::string stamp_text, file, extra;
    in >> stamp_text >> file;
    char* end = nullptr;
    const double stamp = std::strtod(stamp_text.c_str(), &end);
    if (stamp_text.empty() || *end != '\0' || !std::isfinite(stamp) || file.empty() ||
        (in >> extra))
      throw Error(path.string(), "line " + std::to_string(number),
                  "'timestamp filename' (e.g. 1305031102.175304 rgb/1305031102.175304.png)",
                  "'" + (line.size() > 60 ? line.substr(0, 57) + "..." : line) + "'");
    entries.push_back({stamp, file});
  }
  std::stable_sort(entries.begin(), entries.end(),
                   [](const TumEntry& a, const TumEntry& b) { return a.stamp < b.stamp; });
  return entries;
}

std::vector<TimedPose> readTumPoses(const fs::path& path) {
  std::vector<TimedPose> poses;
  for (const auto& [number, line] : readLines(path)) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto n = parseNumbers(line, path.string(), number);
    if (n.size() != 8)
      throw Error(path.string(), "line " + std::to_string(number),
                  "8 numbers: timestamp tx ty tz qx qy qz qw", std::to_string(n.size()) + " numbers");
    if (!std::isfinite(n[0]))
      throw Error(path.string(), "line " + std::to_string(number), "a finite time stamp first",
                  "'" + (line.size() > 60 ? line.substr(0, 57) + "..." : line) + "'");
    TimedPose pose;
    pose.stamp = n[0];
    pose.t = Eigen::Vector3d(n[1], n[2], n[3]);
    const auto q = unitQuaternion(Eigen::Vector4d(n[4], n[5], n[6], n[7]));
    if (!pose.t.allFinite() || !q) continue;  // mocap dropout
    pose.q = *q;
    poses.push_back(pose);
  }
  std::stable_sort(poses.begin(), poses.end(),
                   [](const TimedPose& a, const TimedPose& b) { return a.stamp < b.stamp; });
  return poses;
}

std::string stampText(double stamp) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(6);
  out << stamp;
  return out.str();
}

}  // namespace

// ---------------------------------------------------------------------------
namespace {

// The camera from an intrinsics file in the folder (when there is one) or the
// intrinsics option, as chooseCamera decides; `required` says what is missing otherwise.
void setCameraFromIntrinsicsFile(const fs::path& source, const std::string& skip_prefix,
                                 const ImportOptions& options, SequenceWriter& writer,
                                 const std::string& required) {
  std::optional<CameraIntrinsics> file_camera;
  std::string described = "no intrinsics file";
  if (auto file = findIntrinsicsFile(source, skip_prefix)) {
    file_camera = intrinsicsFromNumbers(readNumbers(*file), file->string());
    described = "the intrinsics of " + file->filename().string();
    // The file is found by its name among others: say which one was taken.
    if (!options.intrinsics)
      writer.note("intrinsics read from " + file->string() + ": fx " +
                  formatNumber(file_camera->fx) + ", fy " + formatNumber(file_camera->fy) +
                  ", cx " + formatNumber(file_camera->cx) + ", cy " +
                  formatNumber(file_camera->cy));
  }
  writer.setCamera(chooseCamera(file_camera, described, options, writer, source, required));
}

}  // namespace

// frames: frame-NNNNNN.color.png / .depth.png (mm) / .pose.txt (4x4), intrinsics file.
// Colour is shown, never fused: an image that cannot be read leaves its
// frame without colour (as the bag import does), with a note naming it,
// instead of dropping the frame's depth.
std::optional<ColorImage> readColorOrLeaveOut(const fs::path& path, SequenceWriter& writer) {
  try {
    return readColorImage(path);
  } catch (const Error& e) {
    writer.note(std::string(kUnreadableColourNote) +
                " (its frame was imported without colour): " + e.what());
    return std::nullopt;
  }
}

void importFrames(const fs::path& source, const ImportOptions& options, SequenceWriter& writer) {
  const auto depth_files = numberedFiles(source, "frame-", ".depth.png");
  if (depth_files.empty())
    throw Error(source.string(), "frames", "frame-NNNNNN.depth.png files (16-bit depth)", "none");

  setCameraFromIntrinsicsFile(
      source, "frame-", options, writer,
      "an intrinsics file (e.g. camera-intrinsics.txt or intrinsics.K.txt with the 3x3 camera "
      "matrix) or the intrinsics option (--intrinsics fx,fy,cx,cy)");
  const double scale = options.depth_scale.value_or(0.001);
  writer.setDepthScale(scale);

  const bool has_labels = !numberedFiles(source, "frame-", ".label.png").empty();
  if (has_labels) {
    writer.setLabels(options.labels.value_or(apc2016Labels()));
    if (!options.labels)
      writer.note("label images read with the APC 2016 label set (give a label list to change)");
    writer.note("label images became one-hot probabilities (confidence " +
                formatNumber(options.label_confidence) + ")");
  } else {
    writer.setLabels(backgroundOnlyLabels());
    writer.setLabelless(true);
    writer.noteOnlyBackground(
        "no label images: the sequence has the single label __background__ and every frame an "
        "all-background label image (geometry only)");
  }

  writer.setFound(depth_files.size());

  const auto selected = selectFrames(depth_files.size(), options);
  writer.setTotal(selected.size());
  size_t without_color = 0;
  for (size_t index : selected) {
    const auto& depth_file = depth_files[index];
    const std::string name = frameName(depth_file.number);
    // The frame's other files are named as its depth image is (frame-15 or frame-000015).
    const fs::path base = source / numberedStem(depth_file, ".depth.png");
    SourceFrame frame;
    frame.name = name;
    const fs::path pose_file = fs::path(base.string() + ".pose.txt");
    if (!isFile(pose_file)) {
      if (!writer.skip(name, "no pose file " + pose_file.filename().string())) return;
      continue;
    }
    const auto error = tryRead([&] {
      const auto numbers = readNumbers(pose_file);
      if (numbers.size() != 16)
        throw Error(pose_file.string(), "pose", "16 numbers (a 4x4 camera-to-world matrix)",
                    std::to_string(numbers.size()) + " numbers");
      frame.pose = matrixFromRowMajor(numbers.data());
      // 7-Scenes marks unknown depth as 65535.
      frame.depth = readDepth16(depth_file.path, scale, std::uint16_t{65535});
      for (const char* ext : {".color.png", ".color.jpg"}) {
        const fs::path color = fs::path(base.string() + ext);
        if (isFile(color)) {
          frame.color = readColorOrLeaveOut(color, writer);
          break;
        }
      }
      const fs::path label = fs::path(base.string() + ".label.png");
      if (has_labels) {
        if (!isFile(label))
          throw Error(label.string(), "label", "a label image for every frame (others have one)",
                      "no such file");
        frame.label = readLabelImage(label);
      }
    });
    if (error) {
      if (!writer.skip(name, *error)) return;
      continue;
    }
    if (!frame.color) ++without_color;
    if (!writer.add(std::move(frame))) return;
  }
  if (without_color) writer.note(std::to_string(without_color) + " frames have no colour image");
}

// ---------------------------------------------------------------------------
// TUM RGB-D: rgb.txt, depth.txt, groundtruth.txt; depth PNG / 5000.
void importTum(const fs::path& source, const ImportOptions& options, SequenceWriter& writer) {
  const auto depth_list = readTumList(source / "depth.txt");
  if (depth_list.empty())
    throw Error((source / "depth.txt").string(), "", "lines 'timestamp filename' of depth images",
                "no entries");
  std::vector<TumEntry> rgb_list;
  if (isFile(source / "rgb.txt")) rgb_list = readTumList(source / "rgb.txt");
  const fs::path gt_file = source / "groundtruth.txt";
  if (!isFile(gt_file))
    throw Error(gt_file.string(), "poses",
                "groundtruth.txt with 'timestamp tx ty tz qx qy qz qw' camera poses",
                "no such file");
  const auto poses = readTumPoses(gt_file);
  if (poses.empty())
    throw Error(gt_file.string(), "poses", "'timestamp tx ty tz qx qy qz qw' lines", "no valid pose");

  // The benchmark's published calibrations, recognised from the folder name.
  std::optional<CameraIntrinsics> known;
  std::string described = "no calibration";
  // The folder's own name first (rgbd_dataset_freiburg1_xyz), then its whole path.
  fs::path normal = fs::absolute(source).lexically_normal();
  if (normal.filename().empty()) normal = normal.parent_path();
  struct Calibration {
    const char* tag;
    double fx, fy, cx, cy;
  };
  const Calibration calibrations[] = {Calibration{"freiburg1", 517.3, 516.5, 318.6, 255.3},
                                      Calibration{"freiburg2", 520.9, 521.0, 325.1, 249.7},
                                      Calibration{"freiburg3", 535.4, 539.2, 320.1, 247.6}};
  std::string folder_name = lower(normal.filename().string());
  bool named = false;
  for (const Calibration& c : calibrations) named |= folder_name.find(c.tag) != std::string::npos;
  if (!named) folder_name = lower(normal.string());
  for (const Calibration& c : calibrations) {
    if (folder_name.find(c.tag) == std::string::npos) continue;
    CameraIntrinsics camera;
    camera.width = camera.height = 0;
    camera.fx = c.fx;
    camera.fy = c.fy;
    camera.cx = c.cx;
    camera.cy = c.cy;
    known = camera;
    described = std::string("the published ") + c.tag + " calibration";
    break;
  }
  if (!known && !options.intrinsics) {
    CameraIntrinsics camera;
    camera.width = camera.height = 0;
    camera.fx = camera.fy = 525.0;
    camera.cx = 319.5;
    camera.cy = 239.5;
    known = camera;
    described = "the benchmark's default calibration";
    writer.note(std::string(kDefaultTumIntrinsicsNote) +
                " fx = fy = 525, cx = 319.5, cy = 239.5 are used (give the intrinsics option if "
                "they are known)");
  } else if (known && !options.intrinsics) {
    writer.note("intrinsics: " + described);
  }
  writer.setCamera(chooseCamera(known, described, options, writer, source, ""));
  const double scale = options.depth_scale.value_or(1.0 / 5000.0);
  writer.setDepthScale(scale);
  writer.setLabels(backgroundOnlyLabels());
  writer.setLabelless(true);
  writer.noteOnlyBackground(
      "no label images: the sequence has the single label __background__ (geometry only)");

  std::vector<double> rgb_stamps;
  for (const auto& e : rgb_list) rgb_stamps.push_back(e.stamp);
  writer.setFound(depth_list.size());
  const auto selected = selectFrames(depth_list.size(), options);
  writer.setTotal(selected.size());
  // Depth and groundtruth stamps that do not overlap at all are two clocks:
  // every frame's reason says by how much they differ.
  std::string clocks;
  if (!depth_list.empty() && !poses.empty()) {
    const double begin = depth_list.front().stamp + options.time_offset;
    const double end = depth_list.back().stamp + options.time_offset;
    const double tol = options.time_tolerance;
    if (end < poses.front().stamp - tol || begin > poses.back().stamp + tol) {
      clocks =
          "the depth stamps (" + stampText(begin) + " to " + stampText(end) +
          ") and the groundtruth (" + stampText(poses.front().stamp) + " to " +
          stampText(poses.back().stamp) + ") do not overlap: the clocks differ by about " +
          formatNumber(0.5 * (poses.front().stamp + poses.back().stamp) - 0.5 * (begin + end), 4) +
          " s (give it as the time offset option)";
      writer.note(clocks);
    }
  }
  for (size_t index : selected) {
    const TumEntry& entry = depth_list[index];
    const std::string name = stampText(entry.stamp);
    const double pose_stamp = entry.stamp + options.time_offset;
    const auto pose = interpolatePose(poses, pose_stamp, options.time_tolerance);
    if (!pose) {
      const std::string reason =
          "no groundtruth pose within " + formatNumber(options.time_tolerance) + " s of " +
          stampText(pose_stamp) +
          (clocks.empty() ? " (groundtruth covers " + stampText(poses.front().stamp) + " to " +
                                stampText(poses.back().stamp) + ")"
                          : "; " + clocks);
      if (!writer.skip(name, reason)) return;
      continue;
    }
    SourceFrame frame;
    frame.name = name;
    frame.stamp = entry.stamp;
    frame.pose = *pose;
    const auto error = tryRead([&] {
      frame.depth = readDepth16(source / entry.file, scale);
      if (auto rgb = nearestStamp(rgb_stamps, entry.stamp, options.time_tolerance))
        frame.color = readColorOrLeaveOut(source / rgb_list[*rgb].file, writer);
      else if (!rgb_list.empty())
        writer.note("depth images without an rgb image within " +
                    formatNumber(options.time_tolerance) + " s were imported without colour");
    });
    if (error) {
      if (!writer.skip(name, *error)) return;
      continue;
    }
    if (!writer.add(std::move(frame))) return;
  }
}

// ---------------------------------------------------------------------------
// Quaternion layout: color/N.png, depth/N.pgm|png (mm), pose.txt "tx ty tz qx qy qz qw".
void importQuaternion(const fs::path& source, const ImportOptions& options,
                      SequenceWriter& writer) {
  const auto depth_files = numberedFiles(source / "depth", "", std::vector<std::string>{".png", ".pgm"});
  if (depth_files.empty())
    throw Error((source / "depth").string(), "frames", "depth/N.png or depth/N.pgm (16-bit)",
                "none");
  const fs::path pose_file = source / "pose.txt";
  std::vector<std::vector<double>> lines;
  std::vector<int> line_numbers;
  for (const auto& [number, line] : readLines(pose_file)) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    auto n = parseNumbers(line, pose_file.string(), number);
    if (n.size() != 7 && n.size() != 8)
      throw Error(pose_file.string(), "line " + std::to_string(number),
                  "7 numbers 'tx ty tz qx qy qz qw' (or 8 with a leading frame number or stamp)",
                  std::to_string(n.size()) + " numbers");
    if (n.size() == 8 && !std::isfinite(n[0]))
      throw Error(pose_file.string(), "line " + std::to_string(number),
                  "a finite frame number or time stamp first", "'" + line + "'");
    lines.push_back(std::move(n));
    line_numbers.push_back(number);
  }
  // 8 columns whose first is an integer naming a depth file: matched by number.
  // A whole number too large for a file number (a stamp such as 1e19) names
  // no depth file.
  constexpr double kLongLimit = 9223372036854775808.0;  // 2^63
  std::map<long, size_t> line_of_number;
  bool by_number = !lines.empty() && lines.front().size() == 8;
  if (by_number) {
    for (size_t i = 0; i < lines.size(); ++i) {
      const double id = lines[i][0];
      if (lines[i].size() != 8 || id != std::floor(id)) {
        by_number = false;
        break;
      }
      if (id >= -kLongLimit && id < kLongLimit) line_of_number[static_cast<long>(id)] = i;
    }
    if (by_number) {
      bool any = false;
      for (const auto& f : depth_files) any |= line_of_number.count(f.number) > 0;
      by_number = any;
    }
  }
  if (by_number) {
    // Lines whose numbers name no depth image. Numbers that are the images'
    // shifted by a constant (lines from 0 for images from 1) would give every
    // image its neighbour's pose: refused, not matched.
    std::set<long> image_numbers;
    for (const auto& f : depth_files) image_numbers.insert(f.number);
    std::vector<long> orphans;
    for (const auto& [id, line] : line_of_number)
      if (!image_numbers.count(id)) orphans.push_back(id);
    if (!orphans.empty() && line_of_number.size() == image_numbers.size()) {
      const long shift = *image_numbers.begin() - line_of_number.begin()->first;
      bool shifted = shift != 0;
      auto image = image_numbers.begin();
      for (auto it = line_of_number.begin(); shifted && it != line_of_number.end(); ++it, ++image)
        shifted = *image - it->first == shift;
      if (shifted)
        throw Error(pose_file.string(), "poses",
                    "lines of 8 numbers starting with the number of their depth image",
                    "lines numbered " + std::to_string(line_of_number.begin()->first) + " to " +
                        std::to_string(line_of_number.rbegin()->first) + " for depth images " +
                        std::to_string(*image_numbers.begin()) + " to " +
                        std::to_string(*image_numbers.rbegin()) + ": each line's number is its " +
                        "image's " + (shift > 0 ? "minus " : "plus ") +
                        std::to_string(std::labs(shift)) +
                        ", so matched by number every image would take another's pose; number "
                        "the lines as the images are, or leave the numbers out (line i is then "
                        "the pose of the i-th image)");
    }
    if (!orphans.empty()) {
      std::string listed;
      for (size_t i = 0; i < std::min<size_t>(orphans.size(), 5); ++i)
        listed += (i ? ", " : "") + std::to_string(orphans[i]);
      if (orphans.size() > 5) listed += ", ...";
      writer.note("pose.txt: " + std::to_string(orphans.size()) +
                  (orphans.size() == 1 ? " line names" : " lines name") +
                  " no depth image (numbers " + listed + "), left out");
    }
  }
  if (!by_number && lines.size() != depth_files.size()) {
    // Line i is the pose of the i-th image only if no image is missing from
    // the numbering: with a gap, or numbers that do not start at 0 or 1, a
    // line may belong to an image that is not there, and every later image
    // would take the pose of the one before it.
    const long first = depth_files.front().number;
    std::string gap;
    if (first != 0 && first != 1) gap = "no image 0 or 1";
    for (size_t i = 1; i < depth_files.size() && gap.empty(); ++i)
      if (depth_files[i].number != depth_files[i - 1].number + 1)
        gap = "no image " + std::to_string(depth_files[i - 1].number + 1);
    if (!gap.empty())
      throw Error(
          pose_file.string(), "poses",
          "one pose per depth image in the order of their numbers, or lines of 8 numbers "
          "starting with the depth image's number",
          std::to_string(lines.size()) + " poses for " + std::to_string(depth_files.size()) +
              " depth images numbered " + std::to_string(first) + " to " +
              std::to_string(depth_files.back().number) + ", with " + gap +
              ": which line is whose pose is ambiguous (start each line with its image's number)");
    writer.note("pose.txt has " + std::to_string(lines.size()) + " poses for " +
                std::to_string(depth_files.size()) +
                " depth images: line i is the pose of the i-th depth image by number");
  }

  setCameraFromIntrinsicsFile(
      source, "pose", options, writer,
      "the intrinsics option (--intrinsics fx,fy,cx,cy or a file), as this layout does not "
      "store them (or an intrinsics.txt in the folder)");
  const double scale = options.depth_scale.value_or(0.001);
  writer.setDepthScale(scale);
  writer.setLabels(backgroundOnlyLabels());
  writer.setLabelless(true);
  writer.noteOnlyBackground(
      "no label images: the sequence has the single label __background__ (geometry only)");

  const auto color_files =
      numberedFiles(source / "color", "", std::vector<std::string>{".png", ".jpg", ".jpeg"});
  std::map<long, fs::path> color_of;
  for (const auto& f : color_files) color_of[f.number] = f.path;

  writer.setFound(depth_files.size());

  const auto selected = selectFrames(depth_files.size(), options);
  writer.setTotal(selected.size());
  for (size_t index : selected) {
    const auto& depth_file = depth_files[index];
    const std::string name = depth_file.path.filename().string();
    std::optional<size_t> line;
    if (by_number) {
      if (auto it = line_of_number.find(depth_file.number); it != line_of_number.end())
        line = it->second;
    } else if (index < lines.size()) {
      line = index;
    }
    if (!line) {
      if (!writer.skip(name, "no pose for it in pose.txt")) return;
      continue;
    }
    const auto& values = lines[*line];
    SourceFrame frame;
    frame.name = name;
    if (values.size() == 8 && !by_number) frame.stamp = values[0];
    frame.pose = poseFromQuaternion(values.data() + (values.size() == 8 ? 1 : 0));
    if (!frame.pose.allFinite()) {
      if (!writer.skip(name, "pose.txt line " + std::to_string(line_numbers[*line]) +
                                 " is not a valid pose (zero or non-finite quaternion)"))
        return;
      continue;
    }
    const auto error = tryRead([&] {
      frame.depth = readDepth16(depth_file.path, scale);
      if (auto it = color_of.find(depth_file.number); it != color_of.end())
        frame.color = readColorOrLeaveOut(it->second, writer);
    });
    if (error) {
      if (!writer.skip(name, *error)) return;
      continue;
    }
    if (!writer.add(std::move(frame))) return;
  }
}

// ---------------------------------------------------------------------------
namespace {

// Category names by ScanNet id from the label table when it is beside the
// scene (in its folder or up to two folders above); empty without one.
std::map<int, std::string> scanNetCategoryNames(const fs::path& source, SequenceWriter& writer) {
  std::map<int, std::string> names;
  for (const fs::path& dir : {source, source.parent_path(), source.parent_path().parent_path()}) {
    const fs::path tsv = dir / "scannetv2-labels.combined.tsv";
    if (!isFile(tsv)) continue;
    int id_column = -1, name_column = -1;
    for (const auto& [number, line] : readLines(tsv)) {
      std::vector<std::string> cells;
      std::stringstream in(line);
      std::string cell;
      while (std::getline(in, cell, '\t')) cells.push_back(cell);
      if (number == 1) {
        for (size_t c = 0; c < cells.size(); ++c) {
          if (cells[c] == "id") id_column = static_cast<int>(c);
          if (cells[c] == "category") name_column = static_cast<int>(c);
        }
        continue;
      }
      if (id_column < 0 || name_column < 0 ||
          cells.size() <= static_cast<size_t>(std::max(id_column, name_column)))
        continue;
      names[std::atoi(cells[static_cast<size_t>(id_column)].c_str())] =
          cells[static_cast<size_t>(name_column)];
    }
    writer.note("label names from " + tsv.string());
    break;
  }
  return names;
}

}  // namespace

// ScanNet: color/N.jpg, depth/N.png (mm), pose/N.txt, intrinsic/*.txt, label-filt/N.png.
void importScanNet(const fs::path& source, const ImportOptions& options, SequenceWriter& writer) {
  const auto depth_files = numberedFiles(source / "depth", "", ".png");
  if (depth_files.empty())
    throw Error((source / "depth").string(), "frames", "depth/N.png (16-bit, millimetres)", "none");
  const fs::path depth_intrinsics = source / "intrinsic" / "intrinsic_depth.txt";
  const fs::path color_intrinsics = source / "intrinsic" / "intrinsic_color.txt";
  std::optional<CameraIntrinsics> depth_camera, color_camera;
  if (isFile(depth_intrinsics))
    depth_camera = intrinsicsFromNumbers(readNumbers(depth_intrinsics), depth_intrinsics.string());
  if (isFile(color_intrinsics))
    color_camera = intrinsicsFromNumbers(readNumbers(color_intrinsics), color_intrinsics.string());
  writer.setCamera(chooseCamera(depth_camera, "intrinsic_depth.txt", options, writer,
                                depth_intrinsics,
                                "intrinsic/intrinsic_depth.txt (4x4) or the intrinsics option"));
  if (!color_camera)
    writer.note("no intrinsic/intrinsic_color.txt: colour and label images of another size are "
                "assumed to cover the depth camera's view");
  const double scale = options.depth_scale.value_or(0.001);
  writer.setDepthScale(scale);

  writer.setFound(depth_files.size());

  const auto selected = selectFrames(depth_files.size(), options);
  writer.setTotal(selected.size());

  // Labels: ScanNet ids found in the selected frames, renumbered 1..n.
  const fs::path label_dir = source / "label-filt";
  std::map<long, fs::path> label_of;
  for (const auto& f : numberedFiles(label_dir, "", ".png")) label_of[f.number] = f.path;
  std::map<int, int> compact;  // ScanNet id -> sequence label id
  if (!label_of.empty()) {
    if (options.labels) {
      for (int id = 0; id < options.labels->size(); ++id) compact[id] = id;
      writer.setLabels(*options.labels);
      writer.note("label images became one-hot probabilities (confidence " +
                  formatNumber(options.label_confidence) + ")");
    } else {
      std::set<int> ids;
      for (size_t index : selected) {
        auto it = label_of.find(depth_files[index].number);
        if (it == label_of.end()) continue;
        try {
          const LabelImage raw = readLabelImage(it->second);
          ids.insert(raw.ids.begin(), raw.ids.end());
        } catch (const Error&) {
          // reported when the frame is read
        }
      }
      ids.erase(0);
      if (ids.size() > 255)
        throw Error(label_dir.string(), "labels", "at most 255 distinct label ids in the frames",
                    std::to_string(ids.size()) + " ids (import fewer frames or give a label list)");
      const std::map<int, std::string> names = scanNetCategoryNames(source, writer);
      std::vector<std::string> label_names;
      std::set<std::string> used{"__background__"};
      compact[0] = 0;
      for (int id : ids) {
        const auto named = names.find(id);
        std::string name = named != names.end() ? named->second : "scannet_" + std::to_string(id);
        if (!used.insert(name).second) name += "_" + std::to_string(id);
        used.insert(name);
        label_names.push_back(name);
        compact[id] = static_cast<int>(label_names.size());
      }
      writer.setLabels(makeLabels(label_names));
      writer.note("label-filt ids renumbered 1.." + std::to_string(label_names.size()) +
                  " in increasing ScanNet id order; label images became one-hot probabilities "
                  "(confidence " + formatNumber(options.label_confidence) + ")");
    }
  } else {
    writer.setLabels(backgroundOnlyLabels());
    writer.setLabelless(true);
    writer.noteOnlyBackground(
        "no label-filt/ folder: the sequence has the single label __background__");
  }

  for (size_t index : selected) {
    const auto& depth_file = depth_files[index];
    const std::string number = std::to_string(depth_file.number);
    const std::string name = number;
    const fs::path pose_file = source / "pose" / (number + ".txt");
    SourceFrame frame;
    frame.name = name;
    if (!isFile(pose_file)) {
      if (!writer.skip(name, "no pose file pose/" + number + ".txt")) return;
      continue;
    }
    std::set<int> unknown;
    const auto error = tryRead([&] {
      const auto numbers = readNumbers(pose_file);
      if (numbers.size() != 16)
        throw Error(pose_file.string(), "pose", "16 numbers (a 4x4 camera-to-world matrix)",
                    std::to_string(numbers.size()) + " numbers");
      frame.pose = matrixFromRowMajor(numbers.data());
      if (!frame.pose.allFinite())
        throw Error(pose_file.string(), "pose", "a finite camera-to-world matrix",
                    "inf or NaN (ScanNet marks frames without tracking so)");
      frame.depth = readDepth16(depth_file.path, scale);
      for (const char* ext : {".jpg", ".png"}) {
        const fs::path color = source / "color" / (number + ext);
        if (isFile(color)) {
          frame.color = readColorOrLeaveOut(color, writer);
          break;
        }
      }
      if (frame.color && color_camera) {
        frame.color_camera = color_camera;
      }
      if (!label_of.empty()) {
        auto it = label_of.find(depth_file.number);
        if (it == label_of.end())
          throw Error((label_dir / (number + ".png")).string(), "label",
                      "a label image for every frame (others have one)", "no such file");
        frame.label = remapLabels(readLabelImage(it->second), compact, &unknown);
        // Labels are annotated on the colour image.
        if (color_camera && frame.color && frame.label->width == frame.color->width &&
            frame.label->height == frame.color->height)
          frame.evidence_camera = color_camera;
        else if (color_camera && !frame.color)
          frame.evidence_camera = color_camera;
      }
    });
    if (error) {
      if (!writer.skip(name, *error)) return;
      continue;
    }
    if (!unknown.empty())
      writer.note("label ids outside the given label list were set to background");
    if (!writer.add(std::move(frame))) return;
  }
}

}  // namespace lom::import_detail

namespace lom {

bool sourceStoresCamera(const std::filesystem::path& path, SourceKind kind) {
  if (kind == SourceKind::Frames)
    return import_detail::findIntrinsicsFile(path, "frame-").has_value();
  if (kind == SourceKind::Quaternion)
    return import_detail::findIntrinsicsFile(path, "pose").has_value();
  return true;
}

}  // namespace lom
