// Outputs made of several files (an OBJ and its MTL, per-label folders)
// replace the old files only once every new one is complete. A full disk is
// simulated with a file size limit: writes beyond it fail as they would on a
// full disk.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <set>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"
#include "test_mesh_checks.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::blockKeys;

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::set<std::string> namesIn(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    names.insert(entry.path().filename().string());
  return names;
}

// Label 1: one voxel (small files); label 2: a 20^3 block (large files
// without coplanar merging).
lom::LabelMap smallAndLargeLabels() {
  return lom::test::MapBuilder(3, 0.01)
      .occupy(blockKeys(-5, -4, 0, 1, 0, 1), 1)
      .occupy(blockKeys(0, 20, 0, 20, 0, 20), 2)
      .build();
}

// The hidden temporary file of a writer killed outright (kill -9) is removed
// by the next write into its folder once it is an hour old and its process
// is gone; anything else that looks alike stays.
TEST(StagedOutputs, TemporaryFilesOfKilledWritersAreRemovedByTheNextWrite) {
  lom::test::TempDir dir;
  const pid_t gone = ::fork();  // an id of a process that has ended
  ASSERT_GE(gone, 0);
  if (gone == 0) ::_exit(0);
  ::waitpid(gone, nullptr, 0);
  const std::string dead = std::to_string(gone);
  const std::string alive = std::to_string(::getppid());
  const auto made = [&](const std::string& name, std::chrono::hours age) {
    std::ofstream(dir / name) << "partial\n";
    fs::last_write_time(dir / name, fs::file_time_type::clock::now() - age);
  };
  made(".map.tmp" + dead + "-123456.ot", std::chrono::hours(2));   // abandoned
  made(".report.tmp" + dead + "-7.json", std::chrono::hours(30));  // abandoned
  made(".boxes.tmp" + dead + "-8.json", std::chrono::hours(0));    // too recent
  made(".map.tmp" + alive + "-9.ot", std::chrono::hours(2));       // its process runs
  made(".notes.tmp" + dead + ".txt", std::chrono::hours(2));       // another name
  made("map.tmp" + dead + "-1.ot", std::chrono::hours(2));         // not hidden
  lom::writeTextFileAtomically(dir / "new.txt", "new\n");
  EXPECT_EQ(
      namesIn(dir.path()),
      (std::set<std::string>{".boxes.tmp" + dead + "-8.json", ".map.tmp" + alive + "-9.ot",
                             ".notes.tmp" + dead + ".txt", "map.tmp" + dead + "-1.ot", "new.txt"}));
}

TEST(StagedOutputs, AFailedObjLeavesTheOldObjAndMtlTogether) {
  lom::test::TempDir dir;
  std::ofstream(dir / "map.obj") << "old obj\n";
  std::ofstream(dir / "map.mtl") << "old mtl\n";
  const lom::LabelMap map = smallAndLargeLabels();
  lom::ExportOptions options;
  options.format = lom::ExportFormat::Obj;
  options.merge_coplanar = false;
  {
    const lom::test::FileSizeLimit limit(16 * 1024);  // room for the MTL, not for the OBJ
    EXPECT_THROW((void)lom::exportMap(map, options, dir / "map.obj"), lom::Error);
  }
  EXPECT_EQ(readText(dir / "map.obj"), "old obj\n");
  EXPECT_EQ(readText(dir / "map.mtl"), "old mtl\n");
  EXPECT_EQ(namesIn(dir.path()), (std::set<std::string>{"map.obj", "map.mtl"}));

  // Without the limit both are replaced.
  (void)lom::exportMap(map, options, dir / "map.obj");
  EXPECT_NE(readText(dir / "map.mtl").find("newmtl"), std::string::npos);
  EXPECT_NE(readText(dir / "map.obj").find("mtllib map.mtl"), std::string::npos);
}

TEST(StagedOutputs, WriteMeshesObjTouchesNoFileWhenTheObjCannotBeWritten) {
  lom::test::TempDir dir;
  std::ofstream(dir / "m.mtl") << "old mtl\n";
  lom::SurfaceMesh mesh = lom::voxelSurface(blockKeys(0, 1, 0, 1, 0, 1), 0.01);
  mesh.label = 1;
  const lom::LabelSet labels({{0, "bg", {0, 0, 0}}, {1, "one", {1, 2, 3}}});
  EXPECT_THROW(lom::writeMeshesObj({mesh}, labels, dir / "missing" / "m.obj", dir / "m.mtl"),
               lom::Error);
  EXPECT_EQ(readText(dir / "m.mtl"), "old mtl\n");
  EXPECT_EQ(namesIn(dir.path()), (std::set<std::string>{"m.mtl"}));
}

TEST(StagedOutputs, PerLabelFilesAreReplacedAllOrNone) {
  lom::test::TempDir dir;
  const lom::LabelMap map = smallAndLargeLabels();
  const std::string one = lom::labelFileStem(map.labels().at(1), map.numLabels()) + ".ply";
  const std::string two = lom::labelFileStem(map.labels().at(2), map.numLabels()) + ".ply";
  fs::create_directories(dir / "out");
  std::ofstream(dir / "out" / one) << "old 1\n";
  std::ofstream(dir / "out" / two) << "old 2\n";
  lom::ExportOptions options;
  options.format = lom::ExportFormat::Ply;
  options.per_label = true;
  options.merge_coplanar = false;
  {
    const lom::test::FileSizeLimit limit(16 * 1024);  // label 1's file fits, label 2's does not
    EXPECT_THROW((void)lom::exportMap(map, options, dir / "out"), lom::Error);
  }
  EXPECT_EQ(readText(dir / "out" / one), "old 1\n");
  EXPECT_EQ(readText(dir / "out" / two), "old 2\n");
  EXPECT_EQ(namesIn(dir / "out"), (std::set<std::string>{one, two}));  // nothing left behind

  const lom::ExportSummary summary = lom::exportMap(map, options, dir / "out");
  ASSERT_EQ(summary.files.size(), 2u);
  EXPECT_EQ(summary.files[0], dir / "out" / one);
  EXPECT_EQ(summary.files[1], dir / "out" / two);
  EXPECT_EQ(readText(dir / "out" / one).rfind("ply\n", 0), 0u);
  EXPECT_EQ(namesIn(dir / "out"), (std::set<std::string>{one, two}));
}

TEST(StagedOutputs, PerLabelPointCloudsAreReplacedAllOrNone) {
  lom::test::TempDir dir;
  const lom::LabelMap map = smallAndLargeLabels();
  const std::string one = lom::labelFileStem(map.labels().at(1), map.numLabels()) + ".pcd";
  fs::create_directories(dir / "out");
  std::ofstream(dir / "out" / one) << "old 1\n";
  lom::ExportOptions options;
  options.format = lom::ExportFormat::Pcd;
  options.per_label = true;
  {
    const lom::test::FileSizeLimit limit(16 * 1024);  // 8000 points of label 2 need about 160 KB
    EXPECT_THROW((void)lom::exportMap(map, options, dir / "out"), lom::Error);
  }
  EXPECT_EQ(readText(dir / "out" / one), "old 1\n");
  EXPECT_EQ(namesIn(dir / "out"), (std::set<std::string>{one}));
}

TEST(StagedOutputs, StagedFilesNotCommittedAreRemoved) {
  lom::test::TempDir dir;
  {
    lom::StagedFiles files;
    files.add(dir / "a.txt", [](std::ostream& out) { out << "a"; });
    files.add(dir / "b.txt", [](std::ostream& out) { out << "b"; });
    EXPECT_EQ(namesIn(dir.path()).size(), 2u);  // the temporary files
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
  lom::StagedFiles files;
  files.add(dir / "a.txt", [](std::ostream& out) { out << "a"; });
  files.add(dir / "b.txt", [](std::ostream& out) { out << "b"; });
  files.commit();
  EXPECT_EQ(namesIn(dir.path()), (std::set<std::string>{"a.txt", "b.txt"}));
  EXPECT_EQ(readText(dir / "b.txt"), "b");
}

// Output folders a failed command created go again, but a symbolic link
// that led nowhere (a drive not mounted) was not created by it and stays.
TEST(StagedOutputs, ANewFolderIsRemovedButADanglingLinkStays) {
  lom::test::TempDir dir;
  {
    lom::NewFolders folders(dir / "new" / "deeper");
    fs::create_directories(dir / "new" / "deeper");
  }
  EXPECT_FALSE(fs::exists(dir / "new")) << "made, unused, removed";
  fs::create_directory_symlink(dir / "nowhere", dir / "link");
  { lom::NewFolders folders(dir / "link"); }
  EXPECT_TRUE(fs::is_symlink(dir / "link"));
}

// "link/.." is the folder above the link's target, as the kernel resolves
// it: the folders made for an output are found, and removed, there.
TEST(StagedOutputs, NewFoldersBehindALinkAndDotsAreTheOnesTheKernelMakes) {
  lom::test::TempDir dir;
  fs::create_directories(dir / "a" / "b");
  fs::create_directories(dir / "work");
  fs::create_directory_symlink(dir / "a" / "b", dir / "work" / "link");
  const fs::path out = dir / "work" / "link" / ".." / "new" / "." / "x";
  const std::vector<fs::path> missing = lom::missingFolders(out);
  ASSERT_EQ(missing.size(), 2u);
  EXPECT_EQ(missing[0].filename(), "x");
  EXPECT_EQ(missing[1].filename(), "new");
  {
    const lom::NewFolders made(out);
    fs::create_directories(out);
    ASSERT_TRUE(fs::is_directory(dir / "a" / "new" / "x"));
  }
  EXPECT_FALSE(fs::exists(dir / "a" / "new")) << "the folders made behind the link are gone";
  EXPECT_TRUE(fs::is_directory(dir / "a" / "b"));
  EXPECT_TRUE(fs::is_symlink(dir / "work" / "link"));
  // "new/.." needs new, made on the way: it goes again too.
  const fs::path around = dir / "out" / "new" / ".." / "seq";
  EXPECT_EQ(lom::missingFolders(around).size(), 3u);
  {
    const lom::NewFolders made(around);
    fs::create_directories(around);
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(LibraryWrites, AFailureOnANearlyFullDiskSaysSo) {
  EXPECT_EQ(lom::libraryWriteFailure(std::uint64_t{0}, "VTK"), "write failed (disk full?)");
  EXPECT_EQ(lom::libraryWriteFailure(std::uint64_t{64} << 10, "OpenCV"),
            "write failed (disk full?)");
  EXPECT_EQ(lom::libraryWriteFailure(std::uint64_t{5} << 30, "PCL"), "PCL could not write it");
  // With room on the disk but a limit on the size of files (ulimit -f), the limit.
  EXPECT_EQ(lom::libraryWriteFailure(std::uint64_t{5} << 30, "VTK", std::uint64_t{1} << 10),
            "write failed (the file-size limit of 1 KiB set by ulimit -f?)");
  EXPECT_EQ(lom::libraryWriteFailure(std::uint64_t{5} << 30, "VTK", std::uint64_t{3} << 29),
            "write failed (the file-size limit of 1.5 GiB set by ulimit -f?)");
  EXPECT_EQ(lom::libraryWriteFailure(std::uint64_t{0}, "VTK", std::uint64_t{1} << 10),
            "write failed (disk full?)");
  // The temporary folder of a test machine is not full.
  lom::test::TempDir dir;
  EXPECT_EQ(lom::libraryWriteFailure(dir / "map.stl", "VTK"), "VTK could not write it");
}

TEST(LibraryWrites, SavingThroughASymbolicLinkReplacesTheFileItPointsTo) {
  lom::test::TempDir dir;
  fs::create_directories(dir / "shared");
  std::ofstream(dir / "shared" / "boxes.json") << "old";
  fs::create_symlink(dir / "shared" / "boxes.json", dir / "annotations.json");
  lom::writeTextFileAtomically(dir / "annotations.json", "new");
  EXPECT_TRUE(fs::is_symlink(dir / "annotations.json"));
  std::ifstream in(dir / "shared" / "boxes.json");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "new");
  // Nothing is left beside the link or the file.
  size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir.path()))
    files += entry.is_regular_file() && !entry.is_symlink();
  EXPECT_EQ(files, 1u);
}

// A link set up before its file exists (a folder of ground truth shared by
// several sequences, before the first save) makes the file where it points,
// link by link (a relative link is relative to its own folder), and stays a
// link; one into a folder that does not exist fails, naming that folder, and
// is kept as it was.
TEST(LibraryWrites, SavingThroughALinkToAFileNotMadeYetMakesThatFile) {
  lom::test::TempDir dir;
  fs::create_directories(dir / "gt");
  fs::create_directories(dir / "seq");
  fs::create_symlink(fs::path("..") / "gt" / "hop.json", dir / "seq" / "annotations.json");
  fs::create_symlink("boxes.json", dir / "gt" / "hop.json");
  lom::writeTextFileAtomically(dir / "seq" / "annotations.json", "new");
  EXPECT_TRUE(fs::is_symlink(dir / "seq" / "annotations.json"));
  EXPECT_TRUE(fs::is_symlink(dir / "gt" / "hop.json"));
  ASSERT_TRUE(fs::is_regular_file(dir / "gt" / "boxes.json"));
  EXPECT_EQ(readText(dir / "gt" / "boxes.json"), "new");
  EXPECT_EQ(lom::writtenFileOf(dir / "seq" / "annotations.json"),
            fs::canonical(dir / "gt" / "boxes.json"));

  fs::create_symlink(dir / "missing" / "boxes.json", dir / "seq" / "nowhere.json");
  try {
    lom::writeTextFileAtomically(dir / "seq" / "nowhere.json", "lost?");
    ADD_FAILURE() << "wrote through a link into a folder that does not exist";
  } catch (const lom::Error& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "missing").string()), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::is_symlink(dir / "seq" / "nowhere.json"));
  EXPECT_FALSE(fs::exists(dir / "missing"));

  // A cycle is no file to make: the link itself is written.
  fs::create_symlink("b.json", dir / "seq" / "a.json");
  fs::create_symlink("a.json", dir / "seq" / "b.json");
  EXPECT_EQ(lom::writtenFileOf(dir / "seq" / "a.json"), dir / "seq" / "a.json");
}

}  // namespace
