#pragma once
// Building blocks of the synthetic scenes, shared by the synth_*.cpp files.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "lom/synth.hpp"

namespace lom::synth {

// Random numbers whose sequence is fixed by the C++ standard: mt19937_64 is
// fully specified, the std:: distributions are not, so they are done by hand.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  std::uint64_t bits() { return engine_(); }
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double low, double high) { return low + (high - low) * uniform(); }
  int below(int n) { return static_cast<int>(uniform() * n); }  // 0..n-1
  bool chance(double p) { return uniform() < p; }
  double normal() {  // Box-Muller; the second value is kept for the next call
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double radius = std::sqrt(-2.0 * std::log(1.0 - uniform()));
    const double angle = 2.0 * M_PI * uniform();
    spare_ = radius * std::sin(angle);
    has_spare_ = true;
    return radius * std::cos(angle);
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Independent streams per purpose and frame, so that e.g. the number of
// frames does not change the objects, and frames render in any order.
enum class Stream : std::uint64_t { Layout = 1, Path = 2, Depth = 3, Color = 4, Segmenter = 5 };
// splitmix64 finaliser: nearby inputs give unrelated seeds.
[[nodiscard]] inline std::uint64_t streamSeed(std::uint64_t seed, Stream stream,
                                              std::uint64_t index = 0) {
  std::uint64_t z = seed;
  for (const std::uint64_t part : {static_cast<std::uint64_t>(stream), index}) {
    z += 0x9e3779b97f4a7c15ULL + part;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
  }
  return z;
}

// Bin interior in the world frame: the opening is the plane x = 0 facing -x,
// the floor is z = 0, the bin is centred on y = 0.
inline constexpr double kBinDepth = 0.38;
inline constexpr double kBinWidth = 0.50;
inline constexpr double kBinHeight = 0.25;

// ---- Camera (synth_camera.cpp) ----

[[nodiscard]] CameraIntrinsics scaledCamera(int width, int height);
// Fills layout.T_world_camera and layout.view.
void makeCameraPath(const SynthOptions& options, SynthLayout& layout);

// ---- Object catalogue (synth_catalogue.cpp) ----

// How an object may rest on the bin floor. Boxes: Flat (shortest edge up),
// Side (middle edge up), Upright (longest edge up). Cylinders: Standing, Lying.
enum class Rest { Flat, Side, Upright, Standing, Lying };

struct CatalogueItem {
  SynthShape shape = SynthShape::Box;
  // Box: edge lengths, longest first. Cylinder: diameter, diameter, height.
  Eigen::Vector3d size;
  std::vector<Rest> rests;
};

[[nodiscard]] const CatalogueItem& catalogueItem(int label);  // label 1..39
// Labels a segmenter tends to mistake `label` for (possibly empty).
[[nodiscard]] std::vector<int> lookAlikesOf(int label);

// ---- Ray casting (synth_raycast.cpp) ----

// What each pixel's ray hits first, before any sensor effect.
struct SurfaceImage {
  int width = 0;
  int height = 0;
  std::vector<float> depth;             // camera z in metres; 0 = nothing hit
  std::vector<Eigen::Vector3f> normal;  // world-frame unit normal facing the camera
  std::vector<float> cos_incidence;     // |cos| of the angle between ray and normal
  std::vector<std::uint16_t> label;     // object label, 0 for the shelf and for nothing
};

[[nodiscard]] SurfaceImage castRays(const SynthLayout& layout, size_t frame);

// ---- Sensor and appearance (synth_sensor.cpp) ----

[[nodiscard]] DepthImage senseDepth(const SurfaceImage& surface, double depth_scale, bool noise,
                                    Rng& rng);
[[nodiscard]] ColorImage shadeColor(const SurfaceImage& surface, Rng& rng);

// ---- Simulated segmenter (synth_segmenter.cpp) ----

[[nodiscard]] std::vector<int> chooseProbaLabels(const std::vector<int>& object_labels, Rng& rng);
[[nodiscard]] ProbabilityImage simulateSegmenter(const LabelImage& truth,
                                                 const std::vector<int>& channel_labels,
                                                 bool mistakes, Rng& rng);

// Smooth random field in about [-1, 1]: random values on a coarse grid,
// interpolated, so that segmenter errors come in patches rather than speckle.
class SmoothField {
 public:
  SmoothField(int width, int height, double cell_pixels, Rng& rng);
  [[nodiscard]] float at(int u, int v) const;

 private:
  int grid_width_;
  int grid_height_;
  double inverse_cell_;
  std::vector<float> values_;
};

}  // namespace lom::synth
