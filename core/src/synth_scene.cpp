// Scene layout: the shelf bin and the objects on its floor.
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "synth_internal.hpp"

namespace lom {

namespace {

using synth::kBinDepth;
using synth::kBinHeight;
using synth::kBinWidth;
using synth::Rest;
using synth::Rng;

constexpr double kMaxObjectHeight = 0.22;
constexpr double kWallClearance = 0.012;
constexpr double kObjectClearance = 0.008;

OrientedBox axisAlignedBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  OrientedBox box;
  box.center = 0.5 * (min + max);
  box.size = max - min;
  return box;
}

// The shelf body around the bin; other bins of the shelf are not modelled.
std::vector<OrientedBox> shelfBoxes() {
  const double x1 = kBinDepth + 0.05, y0 = 0.5 * kBinWidth, y1 = 0.70, z0 = -0.35, z1 = 0.60;
  return {
      axisAlignedBox({0, -y1, z0}, {x1, y1, 0}),                  // below, its top is the floor
      axisAlignedBox({0, -y1, kBinHeight}, {x1, y1, z1}),         // above
      axisAlignedBox({0, -y1, 0}, {x1, -y0, kBinHeight}),         // left wall
      axisAlignedBox({0, y0, 0}, {x1, y1, kBinHeight}),           // right wall
      axisAlignedBox({kBinDepth, -y0, 0}, {x1, y0, kBinHeight}),  // back wall
  };
}

// An object's footprint on the floor: a rectangle of half extents `half` in a
// frame rotated by `yaw`.
struct Footprint {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Vector2d half = Eigen::Vector2d::Zero();
  double yaw = 0.0;

  [[nodiscard]] Eigen::Vector2d axis(int i) const {
    return i == 0 ? Eigen::Vector2d(std::cos(yaw), std::sin(yaw))
                  : Eigen::Vector2d(-std::sin(yaw), std::cos(yaw));
  }
  // Half width of the footprint's shadow on a unit direction.
  [[nodiscard]] double radiusAlong(const Eigen::Vector2d& direction) const {
    return half.x() * std::abs(axis(0).dot(direction)) +
           half.y() * std::abs(axis(1).dot(direction));
  }
};

bool separated(const Footprint& a, const Footprint& b, double clearance) {
  const Eigen::Vector2d offset = b.center - a.center;
  for (const Footprint* f : {&a, &b})
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d axis = f->axis(i);
      if (std::abs(offset.dot(axis)) > a.radiusAlong(axis) + b.radiusAlong(axis) + clearance)
        return true;
    }
  return false;
}

// One object before it is put somewhere: its size and how it rests.
struct ObjectPlan {
  int label = 0;
  synth::CatalogueItem item;
  Eigen::Vector3d size;  // box edge lengths before scaling by the crowd factor
  Eigen::Matrix3d tilt;  // object axes to yaw-frame axes (a permutation)

  [[nodiscard]] Eigen::Vector3d halfExtents(double scale) const {
    return tilt.cwiseAbs() * (0.5 * scale * size);
  }
};

// The object's edge lengths in its own axes, and the tilt of those axes for
// the given rest (before the yaw about z).
struct Resting {
  Eigen::Vector3d size;
  Eigen::Matrix3d tilt = Eigen::Matrix3d::Identity();
};

Resting restingAs(SynthShape shape, Rest rest, const Eigen::Vector3d& catalogue_size) {
  const double a = catalogue_size.x(), b = catalogue_size.y(), c = catalogue_size.z();
  Resting resting;
  if (shape == SynthShape::Cylinder) {
    resting.size = catalogue_size;
    if (rest == Rest::Lying)  // axis across the bin, along y
      resting.tilt = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    return resting;
  }
  // At yaw 0 the longest horizontal edge runs across the bin, facing the cameras.
  switch (rest) {
    case Rest::Side:
      resting.size = {c, a, b};
      break;
    case Rest::Upright:
      resting.size = {c, b, a};
      break;
    default:
      resting.size = {b, a, c};
      break;
  }
  return resting;
}

double heightOf(const Resting& resting) { return (resting.tilt.cwiseAbs() * resting.size).z(); }

ObjectPlan planObject(int label, Rng& rng) {
  ObjectPlan plan;
  plan.label = label;
  plan.item = synth::catalogueItem(label);
  const Eigen::Vector3d size = rng.uniform(0.92, 1.04) * plan.item.size;
  std::vector<Rest> rests;
  for (const Rest rest : plan.item.rests)
    if (heightOf(restingAs(plan.item.shape, rest, size)) <= kMaxObjectHeight) rests.push_back(rest);
  if (rests.empty()) rests.push_back(plan.item.shape == SynthShape::Box ? Rest::Flat : Rest::Lying);
  const Rest rest = rests[static_cast<size_t>(rng.below(static_cast<int>(rests.size())))];
  const Resting resting = restingAs(plan.item.shape, rest, size);
  plan.size = resting.size;
  plan.tilt = resting.tilt;
  return plan;
}

SynthObject placedObject(const ObjectPlan& plan, const Footprint& footprint, double scale,
                         const LabelSet& labels) {
  SynthObject object;
  object.label = plan.label;
  object.name = labels.at(plan.label).name;
  object.shape = plan.item.shape;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(footprint.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * plan.tilt;
  object.box.rotation = Eigen::Quaterniond(rotation).normalized();
  object.box.size = scale * plan.size;
  object.box.center = {footprint.center.x(), footprint.center.y(), plan.halfExtents(scale).z()};
  return object;
}

// Mostly facing the opening, sometimes turned lengthwise.
double randomYaw(Rng& rng) {
  const double yaw = rng.uniform(-0.35, 0.35);
  return rng.chance(0.2) ? yaw + M_PI / 2 : yaw;
}

// Uniform in [low, high] restricted to [preferred_low, preferred_high] when
// the two ranges overlap.
double uniformPreferring(Rng& rng, double low, double high, double preferred_low,
                         double preferred_high) {
  const double a = std::max(low, preferred_low), b = std::min(high, preferred_high);
  return a <= b ? rng.uniform(a, b) : rng.uniform(low, high);
}

constexpr double kRowSplit = 0.19;  // x of the boundary between the front and back rows

// A random footprint for the i-th object with its centre where the footprint
// stays clear of the walls; nullopt when the drawn yaw does not fit at all.
// In the row phase, the first object stands in the back row toward a side
// wall, the second right in front of it so that the central view sees the
// first one partly hidden; the others alternate between the rows.
std::optional<Footprint> drawFootprint(const Eigen::Vector2d& half, size_t i, bool row_phase,
                                       const std::vector<Footprint>& placed, Rng& rng) {
  Footprint f;
  f.half = half;
  f.yaw = randomYaw(rng);
  const double rx = f.radiusAlong({1, 0}), ry = f.radiusAlong({0, 1});
  const double x_low = kWallClearance + rx, x_high = kBinDepth - kWallClearance - rx;
  const double y_high = 0.5 * kBinWidth - kWallClearance - ry;
  if (x_low > x_high || y_high < 0) return std::nullopt;
  double x = rng.uniform(x_low, x_high), y = rng.uniform(-y_high, y_high);
  if (row_phase) {
    const bool back = i % 2 == 0;
    x = uniformPreferring(rng, x_low, x_high, back ? kRowSplit : 0.0, back ? kBinDepth : kRowSplit);
    if (i == 0) {  // at the back, toward a side: room in front and on the other side
      x = rng.uniform(std::max(x_low, x_high - 0.05), x_high);
      const double side = rng.chance(0.5) ? 1.0 : -1.0;
      y = side * rng.uniform(0.4 * y_high, y_high);
    }
    if (i == 1) {
      const Footprint& behind = placed[0];
      x = behind.center.x() - behind.radiusAlong({1, 0}) - rx - kObjectClearance -
          rng.uniform(0.0, 0.02);
      const double overlap = std::min(behind.radiusAlong({0, 1}), ry);
      y = std::clamp(behind.center.y() + rng.uniform(-0.7, 0.7) * overlap, -y_high, y_high);
      if (x < x_low) return std::nullopt;
    }
  }
  f.center = {x, y};
  return f;
}

// Free floor between the footprint and the nearest wall.
double wallGap(const Footprint& f) {
  const double rx = f.radiusAlong({1, 0}), ry = f.radiusAlong({0, 1});
  return std::min({f.center.x() - rx, kBinDepth - f.center.x() - rx,
                   0.5 * kBinWidth - std::abs(f.center.y()) - ry});
}

// Rejection sampling of footprints. Apart from the occluding pair, each
// object takes the free candidate closest to a wall among a few, which keeps
// the middle of the floor open for the objects still to come. Returns false
// when some object found no free spot at this scale.
bool placeAll(const std::vector<ObjectPlan>& plans, double scale, Rng& rng,
              std::vector<Footprint>& placed) {
  constexpr int kTriesInRow = 150;
  constexpr int kTries = 400;
  constexpr int kCandidates = 6;
  placed.clear();
  for (size_t i = 0; i < plans.size(); ++i) {
    const Eigen::Vector2d half = plans[i].halfExtents(scale).head<2>();
    const int wanted = i < 2 ? 1 : kCandidates;
    std::optional<Footprint> best;
    int found = 0;
    for (int attempt = 0; attempt < kTries && found < wanted; ++attempt) {
      const auto candidate = drawFootprint(half, i, attempt < kTriesInRow, placed, rng);
      if (!candidate || !std::all_of(placed.begin(), placed.end(), [&](const Footprint& other) {
            return separated(*candidate, other, kObjectClearance);
          }))
        continue;
      ++found;
      if (!best || wallGap(*candidate) < wallGap(*best)) best = candidate;
    }
    if (!best) return false;
    placed.push_back(*best);
  }
  return true;
}

std::vector<SynthObject> makeObjects(const SynthOptions& options) {
  Rng rng(synth::streamSeed(options.seed, synth::Stream::Layout));
  std::vector<int> pool;
  for (int label = 1; label <= kSynthMaxObjects; ++label) pool.push_back(label);
  std::vector<ObjectPlan> plans;
  for (int i = 0; i < options.objects; ++i) {
    const int pick = i + rng.below(static_cast<int>(pool.size()) - i);
    std::swap(pool[static_cast<size_t>(i)], pool[static_cast<size_t>(pick)]);
    plans.push_back(planObject(pool[static_cast<size_t>(i)], rng));
  }
  // The tallest object goes behind the second tallest (see placeAll); the
  // others follow largest footprint first, which packs the floor best.
  auto taller = [](const ObjectPlan& a, const ObjectPlan& b) {
    return a.halfExtents(1.0).z() > b.halfExtents(1.0).z();
  };
  auto larger = [](const ObjectPlan& a, const ObjectPlan& b) {
    return a.halfExtents(1.0).head<2>().prod() > b.halfExtents(1.0).head<2>().prod();
  };
  std::stable_sort(plans.begin(), plans.end(), taller);
  if (plans.size() > 2) std::stable_sort(plans.begin() + 2, plans.end(), larger);

  // Crowded bins shrink every object until they all fit side by side.
  std::vector<Footprint> placed;
  double scale = 1.0;
  constexpr int kRestartsPerScale = 8;
  for (int restart = 1; !placeAll(plans, scale, rng, placed); ++restart) {
    if (restart % kRestartsPerScale == 0) scale *= 0.96;
    if (scale < 0.2) throw std::logic_error("synthetic objects do not fit into the bin");
  }
  const LabelSet labels = apc2016Labels();
  std::vector<SynthObject> objects;
  for (size_t i = 0; i < plans.size(); ++i)
    objects.push_back(placedObject(plans[i], placed[i], scale, labels));
  return objects;
}

}  // namespace

void checkSynthOptions(const SynthOptions& o) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument("synthetic scene: " + message);
  };
  require(o.objects >= 1 && o.objects <= kSynthMaxObjects,
          "objects must be 1.." + std::to_string(kSynthMaxObjects) + ", got " +
              std::to_string(o.objects));
  require(o.views >= kSynthMinViews, "views must be at least " + std::to_string(kSynthMinViews) +
                                         ", got " + std::to_string(o.views));
  require(o.frames >= o.views && o.frames <= kSynthMaxFrames,
          "frames must be views.." + std::to_string(kSynthMaxFrames) + ", got " +
              std::to_string(o.frames));
  require(o.width >= kSynthMinWidth && o.width <= kSynthMaxImageSide,
          "width must be " + std::to_string(kSynthMinWidth) + ".." +
              std::to_string(kSynthMaxImageSide) + ", got " + std::to_string(o.width));
  require(o.height >= kSynthMinHeight && o.height <= kSynthMaxImageSide,
          "height must be " + std::to_string(kSynthMinHeight) + ".." +
              std::to_string(kSynthMaxImageSide) + ", got " + std::to_string(o.height));
}

SynthLayout makeSynthLayout(const SynthOptions& options) {
  checkSynthOptions(options);
  SynthLayout layout;
  layout.shelf = shelfBoxes();
  layout.bin_interior =
      axisAlignedBox({0, -0.5 * kBinWidth, 0}, {kBinDepth, 0.5 * kBinWidth, kBinHeight});
  layout.objects = makeObjects(options);
  layout.camera = synth::scaledCamera(options.width, options.height);
  synth::makeCameraPath(options, layout);
  std::vector<int> object_labels;
  for (const auto& object : layout.objects) object_labels.push_back(object.label);
  Rng rng(synth::streamSeed(options.seed, synth::Stream::Segmenter));
  layout.proba_labels = synth::chooseProbaLabels(object_labels, rng);
  return layout;
}

Annotations synthAnnotations(const SynthLayout& layout) {
  Annotations annotations;
  annotations.frame_id = "world";
  for (const auto& object : layout.objects)
    annotations.boxes.push_back({object.label, object.name, object.box});
  return annotations;
}

}  // namespace lom
