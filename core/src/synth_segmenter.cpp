// A simulated per-pixel segmenter: confident inside objects, unsure near
// label boundaries, drawn toward look-alike classes, with occasional false
// positives. Scores are turned into probabilities with a softmax.
#include <algorithm>
#include <cmath>
#include <limits>

#include "synth_internal.hpp"

namespace lom::synth {

namespace {

constexpr int kDistractors = 2;
constexpr double kBoundaryBandAt640 = 4.0;  // pixels of uncertainty at 640 px wide

// Distance from each pixel to the edge of its own label region (0.5 for a
// pixel next to a different label) and the label across that edge. Chamfer
// propagation stays inside a region so the label across is the right one.
void boundaryDistance(const LabelImage& truth, std::vector<float>& distance,
                      std::vector<int>& across) {
  const int w = truth.width, h = truth.height;
  distance.assign(truth.ids.size(), std::numeric_limits<float>::infinity());
  across.assign(truth.ids.size(), -1);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const int label = truth.at(u, v);
      const int nu[] = {u + 1, u - 1, u, u}, nv[] = {v, v, v + 1, v - 1};
      for (int k = 0; k < 4; ++k) {
        if (nu[k] < 0 || nv[k] < 0 || nu[k] >= w || nv[k] >= h) continue;
        if (truth.at(nu[k], nv[k]) == label) continue;
        distance[static_cast<size_t>(v) * w + u] = 0.5f;
        across[static_cast<size_t>(v) * w + u] = truth.at(nu[k], nv[k]);
        break;
      }
    }
  const float diagonal = std::sqrt(2.0f);
  auto relax = [&](int u, int v, int du, int dv, float cost) {
    const int su = u + du, sv = v + dv;
    if (su < 0 || sv < 0 || su >= w || sv >= h || truth.at(su, sv) != truth.at(u, v)) return;
    const size_t i = static_cast<size_t>(v) * w + u, j = static_cast<size_t>(sv) * w + su;
    if (distance[j] + cost < distance[i]) {
      distance[i] = distance[j] + cost;
      across[i] = across[j];
    }
  };
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      relax(u, v, -1, 0, 1.0f), relax(u, v, -1, -1, diagonal);
      relax(u, v, 0, -1, 1.0f), relax(u, v, 1, -1, diagonal);
    }
  for (int v = h - 1; v >= 0; --v)
    for (int u = w - 1; u >= 0; --u) {
      relax(u, v, 1, 0, 1.0f), relax(u, v, 1, 1, diagonal);
      relax(u, v, 0, 1, 1.0f), relax(u, v, -1, 1, diagonal);
    }
}

// How the segmenter treats one class in this frame.
struct ClassBehaviour {
  double confidence = 4.0;  // score of the true class well inside a region
  int look_alike = -1;      // channel of a similar class, -1 if none
  double look_alike_ratio = 0.0;
  double confusion = 0.0;  // > 0: patches where the look-alike wins
};

struct FalsePositive {
  int channel = 0;
  double u = 0, v = 0, radius = 1, score = 0;
};

}  // namespace

SmoothField::SmoothField(int width, int height, double cell_pixels, Rng& rng)
    : grid_width_(static_cast<int>(std::ceil(width / cell_pixels)) + 2),
      grid_height_(static_cast<int>(std::ceil(height / cell_pixels)) + 2),
      inverse_cell_(1.0 / cell_pixels) {
  values_.resize(static_cast<size_t>(grid_width_) * grid_height_);
  for (float& value : values_) value = static_cast<float>(rng.uniform(-1.0, 1.0));
}

float SmoothField::at(int u, int v) const {
  const double gx = u * inverse_cell_, gy = v * inverse_cell_;
  const int x0 = static_cast<int>(gx), y0 = static_cast<int>(gy);
  auto smooth = [](double t) { return static_cast<float>(t * t * (3.0 - 2.0 * t)); };
  const float fx = smooth(gx - x0), fy = smooth(gy - y0);
  auto value = [&](int x, int y) { return values_[static_cast<size_t>(y) * grid_width_ + x]; };
  const float top = value(x0, y0) + fx * (value(x0 + 1, y0) - value(x0, y0));
  const float bottom = value(x0, y0 + 1) + fx * (value(x0 + 1, y0 + 1) - value(x0, y0 + 1));
  return top + fy * (bottom - top);
}

std::vector<int> chooseProbaLabels(const std::vector<int>& object_labels, Rng& rng) {
  std::vector<bool> chosen(kSynthMaxObjects + 1, false);
  chosen[0] = true;
  for (const int label : object_labels) {
    chosen[static_cast<size_t>(label)] = true;
    for (const int similar : lookAlikesOf(label)) chosen[static_cast<size_t>(similar)] = true;
  }
  // Labels that are not in the scene at all, for the false positives.
  for (int added = 0; added < kDistractors;) {
    const int free_labels = static_cast<int>(std::count(chosen.begin(), chosen.end(), false));
    if (free_labels == 0) break;
    int pick = rng.below(free_labels);
    for (size_t label = 0; label < chosen.size(); ++label)
      if (!chosen[label] && pick-- == 0) {
        chosen[label] = true;
        ++added;
        break;
      }
  }
  std::vector<int> labels;
  for (size_t label = 0; label < chosen.size(); ++label)
    if (chosen[label]) labels.push_back(static_cast<int>(label));
  return labels;
}

ProbabilityImage simulateSegmenter(const LabelImage& truth, const std::vector<int>& channel_labels,
                                   bool mistakes, Rng& rng) {
  const int channels = static_cast<int>(channel_labels.size());
  std::vector<int> channel_of(kSynthMaxObjects + 1, -1);
  for (int c = 0; c < channels; ++c) channel_of[static_cast<size_t>(channel_labels[c])] = c;

  std::vector<ClassBehaviour> behaviour(static_cast<size_t>(channels));
  for (int c = 0; c < channels; ++c) {
    ClassBehaviour& b = behaviour[static_cast<size_t>(c)];
    b.confidence = channel_labels[c] == 0 ? rng.uniform(5.0, 6.0) : rng.uniform(4.5, 6.0);
    b.look_alike_ratio = rng.uniform(0.4, 0.65);
    const bool confused = rng.chance(0.5);
    const double confusion = rng.uniform(0.4, 0.8);
    b.confusion = mistakes && confused ? confusion : 0.0;
    if (channel_labels[c] == 0) continue;
    b.look_alike = 0;  // without a similar class, parts of the object fade into the background
    for (const int similar : lookAlikesOf(channel_labels[c]))
      if (channel_of[static_cast<size_t>(similar)] >= 0)
        b.look_alike = channel_of[static_cast<size_t>(similar)];
  }
  const int w = truth.width, h = truth.height;
  const double scale = w / 640.0;
  const SmoothField confidence_field(w, h, 40.0 * scale + 2.0, rng);
  const SmoothField confusion_field(w, h, 56.0 * scale + 2.0, rng);
  std::vector<FalsePositive> false_positives;
  if (mistakes && channels > 1) {
    const int count = rng.below(3);
    for (int k = 0; k < count; ++k) {
      FalsePositive fp;
      fp.channel = 1 + rng.below(channels - 1);
      fp.u = rng.uniform(0, w), fp.v = rng.uniform(0, h);
      fp.radius = rng.uniform(0.015, 0.04) * w + 1.0;
      fp.score = rng.uniform(4.0, 6.5);
      false_positives.push_back(fp);
    }
  }

  std::vector<float> distance;
  std::vector<int> across;
  boundaryDistance(truth, distance, across);
  const double band = std::max(1.5, kBoundaryBandAt640 * scale);

  ProbabilityImage proba;
  proba.width = w, proba.height = h, proba.channels = channels;
  proba.channel_labels = channel_labels;
  proba.values.resize(truth.ids.size() * static_cast<size_t>(channels));
  std::vector<double> score(static_cast<size_t>(channels));
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      std::fill(score.begin(), score.end(), 0.0);
      const int own = channel_of[truth.ids[i]];
      const ClassBehaviour& b = behaviour[static_cast<size_t>(own)];
      const double s =
          b.confidence * (1.0 + 0.15 * confidence_field.at(u, v)) + rng.uniform(-0.3, 0.3);
      const double inside = std::min(1.0, distance[i] / band);  // 0 at an edge, 1 well inside
      score[own] = s * (0.8 + 0.2 * inside);
      if (across[i] >= 0 && inside < 1.0) {
        double& neighbour = score[static_cast<size_t>(channel_of[across[i]])];
        neighbour = std::max(neighbour, s * 0.8 * (1.0 - inside));
      }
      if (b.look_alike >= 0) {
        const double pull =
            b.look_alike_ratio + b.confusion * std::max(0.0f, confusion_field.at(u, v));
        double& similar = score[static_cast<size_t>(b.look_alike)];
        similar = std::max(similar, s * pull);
      }
      for (const auto& fp : false_positives) {
        const double du = (u - fp.u) / fp.radius, dv = (v - fp.v) / fp.radius;
        const double r2 = du * du + dv * dv;
        if (r2 < 1.0)
          score[static_cast<size_t>(fp.channel)] =
              std::max(score[static_cast<size_t>(fp.channel)], fp.score * (1.0 - r2));
      }
      const double top = *std::max_element(score.begin(), score.end());
      double sum = 0.0;
      for (double& x : score) sum += (x = std::exp(x - top));
      float* out = proba.values.data() + i * channels;
      for (int c = 0; c < channels; ++c)  // as stored in the uint8 .npy
        out[c] =
            static_cast<float>(std::round(score[static_cast<size_t>(c)] / sum * 255.0) / 255.0);
    }
  return proba;
}

}  // namespace lom::synth
