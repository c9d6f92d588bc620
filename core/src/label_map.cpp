#include "lom/label_map.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "file_checks.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/octree/label_octree.hpp"
#include "voxel_grid.hpp"

namespace lom {

namespace {

std::string str(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

std::string resolutionRange() {
  return "a voxel size from " + str(kMinResolution) + " to " + str(kMaxResolution) + " metres";
}

void requireProbability(double p, const char* field) {
  if (!(p > 0.0 && p < 1.0))
    throw Error("", field, "a probability strictly between 0 and 1", str(p));
}

octomap::OcTreeKey toOctomap(const VoxelKey& key) { return octomap::OcTreeKey(key.x, key.y, key.z); }

VoxelState stateOf(const LabelOcTree& tree, const LabelOcTreeNode* node) {
  VoxelState state;
  if (!node) return state;
  const int n = tree.numLabels();
  std::vector<float> log_odds(static_cast<size_t>(n));
  node->labelLogOdds(n, log_odds.data());
  state.known = true;
  state.label = node->argmaxLabel(n);
  state.occupied = tree.isNodeOccupied(node);
  state.probabilities.resize(log_odds.size());
  for (size_t k = 0; k < log_odds.size(); ++k)
    state.probabilities[k] = static_cast<float>(probabilityFromLogOdds(log_odds[k]));
  return state;
}

}  // namespace

void checkMapParameters(const MapParameters& p) {
  if (!(p.resolution >= kMinResolution && p.resolution <= kMaxResolution))
    throw Error("", "resolution", resolutionRange(), str(p.resolution));
  requireProbability(p.p_miss, "p_miss");
  requireProbability(p.occupancy_threshold, "occupancy_threshold");
  requireProbability(p.clamp_min, "clamp_min");
  requireProbability(p.clamp_max, "clamp_max");
  if (!(p.clamp_min < p.clamp_max))
    throw Error("", "clamp_min", "clamp_min < clamp_max",
                str(p.clamp_min) + " >= " + str(p.clamp_max));
  if (!std::isfinite(p.max_range))
    throw Error("", "max_range", "a finite range in metres (<= 0 for unlimited)", str(p.max_range));
}

LabelMap::LabelMap(LabelSet labels, const MapParameters& parameters)
    : labels_(std::move(labels)), parameters_(parameters) {
  checkMapParameters(parameters_);
  if (labels_.empty() || labels_.size() > 256)
    throw Error("", "labels", "between 1 and 256 labels", std::to_string(labels_.size()));
  for (const auto& label : labels_.all())
    if (const std::string problem = labelNameProblem(label.name); !problem.empty())
      throw Error("", "labels[" + std::to_string(label.id) + "].name", kLabelNameRule, problem);
  tree_ = std::make_unique<LabelOcTree>(labels_, parameters_);
}

LabelMap::LabelMap(LabelSet labels, const MapParameters& parameters,
                   std::unique_ptr<LabelOcTree> tree)
    : labels_(std::move(labels)), parameters_(parameters), tree_(std::move(tree)) {}

LabelMap::~LabelMap() = default;
LabelMap::LabelMap(LabelMap&&) noexcept = default;
LabelMap& LabelMap::operator=(LabelMap&&) noexcept = default;

void LabelMap::setOccupancyThreshold(double threshold) {
  requireProbability(threshold, "occupancy_threshold");
  parameters_.occupancy_threshold = threshold;
  tree_->setOccupancyThreshold(threshold);
}

void LabelMap::setIntegrationParameters(double p_miss, double max_range) {
  MapParameters changed = parameters_;
  changed.p_miss = p_miss;
  changed.max_range = max_range;
  checkMapParameters(changed);
  parameters_ = changed;
  tree_->setIntegrationParameters(p_miss, max_range);
}

bool addCameraView(CameraViewRecord& record, const Eigen::Matrix3d& R_world_camera) {
  const Eigen::Vector3d up = -R_world_camera.col(1), forward = R_world_camera.col(2);
  if (!up.allFinite() || !forward.allFinite()) return false;
  if (record.views == std::numeric_limits<std::uint32_t>::max()) return false;  // enough views
  for (int a = 0; a < 3; ++a) {
    record.up_sum[a] += up[a];
    record.forward_sum[a] += forward[a];
  }
  ++record.views;
  return true;
}

bool sameCameraViews(const CameraViewRecord& a, const CameraViewRecord& b) {
  if (a.views != b.views) return false;
  // Sums of unit vectors: rounding grows with the count, far below what one
  // other view changes (a view differs from another by more than 1e-6).
  const double tolerance = 1e-9 * std::max<double>(a.views, 1.0);
  for (int i = 0; i < 3; ++i)
    if (std::abs(a.up_sum[i] - b.up_sum[i]) > tolerance ||
        std::abs(a.forward_sum[i] - b.forward_sum[i]) > tolerance)
      return false;
  return true;
}

void LabelMap::noteCameraView(const Eigen::Matrix3d& R_world_camera) {
  CameraViewRecord record = tree_->cameraViews();
  // Unknown stays unknown: a map read from a file of before the record
  // (version 1, or one that says neither views nor candidates) was fused from
  // views nobody counted; counting only those fused now would make it look
  // like a map of these frames alone.
  if (record.views == 0 && !tree_->fusedCandidates().recorded) return;
  if (addCameraView(record, R_world_camera)) tree_->setCameraViews(record);
}

const CameraViewRecord& LabelMap::cameraViews() const { return tree_->cameraViews(); }

void LabelMap::noteFusedCandidates(const std::optional<std::vector<int>>& candidates) {
  const FusedCandidates& record = tree_->fusedCandidates();
  // Unknown stays unknown: a map of an old file records no camera views
  // either, so "no views" alone does not tell a fresh map.
  if (!record.recorded) return;
  std::optional<std::vector<int>> sorted = candidates;
  if (sorted) {
    std::sort(sorted->begin(), sorted->end());
    sorted->erase(std::unique(sorted->begin(), sorted->end()), sorted->end());
  }
  if (tree_->cameraViews().views == 0) {
    tree_->setFusedCandidates(FusedCandidates{true, std::move(sorted)});
  } else if (!record.labels) {
    return;  // every label already
  } else if (!sorted) {
    tree_->setFusedCandidates(FusedCandidates{true, std::nullopt});
  } else {
    std::vector<int> both;
    std::set_union(record.labels->begin(), record.labels->end(), sorted->begin(), sorted->end(),
                   std::back_inserter(both));
    tree_->setFusedCandidates(FusedCandidates{true, std::move(both)});
  }
}

const FusedCandidates& LabelMap::fusedCandidates() const { return tree_->fusedCandidates(); }

void LabelMap::noteFusedEvidence(const std::string& model) {
  FusedEvidence record = tree_->fusedEvidence();
  if (!record.recorded) return;  // unknown stays unknown (a map of an older file)
  if (model.empty()) {
    if (record.own_probabilities) return;
    record.own_probabilities = true;
  } else {
    const auto at = std::lower_bound(record.models.begin(), record.models.end(), model);
    if (at != record.models.end() && *at == model) return;
    record.models.insert(at, model);
  }
  tree_->setFusedEvidence(record);
}

const FusedEvidence& LabelMap::fusedEvidence() const { return tree_->fusedEvidence(); }

void LabelMap::noteWorldFrame(const std::string& frame_id) {
  const WorldFrameRecord& record = tree_->worldFrame();
  if (!record.recorded || record.frame_id == frame_id) return;  // unknown stays unknown
  if (!record.frame_id.empty())
    throw Error("", "world frame",
                "the map's world frame \"" + record.frame_id +
                    "\" (the frame the poses fused into it were in)",
                "\"" + frame_id + "\"");
  tree_->setWorldFrame(WorldFrameRecord{true, frame_id});
}

const WorldFrameRecord& LabelMap::worldFrame() const { return tree_->worldFrame(); }

std::string describeEvidence(const FusedEvidence& evidence) {
  std::string models;
  for (size_t i = 0; i < evidence.models.size(); ++i)
    models += (i == 0 ? "" : i + 1 == evidence.models.size() ? " and " : ", ") + evidence.models[i];
  const std::string segmenters =
      models.empty() ? std::string()
                     : (evidence.models.size() == 1 ? "segmenter " : "segmenters ") + models;
  if (evidence.own_probabilities)
    return "the frames' own probabilities" +
           (segmenters.empty() ? std::string() : " and " + segmenters);
  return segmenters.empty() ? std::string("no recorded probabilities") : segmenters;
}

std::vector<Eigen::Vector3d> LabelMap::occupiedCentres() const {
  std::vector<Eigen::Vector3d> centres;
  forEachOccupied([&](const OccupiedVoxel& voxel) { centres.push_back(voxel.center); });
  return centres;
}

std::optional<LevelPlane> LabelMap::levelPlane() const {
  const auto cameras = camerasUp();
  if (!cameras) return std::nullopt;
  return findLevelPlane(occupiedCentres(), *cameras, parameters_.resolution);
}

std::optional<Eigen::Vector3d> LabelMap::upDirection() const {
  const auto cameras = camerasUp();
  if (!cameras) return std::nullopt;
  return levelledUp(occupiedCentres(), *cameras, parameters_.resolution);
}

std::optional<Eigen::Vector3d> LabelMap::camerasUp() const {
  const CameraViewRecord& record = tree_->cameraViews();
  if (record.views == 0) return std::nullopt;
  const Eigen::Vector3d sum(record.up_sum[0], record.up_sum[1], record.up_sum[2]);
  const double length = sum.norm();
  if (!std::isfinite(length) || length < 0.5 * record.views) return std::nullopt;
  return Eigen::Vector3d(sum / length);
}

std::optional<Eigen::Vector3d> LabelMap::meanViewingDirection() const {
  const CameraViewRecord& record = tree_->cameraViews();
  const Eigen::Vector3d sum(record.forward_sum[0], record.forward_sum[1], record.forward_sum[2]);
  const double length = sum.norm();
  if (record.views == 0 || !std::isfinite(length) || !(length > 1e-9 * record.views))
    return std::nullopt;
  return Eigen::Vector3d(sum / length);
}

VoxelKey LabelMap::keyOf(const Eigen::Vector3d& p) const {
  grid::Key key;
  if (!grid::Grid(parameters_.resolution).keyOf(p, key))
    throw Error("", "point", "a point inside the map's extent",
                "(" + str(p.x()) + ", " + str(p.y()) + ", " + str(p.z()) + ")");
  return {key[0], key[1], key[2]};
}

Eigen::Vector3d LabelMap::centerOf(const VoxelKey& key) const {
  return grid::Grid(parameters_.resolution).centerOf(grid::Key{key.x, key.y, key.z});
}

VoxelState LabelMap::voxelAt(const Eigen::Vector3d& p) const {
  grid::Key key;
  if (!grid::Grid(parameters_.resolution).keyOf(p, key)) return {};
  return voxelAt(VoxelKey{key[0], key[1], key[2]});
}

VoxelState LabelMap::voxelAt(const VoxelKey& key) const {
  const octomap::OcTreeKey octo_key = toOctomap(key);
  VoxelState state = stateOf(*tree_, tree_->search(octo_key));
  if (!state.known) return state;
  // The depth of the leaf found: the shallowest node on the key's path without children.
  const unsigned max_depth = tree_->getTreeDepth();
  unsigned depth = max_depth;
  for (unsigned d = 1; d < max_depth; ++d) {
    const LabelOcTreeNode* node = tree_->search(octo_key, d);
    if (node && !tree_->nodeHasChildren(node)) {
      depth = d;
      break;
    }
  }
  state.center = {tree_->keyToCoord(octo_key[0], depth), tree_->keyToCoord(octo_key[1], depth),
                  tree_->keyToCoord(octo_key[2], depth)};
  state.size = tree_->getNodeSize(depth);
  return state;
}

void LabelMap::forEachOccupied(const std::function<void(const OccupiedVoxel&)>& visit) const {
  const int n = numLabels();
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    OccupiedVoxel voxel;
    const octomap::point3d c = it.getCoordinate();
    voxel.center = {c.x(), c.y(), c.z()};
    voxel.size = it.getSize();
    voxel.label = it->argmaxLabel(n);
    voxel.probability = static_cast<float>(probabilityFromLogOdds(it->labelLogOdds(voxel.label)));
    visit(voxel);
  }
}

std::vector<VoxelKey> LabelMap::voxelsOfLabel(int label) const {
  auto by_label = voxelsByLabel(std::set<int>{label});
  return by_label.empty() ? std::vector<VoxelKey>{} : std::move(by_label.begin()->second);
}

size_t LabelMap::expandableOccupiedVoxels(const std::optional<std::set<int>>& only) const {
  const int n = numLabels();
  const unsigned max_depth = tree_->getTreeDepth();
  // Counted in double: the leaves of a hand-made file may stand for more than 2^64 voxels.
  double total = 0.0;
  unsigned shallowest = max_depth;
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    if (only && !only->count(it->argmaxLabel(n))) continue;
    total += std::pow(8.0, static_cast<double>(max_depth - it.getDepth()));
    shallowest = std::min(shallowest, it.getDepth());
  }
  if (total > static_cast<double>(kMaxExpandedVoxels)) {
    const double edge =
        parameters_.resolution * std::ldexp(1.0, static_cast<int>(max_depth - shallowest));
    throw Error(source_file_.string(), "map",
                "at most " + std::to_string(kMaxExpandedVoxels) +
                    " occupied voxels at the map's resolution (occupied leaves larger than a "
                    "voxel stand for all their voxels)",
                str(total) + " voxels; the largest occupied leaf is " + str(edge) +
                    " m a side (depth " + std::to_string(shallowest) + " of " +
                    std::to_string(max_depth) + ")");
  }
  return static_cast<size_t>(total);
}

std::map<int, std::vector<VoxelKey>> LabelMap::voxelsByLabel(
    const std::optional<std::set<int>>& only) const {
  (void)expandableOccupiedVoxels(only);
  std::map<int, std::vector<VoxelKey>> voxels;
  const int n = numLabels();
  const unsigned max_depth = tree_->getTreeDepth();
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    const int label = it->argmaxLabel(n);
    if (only && !only->count(label)) continue;
    auto& keys = voxels[label];
    const octomap::OcTreeKey base = it.getIndexKey();
    const unsigned span = 1u << (max_depth - it.getDepth());
    for (unsigned dx = 0; dx < span; ++dx)
      for (unsigned dy = 0; dy < span; ++dy)
        for (unsigned dz = 0; dz < span; ++dz)
          keys.push_back({static_cast<std::uint16_t>(base[0] + dx),
                          static_cast<std::uint16_t>(base[1] + dy),
                          static_cast<std::uint16_t>(base[2] + dz)});
  }
  for (auto& [label, keys] : voxels) std::sort(keys.begin(), keys.end());
  return voxels;
}

std::map<int, size_t> LabelMap::occupiedCountPerLabel() const {
  std::map<int, size_t> counts;
  const int n = numLabels();
  const unsigned max_depth = tree_->getTreeDepth();
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    const size_t span = size_t{1} << (max_depth - it.getDepth());
    counts[it->argmaxLabel(n)] += span * span * span;
  }
  return counts;
}

std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> LabelMap::bounds() const {
  if (tree_->size() == 0) return std::nullopt;
  double x0, y0, z0, x1, y1, z1;
  tree_->getMetricMin(x0, y0, z0);
  tree_->getMetricMax(x1, y1, z1);
  return std::make_pair(Eigen::Vector3d(x0, y0, z0), Eigen::Vector3d(x1, y1, z1));
}

size_t LabelMap::numNodes() const { return tree_->size(); }
size_t LabelMap::numLeaves() const { return tree_->getNumLeafNodes(); }
size_t LabelMap::memoryBytes() const { return tree_->memoryUsage() + tree_->labelArrayBytes(); }
void LabelMap::prune() { tree_->prune(); }

void LabelMap::save(const std::filesystem::path& path) const {
  // The file stores a name's length in 16 bits: never write a map that cannot be read back.
  for (const auto& label : labels_.all())
    if (label.name.size() > 65535)
      throw Error(path.string(), "labels[" + std::to_string(label.id) + "].name",
                  "a label name of at most 65535 bytes (the map file's limit)",
                  "a name of " + std::to_string(label.name.size()) + " bytes");
  writeFileAtomically(path, [&](std::ostream& out) {
    if (!tree_->write(out)) throw Error(path.string(), "map", "a complete write", "write failed");
  });
}

bool LabelMap::isMapFile(const std::filesystem::path& path) {
  if (!notARegularFile(path).empty()) return false;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line.rfind("# Octomap OcTree file", 0) != 0) return false;
  // Comment lines, then "id TYPE" (OcTree::write's order).
  for (int lines = 0; lines < 64 && std::getline(in, line); ++lines) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string key, id;
    words >> key >> id;
    return key == "id" && id == "LabelOcTree";
  }
  return false;
}

LabelMap LabelMap::load(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (const std::string why = notARegularFile(path); !why.empty())
    throw Error(file, "map file", "a readable LabelOctoMap .ot file", why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(file, "map file", "a readable LabelOctoMap .ot file", "cannot open");
  std::string line;
  std::getline(in, line);
  if (line.rfind("# Octomap OcTree file", 0) != 0)
    throw Error(file, "header", "an OctoMap .ot file starting with '# Octomap OcTree file'",
                line.empty() ? "an empty first line" : "'" + line.substr(0, 40) + "'");
  std::string id;
  std::string res;
  std::string size_text;
  bool has_size = false;
  bool has_data = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string token;
    words >> token;
    if (token == "id") {
      words >> id;
    } else if (token == "res") {
      words >> res;
    } else if (token == "size") {
      has_size = true;
      words >> size_text;
    } else if (token == "data") {
      has_data = true;
      break;
    } else {
      throw Error(file, "header", "one of the keys id, size, res, data",
                  "'" + token.substr(0, 40) + "'");
    }
  }
  if (id != "LabelOcTree")
    throw Error(file, "id", "tree type LabelOcTree (a labelled map written by labeloctomap)",
                id.empty() ? "no id" : "tree type " + id.substr(0, 40));
  if (!has_size || res.empty() || !has_data)
    throw Error(file, "header", "the lines id, size, res and data",
                std::string("no ") +
                    (!has_size     ? "size"
                     : res.empty() ? "res"
                                   : "data") +
                    " line");
  double resolution = 0.0;
  {
    std::istringstream number(res);
    number >> resolution;
    if (!number || !number.eof() || !std::isfinite(resolution) || resolution < kMinResolution ||
        resolution > kMaxResolution)
      throw Error(file, "res", resolutionRange(), "'" + res.substr(0, 40) + "'");
  }
  auto tree = std::make_unique<LabelOcTree>(resolution);
  try {
    tree->readLabelledData(in);
  } catch (const Error& e) {
    Problem problem = e.problem();
    problem.file = file;
    throw Error(problem);
  }
  // The node stream ends the file: a damaged kind byte (an inner node read as
  // a leaf) ended the stream early and the rest of the map was dropped
  // without a word. The size line is a number.
  if (in.peek() != std::char_traits<char>::eof())
    throw Error(file, "data", "the map's nodes up to the end of the file",
                "bytes after the node stream ended at byte " +
                    std::to_string(static_cast<long long>(in.tellg())) +
                    " (a damaged node, or another file appended)");
  {
    std::istringstream number(size_text);
    unsigned long long declared = 0;
    number >> declared;
    if (!number || !number.eof())
      throw Error(file, "size", "the number of nodes of the map",
                  "'" + size_text.substr(0, 40) + "'");
    // (Not compared with the nodes read: files edited by other tools keep a
    // stale count, and OctoMap does not rely on it either.)
  }
  LabelSet labels = tree->labels();
  MapParameters parameters = tree->parameters();
  parameters.resolution = resolution;
  LabelMap map(std::move(labels), parameters, std::move(tree));
  map.source_file_ = path;
  return map;
}

}  // namespace lom
