#include "lom/octree/label_octree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <istream>
#include <ostream>
#include <string>

#include "lom/error.hpp"

namespace lom {

float logit(double p) { return static_cast<float>(std::log(p / (1.0 - p))); }

double probabilityFromLogOdds(double log_odds) { return 1.0 - 1.0 / (1.0 + std::exp(log_odds)); }

// ---------------------------------------------------------------------------
// LabelOcTreeNode

// Header of a leaf's label block; followed by `count` label ids (uint8,
// padded to 4 bytes) and their `count` values. Labels not listed have `base`.
struct LabelOcTreeNode::SparseLabels {
  std::uint16_t num_labels;
  std::uint16_t count;
  float base;

  static size_t bytesFor(unsigned count) { return sizeof(SparseLabels) + ((count + 3u) & ~3u) + 4u * count; }
  [[nodiscard]] size_t bytes() const { return bytesFor(count); }
  std::uint8_t* ids() { return reinterpret_cast<std::uint8_t*>(this + 1); }
  [[nodiscard]] const std::uint8_t* ids() const { return reinterpret_cast<const std::uint8_t*>(this + 1); }
  float* values() { return reinterpret_cast<float*>(ids() + ((count + 3u) & ~3u)); }
  [[nodiscard]] const float* values() const {
    return reinterpret_cast<const float*>(ids() + ((count + 3u) & ~3u));
  }

  static SparseLabels* allocate(unsigned num_labels, unsigned count) {
    void* memory = ::operator new(bytesFor(count));
    std::memset(memory, 0, bytesFor(count));  // padding too: blocks are compared bytewise
    auto* block = static_cast<SparseLabels*>(memory);
    block->num_labels = static_cast<std::uint16_t>(num_labels);
    block->count = static_cast<std::uint16_t>(count);
    return block;
  }
  void decode(float* out) const {
    std::fill(out, out + num_labels, base);
    for (unsigned i = 0; i < count; ++i) out[ids()[i]] = values()[i];
  }
};

namespace {

constexpr int kMaxLabels = 256;

// Label ids 0, 1, ..., 255: a dense label vector as a list of every label.
constexpr std::array<std::uint8_t, kMaxLabels> kEveryLabel = [] {
  std::array<std::uint8_t, kMaxLabels> ids{};
  for (int k = 0; k < kMaxLabels; ++k) ids[static_cast<size_t>(k)] = static_cast<std::uint8_t>(k);
  return ids;
}();

}  // namespace

void LabelOcTreeNode::release() {
  if (const SparseLabels* b = block()) ::operator delete(const_cast<SparseLabels*>(b));
  data_ = 0;
}

LabelOcTreeNode::LabelOcTreeNode(const LabelOcTreeNode& rhs) : octomap::OcTreeNode() {
  copyData(rhs);
}

LabelOcTreeNode::~LabelOcTreeNode() { release(); }

LabelOcTreeNode* LabelOcTreeNode::addChild(unsigned pos) {
  if (!children) {
    children = new octomap::AbstractOcTreeNode*[8];
    for (unsigned i = 0; i < 8; ++i) children[i] = nullptr;
  }
  auto* child = new LabelOcTreeNode();
  children[pos] = child;
  return child;
}

void LabelOcTreeNode::expandChildren() {
  for (unsigned i = 0; i < 8; ++i) addChild(i)->copyData(*this);
}

void LabelOcTreeNode::collapseChildren() {
  copyData(*static_cast<const LabelOcTreeNode*>(children[0]));
  for (unsigned i = 0; i < 8; ++i) {
    delete static_cast<LabelOcTreeNode*>(children[i]);
    children[i] = nullptr;
  }
  delete[] children;
  children = nullptr;
}

bool LabelOcTreeNode::operator==(const LabelOcTreeNode& rhs) const {
  if (value != rhs.value) return false;
  const SparseLabels* a = block();
  const SparseLabels* b = rhs.block();
  if (!a || !b) return a == b && data_ == rhs.data_;
  return a->bytes() == b->bytes() && std::memcmp(a, b, a->bytes()) == 0;
}

void LabelOcTreeNode::copyData(const LabelOcTreeNode& from) {
  if (this == &from) return;
  release();
  value = from.value;
  if (const SparseLabels* b = from.block()) {
    void* copy = ::operator new(b->bytes());
    std::memcpy(copy, b, b->bytes());
    data_ = reinterpret_cast<std::uintptr_t>(copy);
  } else {
    data_ = from.data_;
  }
}

float LabelOcTreeNode::labelLogOdds(int k) const {
  const SparseLabels* b = block();
  if (!b) return value;
  for (unsigned i = 0; i < b->count; ++i)
    if (b->ids()[i] == k) return b->values()[i];
  return b->base;
}

void LabelOcTreeNode::labelLogOdds(int num_labels, float* out) const {
  if (const SparseLabels* b = block())
    b->decode(out);
  else
    std::fill(out, out + num_labels, value);
}

int LabelOcTreeNode::argmaxLabel(int /*num_labels*/) const {
  if (isSummary()) return static_cast<int>(data_ >> 1);
  const SparseLabels* b = block();
  if (!b) return 0;
  // Listed labels are above the base, so the maximum is among them.
  int best = b->ids()[0];
  float best_value = b->values()[0];
  for (unsigned i = 1; i < b->count; ++i) {
    const float v = b->values()[i];
    const int id = b->ids()[i];
    if (v > best_value || (v == best_value && id < best)) {
      best = id;
      best_value = v;
    }
  }
  return best;
}

void LabelOcTreeNode::setLabelLogOdds(int num_labels, const float* values) {
  float low = values[0], high = values[0];
  for (int k = 1; k < num_labels; ++k) {
    low = std::min(low, values[k]);
    high = std::max(high, values[k]);
  }
  storeLabels(num_labels, low, high, kEveryLabel.data(), values, static_cast<unsigned>(num_labels));
}

void LabelOcTreeNode::storeLabels(int num_labels, float low, float high, const std::uint8_t* ids,
                                  const float* values, unsigned count) {
  value = high;
  if (low == high) {
    release();
    return;
  }
  unsigned above = 0;
  for (unsigned i = 0; i < count; ++i) above += values[i] > low ? 1u : 0u;
  // Re-hit voxels usually keep the same labels above the base: reuse the block.
  SparseLabels* b = const_cast<SparseLabels*>(block());
  if (!b || b->count != above || b->num_labels != num_labels) {
    release();
    b = SparseLabels::allocate(static_cast<unsigned>(num_labels), above);
    data_ = reinterpret_cast<std::uintptr_t>(b);
  }
  b->base = low;
  unsigned j = 0;
  for (unsigned i = 0; i < count; ++i) {
    if (values[i] <= low) continue;
    b->ids()[j] = ids[i];
    b->values()[j] = values[i];
    ++j;
  }
}

void LabelOcTreeNode::setUniformLogOdds(float log_odds) {
  release();
  value = log_odds;
}

void LabelOcTreeNode::addLabelLogOdds(int num_labels, const float* update, float lo, float hi) {
  float values[kMaxLabels];
  labelLogOdds(num_labels, values);
  for (int k = 0; k < num_labels; ++k) values[k] = std::clamp(values[k] + update[k], lo, hi);
  setLabelLogOdds(num_labels, values);
}

void LabelOcTreeNode::addListedLogOdds(int num_labels, int count, const std::uint8_t* ids, const float* values,
                                       float rest, float lo, float hi) {
  // The labels listed by the update or by the block, ascending, with their
  // new values; every label in neither list had the block's base (or the
  // uniform value) and gets `rest`.
  const SparseLabels* b = block();
  const float old_other = b ? b->base : value;
  const unsigned block_count = b ? b->count : 0u;
  const std::uint8_t* block_ids = b ? b->ids() : nullptr;
  const float* block_values = b ? b->values() : nullptr;
  std::uint8_t merged_ids[kMaxLabels];
  float merged[kMaxLabels];
  unsigned m = 0, i = 0, j = 0;
  const unsigned listed = static_cast<unsigned>(count);
  while (i < listed || j < block_count) {
    const int a = i < listed ? ids[i] : kMaxLabels, c = j < block_count ? block_ids[j] : kMaxLabels;
    float sum;
    if (a < c) {
      sum = old_other + values[i++];
    } else if (c < a) {
      sum = block_values[j++] + rest;
    } else {
      sum = block_values[j++] + values[i++];
    }
    merged_ids[m] = static_cast<std::uint8_t>(std::min(a, c));
    merged[m++] = std::clamp(sum, lo, hi);
  }
  const bool others = m < static_cast<unsigned>(num_labels);
  const float other = std::clamp(old_other + rest, lo, hi);
  float low = others ? other : merged[0], high = low;
  for (unsigned k = 0; k < m; ++k) {
    low = std::min(low, merged[k]);
    high = std::max(high, merged[k]);
  }
  if (others && other > low) {
    // The other labels are not the smallest: write the update out.
    float update[kMaxLabels];
    std::fill(update, update + num_labels, rest);
    for (unsigned k = 0; k < listed; ++k) update[ids[k]] = values[k];
    addLabelLogOdds(num_labels, update, lo, hi);
    return;
  }
  storeLabels(num_labels, low, high, merged_ids, merged, m);
}

void LabelOcTreeNode::addUniformLogOdds(float update, float lo, float hi) {
  SparseLabels* b = const_cast<SparseLabels*>(block());
  if (!b) {
    value = std::clamp(value + update, lo, hi);
    return;
  }
  float values[kMaxLabels];
  b->decode(values);
  const int num_labels = b->num_labels;
  for (int k = 0; k < num_labels; ++k) values[k] = std::clamp(values[k] + update, lo, hi);
  setLabelLogOdds(num_labels, values);
}

void LabelOcTreeNode::updateOccupancyChildren() {
  bool any_child = false;
  float best_value = 0.f;
  int best_label = 0;
  for (unsigned i = 0; i < 8; ++i) {
    if (!children || !children[i]) continue;
    const auto* child = static_cast<const LabelOcTreeNode*>(children[i]);
    // A child's label is read only when its value can win (a sparse leaf's
    // label is a scan of its block).
    if (!any_child || child->value > best_value) {
      best_value = child->value;
      best_label = child->argmaxLabel(0);
    } else if (child->value == best_value) {
      best_label = std::min(best_label, child->argmaxLabel(0));
    }
    any_child = true;
  }
  if (!any_child) return;
  release();
  value = best_value;
  data_ = (static_cast<std::uintptr_t>(best_label) << 1) | 1u;
}

namespace {
enum NodeKind : std::uint8_t { kUniformLeaf = 0, kSparseLeaf = 1, kSummary = 2 };
}

std::istream& LabelOcTreeNode::readData(std::istream& s) {
  std::uint8_t kind = 0;
  s.read(reinterpret_cast<char*>(&value), sizeof(value));
  s.read(reinterpret_cast<char*>(&kind), sizeof(kind));
  release();
  if (!s) return s;
  if (kind == kUniformLeaf) return s;
  if (kind == kSummary) {
    std::uint16_t label = 0;
    s.read(reinterpret_cast<char*>(&label), sizeof(label));
    data_ = (static_cast<std::uintptr_t>(label) << 1) | 1u;
    return s;
  }
  std::uint16_t header[2] = {0, 0};  // num_labels, count
  float base = 0.f;
  s.read(reinterpret_cast<char*>(header), sizeof(header));
  s.read(reinterpret_cast<char*>(&base), sizeof(base));
  if (kind != kSparseLeaf || !s || header[0] == 0 || header[0] > kMaxLabels || header[1] == 0 ||
      header[1] > header[0]) {
    s.setstate(std::ios::failbit);
    return s;
  }
  SparseLabels* b = SparseLabels::allocate(header[0], header[1]);
  data_ = reinterpret_cast<std::uintptr_t>(b);
  b->base = base;
  s.read(reinterpret_cast<char*>(b->ids()), header[1]);
  s.read(reinterpret_cast<char*>(b->values()), static_cast<std::streamsize>(4u * header[1]));
  for (unsigned i = 0; s && i < b->count; ++i)
    if (b->ids()[i] >= b->num_labels) s.setstate(std::ios::failbit);
  return s;
}

std::ostream& LabelOcTreeNode::writeData(std::ostream& s) const {
  s.write(reinterpret_cast<const char*>(&value), sizeof(value));
  const SparseLabels* b = block();
  const std::uint8_t kind = b ? kSparseLeaf : (isSummary() ? kSummary : kUniformLeaf);
  s.write(reinterpret_cast<const char*>(&kind), sizeof(kind));
  if (kind == kSummary) {
    const auto label = static_cast<std::uint16_t>(data_ >> 1);
    s.write(reinterpret_cast<const char*>(&label), sizeof(label));
  } else if (b) {
    const std::uint16_t header[2] = {b->num_labels, b->count};
    s.write(reinterpret_cast<const char*>(header), sizeof(header));
    s.write(reinterpret_cast<const char*>(&b->base), sizeof(b->base));
    s.write(reinterpret_cast<const char*>(b->ids()), b->count);
    s.write(reinterpret_cast<const char*>(b->values()), static_cast<std::streamsize>(4u * b->count));
  }
  return s;
}

size_t LabelOcTreeNode::labelBytes() const {
  const SparseLabels* b = block();
  return b ? b->bytes() : 0;
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
  applyOccupancyThreshold();
  setClampingThresMin(parameters_.clamp_min);
  setClampingThresMax(parameters_.clamp_max);
}

void LabelOcTree::applyOccupancyThreshold() {
  // Occupied when max_k p_k >= threshold, p and threshold equal within
  // kOccupancyThresholdTolerance: the log-odds are floats, so a voxel seen
  // once with p = 0.9 holds logit(0.9) rounded down to a float, and fell short
  // of a threshold of 0.9 rounded the other way.
  setOccupancyThres(parameters_.occupancy_threshold);
  const double lowered =
      std::max(parameters_.occupancy_threshold - kOccupancyThresholdTolerance, 1e-12);
  occ_prob_thres_log = static_cast<float>(std::log(lowered / (1.0 - lowered)));
}

void LabelOcTree::setOccupancyThreshold(double threshold) {
  parameters_.occupancy_threshold = threshold;
  applyOccupancyThreshold();
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
  for (int depth = 0; depth < static_cast<int>(tree_depth); ++depth)
    node = childForUpdate(node, octomap::computeChildIdx(key, static_cast<int>(tree_depth) - 1 - depth),
                          created);
  return node;
}

void LabelOcTree::finishNode(LabelOcTreeNode* node, long& node_delta) const {
  if (nodeHasChildren(node) && !pruneSaturated(node, node_delta)) node->updateOccupancyChildren();
}

void LabelOcTree::addToNodeCount(long node_delta) {
  if (node_delta == 0) return;
  tree_size = static_cast<size_t>(static_cast<long>(tree_size) + node_delta);
  size_changed = true;
}

bool LabelOcTree::pruneSaturated(LabelOcTreeNode* node, long& node_delta) const {
  // The cheap test first: most finished nodes hold no saturated free space.
  if (!nodeChildExists(node, 0) || !isSaturatedFree(getNodeChild(node, 0), false)) return false;
  if (!isNodeCollapsible(node)) return false;
  node->collapseChildren();
  node_delta -= 8;
  return true;
}

LabelOcTreeNode* LabelOcTree::missingChildForUpdate(LabelOcTreeNode* node, unsigned pos,
                                                    bool& created, long& node_delta) const {
  if (!nodeHasChildren(node) && !created) {
    // A childless node that is not new is a pruned leaf: its children inherit its data.
    node->expandChildren();
    node_delta += 8;
    return getNodeChild(node, pos);
  }
  created = true;
  ++node_delta;
  return node->addChild(pos);
}

LabelOcTreeNode* LabelOcTree::childForUpdate(LabelOcTreeNode* node, unsigned pos, bool& created) {
  long node_delta = 0;
  LabelOcTreeNode* child = childForUpdate(node, pos, created, node_delta);
  addToNodeCount(node_delta);
  return child;
}

void LabelOcTree::applyHit(const octomap::OcTreeKey& key, const float* log_odds) {
  touchLeaf(key)->addLabelLogOdds(numLabels(), log_odds, clamping_thres_min, clamping_thres_max);
}

void LabelOcTree::applyMiss(const octomap::OcTreeKey& key) {
  // A miss cannot lower a voxel that is already at the lower clamp: leave such
  // (often pruned) free space as it is instead of expanding it.
  if (root) {
    const LabelOcTreeNode* node = root;
    for (int depth = 0; depth <= static_cast<int>(tree_depth); ++depth) {
      if (isSaturatedFree(node, false)) return;
      if (depth == static_cast<int>(tree_depth)) break;
      const unsigned pos = octomap::computeChildIdx(key, static_cast<int>(tree_depth) - 1 - depth);
      if (!nodeChildExists(node, pos)) break;
      node = getNodeChild(node, pos);
    }
  }
  touchLeaf(key)->addUniformLogOdds(prob_miss_log, clamping_thres_min, clamping_thres_max);
}

void LabelOcTree::refreshAncestors(std::vector<octomap::OcTreeKey> keys) {
  if (!root) return;
  long node_delta = 0;
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
      if (node) finishNode(node, node_delta);
    }
    // The next level only needs the keys as they are (already truncated further up).
  }
  addToNodeCount(node_delta);
}

size_t LabelOcTree::labelArrayBytes() const {
  size_t bytes = 0;
  for (auto it = begin_tree(), end = end_tree(); it != end; ++it) bytes += it->labelBytes();
  return bytes;
}

namespace {

constexpr char kMagic[4] = {'L', 'O', 'M', 'T'};
// 1: labels, parameters, nodes. 2: and the camera view record after the
// parameters. 3: and the fused candidates after the camera views. 4: and
// where the probabilities came from. 5: and the fused poses' world frame.
constexpr std::uint32_t kFileVersion = 5;

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
  for (const double component : camera_views_.up_sum) writePod(s, component);
  for (const double component : camera_views_.forward_sum) writePod(s, component);
  writePod(s, camera_views_.views);
  // Candidates: 0 (every label), 1 and the listed label ids, or 2 (not
  // known: a map read from a file of version 1 or 2).
  const auto& candidates = fused_candidates_.labels;
  writePod(s, static_cast<std::uint8_t>(!fused_candidates_.recorded ? 2 : candidates ? 1 : 0));
  if (fused_candidates_.recorded && candidates) {
    writePod(s, static_cast<std::uint16_t>(candidates->size()));
    for (const int id : *candidates) writePod(s, static_cast<std::uint16_t>(id));
  }
  // Where the probabilities came from (version 4): 0 not known (a map read
  // from an older file), or 1, whether some frame had its own (0 or 1), and
  // the segmentation models' file names (a count, uint16, then each as a
  // uint16 length and its bytes).
  writePod(s, static_cast<std::uint8_t>(fused_evidence_.recorded ? 1 : 0));
  if (fused_evidence_.recorded) {
    writePod(s, static_cast<std::uint8_t>(fused_evidence_.own_probabilities ? 1 : 0));
    writePod(s, static_cast<std::uint16_t>(fused_evidence_.models.size()));
    for (const std::string& model : fused_evidence_.models) {
      writePod(s, static_cast<std::uint16_t>(model.size()));
      s.write(model.data(), static_cast<std::streamsize>(model.size()));
    }
  }
  // The fused poses' world frame (version 5): 0 not known (a map read from an
  // older file), or 1 and the frame name as a uint16 length (0 before the
  // first frame is fused) and its bytes.
  // (A name too long for its length field, which no sequence has, is not known.)
  const bool frame_known = world_frame_.recorded && world_frame_.frame_id.size() <= 0xffff;
  writePod(s, static_cast<std::uint8_t>(frame_known ? 1 : 0));
  if (frame_known) {
    writePod(s, static_cast<std::uint16_t>(world_frame_.frame_id.size()));
    s.write(world_frame_.frame_id.data(),
            static_cast<std::streamsize>(world_frame_.frame_id.size()));
  }
  // OctoMap's node stream cannot express an empty tree, so say whether one follows.
  writePod(s, static_cast<std::uint8_t>(root != nullptr));
  return octomap::OccupancyOcTreeBase<LabelOcTreeNode>::writeData(s);
}

std::istream& LabelOcTree::readData(std::istream& s) {
  try {
    readLabelledData(s);
  } catch (const Error&) {
    s.setstate(std::ios::failbit);
  }
  return s;
}

namespace {

[[noreturn]] void truncated(const std::string& field, const std::string& expected) {
  throw Error("", field, expected, "the end of the file (truncated data)");
}

// The fused candidates of data version 3 (writeData): a flag, 0 every label,
// 1 a list of `count`-bounded ascending ids, 2 not known.
FusedCandidates readFusedCandidates(std::istream& s, std::uint16_t count) {
  FusedCandidates candidates;
  std::uint8_t listed = 0;
  if (!readPod(s, listed)) truncated("candidates", "a candidate flag");
  if (listed > 2)
    throw Error("", "candidates", "a candidate flag 0 (every label), 1 (a list) or 2 (not known)",
                std::to_string(listed));
  candidates.recorded = listed != 2;
  if (listed == 1) {
    std::uint16_t n = 0;
    if (!readPod(s, n)) truncated("candidates", "a candidate count");
    if (n == 0 || n > count)
      throw Error("", "candidates", "1 to " + std::to_string(count) + " candidate labels",
                  std::to_string(n));
    std::vector<int> ids;
    for (std::uint16_t i = 0; i < n; ++i) {
      std::uint16_t id = 0;
      if (!readPod(s, id)) truncated("candidates", std::to_string(n) + " candidate label ids");
      if (id >= count || (!ids.empty() && id <= ids.back()))
        throw Error("", "candidates[" + std::to_string(i) + "]",
                    "label ids below " + std::to_string(count) + " in increasing order",
                    std::to_string(id));
      ids.push_back(id);
    }
    candidates.labels = std::move(ids);
  }
  return candidates;
}

// Where the probabilities came from (data version 4, writeData).
FusedEvidence readFusedEvidence(std::istream& s) {
  constexpr std::uint16_t kMaxModels = 1024, kMaxName = 4096;
  FusedEvidence evidence;
  std::uint8_t known = 0;
  if (!readPod(s, known)) truncated("evidence", "an evidence flag");
  if (known > 1)
    throw Error("", "evidence", "an evidence flag 0 (not known) or 1", std::to_string(known));
  evidence.recorded = known == 1;
  if (!evidence.recorded) return evidence;
  std::uint8_t own = 0;
  std::uint16_t n = 0;
  if (!readPod(s, own) || !readPod(s, n)) truncated("evidence", "a flag and a model count");
  if (own > 1) throw Error("", "evidence", "an own-probabilities flag 0 or 1", std::to_string(own));
  if (n > kMaxModels)
    throw Error("", "evidence", "at most " + std::to_string(kMaxModels) + " models",
                std::to_string(n));
  evidence.own_probabilities = own == 1;
  for (std::uint16_t i = 0; i < n; ++i) {
    const std::string field = "evidence.models[" + std::to_string(i) + "]";
    std::uint16_t length = 0;
    if (!readPod(s, length)) truncated(field, "a name length");
    if (length == 0 || length > kMaxName)
      throw Error("", field, "a file name of 1 to " + std::to_string(kMaxName) + " bytes",
                  std::to_string(length) + " bytes");
    std::string name(length, '\0');
    s.read(name.data(), length);
    if (!s) truncated(field, "a name of " + std::to_string(length) + " bytes");
    if (!evidence.models.empty() && name <= evidence.models.back())
      throw Error("", field, "model names in increasing order, each once", name);
    evidence.models.push_back(std::move(name));
  }
  return evidence;
}

// The fused poses' world frame (data version 5, writeData).
WorldFrameRecord readWorldFrame(std::istream& s) {
  WorldFrameRecord frame;
  std::uint8_t known = 0;
  if (!readPod(s, known)) truncated("world frame", "a world frame flag");
  if (known > 1)
    throw Error("", "world frame", "a world frame flag 0 (not known) or 1", std::to_string(known));
  frame.recorded = known == 1;
  if (!frame.recorded) return frame;
  std::uint16_t length = 0;
  if (!readPod(s, length)) truncated("world frame", "a name length");
  frame.frame_id.assign(length, '\0');
  s.read(frame.frame_id.data(), length);
  if (!s) truncated("world frame", "a name of " + std::to_string(length) + " bytes");
  if (std::any_of(frame.frame_id.begin(), frame.frame_id.end(),
                  [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
    throw Error("", "world frame", "a frame name without control characters",
                "a name with control characters");
  return frame;
}

}  // namespace

void LabelOcTree::readLabelledData(std::istream& s) {
  char magic[4] = {};
  s.read(magic, sizeof(magic));
  if (!s) truncated("data", "LabelOcTree data starting with 'LOMT'");
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
    throw Error("", "data", "LabelOcTree data starting with 'LOMT'", "other bytes");
  std::uint32_t version = 0;
  if (!readPod(s, version)) truncated("data version", "a data version");
  if (version < 1 || version > kFileVersion)
    throw Error("", "data version",
                "version 1 to " + std::to_string(kFileVersion) +
                    " (the LabelOcTree data versions this program reads)",
                "version " + std::to_string(version) +
                    (version > kFileVersion ? " (written by a newer program?)" : ""));
  std::uint16_t count = 0;
  if (!readPod(s, count)) truncated("label count", "a label count");
  if (count == 0 || count > kMaxLabels)
    throw Error("", "label count", "1 to " + std::to_string(kMaxLabels) + " labels",
                std::to_string(count));
  std::vector<LabelInfo> labels;
  for (std::uint16_t id = 0; id < count; ++id) {
    const std::string field = "labels[" + std::to_string(id) + "]";
    std::uint16_t length = 0;
    if (!readPod(s, length)) truncated(field, "a name length");
    LabelInfo label;
    label.id = id;
    label.name.resize(length);
    s.read(label.name.data(), length);
    s.read(reinterpret_cast<char*>(label.color.data()), 3);
    if (!s) truncated(field, "a name of " + std::to_string(length) + " bytes and a colour");
    labels.push_back(std::move(label));
  }
  MapParameters parameters;
  parameters.resolution = getResolution();
  if (!readPod(s, parameters.p_miss) || !readPod(s, parameters.occupancy_threshold) ||
      !readPod(s, parameters.clamp_min) || !readPod(s, parameters.clamp_max) ||
      !readPod(s, parameters.max_range))
    truncated("parameters", "p_miss, occupancy_threshold, clamp_min, clamp_max, max_range");
  checkMapParameters(parameters);
  CameraViewRecord camera_views;
  if (version >= 2) {
    const std::string expected = "summed up and viewing directions and a view count";
    for (double& component : camera_views.up_sum)
      if (!readPod(s, component)) truncated("camera views", expected);
    for (double& component : camera_views.forward_sum)
      if (!readPod(s, component)) truncated("camera views", expected);
    if (!readPod(s, camera_views.views)) truncated("camera views", expected);
    // Each view adds unit vectors: a sum is at most as long as the count.
    for (const double* summed : {camera_views.up_sum, camera_views.forward_sum}) {
      const Eigen::Vector3d sum(summed[0], summed[1], summed[2]);
      if (!sum.allFinite() || sum.norm() > camera_views.views * (1.0 + 1e-6))
        throw Error("", "camera views",
                    "summed directions no longer than their view count (" +
                        std::to_string(camera_views.views) + ")",
                    "(" + std::to_string(sum.x()) + ", " + std::to_string(sum.y()) + ", " +
                        std::to_string(sum.z()) + ")");
    }
  }
  FusedCandidates candidates =
      version >= 3 ? readFusedCandidates(s, count) : FusedCandidates{false, std::nullopt};
  FusedEvidence evidence = version >= 4 ? readFusedEvidence(s) : FusedEvidence{false, false, {}};
  WorldFrameRecord world_frame = version >= 5 ? readWorldFrame(s) : WorldFrameRecord{false, {}};
  std::uint8_t has_nodes = 0;
  if (!readPod(s, has_nodes)) truncated("nodes", "a node flag");
  if (has_nodes > 1)
    throw Error("", "nodes", "a node flag 0 (empty map) or 1", std::to_string(has_nodes));
  if (root) throw Error("", "nodes", "a map to read into that is empty", "a map with nodes");
  labels_ = LabelSet(std::move(labels));
  parameters_ = parameters;
  camera_views_ = camera_views;
  fused_candidates_ = std::move(candidates);
  fused_evidence_ = std::move(evidence);
  world_frame_ = std::move(world_frame);
  applyParameters();
  if (!has_nodes) return;
  root = new LabelOcTreeNode();
  try {
    readNodes(root, 0, s);
  } catch (...) {
    clear();
    throw;
  }
  tree_size = calcNumNodes();
  size_changed = true;
}

void LabelOcTree::readNodes(LabelOcTreeNode* node, unsigned depth, std::istream& s) {
  node->readData(s);
  if (!s)
    throw Error("", "nodes",
                "a complete node stream (value, kind and labels of every node at depth " +
                    std::to_string(depth) + ")",
                s.eof() ? "the end of the file (truncated data)" : "corrupt node data");
  if (!std::isfinite(node->getValue()))
    throw Error("", "nodes", "finite log-odds in every node",
                std::to_string(node->getValue()) + " at depth " + std::to_string(depth));

  const int n = numLabels();
  const std::string where = " at depth " + std::to_string(depth);
  if (const auto* b = node->block(); b && b->num_labels != n)
    throw Error("", "label count",
                std::to_string(n) + " labels in every node (the label count of the header)",
                "a node with " + std::to_string(b->num_labels) + " labels" + where);
  if (const auto* b = node->block()) {
    // The canonical block the writer stores (storeLabels): the labels above
    // the base, ascending, at least one of them and not all, every value
    // finite, and the node's value their maximum. Readers rely on each
    // (argmax, pruning and comparisons), so a block out of order is refused.
    const auto refuse = [&](const std::string& expected, const std::string& found) {
      throw Error("", "nodes", expected, found + where);
    };
    if (b->count >= b->num_labels)
      refuse("label blocks listing fewer labels than the map has (the others are at the base)",
             "a block listing all " + std::to_string(b->count) + " labels");
    if (!std::isfinite(b->base))
      refuse("finite log-odds in every node", "a label base of " + std::to_string(b->base));
    float highest = b->base;
    for (unsigned i = 0; i < b->count; ++i) {
      const unsigned id = b->ids()[i];
      const float v = b->values()[i];
      if (i > 0 && id <= b->ids()[i - 1])
        refuse("label ids in ascending order in every label block",
               "label " + std::to_string(id) + " after label " + std::to_string(b->ids()[i - 1]));
      if (!std::isfinite(v) || !(v > b->base))
        refuse("listed labels above the block's base " + std::to_string(b->base),
               "label " + std::to_string(id) + " at " + std::to_string(v));
      highest = std::max(highest, v);
    }
    if (node->getValue() != highest)
      refuse("a node value equal to its largest label log-odds (" + std::to_string(highest) + ")",
             "a value of " + std::to_string(node->getValue()));
  }
  if (node->isSummary() && static_cast<int>(node->data_ >> 1) >= n)
    throw Error(
        "", "label count",
        "labels below " + std::to_string(n) + " in every node (the label count of the header)",
        "a node of label " + std::to_string(node->data_ >> 1) + where);
  char children = 0;
  if (!s.read(&children, 1))
    throw Error("", "nodes", "a complete node stream (the children of every node)",
                "the end of the file (truncated data)");
  if (children != 0 && depth >= tree_depth)
    throw Error("", "nodes", "a tree at most " + std::to_string(tree_depth) + " levels deep",
                "children below the finest depth");
  for (unsigned i = 0; i < 8; ++i)
    if ((static_cast<unsigned char>(children) >> i) & 1u)
      readNodes(createNodeChild(node, i), depth + 1, s);
}

}  // namespace lom
