// Map files as another program (or a damaged disk) may leave them: header
// values out of range, unknown data versions, label counts that disagree with
// the nodes, occupied leaves far above the finest depth, label names that
// would break text headers. Loading names the file and the field; every
// consumer either handles the map or refuses it with lom::Error.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "lom/error.hpp"
#include "lom/export.hpp"
#include "lom/label_map.hpp"
#include "lom/objects.hpp"
#include "lom/octree/label_octree.hpp"
#include "test_mesh_checks.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::blockKeys;

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <class T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class T>
T get(const std::string& bytes, size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

// A native map file split into its parts, to be changed and put together again.
struct MapFile {
  std::string text;  // "# Octomap OcTree file ... data\n"
  std::uint32_t version = 0;
  std::vector<std::pair<std::string, lom::Rgb>> labels;
  double parameters[5] = {};  // p_miss, threshold, clamp_min, clamp_max, max_range
  double up_sum[3] = {};      // data version 2: the cameras' summed up directions,
  double forward_sum[3] = {};  // their summed viewing directions
  std::uint32_t up_views = 0;  // and the count
  // Data version 3: the fused candidates (absent: every label, or not known).
  std::uint8_t candidate_flag = 0;
  std::optional<std::vector<std::uint16_t>> candidates;
  std::string evidence;       // data version 4: where the probabilities came from, as written
  std::string world_frame;    // data version 5: the fused poses' world frame, as written
  std::string nodes;          // the node flag and OctoMap's node stream

  static MapFile read(const fs::path& path) {
    const std::string bytes = readBytes(path);
    MapFile file;
    size_t at = bytes.find("\ndata\n") + 6;
    file.text = bytes.substr(0, at);
    EXPECT_EQ(bytes.substr(at, 4), "LOMT");
    file.version = get<std::uint32_t>(bytes, at + 4);
    const auto count = get<std::uint16_t>(bytes, at + 8);
    at += 10;
    for (int i = 0; i < count; ++i) {
      const auto length = get<std::uint16_t>(bytes, at);
      lom::Rgb color;
      std::memcpy(color.data(), bytes.data() + at + 2 + length, 3);
      file.labels.emplace_back(bytes.substr(at + 2, length), color);
      at += 2u + length + 3u;
    }
    for (double& p : file.parameters) {
      p = get<double>(bytes, at);
      at += 8;
    }
    if (file.version >= 2) {
      for (double* sums : {file.up_sum, file.forward_sum})
        for (int i = 0; i < 3; ++i) {
          sums[i] = get<double>(bytes, at);
          at += 8;
        }
      file.up_views = get<std::uint32_t>(bytes, at);
      at += 4;
    }
    if (file.version >= 3) {
      const auto listed = get<std::uint8_t>(bytes, at);
      file.candidate_flag = listed;
      at += 1;
      if (listed == 1) {
        const auto n = get<std::uint16_t>(bytes, at);
        at += 2;
        file.candidates.emplace();
        for (int i = 0; i < n; ++i, at += 2)
          file.candidates->push_back(get<std::uint16_t>(bytes, at));
      }
    }
    if (file.version >= 4) {
      const size_t start = at;
      if (get<std::uint8_t>(bytes, at++) == 1) {
        at += 1;  // own probabilities
        const auto n = get<std::uint16_t>(bytes, at);
        at += 2;
        for (int i = 0; i < n; ++i) at += 2u + get<std::uint16_t>(bytes, at);
      }
      file.evidence = bytes.substr(start, at - start);
    }
    if (file.version >= 5) {
      const size_t start = at;
      if (get<std::uint8_t>(bytes, at++) == 1) at += 2u + get<std::uint16_t>(bytes, at);
      file.world_frame = bytes.substr(start, at - start);
    }
    file.nodes = bytes.substr(at);
    return file;
  }

  void write(const fs::path& path, int count = -1) const {
    std::string bytes = text + "LOMT";
    put(bytes, version);
    put(bytes, static_cast<std::uint16_t>(count < 0 ? static_cast<int>(labels.size()) : count));
    for (const auto& [name, color] : labels) {
      put(bytes, static_cast<std::uint16_t>(name.size()));
      bytes += name;
      bytes.append(reinterpret_cast<const char*>(color.data()), 3);
    }
    for (const double p : parameters) put(bytes, p);
    if (version >= 2) {
      for (const double u : up_sum) put(bytes, u);
      for (const double f : forward_sum) put(bytes, f);
      put(bytes, up_views);
    }
    if (version >= 3) {
      put(bytes, candidates ? std::uint8_t{1} : candidate_flag);
      if (candidates) {
        put(bytes, static_cast<std::uint16_t>(candidates->size()));
        for (const std::uint16_t id : *candidates) put(bytes, id);
      }
    }
    if (version >= 4) {
      bytes += evidence.empty() ? std::string(1, '\0') : evidence;
    }
    if (version >= 5) {
      bytes += world_frame.empty() ? std::string(1, '\0') : world_frame;
    }
    writeBytes(path, bytes + nodes);
  }
};

lom::LabelMap sampleMap() {
  return lom::test::MapBuilder(3, 0.02)
      .occupy(blockKeys(0, 3, 0, 3, 0, 3), 1)
      .occupy(blockKeys(3, 5, 0, 2, 0, 2), 2)
      .clear(blockKeys(-1, 6, -1, 4, -1, 0))
      .build();
}

lom::Problem loadError(const fs::path& path) {
  try {
    (void)lom::LabelMap::load(path);
  } catch (const lom::Error& e) {
    return e.problem();
  }
  ADD_FAILURE() << "loaded " << path;
  return {};
}

class MapFileTest : public ::testing::Test {
 protected:
  void SetUp() override { sampleMap().save(dir / "map.ot"); }
  fs::path changed(const std::function<void(MapFile&)>& change, int count = -1) {
    MapFile file = MapFile::read(dir / "map.ot");
    change(file);
    file.write(dir / "changed.ot", count);
    return dir / "changed.ot";
  }
  lom::test::TempDir dir;
};

TEST_F(MapFileTest, TheUnchangedFileLoads) {
  const fs::path path = changed([](MapFile&) {});
  EXPECT_EQ(readBytes(path), readBytes(dir / "map.ot"));
  EXPECT_EQ(lom::LabelMap::load(path).occupiedCountPerLabel().at(1), 27u);
}

TEST_F(MapFileTest, ParametersOutOfRangeNameTheFieldAndTheRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    int index;
    double value;
    const char* field;
  };
  for (const Case& c :
       {Case{1, nan, "occupancy_threshold"}, Case{1, -1.0, "occupancy_threshold"},
        Case{1, 1e300, "occupancy_threshold"}, Case{0, nan, "p_miss"}, Case{2, nan, "clamp_min"},
        Case{3, 1.5, "clamp_max"}, Case{4, nan, "max_range"}}) {
    const fs::path path = changed([&](MapFile& f) { f.parameters[c.index] = c.value; });
    const lom::Problem problem = loadError(path);
    EXPECT_EQ(problem.file, path.string());
    EXPECT_EQ(problem.field, c.field) << problem.message();
    if (std::string(c.field) != "max_range") {
      EXPECT_NE(problem.expected.find("strictly between 0 and 1"), std::string::npos)
          << problem.message();
    }
  }
  const lom::Problem order =
      loadError(changed([](MapFile& f) { std::swap(f.parameters[2], f.parameters[3]); }));
  EXPECT_EQ(order.field, "clamp_min");
  EXPECT_EQ(order.expected, "clamp_min < clamp_max");
}

TEST_F(MapFileTest, ResolutionOutOfRangeIsRefused) {
  for (const char* res : {"1e300", "nan", "-0.01", "0", "abc", "0.01x"}) {
    const fs::path path = changed([&](MapFile& f) {
      const size_t at = f.text.find("\nres ") + 5;
      f.text.replace(at, f.text.find('\n', at) - at, res);
    });
    const lom::Problem problem = loadError(path);
    EXPECT_EQ(problem.file, path.string());
    EXPECT_EQ(problem.field, "res") << res;
    EXPECT_EQ(problem.expected, "a voxel size from 0.0001 to 10 metres");
    EXPECT_EQ(problem.found, "'" + std::string(res) + "'");
  }
}

TEST_F(MapFileTest, AnUnknownDataVersionIsNamed) {
  const lom::Problem problem = loadError(changed([](MapFile& f) { f.version = 6; }));
  EXPECT_EQ(problem.field, "data version");
  EXPECT_EQ(problem.found, "version 6 (written by a newer program?)");
  EXPECT_NE(problem.expected.find("version 1 to 5"), std::string::npos);
}

TEST_F(MapFileTest, VersionOneMapsWithoutTheCameraViewRecordStillLoad) {
  const fs::path path = changed([](MapFile& f) {
    EXPECT_EQ(f.version, 5u);
    f.version = 1;
  });
  const lom::LabelMap map = lom::LabelMap::load(path);
  EXPECT_EQ(map.occupiedCountPerLabel().at(1), 27u);
  EXPECT_EQ(map.cameraViews().views, 0u);
  EXPECT_FALSE(map.upDirection());
  EXPECT_FALSE(map.meanViewingDirection());
  EXPECT_FALSE(map.fusedCandidates().recorded);
}

// Frames fused into a version-1 map (fuse --start-from) leave its candidates
// unknown: it records no camera views, which made it look fresh, and the new
// frames' candidates were recorded as those of every frame.
TEST_F(MapFileTest, FramesFusedIntoAVersionOneMapLeaveItsCandidatesUnknown) {
  const fs::path path = changed([](MapFile& f) { f.version = 1; });
  lom::LabelMap map = lom::LabelMap::load(path);
  map.noteFusedCandidates(std::vector<int>{0, 1});
  map.noteCameraView(Eigen::Matrix3d::Identity());
  EXPECT_FALSE(map.fusedCandidates().recorded);
  // Its views stay unknown too: counting only the new one would make it look
  // like the map of that frame alone (score --map would compare it so).
  EXPECT_EQ(map.cameraViews().views, 0u);
  EXPECT_FALSE(map.meanViewingDirection());
  map.save(dir / "continued.ot");
  const lom::LabelMap continued = lom::LabelMap::load(dir / "continued.ot");
  EXPECT_FALSE(continued.fusedCandidates().recorded);
  EXPECT_EQ(continued.cameraViews().views, 0u);
}

TEST_F(MapFileTest, VersionTwoMapsKeepCountingTheirRecordedViews) {
  const fs::path path = changed([](MapFile& f) {
    f.version = 2;
    f.up_sum[1] = -1.0;  // one view of a camera with the identity rotation
    f.forward_sum[2] = 1.0;
    f.up_views = 1;
  });
  lom::LabelMap map = lom::LabelMap::load(path);
  ASSERT_EQ(map.cameraViews().views, 1u);
  ASSERT_FALSE(map.fusedCandidates().recorded);
  map.noteCameraView(Eigen::Matrix3d::Identity());
  EXPECT_EQ(map.cameraViews().views, 2u);
  EXPECT_DOUBLE_EQ(map.cameraViews().forward_sum[2], 2.0);
}

TEST(CameraViewRecord, SameViewsAreTheSameFramesInAnyOrder) {
  const Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d b = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d c = Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  lom::CameraViewRecord ab, ba, ac, abb;
  for (const auto* r : {&a, &b}) EXPECT_TRUE(lom::addCameraView(ab, *r));
  for (const auto* r : {&b, &a}) EXPECT_TRUE(lom::addCameraView(ba, *r));
  for (const auto* r : {&a, &c}) EXPECT_TRUE(lom::addCameraView(ac, *r));
  for (const auto* r : {&a, &b, &b}) EXPECT_TRUE(lom::addCameraView(abb, *r));
  EXPECT_TRUE(lom::sameCameraViews(ab, ba));
  EXPECT_FALSE(lom::sameCameraViews(ab, ac));   // as many views, other directions
  EXPECT_FALSE(lom::sameCameraViews(ab, abb));  // another count
  Eigen::Matrix3d broken = a;
  broken(0, 2) = std::nan("");
  EXPECT_FALSE(lom::addCameraView(ab, broken));
  EXPECT_EQ(ab.views, 2u);
}

TEST_F(MapFileTest, VersionTwoMapsLoadWithTheirCandidatesUnknown) {
  const fs::path path = changed([](MapFile& f) { f.version = 2; });
  const lom::LabelMap map = lom::LabelMap::load(path);
  EXPECT_EQ(map.occupiedCountPerLabel().at(1), 27u);
  EXPECT_FALSE(map.fusedCandidates().recorded);
  // Saved again, they stay unknown (not "every label").
  map.save(dir / "again.ot");
  const MapFile again = MapFile::read(dir / "again.ot");
  EXPECT_EQ(again.version, 5u);
  EXPECT_EQ(again.candidate_flag, 2);
  EXPECT_FALSE(lom::LabelMap::load(dir / "again.ot").fusedCandidates().recorded);
}

TEST_F(MapFileTest, FusedCandidatesAreSavedWithTheMapAndWidenedByLaterViews) {
  lom::LabelMap map(lom::test::numberedLabels(5));
  EXPECT_TRUE(map.fusedCandidates().recorded);
  map.noteFusedCandidates(std::vector<int>{3, 0, 3});
  map.noteCameraView(Eigen::Matrix3d::Identity());
  map.save(dir / "candidates.ot");
  const MapFile file = MapFile::read(dir / "candidates.ot");
  ASSERT_TRUE(file.candidates);
  EXPECT_EQ(*file.candidates, (std::vector<std::uint16_t>{0, 3}));
  const lom::LabelMap loaded = lom::LabelMap::load(dir / "candidates.ot");
  EXPECT_TRUE(loaded.fusedCandidates().recorded);
  EXPECT_EQ(loaded.fusedCandidates().labels, (std::vector<int>{0, 3}));
  // A later view with other candidates widens the record to both; one with
  // every label makes it every label.
  map.noteFusedCandidates(std::vector<int>{1});
  map.noteCameraView(Eigen::Matrix3d::Identity());
  EXPECT_EQ(map.fusedCandidates().labels, (std::vector<int>{0, 1, 3}));
  map.noteFusedCandidates(std::nullopt);
  map.noteCameraView(Eigen::Matrix3d::Identity());
  EXPECT_FALSE(map.fusedCandidates().labels);
  map.noteFusedCandidates(std::vector<int>{2});
  EXPECT_FALSE(map.fusedCandidates().labels);
  map.save(dir / "every.ot");
  EXPECT_FALSE(MapFile::read(dir / "every.ot").candidates);
  EXPECT_FALSE(lom::LabelMap::load(dir / "every.ot").fusedCandidates().labels);
}

// Where the probabilities came from: recorded per frame (a model's file name,
// or the frame's own), saved with the map; unknown for a map of a version
// before the record, also once frames are fused into it.
TEST_F(MapFileTest, TheEvidenceRecordIsSavedAndUnknownInOlderMaps) {
  lom::LabelMap map(lom::test::numberedLabels(5));
  EXPECT_TRUE(map.fusedEvidence().recorded);
  EXPECT_TRUE(map.fusedEvidence().empty());
  for (const char* model : {"b.onnx", "a.onnx", "b.onnx", ""}) map.noteFusedEvidence(model);
  EXPECT_EQ(lom::describeEvidence(map.fusedEvidence()),
            "the frames' own probabilities and segmenters a.onnx and b.onnx");
  map.save(dir / "evidence.ot");
  const lom::FusedEvidence loaded = lom::LabelMap::load(dir / "evidence.ot").fusedEvidence();
  EXPECT_TRUE(loaded.recorded);
  EXPECT_TRUE(loaded.own_probabilities);
  EXPECT_EQ(loaded.models, (std::vector<std::string>{"a.onnx", "b.onnx"}));

  lom::LabelMap older = lom::LabelMap::load(changed([](MapFile& f) { f.version = 3; }));
  EXPECT_FALSE(older.fusedEvidence().recorded);
  older.noteFusedEvidence("a.onnx");
  EXPECT_FALSE(older.fusedEvidence().recorded);
  older.save(dir / "older.ot");
  EXPECT_FALSE(lom::LabelMap::load(dir / "older.ot").fusedEvidence().recorded);

  // Names out of order are refused, naming the field.
  const lom::Problem order = loadError(changed([](MapFile& f) {
    f.evidence = std::string("\x01\x00\x02\x00", 4) + std::string("\x01\x00", 2) + "b" +
                 std::string("\x01\x00", 2) + "a";
  }));
  EXPECT_EQ(order.field, "evidence.models[1]");
  EXPECT_EQ(order.found, "a");
}

// The world frame of the fused poses: set by the first fused frame, saved
// with the map; another frame is refused; unknown in maps of a version
// before the record, also once frames are fused into them.
TEST_F(MapFileTest, TheWorldFrameIsSavedAndUnknownInOlderMaps) {
  lom::LabelMap map(lom::test::numberedLabels(5));
  EXPECT_TRUE(map.worldFrame().recorded);
  EXPECT_EQ(map.worldFrame().frame_id, "");
  map.save(dir / "fresh.ot");
  EXPECT_EQ(MapFile::read(dir / "fresh.ot").world_frame, std::string("\x01\x00\x00", 3));
  map.noteWorldFrame("odom");
  map.noteWorldFrame("odom");
  EXPECT_EQ(map.worldFrame().frame_id, "odom");
  try {
    map.noteWorldFrame("map");
    ADD_FAILURE() << "a pose of another world frame was recorded";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().field, "world frame");
    EXPECT_NE(e.problem().expected.find("\"odom\""), std::string::npos) << e.what();
    EXPECT_EQ(e.problem().found, "\"map\"");
  }
  EXPECT_EQ(map.worldFrame().frame_id, "odom");
  map.save(dir / "odom.ot");
  EXPECT_EQ(MapFile::read(dir / "odom.ot").world_frame, std::string("\x01\x04\x00odom", 7));
  const lom::LabelMap loaded = lom::LabelMap::load(dir / "odom.ot");
  EXPECT_TRUE(loaded.worldFrame().recorded);
  EXPECT_EQ(loaded.worldFrame().frame_id, "odom");

  lom::LabelMap older = lom::LabelMap::load(changed([](MapFile& f) { f.version = 4; }));
  EXPECT_FALSE(older.worldFrame().recorded);
  older.noteWorldFrame("world");
  EXPECT_FALSE(older.worldFrame().recorded);
  older.save(dir / "older.ot");
  EXPECT_FALSE(lom::LabelMap::load(dir / "older.ot").worldFrame().recorded);

  // A damaged record names the field.
  const lom::Problem flag =
      loadError(changed([](MapFile& f) { f.world_frame = std::string("\x03", 1); }));
  EXPECT_EQ(flag.field, "world frame");
  EXPECT_EQ(flag.found, "3");
  const lom::Problem control = loadError(
      changed([](MapFile& f) { f.world_frame = std::string("\x01\x02\x00\x61\x0a", 5); }));
  EXPECT_EQ(control.field, "world frame");
  EXPECT_EQ(control.expected, "a frame name without control characters");
  const lom::Problem cut = loadError(changed([](MapFile& f) {
    f.world_frame = std::string("\x01\xff\x00", 3);
    f.nodes = "ab";
  }));
  EXPECT_EQ(cut.field, "world frame");
  EXPECT_NE(cut.found.find("truncated"), std::string::npos) << cut.message();
}

TEST_F(MapFileTest, CandidatesOutOfRangeOrOrderAreRefused) {
  const lom::Problem beyond = loadError(changed([](MapFile& f) {
    f.candidates = std::vector<std::uint16_t>{0, 7};
  }));
  EXPECT_EQ(beyond.field, "candidates[1]");
  EXPECT_EQ(beyond.found, "7");
  const lom::Problem order = loadError(changed([](MapFile& f) {
    f.candidates = std::vector<std::uint16_t>{2, 1};
  }));
  EXPECT_EQ(order.field, "candidates[1]");
  EXPECT_NE(order.expected.find("increasing order"), std::string::npos);
  const lom::Problem none =
      loadError(changed([](MapFile& f) { f.candidates = std::vector<std::uint16_t>{}; }));
  EXPECT_EQ(none.field, "candidates");
  const lom::Problem flag = loadError(changed([](MapFile& f) { f.candidate_flag = 3; }));
  EXPECT_EQ(flag.field, "candidates");
  EXPECT_EQ(flag.found, "3");
}

TEST_F(MapFileTest, CameraViewsAreSavedWithTheMap) {
  lom::LabelMap map = sampleMap();
  EXPECT_FALSE(map.upDirection());
  const Eigen::Matrix3d tilted =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()).toRotationMatrix();
  map.noteCameraView(Eigen::Matrix3d::Identity());
  map.noteCameraView(tilted);
  map.save(dir / "viewed.ot");
  const lom::LabelMap loaded = lom::LabelMap::load(dir / "viewed.ot");
  EXPECT_EQ(loaded.cameraViews().views, 2u);
  ASSERT_TRUE(loaded.upDirection());
  const Eigen::Vector3d expected = (-Eigen::Vector3d::UnitY() - tilted.col(1)).normalized();
  EXPECT_LT((*loaded.upDirection() - expected).norm(), 1e-12);
  ASSERT_TRUE(loaded.meanViewingDirection());
  const Eigen::Vector3d viewing = (Eigen::Vector3d::UnitZ() + tilted.col(2)).normalized();
  EXPECT_LT((*loaded.meanViewingDirection() - viewing).norm(), 1e-12);
}

TEST_F(MapFileTest, TheCameraViewRecordIsReadBackAndChecked) {
  const fs::path path = changed([](MapFile& f) {
    f.up_sum[1] = -3.0;
    f.up_views = 4;
  });
  const lom::LabelMap map = lom::LabelMap::load(path);
  EXPECT_EQ(map.cameraViews().views, 4u);
  ASSERT_TRUE(map.upDirection());
  EXPECT_NEAR((*map.upDirection() - Eigen::Vector3d(0, -1, 0)).norm(), 0.0, 1e-12);
  // Unit vectors cannot sum to more than their count.
  const lom::Problem longer = loadError(changed([](MapFile& f) {
    f.up_sum[2] = 5.0;
    f.up_views = 4;
  }));
  EXPECT_EQ(longer.field, "camera views");
  const lom::Problem nan = loadError(
      changed([](MapFile& f) { f.up_sum[0] = std::numeric_limits<double>::quiet_NaN(); }));
  EXPECT_EQ(nan.field, "camera views");
  const lom::Problem forward = loadError(changed([](MapFile& f) {
    f.forward_sum[0] = 2.5;
    f.up_views = 2;
  }));
  EXPECT_EQ(forward.field, "camera views");
}

TEST_F(MapFileTest, LabelCountsOutOfRangeOrDisagreeingWithTheNodesAreNamed) {
  const lom::Problem none = loadError(changed([](MapFile& f) { f.labels.clear(); }));
  EXPECT_EQ(none.field, "label count");
  EXPECT_EQ(none.found, "0");
  // The header lists two labels, the nodes hold blocks of three.
  const lom::Problem fewer = loadError(changed([](MapFile& f) { f.labels.pop_back(); }));
  EXPECT_EQ(fewer.field, "label count");
  EXPECT_NE(fewer.expected.find("the label count of the header"), std::string::npos)
      << fewer.message();
}

TEST_F(MapFileTest, TruncatedNodesSayWhereTheFileEnds) {
  const fs::path path = changed([](MapFile& f) { f.nodes.resize(f.nodes.size() - 7); });
  const lom::Problem problem = loadError(path);
  EXPECT_EQ(problem.file, path.string());
  EXPECT_EQ(problem.field, "nodes");
  EXPECT_NE(problem.found.find("truncated"), std::string::npos) << problem.message();
  // The node flag and the tree: children below the finest depth are refused
  // instead of recursing as deep as the file says.
  const fs::path deep = changed([](MapFile& f) {
    f.nodes = std::string(1, '\1');
    for (int depth = 0; depth < 40; ++depth) {
      put(f.nodes, 1.0f);
      f.nodes += '\2';  // an inner node's summary
      put(f.nodes, std::uint16_t{1});
      f.nodes += '\1';  // one child
    }
  });
  EXPECT_EQ(loadError(deep).found, "children below the finest depth");
}

// Bytes after the node stream: a damaged node that ended the stream early
// (the rest of the map was dropped without a word) or another file appended.
TEST_F(MapFileTest, BytesAfterTheNodesAreRefused) {
  const fs::path appended = changed([](MapFile& f) { f.nodes += "X"; });
  const lom::Problem problem = loadError(appended);
  EXPECT_EQ(problem.file, appended.string());
  EXPECT_EQ(problem.field, "data");
  EXPECT_NE(problem.found.find("bytes after the node stream ended at byte"), std::string::npos)
      << problem.message();
  // The root's kind byte turned from an inner node into a leaf: one leaf
  // read, the rest left over.
  const fs::path root_leaf = changed([](MapFile& f) {
    ASSERT_GT(f.nodes.size(), 6u);
    ASSERT_EQ(f.nodes[5], '\2') << "the root is an inner node";
    f.nodes[5] = '\0';
  });
  const std::string field = loadError(root_leaf).field;  // what is left over, or what it reads as
  EXPECT_TRUE(field == "data" || field == "nodes") << field;
  // A size line that is no number.
  const fs::path size = changed([](MapFile& f) {
    const size_t at = f.text.find("\nsize ");
    ASSERT_NE(at, std::string::npos);
    f.text.replace(at, f.text.find('\n', at + 1) - at, "\nsize x");
  });
  EXPECT_EQ(loadError(size).field, "size");
}

// A map whose only node is an occupied leaf at `depth` (0 = the root), of label 1.
fs::path mapWithOneLeaf(const fs::path& folder, unsigned depth, int leaf_label = 1) {
  lom::MapParameters parameters;
  lom::LabelMap(lom::LabelSet({{0, "__background__", {0, 0, 0}}, {1, "box", {9, 9, 9}}}),
                parameters)
      .save(folder / "empty.ot");
  MapFile file = MapFile::read(folder / "empty.ot");
  file.nodes = std::string(1, '\1');
  for (unsigned d = 0; d < depth; ++d) {
    put(file.nodes, 2.0f);
    file.nodes += '\2';
    put(file.nodes, static_cast<std::uint16_t>(leaf_label));
    file.nodes += '\1';
  }
  put(file.nodes, 2.0f);
  if (leaf_label == 0) {
    file.nodes += '\0';  // uniform: every label 2.0, the argmax label 0
  } else {
    file.nodes += '\1';  // sparse: label 1 at 2.0 above a base of -2.0
    put(file.nodes, std::uint16_t{2});
    put(file.nodes, std::uint16_t{1});
    put(file.nodes, -2.0f);
    file.nodes += '\1';
    put(file.nodes, 2.0f);
  }
  file.nodes += '\0';  // no children
  const fs::path path = folder / ("leaf" + std::to_string(depth) + ".ot");
  file.write(path);
  return path;
}

// A map of three labels whose only node is a leaf at the finest depth with the
// label block given (value, base, then each listed label id and its value).
fs::path mapWithOneBlock(const fs::path& folder, float value, float base,
                         const std::vector<std::pair<std::uint8_t, float>>& listed) {
  lom::MapParameters parameters;
  lom::LabelMap(lom::LabelSet({{0, "__background__", {0, 0, 0}},
                               {1, "box", {9, 9, 9}},
                               {2, "cup", {7, 7, 7}}}),
                parameters)
      .save(folder / "empty.ot");
  MapFile file = MapFile::read(folder / "empty.ot");
  file.nodes = std::string(1, '\1');
  for (unsigned d = 0; d < 16; ++d) {
    put(file.nodes, value);
    file.nodes += '\2';
    put(file.nodes, std::uint16_t{2});
    file.nodes += '\1';
  }
  put(file.nodes, value);
  file.nodes += '\1';
  put(file.nodes, std::uint16_t{3});
  put(file.nodes, static_cast<std::uint16_t>(listed.size()));
  put(file.nodes, base);
  for (const auto& entry : listed) file.nodes += static_cast<char>(entry.first);
  for (const auto& entry : listed) put(file.nodes, entry.second);
  file.nodes += '\0';
  const fs::path path = folder / "block.ot";
  file.write(path);
  return path;
}

TEST(LabelBlockTest, OnlyCanonicalLabelBlocksAreRead) {
  lom::test::TempDir dir;
  // As the writer stores them: labels above the base, ascending; the value their maximum.
  const lom::LabelMap map = lom::LabelMap::load(mapWithOneBlock(dir.path(), 2.f, -2.f, {{1, 1.f}, {2, 2.f}}));
  EXPECT_EQ(map.occupiedCountPerLabel().at(2), 1u);

  struct Case {
    const char* what;
    float value, base;
    std::vector<std::pair<std::uint8_t, float>> listed;
    const char* found;
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Case cases[] = {
      {"out of order", 2.f, -2.f, {{2, 2.f}, {1, 1.f}}, "label 1 after label 2"},
      {"twice", 2.f, -2.f, {{1, 1.f}, {1, 2.f}}, "label 1 after label 1"},
      {"at the base", 2.f, -2.f, {{1, -2.f}, {2, 2.f}}, "label 1 at -2"},
      {"below the base", 2.f, -2.f, {{1, -3.f}, {2, 2.f}}, "label 1 at -3"},
      {"not finite", 2.f, -2.f, {{1, nan}, {2, 2.f}}, "label 1 at nan"},
      {"every label", 2.f, -2.f, {{0, 0.f}, {1, 1.f}, {2, 2.f}}, "a block listing all 3 labels"},
      {"base not finite", 2.f, nan, {{1, 1.f}, {2, 2.f}}, "a label base of nan"},
      {"value not the maximum", 1.f, -2.f, {{1, 1.f}, {2, 2.f}}, "a value of 1"},
  };
  for (const Case& c : cases) {
    const fs::path path = mapWithOneBlock(dir.path(), c.value, c.base, c.listed);
    const lom::Problem problem = loadError(path);
    EXPECT_EQ(problem.file, path.string()) << c.what;
    EXPECT_EQ(problem.field, "nodes") << c.what;
    EXPECT_NE(problem.found.find(c.found), std::string::npos) << c.what << ": " << problem.message();
    EXPECT_NE(problem.found.find("at depth 16"), std::string::npos) << c.what << ": " << problem.message();
  }
}

TEST(CoarseLeafTest, AnOccupiedInnerLeafStandsForAllItsVoxels) {
  lom::test::TempDir dir;
  const lom::LabelMap map = lom::LabelMap::load(mapWithOneLeaf(dir.path(), 12));
  EXPECT_EQ(map.occupiedCountPerLabel().at(1), 4096u);  // 16^3
  EXPECT_EQ(map.voxelsOfLabel(1).size(), 4096u);

  lom::ExportOptions ply;
  ply.format = lom::ExportFormat::Pcd;
  EXPECT_EQ(lom::exportMap(map, ply, dir / "leaf.pcd").items, 4096u);
  lom::ExportOptions mesh;
  mesh.format = lom::ExportFormat::Ply;
  EXPECT_EQ(lom::exportMap(map, mesh, dir / "leaf.ply").items, 12u);  // one merged cube
  lom::ExportOptions objects;
  objects.format = lom::ExportFormat::Objects;
  EXPECT_EQ(lom::exportMap(map, objects, dir / "objects.json").items, 1u);
  const auto found = lom::extractObjects(map, {});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].voxelCount(), 4096u);
  EXPECT_NEAR(found[0].box.size.x(), 0.16, 1e-9);
}

TEST(CoarseLeafTest, ARootLeafIsRefusedInsteadOfExpandedWithoutBound) {
  lom::test::TempDir dir;
  const fs::path path = mapWithOneLeaf(dir.path(), 0);
  const lom::LabelMap map = lom::LabelMap::load(path);
  size_t leaves = 0;
  map.forEachOccupied([&](const lom::OccupiedVoxel& v) {
    ++leaves;
    EXPECT_NEAR(v.size, 655.36, 1e-6);
  });
  EXPECT_EQ(leaves, 1u);
  EXPECT_EQ(map.occupiedCountPerLabel().at(1), size_t{1} << 48);

  for (const auto format : {lom::ExportFormat::Ply, lom::ExportFormat::Pcd,
                            lom::ExportFormat::Objects, lom::ExportFormat::Stl}) {
    lom::ExportOptions options;
    options.format = format;
    const fs::path out =
        dir / (std::string("out.") +
               (format == lom::ExportFormat::Objects ? "json" : lom::exportFormatName(format)));
    try {
      (void)lom::exportMap(map, options, out);
      ADD_FAILURE() << "exported " << out;
    } catch (const lom::Error& e) {
      EXPECT_EQ(e.problem().field, "map");
      EXPECT_EQ(e.problem().file, path.string());  // the map at fault, not the output
      EXPECT_NE(e.problem().expected.find("at most 16777216 occupied voxels"), std::string::npos)
          << e.what();
      EXPECT_NE(e.problem().found.find("655.36 m a side (depth 0 of 16)"), std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(fs::exists(out));
  }
  lom::ObjectOptions objects;
  objects.map_file = path.string();
  try {
    (void)lom::extractObjects(map, objects);
    ADD_FAILURE() << "extracted objects";
  } catch (const lom::Error& e) {
    EXPECT_EQ(e.problem().file, path.string());
  }
  EXPECT_THROW((void)map.voxelsOfLabel(1), lom::Error);
}

TEST(CoarseLeafTest, ObjectsOfABackgroundOnlyMapSayWhyThereIsNone) {
  lom::test::TempDir dir;
  const lom::LabelMap map = lom::LabelMap::load(mapWithOneLeaf(dir.path(), 14, 0));
  lom::ExportOptions options;
  options.format = lom::ExportFormat::Objects;
  try {
    (void)lom::exportMap(map, options, dir / "objects.json");
    ADD_FAILURE() << "exported objects";
  } catch (const lom::Error& e) {
    EXPECT_NE(e.problem().found.find("background"), std::string::npos) << e.what();
  }
}

TEST_F(MapFileTest, LabelNamesFromAMapFileCannotBreakAPlyHeader) {
  const fs::path path =
      changed([](MapFile& f) { f.labels[1].first = "box\nend_header\nelement vertex 1\r\t\x7f"; });
  const lom::LabelMap map = lom::LabelMap::load(path);
  lom::ExportOptions options;
  options.format = lom::ExportFormat::Ply;
  (void)lom::exportMap(map, options, dir / "mesh.ply");
  const std::string ply = readBytes(dir / "mesh.ply");
  const std::string header = ply.substr(0, ply.find("end_header\n") + 11);
  EXPECT_EQ(header.find("\nelement vertex 1\n"), std::string::npos) << header;
  EXPECT_NE(header.find("comment label 1 box_end_header_element vertex 1___\n"), std::string::npos)
      << header;
  std::istringstream lines(header);
  std::string line;
  int elements = 0;
  while (std::getline(lines, line)) elements += line.rfind("element ", 0) == 0 ? 1 : 0;
  EXPECT_EQ(elements, 2);
}

}  // namespace
