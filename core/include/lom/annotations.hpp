#pragma once
// Ground-truth boxes, format "labeloctomap-annotations" version 1 (docs/annotation-format.md).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "lom/geometry.hpp"
#include "lom/labels.hpp"

namespace lom {

struct GroundTruthBox {
  int label = 0;
  std::string name;
  OrientedBox box;
};

struct Annotations {
  std::string frame_id = "world";
  std::vector<GroundTruthBox> boxes;

  [[nodiscard]] const GroundTruthBox* find(int label) const;
};

// Throws lom::Error naming the file and field on any malformed content.
[[nodiscard]] Annotations loadAnnotations(const std::filesystem::path& path);
void saveAnnotations(const Annotations& annotations, const std::filesystem::path& path);

// The YAML box files of the paper's original experiments:
// boxes: [{dimensions: [dx,dy,dz], position: [x,y,z], orientation: [qx,qy,qz,qw],
//          name: object_N, frame_id: base}]; label N comes from "object_N", the
// name is looked up in `labels` when given. With `frame_id`, the boxes are
// taken to be in that frame, the sequence's, whatever frame the file names (the
// original experiments name their robot's frame, "base").
[[nodiscard]] Annotations importYamlBoxes(const std::filesystem::path& path,
                                          const LabelSet& labels = {},
                                          const std::optional<std::string>& frame_id = {});

// Whether `path` names a YAML box file (.yaml or .yml, any case).
[[nodiscard]] bool isYamlBoxesPath(const std::filesystem::path& path);

// The boxes annotating a sequence: annotations.json, or for a YAML box file
// (isYamlBoxesPath) its boxes named with `labels` and taken to be in
// `frame_id`, the sequence's frame, as the studio's YAML import reads them.
[[nodiscard]] Annotations loadAnnotationsFor(const std::filesystem::path& path,
                                             const LabelSet& labels, const std::string& frame_id);

}  // namespace lom
