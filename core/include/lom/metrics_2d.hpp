#pragma once
// 2D segmentation metrics of the paper (section V.A, after Long et al., FCN):
// pixel accuracy, mean accuracy, mean IU and frequency-weighted IU.
#include <cstdint>
#include <vector>

namespace lom {

struct Metrics2d {
  double pixel_accuracy = 0.0;
  double mean_accuracy = 0.0;
  double mean_iu = 0.0;
  double fw_iu = 0.0;
  std::uint64_t pixels = 0;  // pixels counted (ground truth and prediction both valid labels)
  int classes = 0;           // n_cl: classes present in the ground truth
};

// n_ij = number of pixels of true class i predicted as class j.
class ConfusionMatrix {
 public:
  explicit ConfusionMatrix(int num_labels);
  [[nodiscard]] int numLabels() const { return n_; }
  // Pairs with a label outside 0..n-1 are ignored (unlabelled pixels).
  void add(int truth, int predicted, std::uint64_t count = 1);
  void merge(const ConfusionMatrix& other);
  [[nodiscard]] std::uint64_t at(int truth, int predicted) const;
  [[nodiscard]] std::uint64_t total() const;
  // Averages run over the classes present in the ground truth (t_i > 0); a class
  // that is only predicted lowers the scores of the classes it was mistaken for.
  // All zero when no pixel was counted.
  [[nodiscard]] Metrics2d metrics() const;

 private:
  int n_;
  std::vector<std::uint64_t> counts_;  // row-major n x n
};

}  // namespace lom
