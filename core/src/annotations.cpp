// Ground-truth boxes: annotations.json (format "labeloctomap-annotations"
// version 1, docs/annotation-format.md) and the YAML box files of the paper's
// original experiments.
#include "lom/annotations.hpp"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "file_checks.hpp"
#include "json_text.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"

namespace lom {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

using json_text::describe;
using json_text::field;
using json_text::indexed;
using json_text::inlineJson;

namespace {

constexpr const char* kFormat = "labeloctomap-annotations";
constexpr int kVersion = 1;
constexpr int kMaxLabel = 65535;
// Unit quaternions already this close to norm 1 are kept bit for bit, so
// that a load/save round trip reproduces the file exactly.
constexpr double kAlreadyUnit = 1e-12;

// Checks shared by the JSON and the YAML reader once the numbers are parsed.
struct BoxChecker {
  std::string file;
  std::map<int, std::string> label_field;

  void label(int id, const std::string& where) {
    const auto [previous, inserted] = label_field.emplace(id, where);
    if (!inserted)
      throw Error(file, where, "each label in at most one box",
                  "label " + std::to_string(id) + " again (also " + previous->second + ")");
  }

  void size(const Eigen::Vector3d& size, const std::string& where) const {
    // A finite volume too: scores divide by it (1e300 m edges overflow it).
    if ((size.array() > 0.0).all() && std::isfinite(size.prod())) return;
    std::ostringstream found;
    found << "[" << size.x() << ", " << size.y() << ", " << size.z() << "]";
    if ((size.array() > 0.0).all()) found << ", a volume too large for a number";
    throw Error(file, where, "3 positive edge lengths [dx, dy, dz]", found.str());
  }

  Eigen::Quaterniond rotation(const Eigen::Vector4d& xyzw, const std::string& where) const {
    const std::optional<Eigen::Quaterniond> unit = unitQuaternion(xyzw);
    if (!unit) {
      std::ostringstream found;
      found << "[" << xyzw[0] << ", " << xyzw[1] << ", " << xyzw[2] << ", " << xyzw[3] << "]";
      throw Error(file, where, "a non-zero quaternion [qx, qy, qz, qw]", found.str());
    }
    if (std::abs(xyzw.norm() - 1.0) <= kAlreadyUnit)
      return Eigen::Quaterniond(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
    return *unit;
  }
};

// ---- JSON ------------------------------------------------------------------

class JsonReader {
 public:
  explicit JsonReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& expected,
                         const std::string& found) const {
    throw Error(file_, where, expected, found);
  }

  void allowOnly(const Json& object, const std::string& where,
                 std::initializer_list<const char*> keys) const {
    if (!object.is_object())
      fail(where.empty() ? "(top level)" : where, "an object", describe(object));
    std::string list;
    for (const char* key : keys) list += (list.empty() ? "" : ", ") + std::string(key);
    for (const auto& item : object.items()) {
      bool known = false;
      for (const char* key : keys) known = known || item.key() == key;
      if (!known) fail(field(where, item.key()), "only the keys " + list, "an unknown key");
    }
  }

  const Json& required(const Json& object, const std::string& where, const char* key) const {
    const auto it = object.find(key);
    if (it == object.end()) fail(field(where, key), "a value", "nothing (the key is missing)");
    return *it;
  }

  template <int N>
  Eigen::Matrix<double, N, 1> numbers(const Json& value, const std::string& where,
                                      const std::string& what) const {
    if (!value.is_array() || value.size() != N) fail(where, what, describe(value));
    Eigen::Matrix<double, N, 1> out;
    for (int i = 0; i < N; ++i) {
      const Json& item = value[static_cast<size_t>(i)];
      if (!item.is_number() || !std::isfinite(item.get<double>()))
        fail(indexed(where, static_cast<size_t>(i)), "a finite number", describe(item));
      out[i] = item.get<double>();
    }
    return out;
  }

  int label(const Json& value, const std::string& where) const {
    const std::string what = "a label id from 0 to " + std::to_string(kMaxLabel);
    if (!value.is_number()) fail(where, what, describe(value));
    const double v = value.get<double>();
    if (std::floor(v) != v || v < 0 || v > kMaxLabel) fail(where, what, describe(value));
    return static_cast<int>(v);
  }

  std::string text(const Json& value, const std::string& where, bool allow_empty) const {
    if (!value.is_string() || (!allow_empty && value.get<std::string>().empty()))
      fail(where, allow_empty ? "a string" : "a non-empty string", describe(value));
    return value.get<std::string>();
  }

 private:
  std::string file_;
};

void requireFinite(const fs::path& path, const std::string& where, const Eigen::VectorXd& values) {
  if (!values.allFinite())
    throw Error(path.string(), where, "finite numbers (JSON has no NaN or infinity)",
                "a non-finite value");
}

// ---- YAML ------------------------------------------------------------------

class YamlReader {
 public:
  explicit YamlReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& expected,
                         const std::string& found) const {
    throw Error(file_, where, expected, found);
  }

  // A mapping's keys are among `keys` and each is given once (a misspelt
  // frame_id would otherwise be ignored, and a repeated key keep one value).
  void allowOnly(const YAML::Node& mapping, const std::string& where,
                 std::initializer_list<const char*> keys) const {
    std::string list;
    for (const char* key : keys) list += (list.empty() ? "" : ", ") + std::string(key);
    std::set<std::string> seen;
    for (const auto& item : mapping) {
      const std::string key =
          item.first.IsScalar() ? item.first.Scalar() : "(a " + describe(item.first) + ")";
      bool known = false;
      for (const char* allowed : keys) known = known || key == allowed;
      if (!known) fail(field(where, key), "only the keys " + list, "an unknown key");
      if (!seen.insert(key).second)
        fail(field(where, key), "each key once in its mapping",
             "the key '" + key + "' a second time");
    }
  }

  static std::string describe(const YAML::Node& node) {
    if (!node.IsDefined() || node.IsNull()) return "nothing";
    if (node.IsScalar()) return "'" + node.Scalar() + "'";
    if (node.IsSequence()) return "a list of " + std::to_string(node.size()) + " items";
    return "a mapping";
  }

  template <int N>
  Eigen::Matrix<double, N, 1> numbers(const YAML::Node& node, const std::string& where,
                                      const std::string& what) const {
    // An absent key first: asking an absent node its type throws yaml-cpp's
    // "invalid node", which names neither the file nor the field.
    if (!node.IsDefined() || !node.IsSequence() || node.size() != N)
      fail(where, what, describe(node));
    Eigen::Matrix<double, N, 1> out;
    for (int i = 0; i < N; ++i) {
      const YAML::Node item = node[static_cast<size_t>(i)];
      double value = 0.0;
      try {
        value = item.as<double>();
      } catch (const YAML::Exception&) {
        fail(indexed(where, static_cast<size_t>(i)), "a number", describe(item));
      }
      if (!std::isfinite(value))
        fail(indexed(where, static_cast<size_t>(i)), "a finite number", describe(item));
      out[i] = value;
    }
    return out;
  }

  std::string text(const YAML::Node& node, const std::string& where) const {
    if (!node.IsDefined() || !node.IsScalar() || node.Scalar().empty())
      fail(where, "a non-empty string", describe(node));
    return node.Scalar();
  }

 private:
  std::string file_;
};

YAML::Node loadYamlFile(const fs::path& path) {
  if (const std::string why = notARegularFile(path); !why.empty())
    throw Error(path.string(), "", "an existing YAML box file", why);
  try {
    // Every document, to refuse a file of several: the boxes of the second
    // and later ones would be left out without a word.
    const std::vector<YAML::Node> documents = YAML::LoadAllFromFile(path.string());
    if (documents.size() > 1)
      throw Error(path.string(), "", "one YAML document of boxes",
                  std::to_string(documents.size()) +
                      " documents (separated by ---): merge their boxes into one list");
    return documents.empty() ? YAML::Node() : documents.front();
  } catch (const YAML::ParserException& e) {
    throw Error(path.string(), "", "valid YAML",
                e.msg + " at line " + std::to_string(e.mark.line + 1) + ", column " +
                    std::to_string(e.mark.column + 1));
  } catch (const YAML::Exception& e) {
    throw Error(path.string(), "", "a readable YAML file", e.what());
  }
}

// "object_19" -> 19
int labelFromObjectName(const YamlReader& in, const std::string& name, const std::string& where) {
  const std::string prefix = "object_";
  const std::string expected =
      "a name object_N with a label id N from 0 to " + std::to_string(kMaxLabel);
  if (name.rfind(prefix, 0) != 0 || name.size() == prefix.size() || name.size() > prefix.size() + 5)
    in.fail(where, expected, "'" + name + "'");
  int id = 0;
  for (size_t i = prefix.size(); i < name.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i])))
      in.fail(where, expected, "'" + name + "'");
    id = id * 10 + (name[i] - '0');
  }
  if (id > kMaxLabel) in.fail(where, expected, "'" + name + "'");
  return id;
}

}  // namespace

const GroundTruthBox* Annotations::find(int label) const {
  for (const auto& box : boxes)
    if (box.label == label) return &box;
  return nullptr;
}

Annotations loadAnnotations(const fs::path& path) {
  const JsonReader in(path.string());
  const Json root = json_text::parseFile(path, "a readable annotations file");
  if (!root.is_object()) in.fail("(top level)", "an object", describe(root));
  // The format first: another kind of file (a sequence.json given by
  // mistake) is named as such, not by its first key this one lacks.
  const Json& format = in.required(root, "", "format");
  if (!format.is_string() || format.get<std::string>() != kFormat)
    in.fail("format", std::string("\"") + kFormat + "\"", describe(format));
  in.allowOnly(root, "", {"format", "version", "frame_id", "boxes"});
  const Json& version = in.required(root, "", "version");
  if (!version.is_number() || version.get<double>() != kVersion)
    in.fail("version", std::to_string(kVersion) + " (the only version this program reads)",
            describe(version));

  Annotations annotations;
  if (root.contains("frame_id"))
    annotations.frame_id = in.text(root["frame_id"], "frame_id", false);
  const Json& boxes = in.required(root, "", "boxes");
  if (!boxes.is_array()) in.fail("boxes", "an array of boxes", describe(boxes));

  BoxChecker check{path.string(), {}};
  for (size_t i = 0; i < boxes.size(); ++i) {
    const std::string where = indexed("boxes", i);
    const Json& item = boxes[i];
    in.allowOnly(item, where, {"label", "name", "center", "size", "rotation"});
    GroundTruthBox box;
    box.label = in.label(in.required(item, where, "label"), field(where, "label"));
    check.label(box.label, field(where, "label"));
    if (item.contains("name")) box.name = in.text(item["name"], field(where, "name"), true);
    box.box.center = in.numbers<3>(in.required(item, where, "center"), field(where, "center"),
                                   "3 numbers [x, y, z]");
    box.box.size = in.numbers<3>(in.required(item, where, "size"), field(where, "size"),
                                 "3 positive edge lengths [dx, dy, dz]");
    check.size(box.box.size, field(where, "size"));
    if (item.contains("rotation"))
      box.box.rotation = check.rotation(in.numbers<4>(item["rotation"], field(where, "rotation"),
                                                      "a quaternion [qx, qy, qz, qw]"),
                                        field(where, "rotation"));
    annotations.boxes.push_back(std::move(box));
  }
  return annotations;
}

void saveAnnotations(const Annotations& annotations, const fs::path& path) {
  OrderedJson boxes = OrderedJson::array();
  for (size_t i = 0; i < annotations.boxes.size(); ++i) {
    const GroundTruthBox& box = annotations.boxes[i];
    const std::string where = indexed("boxes", i);
    const auto& q = box.box.rotation;
    requireFinite(path, field(where, "center"), box.box.center);
    requireFinite(path, field(where, "size"), box.box.size);
    requireFinite(path, field(where, "rotation"), q.coeffs());
    OrderedJson json;
    json["label"] = box.label;
    json["name"] = box.name;
    json["center"] = {box.box.center.x(), box.box.center.y(), box.box.center.z()};
    json["size"] = {box.box.size.x(), box.box.size.y(), box.box.size.z()};
    json["rotation"] = {q.x(), q.y(), q.z(), q.w()};
    boxes.push_back(json);
  }
  // One box per line keeps files diffable and easy to edit by hand.
  std::string text =
      "{\n  \"format\": \"" + std::string(kFormat) +
      "\",\n  \"version\": " + std::to_string(kVersion) + ",\n  \"frame_id\": " +
      inlineJson(OrderedJson(annotations.frame_id.empty() ? "world" : annotations.frame_id)) +
      ",\n  \"boxes\": [";
  for (size_t i = 0; i < boxes.size(); ++i)
    text += (i ? ",\n    " : "\n    ") + inlineJson(boxes[i]);
  text += boxes.empty() ? "]\n}\n" : "\n  ]\n}\n";
  writeTextFileAtomically(path, text);
}

Annotations importYamlBoxes(const fs::path& path, const LabelSet& labels,
                            const std::optional<std::string>& frame_id) {
  const YamlReader in(path.string());
  const YAML::Node root = loadYamlFile(path);
  if (!root.IsMap())
    in.fail("(top level)", "a mapping with a 'boxes' list", YamlReader::describe(root));
  in.allowOnly(root, "", {"boxes"});
  const YAML::Node list = root["boxes"];
  if (!list.IsDefined() || !list.IsSequence())
    in.fail("boxes", "a list of boxes", YamlReader::describe(list));

  Annotations annotations;
  std::string frame_id_field;
  BoxChecker check{path.string(), {}};
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = indexed("boxes", i);
    const YAML::Node item = list[i];
    if (!item.IsMap())
      in.fail(where, "a mapping with dimensions, position, orientation, name",
              YamlReader::describe(item));
    in.allowOnly(item, where, {"dimensions", "position", "orientation", "name", "frame_id"});
    GroundTruthBox box;
    const std::string object_name = in.text(item["name"], field(where, "name"));
    box.label = labelFromObjectName(in, object_name, field(where, "name"));
    check.label(box.label, field(where, "name"));
    box.name = labels.contains(box.label) ? labels.at(box.label).name : object_name;
    box.box.size = in.numbers<3>(item["dimensions"], field(where, "dimensions"),
                                 "3 positive edge lengths [dx, dy, dz]");
    check.size(box.box.size, field(where, "dimensions"));
    box.box.center =
        in.numbers<3>(item["position"], field(where, "position"), "3 numbers [x, y, z]");
    box.box.rotation =
        check.rotation(in.numbers<4>(item["orientation"], field(where, "orientation"),
                                     "a quaternion [qx, qy, qz, qw]"),
                       field(where, "orientation"));
    if (item["frame_id"].IsDefined()) {
      const std::string frame_id = in.text(item["frame_id"], field(where, "frame_id"));
      if (frame_id_field.empty()) {
        annotations.frame_id = frame_id;
        frame_id_field = field(where, "frame_id");
      } else if (frame_id != annotations.frame_id) {
        in.fail(field(where, "frame_id"),
                "the same frame_id in every box (\"" + annotations.frame_id + "\" as in " +
                    frame_id_field + ")",
                "\"" + frame_id + "\"");
      }
    }
    annotations.boxes.push_back(std::move(box));
  }
  if (frame_id) annotations.frame_id = *frame_id;
  return annotations;
}

bool isYamlBoxesPath(const fs::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".yaml" || extension == ".yml";
}

Annotations loadAnnotationsFor(const fs::path& path, const LabelSet& labels,
                               const std::string& frame_id) {
  if (!isYamlBoxesPath(path)) return loadAnnotations(path);
  return importYamlBoxes(path, labels, frame_id);
}

}  // namespace lom
