#include "lom/metrics_2d.hpp"

#include <numeric>
#include <stdexcept>
#include <string>

namespace lom {

ConfusionMatrix::ConfusionMatrix(int num_labels) : n_(num_labels) {
  if (num_labels <= 0)
    throw std::invalid_argument("ConfusionMatrix needs at least one label, got " +
                                std::to_string(num_labels));
  counts_.assign(static_cast<size_t>(n_) * static_cast<size_t>(n_), 0);
}

void ConfusionMatrix::add(int truth, int predicted, std::uint64_t count) {
  if (truth < 0 || truth >= n_ || predicted < 0 || predicted >= n_) return;
  counts_[static_cast<size_t>(truth) * static_cast<size_t>(n_) + static_cast<size_t>(predicted)] += count;
}

void ConfusionMatrix::merge(const ConfusionMatrix& other) {
  if (other.n_ != n_)
    throw std::invalid_argument("ConfusionMatrix::merge: " + std::to_string(other.n_) +
                                " labels, expected " + std::to_string(n_));
  for (size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i];
}

std::uint64_t ConfusionMatrix::at(int truth, int predicted) const {
  return counts_.at(static_cast<size_t>(truth) * static_cast<size_t>(n_) + static_cast<size_t>(predicted));
}

std::uint64_t ConfusionMatrix::total() const {
  return std::accumulate(counts_.begin(), counts_.end(), std::uint64_t{0});
}

Metrics2d ConfusionMatrix::metrics() const {
  Metrics2d m;
  std::vector<double> t(static_cast<size_t>(n_), 0.0);          // t_i = sum_j n_ij
  std::vector<double> predicted(static_cast<size_t>(n_), 0.0);  // sum_j n_ji
  double correct = 0.0;
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) {
      const double n_ij = static_cast<double>(at(i, j));
      t[static_cast<size_t>(i)] += n_ij;
      predicted[static_cast<size_t>(j)] += n_ij;
      if (i == j) correct += n_ij;
    }
  const double all = std::accumulate(t.begin(), t.end(), 0.0);
  m.pixels = total();
  if (!(all > 0.0)) return m;

  double accuracy_sum = 0.0, iu_sum = 0.0, weighted_iu_sum = 0.0;
  for (int i = 0; i < n_; ++i) {
    const double t_i = t[static_cast<size_t>(i)];
    if (!(t_i > 0.0)) continue;
    const double n_ii = static_cast<double>(at(i, i));
    const double iu = n_ii / (t_i + predicted[static_cast<size_t>(i)] - n_ii);
    ++m.classes;
    accuracy_sum += n_ii / t_i;
    iu_sum += iu;
    weighted_iu_sum += t_i * iu;
  }
  m.pixel_accuracy = correct / all;
  m.mean_accuracy = accuracy_sum / m.classes;
  m.mean_iu = iu_sum / m.classes;
  m.fw_iu = weighted_iu_sum / all;
  return m;
}

}  // namespace lom
