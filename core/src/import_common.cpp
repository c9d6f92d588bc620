// Helpers shared by the importers: text and matrix parsing, numbered frame
// files, camera choice, pose interpolation.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "file_checks.hpp"
#include "import_internal.hpp"
#include "lom/geometry.hpp"

namespace lom::import_detail {

std::string formatNumber(double value, int precision) {
  std::ostringstream out;
  out << std::setprecision(precision) << value;
  return out.str();
}

std::string readText(const fs::path& path) {
  if (const std::string why = notARegularFile(path); !why.empty())
    throw Error(path.string(), "", "an existing text file", why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string(), "", "a readable text file", "it cannot be opened");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

std::vector<std::pair<int, std::string>> readLines(const fs::path& path) {
  const std::string text = readText(path);
  std::vector<std::pair<int, std::string>> lines;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.emplace_back(number, line);
  }
  return lines;
}

std::vector<double> parseNumbers(const std::string& text, const std::string& file, int line) {
  std::vector<double> numbers;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (std::isspace(static_cast<unsigned char>(text[i])) || text[i] == ','))
      ++i;
    if (i >= text.size()) break;
    size_t end = i;
    while (end < text.size() && !std::isspace(static_cast<unsigned char>(text[end])) &&
           text[end] != ',')
      ++end;
    const std::string token = text.substr(i, end - i);
    char* stop = nullptr;
    errno = 0;
    const double value = std::strtod(token.c_str(), &stop);
    if (stop == token.c_str() || *stop != '\0') {
      std::string shown = token.size() > 30 ? token.substr(0, 27) + "..." : token;
      throw Error(file, line > 0 ? "line " + std::to_string(line) : std::string(),
                  "numbers separated by spaces", "'" + shown + "'");
    }
    numbers.push_back(value);
    i = end;
  }
  return numbers;
}

std::vector<double> readNumbers(const fs::path& path) {
  std::vector<double> numbers;
  for (const auto& [number, line] : readLines(path)) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto values = parseNumbers(line, path.string(), number);
    numbers.insert(numbers.end(), values.begin(), values.end());
  }
  return numbers;
}

CameraIntrinsics intrinsicsFromNumbers(const std::vector<double>& n, const std::string& file) {
  CameraIntrinsics camera;
  camera.width = 0;
  camera.height = 0;
  if (n.size() == 4) {
    camera.fx = n[0];
    camera.fy = n[1];
    camera.cx = n[2];
    camera.cy = n[3];
  } else if (n.size() == 9 || n.size() == 16) {
    const size_t row = n.size() == 9 ? 3 : 4;
    camera.fx = n[0];
    camera.cx = n[2];
    camera.fy = n[row + 1];
    camera.cy = n[row + 2];
    if (n[1] != 0.0 || n[row] != 0.0 || n[2 * row] != 0.0 || n[2 * row + 1] != 0.0 ||
        std::abs(n[2 * row + 2] - 1.0) > 1e-9)
      throw Error(file, "camera matrix",
                  "a pinhole camera matrix [fx 0 cx; 0 fy cy; 0 0 1] (no skew)",
                  "[" + formatNumber(n[0]) + " " + formatNumber(n[1]) + " " + formatNumber(n[2]) +
                      "; " + formatNumber(n[row]) + " " + formatNumber(n[row + 1]) + " " +
                      formatNumber(n[row + 2]) + "; " + formatNumber(n[2 * row]) + " " +
                      formatNumber(n[2 * row + 1]) + " " + formatNumber(n[2 * row + 2]) + "]");
  } else {
    throw Error(file, "intrinsics",
                "4 numbers (fx fy cx cy), a 3x3 camera matrix or a 4x4 matrix",
                std::to_string(n.size()) + " numbers");
  }
  for (double v : {camera.fx, camera.fy, camera.cx, camera.cy})
    if (!std::isfinite(v))
      throw Error(file, "intrinsics", "finite numbers", formatNumber(v));
  if (!(camera.fx > 0.0) || !(camera.fy > 0.0))
    throw Error(file, "intrinsics", "positive focal lengths fx, fy",
                "fx = " + formatNumber(camera.fx) + ", fy = " + formatNumber(camera.fy));
  return camera;
}

Eigen::Matrix4d poseFromQuaternion(const double* p) {
  const std::optional<Eigen::Quaterniond> q =
      unitQuaternion(Eigen::Vector4d(p[3], p[4], p[5], p[6]));
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  if (!q) {
    pose(0, 0) = NAN;
    return pose;
  }
  pose.topLeftCorner<3, 3>() = q->toRotationMatrix();
  pose.topRightCorner<3, 1>() = Eigen::Vector3d(p[0], p[1], p[2]);
  return pose;
}

Eigen::Matrix4d matrixFromRowMajor(const double* values) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = values[r * 4 + c];
  return m;
}

std::vector<NumberedFile> numberedFiles(const fs::path& folder, const std::string& prefix,
                                        const std::vector<std::string>& suffixes) {
  std::vector<NumberedFile> files;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return files;
  std::map<long, fs::path> by_number;
  std::map<long, size_t> suffix_rank;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    for (size_t s = 0; s < suffixes.size(); ++s) {
      const std::string& suffix = suffixes[s];
      if (name.size() <= prefix.size() + suffix.size()) continue;
      if (name.compare(0, prefix.size(), prefix) != 0) continue;
      if (name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
      const std::string digits =
          name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
      if (digits.empty() || digits.size() > 12 ||
          !std::all_of(digits.begin(), digits.end(),
                       [](unsigned char c) { return std::isdigit(c); }))
        continue;
      const long number = std::stol(digits);
      auto rank = suffix_rank.find(number);
      if (rank == suffix_rank.end() || s < rank->second) {
        by_number[number] = entry.path();
        suffix_rank[number] = s;
      }
      break;
    }
  }
  for (const auto& [number, path] : by_number) files.push_back({number, path});
  return files;
}

std::vector<NumberedFile> numberedFiles(const fs::path& folder, const std::string& prefix,
                                        const std::string& suffix) {
  return numberedFiles(folder, prefix, std::vector<std::string>{suffix});
}

CameraIntrinsics chooseCamera(const std::optional<CameraIntrinsics>& from_source,
                              const std::string& from_source_description,
                              const ImportOptions& options, SequenceWriter& writer,
                              const fs::path& source, const std::string& hint) {
  if (options.intrinsics) {
    CameraIntrinsics camera = *options.intrinsics;
    writer.note("intrinsics given as an option used: fx " + formatNumber(camera.fx) + ", fy " +
                formatNumber(camera.fy) + ", cx " + formatNumber(camera.cx) + ", cy " +
                formatNumber(camera.cy) +
                (from_source ? " (instead of " + from_source_description + ")" : std::string()));
    return camera;
  }
  if (!from_source)
    throw Error(source.string(), "intrinsics", hint, "none");
  return *from_source;
}

DepthImage readRaw16(const fs::path& path) { return readDepthImage(path, 1.0); }

DepthImage readDepth16(const fs::path& path, double scale, std::optional<std::uint16_t> invalid) {
  DepthImage depth = readRaw16(path);
  const float invalid_value = invalid ? static_cast<float>(*invalid) : -1.0f;
  for (float& z : depth.metres) z = (z == invalid_value) ? 0.0f : static_cast<float>(z * scale);
  return depth;
}

LabelImage remapLabels(const LabelImage& raw, const std::map<int, int>& map, std::set<int>* unknown) {
  LabelImage out = raw;
  for (auto& id : out.ids) {
    const auto it = map.find(id);
    if (it == map.end()) {
      if (unknown) unknown->insert(id);
      id = 0;
    } else {
      id = static_cast<std::uint16_t>(it->second);
    }
  }
  return out;
}

LabelSet makeLabels(const std::vector<std::string>& names) {
  std::vector<LabelInfo> labels;
  labels.push_back({0, "__background__", vocColor(0)});
  for (size_t i = 0; i < names.size(); ++i) {
    const int id = static_cast<int>(i) + 1;
    labels.push_back({id, names[i], vocColor(id)});
  }
  return LabelSet(std::move(labels));
}

LabelSet backgroundOnlyLabels() { return makeLabels({}); }

std::optional<size_t> nearestStamp(const std::vector<double>& stamps, double stamp,
                                   double tolerance) {
  if (stamps.empty()) return std::nullopt;
  const auto it = std::lower_bound(stamps.begin(), stamps.end(), stamp);
  std::optional<size_t> best;
  double best_distance = tolerance;
  auto consider = [&](std::vector<double>::const_iterator candidate) {
    const double distance = std::abs(*candidate - stamp);
    if (distance <= best_distance) {
      if (!best || distance < best_distance) best = static_cast<size_t>(candidate - stamps.begin());
      best_distance = distance;
    }
  };
  if (it != stamps.begin()) consider(std::prev(it));
  if (it != stamps.end()) consider(it);
  return best;
}

std::optional<Eigen::Matrix4d> interpolatePose(const std::vector<TimedPose>& poses, double stamp,
                                               double tolerance) {
  if (poses.empty()) return std::nullopt;
  const auto after = std::lower_bound(poses.begin(), poses.end(), stamp,
                                      [](const TimedPose& p, double t) { return p.stamp < t; });
  auto toMatrix = [](const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
    m.topRightCorner<3, 1>() = t;
    return m;
  };
  if (after != poses.end() && after->stamp == stamp) return toMatrix(after->t, after->q);
  if (after != poses.begin() && after != poses.end()) {
    const TimedPose& a = *std::prev(after);
    const TimedPose& b = *after;
    if (stamp - a.stamp <= tolerance && b.stamp - stamp <= tolerance) {
      const double s = (stamp - a.stamp) / (b.stamp - a.stamp);
      return toMatrix((1.0 - s) * a.t + s * b.t, a.q.normalized().slerp(s, b.q.normalized()));
    }
  }
  const TimedPose* nearest = nullptr;
  double distance = tolerance;
  if (after != poses.end() && after->stamp - stamp <= distance) {
    nearest = &*after;
    distance = after->stamp - stamp;
  }
  if (after != poses.begin() && stamp - std::prev(after)->stamp <= distance)
    nearest = &*std::prev(after);
  if (!nearest) return std::nullopt;
  return toMatrix(nearest->t, nearest->q);
}

}  // namespace lom::import_detail
