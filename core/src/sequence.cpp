// sequence.json (format "labeloctomap-sequence" version 1, docs/sequence-format.md):
// parsing with precise error messages, writing, and checking the frame files.
#include "lom/sequence.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string_view>
#include <thread>

#include "file_checks.hpp"
#include "image_header.hpp"
#include "json_text.hpp"
#include "lom/atomic_file.hpp"
#include "lom/import.hpp"
#include "worker_pool.hpp"

namespace lom {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

using json_text::describe;
using json_text::indexed;
using json_text::inlineJson;

namespace {

constexpr const char* kFormat = "labeloctomap-sequence";
constexpr int kVersion = 1;
constexpr int kMaxLabels = 256;
constexpr double kRotationTolerance = 1e-4;
constexpr double kLastRowTolerance = 1e-6;
// Rotations this close to orthonormal are kept bit for bit, so that saving a
// loaded sequence reproduces its poses exactly.
constexpr double kAlreadyOrthonormal = 1e-12;
constexpr size_t kLineWidth = 100;
constexpr double kMinDepthScale = 1e-12;  // metres per depth unit
constexpr double kMaxDepthScale = 1e6;

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}


// Typed access to the JSON tree; every failure names the file and the field.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& expected,
                         const std::string& found) const {
    throw Error(file_, field, expected, found);
  }

  void expectObject(const Json& value, const std::string& field) const {
    if (!value.is_object()) fail(field, "an object", describe(value));
  }

  void allowOnly(const Json& object, const std::string& field,
                 std::initializer_list<const char*> keys) const {
    for (const auto& item : object.items()) {
      bool known = false;
      std::string list;
      for (const char* key : keys) {
        known = known || item.key() == key;
        list += (list.empty() ? "" : ", ") + std::string(key);
      }
      if (!known) fail(join(field, item.key()), "only the keys " + list, "an unknown key");
    }
  }

  const Json& required(const Json& object, const std::string& field, const char* key) const {
    const auto it = object.find(key);
    if (it == object.end()) fail(join(field, key), "a value", "nothing (the key is missing)");
    return *it;
  }

  static const Json* optional(const Json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  double number(const Json& value, const std::string& field) const {
    if (!value.is_number()) fail(field, "a number", describe(value));
    const double number = value.get<double>();
    if (!std::isfinite(number)) fail(field, "a finite number", describe(value));
    return number;
  }

  double positive(const Json& value, const std::string& field) const {
    const double v = number(value, field);
    if (!(v > 0.0)) fail(field, "a positive number", describe(value));
    return v;
  }

  int integer(const Json& value, const std::string& field, int min, int max) const {
    const std::string expected =
        "an integer from " + std::to_string(min) + " to " + std::to_string(max);
    if (!value.is_number()) fail(field, expected, describe(value));
    const double v = value.get<double>();
    if (std::floor(v) != v || v < min || v > max) fail(field, expected, describe(value));
    return static_cast<int>(v);
  }

  std::string text(const Json& value, const std::string& field, const std::string& what) const {
    if (!value.is_string() || value.get<std::string>().empty()) fail(field, what, describe(value));
    return value.get<std::string>();
  }

  // A file path: a non-empty string without NUL characters (a NUL would end
  // the path early when it is handed to the system).
  std::string path(const Json& value, const std::string& field, const std::string& what) const {
    std::string path = text(value, field, what);
    if (const size_t nul = path.find('\0'); nul != std::string::npos)
      fail(field, what + ", without NUL characters",
           "a NUL character (\\u0000) at position " + std::to_string(nul));
    return path;
  }

  bool boolean(const Json& value, const std::string& field) const {
    if (!value.is_boolean()) fail(field, "true or false", describe(value));
    return value.get<bool>();
  }

  const Json& array(const Json& value, const std::string& field, const std::string& what) const {
    if (!value.is_array()) fail(field, what, describe(value));
    return value;
  }

  [[nodiscard]] const std::string& file() const { return file_; }

 private:
  std::string file_;
};

LabelSet parseLabels(const Reader& in, const Json& value) {
  const Json& list = in.array(value, "labels", "an array of {id, name, color} objects");
  if (list.empty() || list.size() > static_cast<size_t>(kMaxLabels))
    in.fail("labels", "from 1 to " + std::to_string(kMaxLabels) + " labels",
            std::to_string(list.size()) + " labels");
  const int count = static_cast<int>(list.size());
  std::vector<LabelInfo> labels(list.size());
  std::vector<std::string> id_field(list.size());
  std::map<std::string, std::string> name_field;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string field = indexed("labels", i);
    in.expectObject(list[i], field);
    in.allowOnly(list[i], field, {"id", "name", "color"});
    const int id = in.integer(in.required(list[i], field, "id"), join(field, "id"), 0, count - 1);
    if (!id_field[static_cast<size_t>(id)].empty())
      in.fail(join(field, "id"), "each id from 0 to " + std::to_string(count - 1) + " once",
              std::to_string(id) + " again (also " + id_field[static_cast<size_t>(id)] + ")");
    id_field[static_cast<size_t>(id)] = join(field, "id");
    LabelInfo label;
    label.id = id;
    label.name =
        in.text(in.required(list[i], field, "name"), join(field, "name"), "a non-empty string");
    if (const std::string problem = labelNameProblem(label.name); !problem.empty())
      in.fail(join(field, "name"), kLabelNameRule, problem);
    const auto [previous, inserted] = name_field.emplace(label.name, join(field, "name"));
    if (!inserted)
      in.fail(join(field, "name"), "a unique name",
              "\"" + label.name + "\" again (also " + previous->second + ")");
    label.color = vocColor(id);
    if (const Json* color = Reader::optional(list[i], "color")) {
      const std::string color_field = join(field, "color");
      const Json& rgb = in.array(*color, color_field, "3 integers [r, g, b] from 0 to 255");
      if (rgb.size() != 3)
        in.fail(color_field, "3 integers [r, g, b] from 0 to 255", describe(rgb));
      for (size_t c = 0; c < 3; ++c)
        label.color[c] =
            static_cast<std::uint8_t>(in.integer(rgb[c], indexed(color_field, c), 0, 255));
    }
    labels[static_cast<size_t>(id)] = label;
  }
  return LabelSet(std::move(labels));
}

CameraIntrinsics parseCamera(const Reader& in, const Json& value, const std::string& field,
                             const CameraIntrinsics* fallback) {
  in.expectObject(value, field);
  in.allowOnly(value, field, {"width", "height", "fx", "fy", "cx", "cy", "depth_scale"});
  // A per-frame camera only needs the fields that differ from the sequence camera.
  auto get = [&](const char* key) -> const Json* {
    const Json* found = Reader::optional(value, key);
    if (!found && !fallback && std::string(key) != "depth_scale") in.required(value, field, key);
    return found;
  };
  CameraIntrinsics camera = fallback ? *fallback : CameraIntrinsics{};
  if (!fallback) camera.depth_scale = 0.001;
  if (const Json* v = get("width")) camera.width = in.integer(*v, join(field, "width"), 1, 65535);
  if (const Json* v = get("height"))
    camera.height = in.integer(*v, join(field, "height"), 1, 65535);
  if (const Json* v = get("fx")) camera.fx = in.positive(*v, join(field, "fx"));
  if (const Json* v = get("fy")) camera.fy = in.positive(*v, join(field, "fy"));
  if (const Json* v = get("cx")) camera.cx = in.number(*v, join(field, "cx"));
  if (const Json* v = get("cy")) camera.cy = in.number(*v, join(field, "cy"));
  if (const Json* v = get("depth_scale")) {
    // Depths are single-precision metres: past these bounds a 16-bit depth
    // times the scale overflows to infinity or vanishes to zero (fusion then
    // found "no valid depths" without naming the scale).
    camera.depth_scale = in.positive(*v, join(field, "depth_scale"));
    if (camera.depth_scale < kMinDepthScale || camera.depth_scale > kMaxDepthScale)
      in.fail(join(field, "depth_scale"),
              "metres per depth unit from 1e-12 to 1e6 (0.001 for millimetres)", describe(*v));
  }
  return camera;
}

// The shortest text that reads back as `value` ("1.000003", not "1"): a
// pose that fails by 3e-06 must not print as the values it should have.
std::string exactNumber(double value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

std::string matrixRowText(const Eigen::Matrix4d& m, int row) {
  return "[" + exactNumber(m(row, 0)) + " " + exactNumber(m(row, 1)) + " " +
         exactNumber(m(row, 2)) + " " + exactNumber(m(row, 3)) + "]";
}

// "<deviation> > <tolerance>", the deviation with as many digits as it takes
// to differ from the tolerance (1.00000001e-04 is not "0.0001 > 0.0001").
std::string exceeding(double deviation, double tolerance) {
  char limit[32];
  std::snprintf(limit, sizeof limit, "%g", tolerance);
  char shown[32];
  for (int digits = 3; digits <= 17; ++digits) {
    std::snprintf(shown, sizeof shown, "%.*g", digits, deviation);
    if (std::strtod(shown, nullptr) > tolerance) break;
  }
  return std::string(shown) + " > " + limit;
}

Eigen::Isometry3d parsePose(const Reader& in, const Json& value, const std::string& field) {
  const std::string what = "16 numbers (row-major 4x4 camera-to-world matrix)";
  const Json& list = in.array(value, field, what);
  if (list.size() != 16) in.fail(field, what, std::to_string(list.size()) + " elements");
  Eigen::Matrix4d m;
  for (size_t i = 0; i < 16; ++i)
    m(static_cast<int>(i / 4), static_cast<int>(i % 4)) = in.number(list[i], indexed(field, i));

  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const double det = r.determinant();
  const double orthogonality =
      (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const double last_row = (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff();
  if (std::abs(det - 1.0) > kRotationTolerance || orthogonality > kRotationTolerance ||
      last_row > kLastRowTolerance) {
    // Only the conditions that fail, each with its tolerance and by how much:
    // the values themselves, rounded, can look exactly right.
    std::vector<std::string> failing;
    if (std::abs(det - 1.0) > kRotationTolerance) {
      char value[32];
      std::snprintf(value, sizeof value, "%.9g", det);
      failing.push_back("det(R) = " + std::string(value) +
                        ": |det(R) - 1| = " + exceeding(std::abs(det - 1.0), kRotationTolerance));
    }
    if (orthogonality > kRotationTolerance)
      failing.push_back("max |R^T R - I| = " + exceeding(orthogonality, kRotationTolerance));
    if (last_row > kLastRowTolerance)
      failing.push_back("last row " + matrixRowText(m, 3) + " differs from [0 0 0 1] by " +
                        exceeding(last_row, kLastRowTolerance));
    std::string found;
    for (const std::string& part : failing) found += (found.empty() ? "" : "; ") + part;
    in.fail(field, "a rigid transform (orthonormal rotation, det +1, last row 0 0 0 1)", found);
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = m.topRightCorner<3, 1>();
  if (orthogonality <= kAlreadyOrthonormal && std::abs(det - 1.0) <= kAlreadyOrthonormal)
    pose.linear() = r;
  else
    pose.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
  return pose;
}

std::vector<int> parseProbaLabels(const Reader& in, const Json& value, const std::string& field,
                                  const LabelSet& labels) {
  const std::string what = "a non-empty array of label ids";
  const Json& list = in.array(value, field, what);
  if (list.empty()) in.fail(field, what, "an empty array");
  std::vector<int> ids;
  std::map<int, size_t> first_index;
  for (size_t c = 0; c < list.size(); ++c) {
    const std::string item = indexed(field, c);
    const int id = in.integer(list[c], item, 0, 65535);
    if (!labels.contains(id))
      in.fail(item,
              "a label id from 0 to " + std::to_string(labels.size() - 1) + " (the sequence has " +
                  std::to_string(labels.size()) + " labels)",
              "unknown label id " + std::to_string(id));
    const auto [previous, inserted] = first_index.emplace(id, c);
    if (!inserted)
      in.fail(item, "each label id once",
              std::to_string(id) + " again (also " + indexed(field, previous->second) + ")");
    ids.push_back(id);
  }
  return ids;
}

FrameRecord parseFrame(const Reader& in, const Json& value, size_t index,
                       const Sequence& sequence) {
  const std::string field = indexed("frames", index);
  in.expectObject(value, field);
  in.allowOnly(value, field,
               {"stamp", "pose", "depth", "color", "proba", "proba_labels", "proba_from_label",
                "label", "label_placeholder", "view", "camera"});
  const std::string path_what = "a non-empty file path relative to the sequence folder";
  FrameRecord frame;
  if (const Json* v = Reader::optional(value, "stamp"))
    frame.stamp = in.number(*v, join(field, "stamp"));
  frame.T_world_camera = parsePose(in, in.required(value, field, "pose"), join(field, "pose"));
  frame.depth = in.path(in.required(value, field, "depth"), join(field, "depth"), path_what);
  if (const Json* v = Reader::optional(value, "color"))
    frame.color = in.path(*v, join(field, "color"), path_what);
  if (const Json* v = Reader::optional(value, "proba"))
    frame.proba = in.path(*v, join(field, "proba"), path_what);
  if (const Json* v = Reader::optional(value, "label"))
    frame.label = in.path(*v, join(field, "label"), path_what);
  if (const Json* v = Reader::optional(value, "proba_labels")) {
    if (frame.proba.empty())
      in.fail(join(field, "proba_labels"),
              "proba_labels only together with " + join(field, "proba"),
              "proba_labels without a proba file");
    frame.proba_labels = parseProbaLabels(in, *v, join(field, "proba_labels"), sequence.labels);
  }
  if (const Json* v = Reader::optional(value, "proba_from_label")) {
    frame.proba_from_label = in.boolean(*v, join(field, "proba_from_label"));
    if (frame.proba.empty())
      in.fail(join(field, "proba_from_label"),
              "proba_from_label only together with " + join(field, "proba"),
              "proba_from_label without a proba file");
  }
  if (const Json* v = Reader::optional(value, "label_placeholder")) {
    frame.label_placeholder = in.boolean(*v, join(field, "label_placeholder"));
    if (frame.label.empty())
      in.fail(join(field, "label_placeholder"),
              "label_placeholder only together with " + join(field, "label"),
              "label_placeholder without a label file");
  }
  if (const Json* v = Reader::optional(value, "view"))
    frame.view = in.boolean(*v, join(field, "view"));
  if (const Json* v = Reader::optional(value, "camera"))
    frame.camera = parseCamera(in, *v, join(field, "camera"), &sequence.camera);
  return frame;
}

namespace {

// `path` as one word of a shell command: in single quotes unless it is plain.
std::string shellWord(const std::string& path) {
  const bool plain = !path.empty() && std::all_of(path.begin(), path.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) ||
           std::string_view("_./-+:,=@%").find(c) != std::string_view::npos;
  });
  if (plain) return path;
  std::string quoted = "'";
  for (const char c : path) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// For a recording that `labeloctomap import` reads (a bag or a dataset
// folder): "<what it is>: convert it with ...", else "".
std::string importHint(const fs::path& path) {
  const SourceDetection detection = detectSource(path);
  if (!detection.kind || *detection.kind == SourceKind::Sequence) return "";
  // A layout that stores no camera needs its intrinsics, in both ways of
  // opening it: the hint gives the option rather than a command that fails.
  const bool camera = sourceStoresCamera(path, *detection.kind);
  const std::string intrinsics = camera ? "" : " --intrinsics fx,fy,cx,cy";
  return detection.explanation + ": convert it with `labeloctomap import " +
         sourceKindName(*detection.kind) + " " + shellWord(path.string()) + intrinsics +
         " --out SEQ` (`labeloctomap-studio" + intrinsics + " " + shellWord(path.string()) +
         "` opens it as it is" + (camera ? "" : "; the folder stores no camera intrinsics") + ")";
}

}  // namespace

fs::path sequenceJsonPath(const fs::path& folder_or_json) {
  if (folder_or_json.empty())
    throw Error("", "sequence",
                "a sequence folder holding sequence.json, or the path of a sequence.json file",
                "an empty path ('')");
  std::error_code ec;
  const bool folder = fs::is_directory(folder_or_json, ec);
  fs::path path = folder ? folder_or_json / "sequence.json" : folder_or_json;
  // ".." after a symbolic link is resolved as the kernel does, through the
  // link; without one, the path is only tidied ("a/./b" is "a/b"). Only the
  // folders are resolved: a sequence.json that is itself a link keeps its
  // folder (the frames are beside it).
  const fs::path absolute = fs::absolute(path, ec);
  const bool up = std::any_of(absolute.begin(), absolute.end(),
                              [](const fs::path& part) { return part == ".."; });
  std::error_code resolve_error;
  path = up ? fs::weakly_canonical(absolute.parent_path(), resolve_error) / absolute.filename()
            : absolute.lexically_normal();
  if (resolve_error) path = absolute.lexically_normal();
  const char* expected =
      "a sequence folder holding sequence.json, or the path of a sequence.json file";
  if (const std::string why = notARegularFile(path); !why.empty()) {
    const std::string hint = folder ? importHint(folder_or_json) : "";
    throw Error(path.string(), "", expected, why + (hint.empty() ? "" : "; the folder is " + hint));
  }
  // A recording that `labeloctomap import` reads is not a sequence yet: say so
  // instead of reporting a bag's bytes as broken JSON.
  if (!folder && path.filename() != "sequence.json" && path.extension() != ".json") {
    const std::string hint = importHint(folder_or_json);
    if (!hint.empty()) throw Error(path.string(), "", expected, hint);
  }
  // A sequence is its folder's sequence.json: every message, the studio and
  // every file written back (segment, import) name that file, so another
  // name would be read here and reported or replaced there.
  if (!folder && path.filename() != "sequence.json")
    throw Error(path.string(), "", expected,
                "a file named " + path.filename().string() +
                    " (a sequence's file is named sequence.json: rename it, or give its folder)");
  return path;
}

// JSON with short objects and all number arrays on one line: poses stay
// readable as one line each instead of sixteen (json_text::inlineJson).
void prettyJson(const OrderedJson& value, size_t column, size_t indent, std::string& out) {
  const std::string flat = inlineJson(value);
  const bool scalars_only =
      value.is_array() && std::none_of(value.begin(), value.end(),
                                       [](const OrderedJson& v) { return v.is_structured(); });
  if (!value.is_structured() || value.empty() || scalars_only ||
      column + flat.size() <= kLineWidth) {
    out += flat;
    return;
  }
  const std::string pad(indent + 2, ' ');
  out += value.is_array() ? "[\n" : "{\n";
  bool first = true;
  for (const auto& item : value.items()) {
    if (!first) out += ",\n";
    first = false;
    out += pad;
    std::string key;
    if (value.is_object()) key = OrderedJson(item.key()).dump() + ": ";
    out += key;
    prettyJson(item.value(), pad.size() + key.size(), indent + 2, out);
  }
  out += "\n" + std::string(indent, ' ') + (value.is_array() ? "]" : "}");
}

OrderedJson cameraJson(const CameraIntrinsics& camera) {
  OrderedJson json;
  json["width"] = camera.width;
  json["height"] = camera.height;
  json["fx"] = camera.fx;
  json["fy"] = camera.fy;
  json["cx"] = camera.cx;
  json["cy"] = camera.cy;
  json["depth_scale"] = camera.depth_scale;
  return json;
}

void requireFinite(const fs::path& file, const std::string& field, double value) {
  if (!std::isfinite(value))
    throw Error(file.string(), field, "a finite number (JSON has no NaN or infinity)",
                std::to_string(value));
}

OrderedJson frameJson(const FrameRecord& frame, size_t index, const fs::path& file) {
  const std::string field = indexed("frames", index);
  OrderedJson json;
  if (frame.stamp) {
    requireFinite(file, join(field, "stamp"), *frame.stamp);
    json["stamp"] = *frame.stamp;
  }
  OrderedJson pose = OrderedJson::array();
  const Eigen::Matrix4d m = frame.T_world_camera.matrix();
  for (int i = 0; i < 16; ++i) {
    requireFinite(file, indexed(join(field, "pose"), static_cast<size_t>(i)), m(i / 4, i % 4));
    pose.push_back(m(i / 4, i % 4));
  }
  json["pose"] = pose;
  if (frame.depth.empty())
    throw Error(file.string(), join(field, "depth"), "a depth file path", "an empty path");
  json["depth"] = frame.depth;
  if (!frame.color.empty()) json["color"] = frame.color;
  if (!frame.proba.empty()) json["proba"] = frame.proba;
  if (!frame.proba_labels.empty()) {
    if (frame.proba.empty())
      throw Error(file.string(), join(field, "proba_labels"),
                  "proba_labels only together with " + join(field, "proba"),
                  "proba_labels without a proba file");
    json["proba_labels"] = frame.proba_labels;
  }
  if (frame.proba_from_label) {
    if (frame.proba.empty())
      throw Error(file.string(), join(field, "proba_from_label"),
                  "proba_from_label only together with " + join(field, "proba"),
                  "proba_from_label without a proba file");
    json["proba_from_label"] = true;
  }
  if (!frame.label.empty()) json["label"] = frame.label;
  if (frame.label_placeholder) {
    if (frame.label.empty())
      throw Error(file.string(), join(field, "label_placeholder"),
                  "label_placeholder only together with " + join(field, "label"),
                  "label_placeholder without a label file");
    json["label_placeholder"] = true;
  }
  json["view"] = frame.view;
  if (frame.camera) json["camera"] = cameraJson(*frame.camera);
  return json;
}

// Reads one image of a frame and checks its size against the frame's camera;
// failures become problems naming the frame field instead of exceptions.
template <class Image, class Read>
std::optional<Image> readPart(const Sequence& sequence, const std::string& relative,
                              const std::string& field, const CameraIntrinsics& camera, Read read,
                              std::vector<Problem>& problems) {
  const fs::path path = sequence.pathOf(relative);
  const auto wrongSize = [&](std::uint64_t width, std::uint64_t height) {
    if (width == static_cast<std::uint64_t>(camera.width) &&
        height == static_cast<std::uint64_t>(camera.height))
      return false;
    problems.push_back({path.string(), field + " (image size)",
                        std::to_string(camera.width) + " x " + std::to_string(camera.height) +
                            " pixels (the frame's camera width x height)",
                        std::to_string(width) + " x " + std::to_string(height)});
    return true;
  };
  try {
    // The size a header declares is checked before decoding anything: a small
    // compressed file can declare an image of gigabytes.
    if (const auto size = readImageHeaderSize(path); size && wrongSize(size->width, size->height))
      return std::nullopt;
    Image image = read(path);
    if (wrongSize(static_cast<std::uint64_t>(image.width),
                  static_cast<std::uint64_t>(image.height)))
      return std::nullopt;
    return image;
  } catch (const Error& e) {
    Problem problem = e.problem();
    problem.file = path.string();
    problem.field = problem.field.empty() ? field : field + " (" + problem.field + ")";
    problems.push_back(std::move(problem));
    return std::nullopt;
  }
}

void checkLabelIds(const fs::path& path, const std::string& field, const LabelImage& label,
                   int num_labels, std::vector<Problem>& problems) {
  size_t unknown = 0;
  size_t first = 0;
  for (size_t i = 0; i < label.ids.size(); ++i)
    if (label.ids[i] >= num_labels && unknown++ == 0) first = i;
  if (unknown == 0) return;
  const size_t width = static_cast<size_t>(label.width);
  problems.push_back(
      {path.string(), field + " (label ids)",
       "label ids from 0 to " + std::to_string(num_labels - 1) + " (the labels of the sequence)",
       "id " + std::to_string(label.ids[first]) + " at pixel (u=" + std::to_string(first % width) +
           ", v=" + std::to_string(first / width) + "), " + std::to_string(unknown) +
           " pixel(s) with unknown ids"});
}

FrameData readFrame(const Sequence& sequence, size_t index, FrameParts parts,
                    std::vector<Problem>& problems) {
  const FrameRecord& record = sequence.frames[index];
  const CameraIntrinsics& camera = sequence.cameraOf(index);
  const std::string field = indexed("frames", index);
  FrameData data;
  // The images read besides the depth: asked for, and named by the frame.
  const bool color = parts.color && !record.color.empty();
  const bool proba = parts.proba && !record.proba.empty();
  const bool label = parts.label && !record.label.empty();
  std::vector<Problem> depth_problems, other_problems;
  auto readDepth = [&] {
    if (auto depth = readPart<DepthImage>(
            sequence, record.depth, join(field, "depth"), camera,
            [&](const fs::path& p) { return readDepthImage(p, camera.depth_scale); },
            depth_problems))
      data.depth = std::move(*depth);
  };
  auto readOthers = [&] {
    std::vector<Problem>& out = other_problems;
    if (color)
      data.color = readPart<ColorImage>(
          sequence, record.color, join(field, "color"), camera,
          [](const fs::path& p) { return readColorImage(p); }, out);
    if (proba)
      data.proba = readPart<ProbabilityImage>(
          sequence, record.proba, join(field, "proba"), camera,
          [&](const fs::path& p) {
            return readProbabilityImage(p, record.proba_labels, sequence.labels.size(),
                                        parts.proba_floats);
          },
          out);
    if (label) {
      data.label = readPart<LabelImage>(
          sequence, record.label, join(field, "label"), camera,
          [](const fs::path& p) { return readLabelImage(p); }, out);
      if (data.label)
        checkLabelIds(sequence.pathOf(record.label), join(field, "label"), *data.label,
                      sequence.labels.size(), out);
    }
  };
  // The depth image and the others are decoded at once, on two cores: a
  // 640x480 depth PNG takes 3.5 ms to decode, the 8-bit proba 1 ms, a colour
  // PNG (for a segmenter) 6.7 ms, and fusion does not run meanwhile.
  if ((color || proba || label) && std::thread::hardware_concurrency() > 1) {
    runParts(2, [&](int part) { part == 0 ? readDepth() : readOthers(); });
  } else {
    readDepth();
    readOthers();
  }
  // Problems in the order of the fields, depth first, however the reads interleaved.
  problems.insert(problems.end(), depth_problems.begin(), depth_problems.end());
  problems.insert(problems.end(), other_problems.begin(), other_problems.end());
  return data;
}

}  // namespace

Sequence loadSequence(const fs::path& folder_or_json) {
  const fs::path json_path = sequenceJsonPath(folder_or_json);
  const Reader in(json_path.string());
  const Json root = json_text::parseFile(json_path, "a readable sequence.json");
  in.expectObject(root, "(top level)");
  // The format first: another kind of file (an annotations.json given by
  // mistake) is named as such, not by its first key this one lacks.
  const Json& format = in.required(root, "", "format");
  if (!format.is_string() || format.get<std::string>() != kFormat)
    in.fail("format", std::string("\"") + kFormat + "\"", describe(format));
  in.allowOnly(root, "", {"format", "version", "frame_id", "labels", "camera", "frames"});
  const Json& version = in.required(root, "", "version");
  if (!version.is_number() || version.get<double>() != kVersion)
    in.fail("version", std::to_string(kVersion) + " (the only version this program reads)",
            describe(version));

  Sequence sequence;
  sequence.root = json_path.parent_path();
  if (const Json* v = Reader::optional(root, "frame_id")) {
    sequence.frame_id = in.text(*v, "frame_id", "a non-empty string");
    // One line: it is printed by info and in box files' frame messages.
    if (const std::string problem = labelNameProblem(sequence.frame_id);
        !problem.empty() && problem.rfind("a name of", 0) != 0)
      in.fail("frame_id", "a frame name without control characters", problem);
  }
  const Json* labels = Reader::optional(root, "labels");
  sequence.labels = labels ? parseLabels(in, *labels) : apc2016Labels();
  sequence.camera = parseCamera(in, in.required(root, "", "camera"), "camera", nullptr);

  const Json& frames = in.array(in.required(root, "", "frames"), "frames", "an array of frames");
  if (frames.empty()) in.fail("frames", "at least one frame", "an empty array");
  for (size_t i = 0; i < frames.size(); ++i)
    sequence.frames.push_back(parseFrame(in, frames[i], i, sequence));
  return sequence;
}

std::string sequenceJsonText(const Sequence& sequence, const fs::path& folder) {
  const fs::path file = folder / "sequence.json";
  if (sequence.labels.empty())
    throw Error(file.string(), "labels", "at least one label", "an empty label set");
  OrderedJson root;
  root["format"] = kFormat;
  root["version"] = kVersion;
  root["frame_id"] = sequence.frame_id.empty() ? std::string("world") : sequence.frame_id;
  OrderedJson labels = OrderedJson::array();
  for (const auto& label : sequence.labels.all()) {
    // Never write a sequence that loadSequence would refuse.
    if (const std::string problem = labelNameProblem(label.name); !problem.empty())
      throw Error(file.string(), "labels[" + std::to_string(label.id) + "].name", kLabelNameRule,
                  problem);
    labels.push_back(OrderedJson{{"id", label.id},
                                 {"name", label.name},
                                 {"color", {label.color[0], label.color[1], label.color[2]}}});
  }
  root["labels"] = labels;
  root["camera"] = cameraJson(sequence.camera);
  OrderedJson frames = OrderedJson::array();
  for (size_t i = 0; i < sequence.frames.size(); ++i)
    frames.push_back(frameJson(sequence.frames[i], i, file));
  root["frames"] = frames;

  std::string text;
  prettyJson(root, 0, 0, text);
  return text + "\n";
}

void saveSequence(const Sequence& sequence, const fs::path& folder) {
  const std::string text = sequenceJsonText(sequence, folder);
  std::error_code ec;
  fs::create_directories(folder, ec);
  writeTextFileAtomically(folder / "sequence.json", text);
}

namespace {

// Non-negative finite floats in order of their bit patterns, binned by all
// but the lowest 13 of their 23 mantissa bits: bins 2^-10 (0.1 %) of their
// value wide, 261,120 bins from the smallest float to the largest.
class DepthHistogram {
 public:
  void add(float z) {
    if (counts_.empty()) counts_.assign(kBins, 0);
    ++counts_[bitsOf(z) >> kDroppedBits];
  }
  // The value of rank `rank` (0-based, ascending) to within its bin's width:
  // the bin's middle.
  [[nodiscard]] double valueOfRank(std::uint64_t rank) const {
    std::uint64_t below = 0;
    for (size_t bin = 0; bin < counts_.size(); ++bin) {
      below += counts_[bin];
      if (below > rank) {
        const std::uint32_t middle =
            (static_cast<std::uint32_t>(bin) << kDroppedBits) | (1u << (kDroppedBits - 1));
        float value = 0.f;
        std::memcpy(&value, &middle, sizeof value);
        return value;
      }
    }
    return 0.0;
  }

 private:
  static constexpr int kDroppedBits = 13;
  static constexpr size_t kBins = size_t{0x7f800000} >> kDroppedBits;  // up to infinity
  static std::uint32_t bitsOf(float z) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &z, sizeof bits);
    return bits;
  }
  std::vector<std::uint64_t> counts_;
};

bool measured(float z) { return z > 0.f && z <= std::numeric_limits<float>::max(); }

std::string significant(double value, int digits = 3) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

// "a, b, c and 4 more": at most `shown` items of a list that may be long.
std::string listSome(const std::vector<std::string>& items, size_t shown = 5) {
  std::string text;
  for (size_t i = 0; i < items.size() && i < shown; ++i)
    text += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
  if (items.size() > shown) text += " and " + std::to_string(items.size() - shown) + " more";
  return text;
}

std::string lowerExtension(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

// The file a frame path names, however it is spelt ("depth/0.png",
// "./depth/0.png", a link to it).
std::string resolvedFile(const Sequence& sequence, const std::string& relative) {
  const fs::path path = sequence.pathOf(relative);
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(path, ec);
  return (ec ? path.lexically_normal() : canonical).string();
}

// Frames listed twice, depth files shared by frames taken from different
// places, and stamps that go back: valid files, but a fusion of them counts
// one image's evidence twice or spreads it over two places.
void addFrameListWarnings(const Sequence& sequence, const std::string& json_file,
                          std::vector<std::string>& warnings) {
  std::map<std::string, std::vector<size_t>> frames_of_file;
  for (size_t i = 0; i < sequence.frames.size(); ++i)
    frames_of_file[resolvedFile(sequence, sequence.frames[i].depth)].push_back(i);
  std::vector<std::pair<size_t, size_t>> repeats;  // (frame, the earlier frame it repeats)
  std::vector<std::string> shared;
  for (const auto& [file, frames] : frames_of_file) {
    if (frames.size() < 2) continue;
    std::vector<size_t> places;  // the first frame of each pose
    for (const size_t i : frames) {
      const Eigen::Matrix4d& pose = sequence.frames[i].T_world_camera.matrix();
      const auto same = std::find_if(places.begin(), places.end(), [&](size_t earlier) {
        return sequence.frames[earlier].T_world_camera.matrix() == pose;
      });
      if (same == places.end())
        places.push_back(i);
      else
        repeats.emplace_back(i, *same);
    }
    if (places.size() < 2) continue;
    std::vector<std::string> fields;
    for (const size_t i : places) fields.push_back(indexed("frames", i) + ".depth");
    shared.push_back(file + " (" + listSome(fields) + ", " + std::to_string(places.size()) +
                     " poses)");
  }
  std::sort(repeats.begin(), repeats.end());
  if (!repeats.empty()) {
    std::vector<std::string> pairs;
    for (const auto& [frame, earlier] : repeats)
      pairs.push_back(indexed("frames", frame) + " repeats " + indexed("frames", earlier));
    warnings.push_back(json_file + ": frames: " + listSome(pairs) +
                       " (the same depth file and the same pose): fused, " +
                       (repeats.size() == 1 ? "its" : "their") +
                       " evidence counts twice (a frame listed again by mistake?)");
  }
  if (!shared.empty())
    warnings.push_back(json_file + ": frames[].depth: " +
                       (shared.size() == 1 ? std::string("a depth file is")
                                           : std::to_string(shared.size()) + " depth files are") +
                       " named by frames with different poses: " + listSome(shared, 3) +
                       "; one image was taken from one place, so all but one of those poses "
                       "put its depths where nothing was measured (a frame's file named twice "
                       "by mistake?)");
  // The format lists frames in recording order; stamps that go back are
  // frames out of order (or another recording's stamps).
  std::vector<std::string> back;
  std::optional<size_t> previous;
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    const auto& stamp = sequence.frames[i].stamp;
    if (!stamp) continue;
    if (previous && *stamp < *sequence.frames[*previous].stamp)
      back.push_back(indexed("frames", i) + ".stamp " + fixedDigits(*stamp, 6) + " after " +
                     indexed("frames", *previous) + ".stamp " +
                     fixedDigits(*sequence.frames[*previous].stamp, 6));
    previous = i;
  }
  if (!back.empty())
    warnings.push_back(
        json_file + ": frames[].stamp: the stamps go back " +
        (back.size() == 1 ? std::string("once") : std::to_string(back.size()) + " times") + ", " +
        listSome(back, 3) + ", but frames are listed in recording order (frames out of order?)");
}

}  // namespace

DepthFigures depthFigures(const DepthImage& depth) {
  DepthFigures figures;
  figures.pixels = depth.metres.size();
  std::vector<float> valid;
  valid.reserve(depth.metres.size());
  for (const float z : depth.metres)
    if (measured(z)) valid.push_back(z);
  figures.valid = valid.size();
  if (valid.empty()) return figures;
  const auto [low, high] = std::minmax_element(valid.begin(), valid.end());
  figures.min = *low;
  figures.max = *high;
  // The lower middle of an even count: a depth that was measured.
  const auto middle = valid.begin() + static_cast<std::ptrdiff_t>((valid.size() - 1) / 2);
  std::nth_element(valid.begin(), middle, valid.end());
  figures.median = *middle;
  return figures;
}

std::string implausibleDepthWarning(const Sequence& sequence, const std::vector<size_t>& frames,
                                    const DepthFigures& figures, bool sampled) {
  const bool near = figures.median < kMinPlausibleMedianDepth;
  if (figures.valid == 0 || frames.empty() || (!near && figures.median <= kMaxPlausibleMedianDepth))
    return "";
  // A 16-bit image holds units of its camera's depth_scale; a .npy holds metres.
  std::vector<std::string> fields;
  std::set<double> scales;
  size_t npy = 0;
  for (const size_t i : frames) {
    if (lowerExtension(sequence.frames[i].depth) == ".npy") {
      ++npy;
      continue;
    }
    const double scale = sequence.cameraOf(i).depth_scale;
    scales.insert(scale);
    const std::string field = scale == sequence.camera.depth_scale
                                  ? std::string("camera.depth_scale")
                                  : indexed("frames", i) + ".camera.depth_scale";
    if (std::find(fields.begin(), fields.end(), field) == fields.end()) fields.push_back(field);
  }
  if (npy > 0) fields.push_back("frames[].depth (.npy, in metres)");
  const std::string over = "the " + std::to_string(frames.size()) +
                           (frames.size() == 1 ? " frame" : " frames") +
                           (sampled ? " sampled" : "");
  std::string text = (sequence.root / "sequence.json").string() + ": " + listSome(fields, 3) +
                     ": the median valid depth of " + over + " is " + significant(figures.median) +
                     " m (" + significant(figures.min) + " .. " + significant(figures.max) +
                     " m), " + (near ? "nearer" : "farther") +
                     " than depth cameras measure (a median of " +
                     significant(kMinPlausibleMedianDepth) + " to " +
                     significant(kMaxPlausibleMedianDepth) + " m expected)";
  // The power of ten that brings the median nearest 1 m: depth units are
  // metres, millimetres or tenths of them, rarely anything between.
  const double factor = std::pow(10.0, std::round(-std::log10(figures.median)));
  const std::string times = significant(factor >= 1.0 ? factor : 1.0 / factor, 6) +
                            (factor >= 1.0 ? " times too small" : " times too large");
  if (npy == 0 && scales.size() == 1) {
    const double scale = *scales.begin();
    text += ": depth_scale " + significant(scale, 6) + " metres per unit is likely wrong; " +
            significant(scale * factor, 6) + " would give a median of " +
            significant(figures.median * factor) + " m (fused as it is, the map comes out " +
            times + ")";
  } else if (npy == frames.size()) {
    text += ": .npy depths are metres (depth_scale does not apply); scaled by " +
            significant(factor, 6) + " they would have a median of " +
            significant(figures.median * factor) + " m (fused as they are, the map comes out " +
            times + ")";
  } else {
    text += ": check the depth scales of the frames (fused as they are, the map comes out about " +
            times + ")";
  }
  return text;
}

SequenceCheck checkSequence(const Sequence& sequence) {
  SequenceCheck check;
  const std::string json_file = (sequence.root / "sequence.json").string();
  check.frame_depths.resize(sequence.frames.size());
  DepthHistogram histogram;
  std::vector<size_t> read;  // frames whose depth image was read
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    const FrameRecord& record = sequence.frames[i];
    if (record.proba.empty() && record.label.empty())
      check.problems.push_back({json_file, indexed("frames", i),
                                "a \"proba\" or a \"label\" file (fusion needs per-pixel labels)",
                                "neither"});
    const FrameData frame = readFrame(sequence, i, FrameParts{}, check.problems);
    // The depth counts whatever the frame's other images: a broken label
    // image leaves its depths as they are (readFrame leaves an image that
    // could not be read, or has the wrong size, empty).
    if (frame.depth.metres.empty()) continue;
    read.push_back(i);
    const DepthFigures figures = depthFigures(frame.depth);
    check.frame_depths[i] = figures;
    DepthFigures& all = check.depths;
    all.pixels += figures.pixels;
    if (figures.valid == 0) continue;
    all.min = all.valid == 0 ? figures.min : std::min(all.min, figures.min);
    all.max = std::max(all.max, figures.max);
    all.valid += figures.valid;
    for (const float z : frame.depth.metres)
      if (measured(z)) histogram.add(z);
  }
  if (check.depths.valid > 0) {
    // The lower middle, as depthFigures takes it; clamped for a bin wider than the range.
    const double median = histogram.valueOfRank((check.depths.valid - 1) / 2);
    check.depths.median = std::clamp(median, check.depths.min, check.depths.max);
  }
  // Frames without a measurement are left out of fusion one by one; with
  // none at all there is nothing to fuse, which fuse refuses. Said whatever
  // else is wrong (it is the one problem that fixing the others leaves),
  // unless no depth image could be read: each frame's problem says so.
  if (!read.empty() && check.depths.valid == 0) {
    const size_t count = sequence.frames.size();
    const size_t unread = count - read.size();
    std::string found = "none in the " + std::to_string(count) + " frames: ";
    if (unread == 0)
      found += "every depth pixel is 0 (no measurement) or invalid";
    else
      found += std::to_string(unread) + " of the " + std::to_string(count) +
               " depth images could not be read (see the frames[i].depth problems), and every "
               "pixel of the " +
               (read.size() == 1 ? "other" : "others") + " is 0 (no measurement) or invalid";
    check.problems.push_back(
        {json_file, "frames[].depth",
         "depth images with valid measurements (finite, > 0) in at least one frame", found});
  }
  if (std::string depth = implausibleDepthWarning(sequence, read, check.depths); !depth.empty())
    check.warnings.push_back(std::move(depth));
  addFrameListWarnings(sequence, json_file, check.warnings);
  return check;
}

std::vector<Problem> validateSequence(const Sequence& sequence) {
  return checkSequence(sequence).problems;
}

FrameData loadFrame(const Sequence& sequence, size_t index, FrameParts parts) {
  if (index >= sequence.frames.size())
    throw Error((sequence.root / "sequence.json").string(), indexed("frames", index),
                "a frame index below " + std::to_string(sequence.frames.size()),
                std::to_string(index));
  std::vector<Problem> problems;
  FrameData data = readFrame(sequence, index, parts, problems);
  if (!problems.empty()) throw Error(problems.front());
  return data;
}

std::vector<fs::path> frameFilesOf(const Sequence& sequence) {
  std::vector<fs::path> files;
  for (const auto& frame : sequence.frames)
    for (const std::string* name : {&frame.depth, &frame.color, &frame.proba, &frame.label})
      if (!name->empty()) files.push_back(sequence.pathOf(*name));
  return files;
}

std::string fixedDigits(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  std::string shown = text;
  while (shown.back() == '0') shown.pop_back();
  if (shown.back() == '.') shown.pop_back();
  return shown == "-0" ? std::string("0") : shown;
}

}  // namespace lom
