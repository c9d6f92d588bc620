#include "lom/octree/label_octree.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <istream>
#include <ostream>

namespace lom {

float logit(double p) { return static_cast<float>(std::log(p / (1.0 - p))); }

double probabilityFromLogOdds(double log_odds) { return 1.0 - 1.0 / (1.0 + std::exp(log_odds)); }

// ---------------------------------------------------------------------------
// LabelOcTreeNode

namespace {

std::uint32_t storedCount(const float* labels) {
  std::uint32_t count;
  std::memcpy(&count, labels, sizeof(count));
  return count;
}

float* allocateLabels(std::uint32_t count) {
  auto* labels = new float[count + 1];
  std::memcpy(labels, &count, sizeof(count));
  return labels;
}

}  // namespace

LabelOcTreeNode::LabelOcTreeNode(const LabelOcTreeNode& rhs) : octomap::OcTreeNode() {
  copyData(rhs);
}

LabelOcTreeNode::~LabelOcTreeNode() { releaseLabels(); }

void LabelOcTreeNode::releaseLabels() {
  delete[] labels_;
  labels_ = nullptr;
}

bool LabelOcTreeNode::operator==(const LabelOcTreeNode& rhs) const {
  if (value != rhs.value || isUniform() != rhs.isUniform()) return false;
  if (isUniform()) return true;
  const std::uint32_t count = storedCount(labels_);
  return count == storedCount(rhs.labels_) &&
         std::memcmp(labels_ + 1, rhs.labels_ + 1, count * sizeof(float)) == 0;
}

void LabelOcTreeNode::copyData(const LabelOcTreeNode& from) {
  if (this == &from) return;
  value = from.value;
  if (from.isUniform()) {
    releaseLabels();
    return;
  }
  const std::uint32_t count = storedCount(from.labels_);
  if (!labels_ || storedCount(labels_) != count) {
    releaseLabels();
    labels_ = allocateLabels(count);
  }
  std::memcpy(labels_ + 1, from.labels_ + 1, count * sizeof(float));
}

void LabelOcTreeNode::labelLogOdds(int num_labels, float* out) const {
  if (isUniform()) {
    std::fill(out, out + num_labels, value);
  } else {
    std::memcpy(out, labels_ + 1, static_cast<size_t>(num_labels) * sizeof(float));
  }
}

int LabelOcTreeNode::argmaxLabel(int num_labels) const {
  if (isUniform()) return 0;
  const float* values = labels_ + 1;
  int best = 0;
  for (int k = 1; k < num_labels; ++k)
    if (values[k] > values[best]) best = k;
  return best;
}

float* LabelOcTreeNode::ensureLabels(int num_labels) {
  if (!labels_) {
    labels_ = allocateLabels(static_cast<std::uint32_t>(num_labels));
    std::fill(labels_ + 1, labels_ + 1 + num_labels, value);
  }
  return labels_ + 1;
}

void LabelOcTreeNode::canonicalise(int num_labels) {
  if (!labels_) return;
  const float* values = labels_ + 1;
  float max_value = values[0];
  bool all_equal = true;
  for (int k = 1; k < num_labels; ++k) {
    if (values[k] != values[0]) all_equal = false;
    max_value = std::max(max_value, values[k]);
  }
  value = max_value;
  if (all_equal) releaseLabels();
}

void LabelOcTreeNode::setLabelLogOdds(int num_labels, const float* values) {
  std::memcpy(ensureLabels(num_labels), values, static_cast<size_t>(num_labels) * sizeof(float));
  canonicalise(num_labels);
}

void LabelOcTreeNode::setUniformLogOdds(float log_odds) {
  releaseLabels();
  value = log_odds;
}

void LabelOcTreeNode::addLabelLogOdds(int num_labels, const float* update, float lo, float hi) {
  float* values = ensureLabels(num_labels);
  for (int k = 0; k < num_labels; ++k) values[k] = std::clamp(values[k] + update[k], lo, hi);
  canonicalise(num_labels);
}

void LabelOcTreeNode::addUniformLogOdds(float update, float lo, float hi) {
  if (isUniform()) {
    value = std::clamp(value + update, lo, hi);
    return;
  }
  const int num_labels = static_cast<int>(storedCount(labels_));
  float* values = labels_ + 1;
  for (int k = 0; k < num_labels; ++k) values[k] = std::clamp(values[k] + update, lo, hi);
  canonicalise(num_labels);
}

void LabelOcTreeNode::updateOccupancyChildren() {
  // Children are reached through OctoMap's untyped child array; all are LabelOcTreeNodes.
  const LabelOcTreeNode* explicit_child = nullptr;
  float uniform_max = -std::numeric_limits<float>::infinity();
  bool any_child = false;
  for (unsigned i = 0; i < 8; ++i) {
    if (!children || !children[i]) continue;
    const auto* child = static_cast<const LabelOcTreeNode*>(children[i]);
    any_child = true;
    if (child->isUniform())
      uniform_max = std::max(uniform_max, child->value);
    else if (!explicit_child)
      explicit_child = child;
  }
  if (!any_child) return;
  if (!explicit_child) {
    setUniformLogOdds(uniform_max);
    return;
  }
  const int num_labels = static_cast<int>(storedCount(explicit_child->labels_));
  float* values = ensureLabels(num_labels);
  std::fill(values, values + num_labels, uniform_max);
  for (unsigned i = 0; i < 8; ++i) {
    if (!children[i]) continue;
    const auto* child = static_cast<const LabelOcTreeNode*>(children[i]);
    if (child->isUniform()) continue;
    const float* child_values = child->labels_ + 1;
    for (int k = 0; k < num_labels; ++k) values[k] = std::max(values[k], child_values[k]);
  }
  canonicalise(num_labels);
}

std::istream& LabelOcTreeNode::readData(std::istream& s) {
  std::uint8_t has_labels = 0;
  s.read(reinterpret_cast<char*>(&value), sizeof(value));
  s.read(reinterpret_cast<char*>(&has_labels), sizeof(has_labels));
  releaseLabels();
  if (!s) return s;
  if (has_labels > 1) {
    s.setstate(std::ios::failbit);
    return s;
  }
  if (has_labels) {
    std::uint16_t count = 0;
    s.read(reinterpret_cast<char*>(&count), sizeof(count));
    if (!s || count == 0) {
      s.setstate(std::ios::failbit);
      return s;
    }
    labels_ = allocateLabels(count);
    s.read(reinterpret_cast<char*>(labels_ + 1), static_cast<std::streamsize>(count * sizeof(float)));
  }
  return s;
}

std::ostream& LabelOcTreeNode::writeData(std::ostream& s) const {
  const std::uint8_t has_labels = isUniform() ? 0 : 1;
  s.write(reinterpret_cast<const char*>(&value), sizeof(value));
  s.write(reinterpret_cast<const char*>(&has_labels), sizeof(has_labels));
  if (has_labels) {
    const auto count = static_cast<std::uint16_t>(storedCount(labels_));
    s.write(reinterpret_cast<const char*>(&count), sizeof(count));
    s.write(reinterpret_cast<const char*>(labels_ + 1),
            static_cast<std::streamsize>(count * sizeof(float)));
  }
  return s;
}

size_t LabelOcTreeNode::labelBytes() const {
  return labels_ ? (storedCount(labels_) + 1) * sizeof(float) : 0;
}

// ---------------------------------------------------------------------------
// LabelOcTree

LabelOcTree::StaticMemberInitializer LabelOcTree::label_octree_member_init_;

LabelOcTree::StaticMemberInitializer::StaticMemberInitializer() {
  auto* prototype = new LabelOcTree(0.1);
  prototype->clearKeyRays();
  AbstractOcTree::registerTreeType(prototype);
}

LabelOcTree::LabelOcTree(double resolution)
    : LabelOcTree(LabelSet({LabelInfo{0, "__background__", {0, 0, 0}}}), [&] {
        MapParameters p;
        p.resolution = resolution;
        return p;
      }()) {}

LabelOcTree::LabelOcTree(const LabelSet& labels, const MapParameters& parameters)
    : octomap::OccupancyOcTreeBase<LabelOcTreeNode>(parameters.resolution),
      labels_(labels),
      parameters_(parameters) {
  applyParameters();
  label_octree_member_init_.ensureLinking();
}

LabelOcTree* LabelOcTree::create() const { return new LabelOcTree(labels_, parameters_); }

void LabelOcTree::applyParameters() {
  // OctoMap's own members mirror the parameters so that its API (isNodeOccupied,
  // clamping, iterators) agrees with the paper's rule.
  setResolution(parameters_.resolution);
  setProbMiss(parameters_.p_miss);
  setOccupancyThres(parameters_.occupancy_threshold);
  setClampingThresMin(parameters_.clamp_min);
  setClampingThresMax(parameters_.clamp_max);
}

void LabelOcTree::setOccupancyThreshold(double threshold) {
  parameters_.occupancy_threshold = threshold;
  setOccupancyThres(threshold);
}

void LabelOcTree::setIntegrationParameters(double p_miss, double max_range) {
  parameters_.p_miss = p_miss;
  parameters_.max_range = max_range;
  setProbMiss(p_miss);
}

LabelOcTreeNode* LabelOcTree::touchLeaf(const octomap::OcTreeKey& key) {
  bool created = false;
  if (!root) {
    root = new LabelOcTreeNode();
    ++tree_size;
    created = true;
  }
  LabelOcTreeNode* node = root;
  for (int depth = 0; depth < static_cast<int>(tree_depth); ++depth) {
    const unsigned pos = octomap::computeChildIdx(key, static_cast<int>(tree_depth) - 1 - depth);
    if (!nodeChildExists(node, pos)) {
      if (!nodeHasChildren(node) && !created) {
        // A pruned leaf: its eight children inherit its data.
        expandNode(node);
      } else {
        createNodeChild(node, pos);
        created = true;
      }
    } else {
      created = false;
    }
    node = getNodeChild(node, pos);
  }
  return node;
}

void LabelOcTree::applyHit(const octomap::OcTreeKey& key, const float* log_odds) {
  touchLeaf(key)->addLabelLogOdds(numLabels(), log_odds, clamping_thres_min, clamping_thres_max);
}

void LabelOcTree::applyMiss(const octomap::OcTreeKey& key) {
  touchLeaf(key)->addUniformLogOdds(prob_miss_log, clamping_thres_min, clamping_thres_max);
}

void LabelOcTree::refreshAncestors(std::vector<octomap::OcTreeKey> keys) {
  if (!root) return;
  auto packed = [](const octomap::OcTreeKey& k) {
    return (static_cast<std::uint64_t>(k[0]) << 32) | (static_cast<std::uint64_t>(k[1]) << 16) |
           k[2];
  };
  for (int depth = static_cast<int>(tree_depth) - 1; depth >= 0; --depth) {
    // Keys of the ancestors at `depth`: drop the lower bits below that depth.
    const int shift = static_cast<int>(tree_depth) - depth;
    for (auto& key : keys)
      for (int i = 0; i < 3; ++i)
        key[i] = static_cast<octomap::key_type>((key[i] >> shift) << shift);
    std::sort(keys.begin(), keys.end(),
              [&](const auto& a, const auto& b) { return packed(a) < packed(b); });
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (const auto& key : keys) {
      LabelOcTreeNode* node = root;
      for (int d = 0; d < depth && node; ++d) {
        const unsigned pos = octomap::computeChildIdx(key, static_cast<int>(tree_depth) - 1 - d);
        node = nodeChildExists(node, pos) ? getNodeChild(node, pos) : nullptr;
      }
      if (!node || !nodeHasChildren(node)) continue;
      if (!pruneNode(node)) node->updateOccupancyChildren();
    }
    // The next level only needs the keys as they are (already truncated further up).
  }
}

size_t LabelOcTree::labelArrayBytes() const {
  size_t bytes = 0;
  for (auto it = begin_tree(), end = end_tree(); it != end; ++it) bytes += it->labelBytes();
  return bytes;
}

namespace {

constexpr char kMagic[4] = {'L', 'O', 'M', 'T'};
constexpr std::uint32_t kFileVersion = 1;

template <typename T>
void writePod(std::ostream& s, const T& v) {
  s.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
bool readPod(std::istream& s, T& v) {
  s.read(reinterpret_cast<char*>(&v), sizeof(T));
  return static_cast<bool>(s);
}

}  // namespace

std::ostream& LabelOcTree::writeData(std::ostream& s) const {
  s.write(kMagic, sizeof(kMagic));
  writePod(s, kFileVersion);
  writePod(s, static_cast<std::uint16_t>(numLabels()));
  for (const auto& label : labels_.all()) {
    writePod(s, static_cast<std::uint16_t>(label.name.size()));
    s.write(label.name.data(), static_cast<std::streamsize>(label.name.size()));
    s.write(reinterpret_cast<const char*>(label.color.data()), 3);
  }
  writePod(s, parameters_.p_miss);
  writePod(s, parameters_.occupancy_threshold);
  writePod(s, parameters_.clamp_min);
  writePod(s, parameters_.clamp_max);
  writePod(s, parameters_.max_range);
  // OctoMap's node stream cannot express an empty tree, so say whether one follows.
  writePod(s, static_cast<std::uint8_t>(root != nullptr));
  return octomap::OccupancyOcTreeBase<LabelOcTreeNode>::writeData(s);
}

std::istream& LabelOcTree::readData(std::istream& s) {
  char magic[4] = {};
  std::uint32_t version = 0;
  std::uint16_t count = 0;
  s.read(magic, sizeof(magic));
  if (!s || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0 || !readPod(s, version) ||
      version != kFileVersion || !readPod(s, count) || count == 0) {
    s.setstate(std::ios::failbit);
    return s;
  }
  std::vector<LabelInfo> labels;
  for (std::uint16_t id = 0; id < count; ++id) {
    std::uint16_t length = 0;
    if (!readPod(s, length)) return s;
    LabelInfo label;
    label.id = id;
    label.name.resize(length);
    s.read(label.name.data(), length);
    s.read(reinterpret_cast<char*>(label.color.data()), 3);
    if (!s) return s;
    labels.push_back(std::move(label));
  }
  MapParameters parameters;
  parameters.resolution = getResolution();
  if (!readPod(s, parameters.p_miss) || !readPod(s, parameters.occupancy_threshold) ||
      !readPod(s, parameters.clamp_min) || !readPod(s, parameters.clamp_max) ||
      !readPod(s, parameters.max_range))
    return s;
  std::uint8_t has_nodes = 0;
  if (!readPod(s, has_nodes) || has_nodes > 1) {
    s.setstate(std::ios::failbit);
    return s;
  }
  labels_ = LabelSet(std::move(labels));
  parameters_ = parameters;
  applyParameters();
  if (!has_nodes) return s;
  octomap::OccupancyOcTreeBase<LabelOcTreeNode>::readData(s);
  if (!s) return s;
  // Every explicit label array must have the tree's label count.
  for (auto it = begin_tree(), end = end_tree(); it != end; ++it) {
    if (!it->isUniform() && it->labelBytes() != (static_cast<size_t>(count) + 1) * sizeof(float)) {
      s.setstate(std::ios::failbit);
      break;
    }
  }
  return s;
}

}  // namespace lom
