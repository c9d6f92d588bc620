// labeloctomap export / render end to end on a fused synthetic sequence; the
// meshes are opened with assimp (Debian package assimp-utils) as other tools would.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

#include "lom/export.hpp"
#include "lom/label_map.hpp"
#include "lom/objects.hpp"
#include "lom/sequence.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::runCli;
using lom::test::slurp;
using lom::test::TempDir;

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }  // for the shell

bool onPath(const std::string& program) {
  return std::system(("command -v " + program + " >/dev/null 2>&1").c_str()) == 0;
}

// The number after "wrote " in the command's output.
size_t written(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex("wrote ([0-9]+) "))) return 0;
  return std::stoul(m[1]);
}

// Runs `assimp info FILE`; returns its exit code and the "Faces:" count.
std::pair<int, long> assimpInfo(const fs::path& file) {
  TempDir dir;
  const std::string command = "assimp info " + q(file) + " >" + q(dir / "out.txt") + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(dir / "out.txt");
  std::stringstream text;
  text << in.rdbuf();
  std::smatch m;
  const std::string s = text.str();
  long faces = -1;
  if (std::regex_search(s, m, std::regex("\nFaces:\\s+([0-9]+)"))) faces = std::stol(m[1]);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, faces};
}

class CliExportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    auto r = runCli("synth --out " + q(dir_->path() / "scene") +
                    " --seed 3 --objects 4 --frames 4 --views 3 --width 160 --height 120");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = runCli("fuse " + q(dir_->path() / "scene") + " --out " + q(map()) +
               " --resolution 0.01 --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path map() { return dir_->path() / "map.ot"; }
  static fs::path scene() { return dir_->path() / "scene"; }
  static TempDir* dir_;
};
TempDir* CliExportTest::dir_ = nullptr;

// A colour octree never replaces a labelled map (another sequence's, say):
// the file left would hold no label, and no command reads it as a map.
TEST_F(CliExportTest, AColourOctreeNeverReplacesALabelledMap) {
  TempDir out;
  const fs::path other = out / "other.ot";
  fs::copy_file(map(), other);
  const std::string before = slurp(other);
  auto r = runCli("export " + q(map()) + " --format ot --out " + q(other));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("holds a labelled map (LabelOcTree): format ot would replace it without "
                       "its labels"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(other), before);
  // The labelled map itself may replace it; a colour octree replaces a colour octree.
  r = runCli("export " + q(map()) + " --format ot --native --out " + q(other));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = runCli("export " + q(map()) + " --format ot --out " + q(out / "colour.ot"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = runCli("export " + q(map()) + " --format ot --out " + q(out / "colour.ot"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(CliExportTest, EveryMeshFormatOpensInAssimp) {
  if (!onPath("assimp"))
    GTEST_SKIP() << "assimp is not on PATH (Debian package assimp-utils); skipping";
  TempDir out;
  struct Case {
    std::string args;
    fs::path file;
  };
  const std::vector<Case> cases = {
      {"--format ply", out / "map.ply"},
      {"--format obj", out / "map.obj"},
      {"--format stl", out / "map.stl"},
      {"--format ply --smooth", out / "smooth.ply"},
      {"--format obj --smooth --labels 0", out / "smooth.obj"},
      {"--format stl --no-merge", out / "unit.stl"},
  };
  for (const auto& c : cases) {
    const auto r = runCli("export " + q(map()) + " " + c.args + " --out " + q(c.file));
    ASSERT_EQ(r.exit_code, 0) << c.args << ": " << r.err;
    const size_t triangles = written(r.out);
    EXPECT_GT(triangles, 100u) << c.args << ": " << r.out;
    const auto [code, faces] = assimpInfo(c.file);
    EXPECT_EQ(code, 0) << c.args;
    EXPECT_EQ(faces, static_cast<long>(triangles)) << c.args;
  }
  // One file per label, each opening on its own.
  const auto r =
      runCli("export " + q(map()) + " --format ply --per-label --out " + q(out / "labels"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(out / "labels")) {
    ++files;
    EXPECT_EQ(assimpInfo(entry.path()).first, 0) << entry.path();
  }
  EXPECT_GE(files, 4u);
}

TEST_F(CliExportTest, PerLabelFilesAreNamedByLabelIdAndName) {
  TempDir out;
  const lom::LabelMap m = lom::LabelMap::load(map());
  const auto r =
      runCli("export " + q(map()) + " --format obj --per-label --out " + q(out / "meshes"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::set<std::string> expected, found;
  for (const auto& [label, count] : m.occupiedCountPerLabel()) {
    const std::string stem = lom::labelFileStem(m.labels().at(label), m.numLabels());
    expected.insert(stem + ".obj");
    expected.insert(stem + ".mtl");
  }
  for (const auto& entry : fs::directory_iterator(out / "meshes"))
    found.insert(entry.path().filename().string());
  EXPECT_EQ(found, expected);
}

// A per-label export into a folder that holds an earlier one's files (of
// labels this export leaves out) names them: they stay (they may be the
// user's), but the folder no longer holds one map's objects. Files of other
// formats and other names are not counted.
TEST_F(CliExportTest, PerLabelExportNamesTheFilesOfAnEarlierExportLeftInItsFolder) {
  TempDir out;
  const lom::LabelMap m = lom::LabelMap::load(map());
  std::vector<int> labels;
  for (const auto& [label, count] : m.occupiedCountPerLabel()) labels.push_back(label);
  ASSERT_GE(labels.size(), 3u);
  const auto first =
      runCli("export " + q(map()) + " --format obj --per-label --out " + q(out / "meshes"));
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(first.err.find("not from this export"), std::string::npos) << first.err;
  std::ofstream(out / "meshes" / "notes.obj") << "# the user's\n";
  std::ofstream(out / "meshes" / "01_mine.ply") << "ply\n";
  const auto again = runCli("export " + q(map()) + " --format obj --per-label --labels " +
                            std::to_string(labels[1]) + " --out " + q(out / "meshes"));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const size_t earlier = 2 * (labels.size() - 1);  // an OBJ and its MTL per label left out
  EXPECT_NE(again.err.find("note: " + std::to_string(earlier) + " files in "), std::string::npos)
      << again.err;
  const std::string left = lom::labelFileStem(m.labels().at(labels[0]), m.numLabels());
  EXPECT_NE(again.err.find(left + ".mtl, " + left + ".obj"), std::string::npos) << again.err;
  EXPECT_EQ(again.err.find("notes.obj"), std::string::npos) << again.err;
  EXPECT_EQ(again.err.find("01_mine.ply"), std::string::npos) << again.err;
  EXPECT_TRUE(fs::exists(out / "meshes" / (left + ".obj")));
  EXPECT_TRUE(fs::exists(out / "meshes" / "notes.obj"));
}

// OBJ cannot quote the material file's name: a space in it loses the colours
// in OBJ readers, which the command says.
TEST_F(CliExportTest, AnObjNamedWithASpaceGetsANote) {
  TempDir out;
  const auto spaced = runCli("export " + q(map()) + " --format obj --out " + q(out / "my map.obj"));
  ASSERT_EQ(spaced.exit_code, 0) << spaced.err;
  EXPECT_NE(spaced.err.find("note: OBJ readers split the mtllib line at spaces: they will not find "
                            "my map.mtl"),
            std::string::npos)
      << spaced.err;
  EXPECT_TRUE(fs::exists(out / "my map.mtl"));
  const auto plain = runCli("export " + q(map()) + " --format obj --out " + q(out / "my_map.obj"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(plain.err.find("note:"), std::string::npos) << plain.err;
}

// --level: the fused map records its cameras, so it has an up to turn onto
// +z; a map without any (a v1 file, a generated one) needs --sequence; and
// octrees and boxes stay in the map's frame.
TEST_F(CliExportTest, LevelTurnsTheMapsUpOntoZAndSaysHow) {
  TempDir out;
  auto r = runCli("export " + q(map()) + " --format ply --level --out " + q(out / "level.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("levelled: the map's up ("), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("turned onto +z about the origin, x' = R x with R = ["), std::string::npos)
      << r.out;
  EXPECT_NE(slurp(out / "level.ply").find("comment frame: levelled"), std::string::npos);

  for (const char* format : {"ot", "bt", "objects"}) {
    const std::string file =
        std::string("level.") + (std::string(format) == "objects" ? "json" : format);
    r = runCli("export " + q(map()) + " --format " + format + " --level --out " + q(out / file));
    EXPECT_EQ(r.exit_code, 2) << format << r.err;
    EXPECT_NE(r.err.find("option --level applies to the mesh and point cloud formats"),
              std::string::npos)
        << r.err;
  }

  lom::LabelMap bare(lom::LabelMap::load(map()).labels());  // records no camera
  lom::OrientedBox block;
  block.size = Eigen::Vector3d(0.05, 0.05, 0.05);
  ASSERT_GT(lom::rasterizeBox(bare, block, 1, 0.9), 0u);
  bare.save(out / "bare.ot");
  r = runCli("export " + q(out / "bare.ot") + " --format pcd --level --out " + q(out / "b.pcd"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("bare.ot: --level: expected a map that records the cameras it was fused "
                       "from (or --sequence SEQ"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out / "b.pcd"));
  r = runCli("export " + q(out / "bare.ot") + " --format pcd --level --sequence " + q(scene()) +
             " --out " + q(out / "b.pcd"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "b.pcd"));
}

TEST_F(CliExportTest, LabelSelectionWritesOnlyThoseLabels) {
  TempDir out;
  const lom::LabelMap m = lom::LabelMap::load(map());
  const auto counts = m.occupiedCountPerLabel();
  ASSERT_GE(counts.size(), 3u);
  const int a = std::next(counts.begin())->first, b = std::next(counts.begin(), 2)->first;
  const auto r = runCli("export " + q(map()) + " --format pcd --labels " + std::to_string(a) + "," +
                        std::to_string(b) + " --out " + q(out / "ab.pcd"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(written(r.out), counts.at(a) + counts.at(b));
}

TEST_F(CliExportTest, OctreesAndObjectsAreWritten) {
  TempDir out;
  for (const std::string format : {"ot", "bt"}) {
    const auto r = runCli("export " + q(map()) + " --format " + format + " --out " +
                          q(out / ("map." + format)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_GT(written(r.out), 0u);
  }
  // A label selection needs occupied voxels of its labels, octrees included;
  // a label without any is reported and skipped.
  const auto counts = lom::LabelMap::load(map()).occupiedCountPerLabel();
  int absent = 1;
  while (counts.count(absent)) ++absent;
  const int present = std::next(counts.begin())->first;
  for (const std::string format : {"ot", "bt"}) {
    auto r = runCli("export " + q(map()) + " --format " + format + " --labels " +
                    std::to_string(absent) + " --out " + q(out / ("none." + format)));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.err.find("without any occupied voxel"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / ("none." + format)));
    r = runCli("export " + q(map()) + " --format " + format + " --labels " +
               std::to_string(present) + "," + std::to_string(absent) + " --out " +
               q(out / ("some." + format)));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("note: label " + std::to_string(absent) + " "), std::string::npos)
        << r.err;
  }
  std::ifstream ot(out / "map.ot");
  std::string first;
  std::getline(ot, first);
  EXPECT_EQ(first, "# Octomap OcTree file");
  auto r = runCli("export " + q(map()) + " --format ot --native --out " + q(out / "n.ot"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lom::LabelMap::load(out / "n.ot").occupiedCountPerLabel(),
            lom::LabelMap::load(map()).occupiedCountPerLabel());
  r = runCli("export " + q(map()) + " --format objects --out " + q(out / "objects.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream json(out / "objects.json");
  std::stringstream text;
  text << json.rdbuf();
  EXPECT_NE(text.str().find("\"format\": \"labeloctomap-objects\""), std::string::npos);
  EXPECT_EQ(text.str().find("\"label\": 0,"), std::string::npos);  // the background is no object
}

// A map that records no camera (built here without any) has its boxes stand
// on the world's +z, said on stderr; --sequence gives them its cameras' up.
// Boxes that leave out much of their label say so too.
TEST_F(CliExportTest, ObjectsOfAMapWithoutCamerasSayWhichUpTheyStandOn) {
  TempDir out;
  lom::LabelMap bare(lom::loadSequence(scene()).labels);
  lom::OrientedBox big;
  big.center = Eigen::Vector3d(0.3, 0.0, 0.1);
  big.size = Eigen::Vector3d(0.2, 0.2, 0.1);
  lom::OrientedBox far = big;
  far.center.x() = -0.3;
  far.size = Eigen::Vector3d(0.1, 0.1, 0.1);
  ASSERT_GT(lom::rasterizeBox(bare, big, 1, 0.9), 0u);
  ASSERT_GT(lom::rasterizeBox(bare, far, 1, 0.9), 0u);
  bare.save(out / "bare.ot");
  const std::string bare_map = q(out / "bare.ot");
  auto r = runCli("export " + bare_map + " --format objects --out " + q(out / "o.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("note: " + (out / "bare.ot").string() +
                       " does not record which way up its cameras were"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("the object boxes stand on the world's +z axis; --sequence SEQ"),
            std::string::npos)
      << r.err;
  const std::string name = lom::loadSequence(scene()).labels.at(1).name;
  EXPECT_NE(r.err.find("note: the box of label 1 (" + name +
                       ") holds the 4000 voxels of its "
                       "largest cluster; 1000 more of its 5000 lie in another cluster, left out"),
            std::string::npos)
      << r.err;
  r = runCli("export " + bare_map + " --format objects --sequence " + q(scene()) + " --out " +
             q(out / "s.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("does not record which way up"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "s.json"));
  // The fused map records its cameras: nothing to say.
  r = runCli("export " + q(map()) + " --format objects --out " + q(out / "f.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("does not record which way up"), std::string::npos) << r.err;
  // --sequence is for object boxes only.
  r = runCli("export " + bare_map + " --format ply --sequence " + q(scene()) + " --out " +
             q(out / "m.ply"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("option --sequence goes only with --format objects"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out / "m.ply"));
}

TEST_F(CliExportTest, MistakesGiveClearMessagesAndNoFile) {
  TempDir out;
  auto r = runCli("export " + q(map()) + " --out " + q(out / "m.ply"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--format"), std::string::npos) << r.err;
  r = runCli("export " + q(map()) + " --format fbx --out " + q(out / "m.fbx"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("ply, obj, stl, pcd, ot, bt or objects"), std::string::npos) << r.err;
  r = runCli("export " + q(map()) + " --format ply --labels 99 --out " + q(out / "m.ply"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("labels"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("99"), std::string::npos) << r.err;
  r = runCli("export " + q(map()) + " --format ply --out " + q(out / "m.stl"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(".ply"), std::string::npos) << r.err;
  r = runCli("export " + q(map()) + " --format pcd --smooth --out " + q(out / "m.pcd"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("smooth"), std::string::npos) << r.err;
  // --no-merge changes only the voxel meshes: elsewhere it would do nothing.
  for (const std::string options : {"--format pcd", "--format ot", "--format ply --points",
                                    "--format ply --smooth", "--format objects"}) {
    const std::string name = options == "--format pcd"       ? "m.pcd"
                             : options == "--format ot"      ? "m.ot"
                             : options == "--format objects" ? "m.json"
                                                             : "m.ply";
    r = runCli("export " + q(map()) + " " + options + " --no-merge --out " + q(out / name));
    EXPECT_EQ(r.exit_code, 2) << options;
    EXPECT_NE(r.err.find("--no-merge applies to the voxel meshes"), std::string::npos) << r.err;
  }
  r = runCli("export " + q(map()) + " --voxels " + q(out / "v.pcd") + " --format ply");
  EXPECT_EQ(r.exit_code, 2);
  r = runCli("export " + q(map()) + " --format ot --out " + q(map()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("input map"), std::string::npos) << r.err;
  // A folder in the way of the output's folder is named as a file.
  std::ofstream(out / "afile") << "x";
  r = runCli("export " + q(map()) + " --format ply --out " + q(out / "afile" / "m.ply"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((out / "afile").string() + " is a file, not a folder"), std::string::npos)
      << r.err;
  fs::remove(out / "afile");
  EXPECT_TRUE(fs::is_empty(out.path()));
  EXPECT_NO_THROW((void)lom::LabelMap::load(map()));
}

// A full disk (here: a limit on the size of any file written) fails every
// export with one line of the product's own, keeps the file it would have
// replaced and leaves nothing half-written. PCL's PLY writer does not notice a
// failed write itself: its file is checked after writing.
TEST_F(CliExportTest, AFullDiskFailsEveryExportAndKeepsTheOldFile) {
  TempDir out;
  lom::test::CliLimits full_disk;
  full_disk.file_kib = 1;
  const std::vector<std::pair<std::string, std::string>> exports = {
      {"--format ply", "m.ply"},          {"--format ply --points", "p.ply"},
      {"--format obj", "m.obj"},          {"--format stl", "m.stl"},
      {"--format pcd", "m.pcd"},          {"--voxels", "v.pcd"},
      {"--format ot", "m.ot"},            {"--format bt", "m.bt"},
      {"--format ply --per-label", "per"}};
  for (const auto& [options, name] : exports) {
    SCOPED_TRACE(options);
    const fs::path target = out / name;
    if (name != "per") std::ofstream(target) << "an earlier file";
    const std::string where = options == "--voxels" ? " " : " --out ";
    const auto r = runCli("export " + q(map()) + " " + options + where + q(target), full_disk);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err.rfind("labeloctomap export: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // The limit is the likely cause here, whichever library wrote the file.
    EXPECT_NE(r.err.find("(the file-size limit of "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(" set by ulimit -f?)"), std::string::npos) << r.err;
    if (name != "per") {
      std::ifstream in(target);
      std::string kept;
      std::getline(in, kept);
      EXPECT_EQ(kept, "an earlier file");
    } else {
      EXPECT_FALSE(fs::exists(target)) << "the folder it created is taken away again";
      // The file named is where it was going, not the staging folder gone with it.
      EXPECT_NE(r.err.find((target / "00___background__.ply").string() + ": "), std::string::npos)
          << r.err;
    }
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(out.path()), fs::directory_iterator()), 8)
      << "no temporary file left";
}

TEST_F(CliExportTest, RenderWithoutDisplaySaysHowToRunIt) {
  TempDir out;
  const char* saved = std::getenv("DISPLAY");
  const std::string display = saved ? saved : "";
  ::unsetenv("DISPLAY");
  const auto r = runCli("render " + q(map()) + " --out " + q(out / "view.png"));
  if (!display.empty()) ::setenv("DISPLAY", display.c_str(), 1);
  EXPECT_EQ(r.exit_code, 3);
  if (r.err.find("built without the VTK rendering library") != std::string::npos)
    GTEST_SKIP() << "this labeloctomap cannot render at all (configured with LOM_BUILD_UI=OFF)";
  EXPECT_NE(r.err.find("X server"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("xvfb-run"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "view.png"));
}

// An X server without GLX (some VNC servers), or OpenGL only through
// indirect GLX (ssh -X; LIBGL_ALWAYS_INDIRECT stands in for it): VTK would
// abort the process or crash; render says why and exits 3 like without a
// display.
TEST_F(CliExportTest, RenderOnADisplayWithoutGlxSaysWhyAndExits3) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (Debian's xvfb package)";
  TempDir out;
  std::ofstream(out / "view.png") << "an earlier picture";
  for (const std::string setup : {"-s '-screen 0 320x240x24 -extension GLX'",
                                  "-s '-screen 0 320x240x24 +iglx' env LIBGL_ALWAYS_INDIRECT=1"}) {
    SCOPED_TRACE(setup);
    // The program's own exit status, written by the shell it runs in:
    // xvfb-run's may be its own ("problem while cleaning up temporary
    // directory" exits 5 when other X servers come and go meanwhile).
    fs::remove(out / "status.txt");
    const std::string command = "xvfb-run -a " + setup + " sh -c \"'" + std::string(LOM_CLI_PATH) +
                                "' render " + q(map()) + " --out " + q(out / "view.png") + " 2>" +
                                q(out / "err.txt") + "; echo \\$? >" + q(out / "status.txt") + "\"";
    const int status = std::system(command.c_str());
    const std::string err = slurp(out / "err.txt");
    if (err.find("built without the VTK rendering library") != std::string::npos)
      GTEST_SKIP() << "this labeloctomap cannot render at all (configured with LOM_BUILD_UI=OFF)";
    ASSERT_TRUE(fs::exists(out / "status.txt")) << "xvfb-run status " << status << "\n" << err;
    EXPECT_EQ(slurp(out / "status.txt"), "3\n") << err;
    EXPECT_NE(err.find("gives no OpenGL context drawn on this machine"), std::string::npos) << err;
    EXPECT_EQ(slurp(out / "view.png"), "an earlier picture");
  }
}

TEST_F(CliExportTest, RenderWritesAPictureOfTheMap) {
  if (!std::getenv("DISPLAY") || !*std::getenv("DISPLAY"))
    GTEST_SKIP() << "DISPLAY is not set: rendering needs an X server (run under xvfb-run)";
  TempDir out;
  auto r = runCli("render " + q(map()) + " --out " + q(out / "orbit.png") +
                  " --size 320x240 --azimuth 200 --elevation 35");
  if (r.exit_code == 3) GTEST_SKIP() << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const lom::ColorImage orbit = lom::readColorImage(out / "orbit.png");
  EXPECT_EQ(orbit.width, 320);
  EXPECT_EQ(orbit.height, 240);
  size_t not_background = 0;
  for (size_t i = 0; i < orbit.rgb.size(); i += 3)
    not_background += !(orbit.rgb[i] == 255 && orbit.rgb[i + 1] == 255 && orbit.rgb[i + 2] == 255);
  EXPECT_GT(not_background, orbit.rgb.size() / 3 / 20);
  // The map was fused from the generated scene's cameras, whose world has z up.
  EXPECT_NE(
      r.out.find(
          "the normal of the map's largest level plane, near the mean up of its 4 camera views"),
      std::string::npos)
      << r.out;
  // Every voxel framed: nothing is left out, so nothing is said about it.
  r = runCli("render " + q(map()) + " --out " + q(out / "all.png") + " --size 320x240 --frame all");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("framed:"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out / "all.png"));
  r = runCli("render " + q(map()) + " --out " + q(out / "up.png") + " --size 320x240 --up 0,-2,0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("up in the picture: (0, -1, 0), given with --up"), std::string::npos)
      << r.out;
  // A labelled map keeps its label colours unless height is asked for.
  EXPECT_EQ(r.out.find("colours: height"), std::string::npos) << r.out;
  r = runCli("render " + q(map()) + " --out " + q(out / "height.png") +
             " --size 320x240 --colour height --flat");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Along the picture's up (the cameras' mean up), asked for: no note about the default.
  EXPECT_NE(r.out.find("colours: height along ("), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("), blue lowest to red highest\n"), std::string::npos) << r.out;
  const lom::ColorImage height = lom::readColorImage(out / "height.png");
  size_t red = 0;
  for (size_t i = 0; i < height.rgb.size(); i += 3)
    red += height.rgb[i] == 215 && height.rgb[i + 1] == 48 && height.rgb[i + 2] == 39;
  EXPECT_GT(red, 20u) << "no face at the top of the ramp";

  // A recorded camera: the picture has that camera's size.
  r = runCli("render " + q(map()) + " --out " + q(out / "frame.png") + " --camera " +
             q(fs::path(scene().string() + ":1")) + " --flat");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const lom::ColorImage frame = lom::readColorImage(out / "frame.png");
  EXPECT_EQ(frame.width, 160);
  EXPECT_EQ(frame.height, 120);

  r = runCli("render " + q(map()) + " --out " + q(out / "x.png") + " --camera " +
             q(fs::path(scene().string() + ":99")));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("frame index"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("which has 4 frames"), std::string::npos) << r.err;

  // Labels without voxels: the map and the option are named.
  const auto counts = lom::LabelMap::load(map()).occupiedCountPerLabel();
  int empty = 1;
  while (counts.count(empty)) ++empty;
  r = runCli("render " + q(map()) + " --out " + q(out / "empty.png") + " --labels " +
             std::to_string(empty));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(map().string() + ": --labels: expected labels with occupied voxels"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out / "empty.png"));
}

TEST_F(CliExportTest, RenderScoreColoursCountWhatTheScoreCounts) {
  if (!std::getenv("DISPLAY") || !*std::getenv("DISPLAY"))
    GTEST_SKIP() << "DISPLAY is not set: rendering needs an X server (run under xvfb-run)";
  TempDir out;
  const fs::path boxes = scene() / "annotations.json";
  auto r = runCli("render " + q(map()) + " --out " + q(out / "score.png") +
                  " --size 320x240 --flat --colour score --annotations " + q(boxes));
  if (r.exit_code == 3) GTEST_SKIP() << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("colours: each boxed label's voxels by how IU_3d (exact) counts them"),
            std::string::npos)
      << r.out;
  // Every scored object's line gives the IU_3d that `score --map` gives it.
  ASSERT_EQ(runCli("score " + q(scene()) + " --annotations " + q(boxes) + " --map " + q(map()) +
                   " --out " + q(out / "report") + " --quiet")
                .exit_code,
            0);
  const std::string report = slurp(out / "report" / "report.csv");
  std::istringstream rows(report);
  std::string row;
  std::getline(rows, row);  // header
  size_t objects = 0;
  while (std::getline(rows, row)) {
    std::vector<std::string> cells;
    std::stringstream fields(row);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 6u) << row;
    char iou[32];
    std::snprintf(iou, sizeof iou, "%.2f", std::stod(cells[5]) * 100.0);
    const std::string prefix = "  label " + cells[0] + " " + cells[1] + ": ";
    const size_t line = r.out.find(prefix);
    ASSERT_NE(line, std::string::npos) << prefix << "\n" << r.out;
    const std::string text = r.out.substr(line, r.out.find('\n', line) - line);
    if (cells[2] == "0") {
      EXPECT_EQ(text, prefix + "no voxels");
    } else {
      EXPECT_NE(text.find(" voxels inside, "), std::string::npos) << text;
      EXPECT_NE(text.find("; IU_3d " + std::string(iou)), std::string::npos)
          << text << " vs " << iou;
    }
    ++objects;
  }
  EXPECT_GT(objects, 1u);
  // Flat faces: the boxed objects in score colours (red where outside their
  // box), everything else white background or grey.
  const lom::ColorImage picture = lom::readColorImage(out / "score.png");
  size_t scored = 0, red = 0;
  for (size_t i = 0; i < picture.rgb.size(); i += 3) {
    const std::array<int, 3> p{picture.rgb[i], picture.rgb[i + 1], picture.rgb[i + 2]};
    const bool plain = p == std::array<int, 3>{255, 255, 255} ||
                       p == std::array<int, 3>{195, 195, 200} ||
                       p == std::array<int, 3>{150, 150, 160};
    scored += !plain;
    red += p == std::array<int, 3>{230, 45, 45};
  }
  EXPECT_GT(scored, 200u);
  EXPECT_GT(red, 0u);

  // A box of a label the map does not have: the file and the box are named.
  std::ofstream(out / "bad.json") << R"({"format": "labeloctomap-annotations", "version": 1,
    "frame_id": "world", "boxes": [{"label": 99, "center": [0, 0, 0], "size": [0.1, 0.1, 0.1],
    "rotation": [0, 0, 0, 1]}]})";
  r = runCli("render " + q(map()) + " --out " + q(out / "bad.png") +
             " --colour score --annotations " + q(out / "bad.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("boxes[0].label: expected an object label of the map"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out / "bad.png"));

  // A box named after another label than its own is painted as its label,
  // with score's warning (boxes drawn for another label numbering?).
  const lom::LabelMap labelled = lom::LabelMap::load(map());
  std::ofstream(out / "misnamed.json") << R"({"format": "labeloctomap-annotations", "version": 1,
    "frame_id": "world", "boxes": [{"label": 3, "name": "not_its_name", "center": [0, 0, 0],
    "size": [0.1, 0.1, 0.1], "rotation": [0, 0, 0, 1]}]})";
  r = runCli("render " + q(map()) + " --out " + q(out / "misnamed.png") +
             " --size 64x48 --colour score --annotations " + q(out / "misnamed.json"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + (out / "misnamed.json").string() +
                       ": boxes[0].name is 'not_its_name', but label 3 of " + map().string() +
                       " is '" + labelled.labels().at(3).name + "'"),
            std::string::npos)
      << r.err;
}

TEST_F(CliExportTest, RenderUsageMistakes) {
  TempDir out;
  auto r =
      runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --camera x:1 --azimuth 10");
  EXPECT_EQ(r.exit_code, 2);
  for (const char* up : {"0,0,0", "1,2", "1,nan,0", "x,y,z"}) {
    r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --up " + up);
    EXPECT_EQ(r.exit_code, 2) << up;
    EXPECT_NE(r.err.find("option --up expects a direction x,y,z"), std::string::npos) << r.err;
  }
  r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --camera x:1 --up 0,0,1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--up"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "v.png"));
  r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --frame most");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("option --frame expects bulk or all, got 'most'"), std::string::npos)
      << r.err;
  r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --camera " +
             q(scene().string() + ":0") + " --frame all");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--frame is for the orbit view"), std::string::npos) << r.err;
  r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --colour purple");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("option --colour expects labels, height or score, got 'purple'"),
            std::string::npos)
      << r.err;
  // Score colours need boxes, and boxes or an IoU mode need score colours.
  const std::string boxes = q(scene() / "annotations.json");
  const std::pair<std::string, std::string> mistakes[] = {
      {" --colour score", "--colour score needs --annotations"},
      {" --annotations " + boxes, "--annotations is for --colour score"},
      {" --colour height --iou exact", "--iou is for --colour score"},
      {" --colour score --annotations " + boxes + " --iou middle",
       "option --iou expects exact or center, got 'middle'"}};
  for (const auto& [args, message] : mistakes) {
    r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
  }
  for (const char* size : {"640", "640x", "x480", "640x480px", "64ax48", "0x480", "16385x10"}) {
    r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --size " + size);
    EXPECT_EQ(r.exit_code, 2) << size;
    EXPECT_NE(r.err.find("WIDTHxHEIGHT in pixels, each from 1 to 16384"), std::string::npos)
        << r.err;
  }
  // The frame index is checked to its last character (parsed from a part of the text).
  for (const char* camera : {"x:1a", "x:-1", "x:", ":1", "x"}) {
    r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --camera " + camera);
    EXPECT_EQ(r.exit_code, 2) << camera;
    EXPECT_NE(r.err.find("option --camera expects SEQ:INDEX"), std::string::npos) << r.err;
  }
  // A recorded camera's picture keeps the camera's shape (the scene's is 160x120).
  r = runCli("render " + q(map()) + " --out " + q(out / "v.png") + " --camera " +
             q(scene().string() + ":0") + " --size 120x120");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the camera's images are 160x120 and its picture keeps that shape"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out / "v.png"));
}

}  // namespace
