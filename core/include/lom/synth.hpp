#pragma once
// Synthetic shelf-bin scenes: the built-in demo data and the test fixture.
// Scene description, sensor model and file layout: docs/synthetic-scenes.md.
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "lom/annotations.hpp"
#include "lom/camera.hpp"
#include "lom/geometry.hpp"
#include "lom/images.hpp"
#include "lom/sequence.hpp"

namespace lom {

inline constexpr int kSynthMaxObjects = 39;  // every APC 2016 object at most once
inline constexpr int kSynthMinViews = 3;
inline constexpr int kSynthMaxFrames = 10000;
inline constexpr int kSynthMinWidth = 32;
inline constexpr int kSynthMinHeight = 24;
inline constexpr int kSynthMaxImageSide = 2048;  // keeps the float probabilities in memory small
// The object without depth (like a transparent bottle): dasani_water_bottle.
inline constexpr int kSynthTransparentLabel = 9;

struct SynthOptions {
  std::uint64_t seed = 1;
  int objects = 6;  // number of objects from the 39-label catalogue
  int frames = 15;  // total frames along the camera path (>= views)
  int views = 3;    // distinct viewpoints marked view: true (>= 3)
  int width = 640;
  int height = 480;
  bool write_color = true;
  bool write_label = true;  // ground-truth label images
  // Depth sensor imperfections: noise, dropouts, holes at depth edges and at
  // grazing angles. The transparent object has no depth either way.
  bool noise = true;
  // Segmenter mistakes: look-alike confusion patches and false-positive blobs.
  // Without them the argmax of every probability image is the true label.
  bool segmenter_mistakes = true;
};

// Throws std::invalid_argument naming the field when an option is out of range.
void checkSynthOptions(const SynthOptions& options);

struct SynthScene {
  Sequence sequence;
  Annotations annotations;  // exact ground-truth boxes of the objects
};

// Generates the scene and writes into `out` (created when missing):
// synth.json (the options), depth/, color/, label/, proba/ frame files,
// annotations.json, and sequence.json last. `out` must be missing, empty or a
// previous synth output (it holds synth.json); otherwise throws lom::Error
// naming it. Deterministic: the same options give byte-identical files.
SynthScene writeSyntheticScene(const SynthOptions& options, const std::filesystem::path& out);

// ---- The scene in memory (used by the writer and by tests) ----

enum class SynthShape { Box, Cylinder };

struct SynthObject {
  int label = 0;
  std::string name;
  SynthShape shape = SynthShape::Box;
  // Exact box; a cylinder's axis is the box z axis, its radius size.x() / 2.
  OrientedBox box;
};

struct SynthLayout {
  std::vector<OrientedBox> shelf;    // shelf body and bin walls, label 0
  OrientedBox bin_interior;          // the free space inside the bin
  std::vector<SynthObject> objects;  // distinct labels, resting on the bin floor
  CameraIntrinsics camera;
  std::vector<Eigen::Isometry3d> T_world_camera;  // one per frame
  std::vector<bool> view;                         // one per frame
  // Label of each probability channel, ascending: background, the objects'
  // labels, their look-alikes and a few distractors (see the docs).
  std::vector<int> proba_labels;
};

// Bin, objects and camera path. The objects depend on the seed and the object
// count only, the path on the seed, frames and views, the intrinsics on the
// image size. Throws std::invalid_argument like checkSynthOptions.
[[nodiscard]] SynthLayout makeSynthLayout(const SynthOptions& options);

struct SynthFrame {
  DepthImage depth;  // metres, quantised to the 1 mm PNG step; 0 = no measurement
  ColorImage color;
  LabelImage label;        // exact label of the surface hit by each pixel's ray
  ProbabilityImage proba;  // values are multiples of 1/255, as stored in the .npy
};

// Renders frame `index` of the layout. Depends on the layout, the seed, the
// noise switches and the index only, so frames can be rendered in any order.
[[nodiscard]] SynthFrame renderSynthFrame(const SynthLayout& layout, const SynthOptions& options,
                                          size_t index);

// Ground-truth boxes of the layout's objects (a cylinder's enclosing box).
[[nodiscard]] Annotations synthAnnotations(const SynthLayout& layout);

}  // namespace lom
