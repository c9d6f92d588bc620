// Objects of the map (lom::extractObjects): fitted oriented box, centroid and
// voxel counts per label, as JSON "labeloctomap-objects" version 1 (docs/export.md).
#include <nlohmann/json.hpp>

#include "json_text.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"

namespace lom {

using json_text::inlineJson;

namespace {

using Json = nlohmann::ordered_json;

}  // namespace

void writeObjectsJson(const std::vector<ObjectInstance>& objects, const LabelMap& map,
                      const std::filesystem::path& path) {
  // One object per line, numbers at full precision.
  std::string text = "{\n  \"format\": \"labeloctomap-objects\",\n  \"version\": 1,\n";
  text += "  \"resolution\": " + Json(map.parameters().resolution).dump() + ",\n";
  text += "  \"occupancy_threshold\": " + Json(map.parameters().occupancy_threshold).dump() + ",\n";
  text += "  \"objects\": [";
  for (size_t i = 0; i < objects.size(); ++i) {
    const ObjectInstance& o = objects[i];
    const Rgb color = map.labels().at(o.label).color;
    const auto& q = o.box.rotation;
    const Json item{{"label", o.label},
                    {"name", o.name},
                    {"color", {color[0], color[1], color[2]}},
                    {"voxels", o.label_voxels},
                    {"label_voxels", o.label_voxels},  // as plan.json names them
                    {"cluster_voxels", o.voxelCount()},
                    {"centroid", {o.centroid.x(), o.centroid.y(), o.centroid.z()}},
                    {"mean_probability", o.mean_probability},
                    {"center", {o.box.center.x(), o.box.center.y(), o.box.center.z()}},
                    {"size", {o.box.size.x(), o.box.size.y(), o.box.size.z()}},
                    {"rotation", {q.x(), q.y(), q.z(), q.w()}}};
    text += (i ? ",\n    " : "\n    ") + inlineJson(item);
  }
  text += objects.empty() ? "]\n}\n" : "\n  ]\n}\n";
  writeTextFileAtomically(path, text);
}

}  // namespace lom
