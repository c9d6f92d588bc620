// What the commands write: never one of their own inputs, never into a sequence folder they
// read (fuse, score), never a folder, device or FIFO given as a file, and only under the
// extension of what is written. Each refusal is a usage mistake (exit 2) made before any work.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "cli_scene_fixture.hpp"
#include "lom/label_map.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::q;
using lom::test::runCli;
using lom::test::slurp;
using lom::test::TempDir;

class CliOutputTest : public lom::test::CliSceneTest {};

void expectUsage(const lom::test::CliResult& r, const std::string& text) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
}

TEST_F(CliOutputTest, FuseNeverWritesIntoTheSequenceItReads) {
  TempDir out;
  const fs::path copy = out / "scene";
  fs::copy(scene(), copy, fs::copy_options::recursive);
  const std::string sequence = slurp(copy / "sequence.json");
  const std::string proba = slurp(copy / "proba" / "000000.npy");

  expectUsage(runCli("fuse " + q(copy) + " --out " + q(copy / "sequence.json") + " --quiet"),
              "ending in .ot");
  expectUsage(runCli("fuse " + q(copy) + " --out " + q(copy / "proba" / "000000.npy") + " --quiet"),
              "ending in .ot");
  expectUsage(
      runCli("fuse " + q(copy / "sequence.json") + " --out " + q(copy / "map.ot") + " --quiet"),
      "lies inside the input sequence folder");
  expectUsage(runCli("fuse " + q(copy) + " --out " + q(copy / "proba" / "map.ot") + " --quiet"),
              "lies inside the input sequence folder");
  // A frame file outside the sequence folder is an input too.
  fs::rename(copy / "proba" / "000001.npy", out / "frame1.ot");
  std::string text = sequence;
  const std::string name = "proba/000001.npy";
  text.replace(text.find(name), name.size(), "../frame1.ot");
  std::ofstream(copy / "sequence.json") << text;
  const std::string frame1 = slurp(out / "frame1.ot");
  expectUsage(runCli("fuse " + q(copy) + " --out " + q(out / "frame1.ot") + " --quiet"),
              "is the frame file");
  EXPECT_EQ(slurp(out / "frame1.ot"), frame1);

  EXPECT_EQ(slurp(copy / "proba" / "000000.npy"), proba);
  EXPECT_FALSE(fs::exists(copy / "map.ot"));
  EXPECT_FALSE(fs::exists(copy / "proba" / "map.ot"));
}

TEST_F(CliOutputTest, FuseWritesOnlyOtFiles) {
  TempDir out;
  const auto r = runCli("fuse " + q(scene()) + " --out " + q(out / "x.map") + " --quiet");
  expectUsage(r, "--out expects a file name ending in .ot");
  EXPECT_NE(r.err.find("x.map"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(out.path()));
  // Any case of the extension will do.
  EXPECT_EQ(runCli("fuse " + q(scene()) + " --out " + q(out / "m.OT") + " --quiet").exit_code, 0);
}

TEST_F(CliOutputTest, OutputsThatAreNotRegularFilesAreRefused) {
  TempDir out;
  fs::create_directory(out / "folder.ot");
  expectUsage(runCli("fuse " + q(scene()) + " --out " + q(out / "folder.ot") + " --quiet"),
              "is an existing folder");
  ASSERT_EQ(::mkfifo((out / "pipe.ot").c_str(), 0600), 0);
  expectUsage(runCli("fuse " + q(scene()) + " --out " + q(out / "pipe.ot") + " --quiet"),
              "is a FIFO");
  EXPECT_TRUE(fs::is_fifo(out / "pipe.ot"));
  expectUsage(runCli("fuse " + q(scene()) + " --out /dev/full --quiet"), "--out");
  expectUsage(runCli("export " + q(map()) + " --format ply --out " + q(out / "folder.ot")),
              "ending in .ply");
  fs::create_directory(out / "folder.ply");
  expectUsage(runCli("export " + q(map()) + " --format ply --out " + q(out / "folder.ply")),
              "is an existing folder");
  expectUsage(runCli("export " + q(map()) + " --format ot --out " + q(out / "pipe.ot")),
              "is a FIFO");
  std::ofstream(out / "file") << "keep";
  expectUsage(runCli("export " + q(map()) + " --format ply --per-label --out " + q(out / "file")),
              "is an existing file; expected a folder");
  expectUsage(runCli("plan " + q(map()) + " --target " + target() + " --approach 1,0,0 --out " +
                     q(out.path())),
              "--out");
  expectUsage(runCli("synth --out " + q(out / "file")), "is an existing file; expected a folder");
  EXPECT_EQ(slurp(out / "file"), "keep");
  EXPECT_TRUE(fs::is_directory(out / "folder.ot"));
  EXPECT_TRUE(fs::is_empty(out / "folder.ot"));
}

TEST_F(CliOutputTest, PlanAndExportNeverReplaceTheInputMap) {
  TempDir out;
  fs::copy_file(map(), out / "m.ot");
  const std::string before = slurp(out / "m.ot");
  // Another name of the same file.
  fs::create_symlink(out / "m.ot", out / "plan.json");
  fs::create_symlink(out / "m.ot", out / "m2.ot");
  expectUsage(runCli("plan " + q(out / "m.ot") + " --target " + target() +
                     " --approach 1,0,0 --out " + q(out / "plan.json")),
              "is the input map");
  expectUsage(runCli("plan " + q(out / "m.ot") + " --target " + target() +
                     " --approach 1,0,0 --out " + q(out / "m.ot")),
              "ending in .json");
  expectUsage(
      runCli("export " + q(out / "m.ot") + " --format ot --native --out " + q(out / "m2.ot")),
      "is the input map");
  EXPECT_EQ(slurp(out / "m.ot"), before);
  EXPECT_TRUE(fs::is_symlink(out / "plan.json"));
}

TEST_F(CliOutputTest, PlanNeverReplacesTheSequenceItReads) {
  TempDir out;
  const fs::path copy = out / "scene";
  fs::copy(scene(), copy, fs::copy_options::recursive);
  const std::string before = slurp(copy / "sequence.json");
  expectUsage(runCli("plan " + q(map()) + " --target " + target() + " --sequence " + q(copy) +
                     " --out " + q(copy / "sequence.json")),
              "is the sequence file");
  EXPECT_EQ(slurp(copy / "sequence.json"), before);
}

// A sequence the command does not read keeps its files: an output path typed
// into a sequence folder never replaces its boxes, its sequence.json or a frame.
TEST_F(CliOutputTest, NoCommandWritesOverTheFilesOfASequence) {
  TempDir out;
  const fs::path copy = out / "scene";
  fs::copy(scene(), copy, fs::copy_options::recursive);
  std::map<fs::path, std::string> before;
  for (const fs::path& file : {copy / "annotations.json", copy / "sequence.json",
                               copy / "color" / "000000.png", copy / "proba" / "000001.npy"})
    before[file] = slurp(file);
  const std::string plan =
      "plan " + q(map()) + " --target " + target() + " --approach 1,0,0 --out ";
  expectUsage(runCli(plan + q(copy / "annotations.json")),
              "would overwrite the ground-truth boxes");
  expectUsage(runCli(plan + q(copy / "sequence.json")), "would overwrite the sequence file");
  expectUsage(
      runCli("export " + q(map()) + " --format objects --out " + q(copy / "annotations.json")),
      "would overwrite the ground-truth boxes");
  expectUsage(runCli("render " + q(map()) + " --out " + q(copy / "color" / "000000.png")),
              "would overwrite a frame file");
  // A damaged sequence.json still protects itself and the boxes beside it.
  std::ofstream(copy / "sequence.json", std::ios::app) << "not json";
  before[copy / "sequence.json"] = slurp(copy / "sequence.json");
  expectUsage(runCli(plan + q(copy / "annotations.json")),
              "would overwrite the ground-truth boxes");
  for (const auto& [file, text] : before) EXPECT_EQ(slurp(file), text) << file;
  // The boxes' name is reserved while there are no boxes yet; the message says so.
  fs::remove(copy / "annotations.json");
  expectUsage(runCli(plan + q(copy / "annotations.json")),
              "is the name reserved for the ground-truth boxes");
  EXPECT_FALSE(fs::exists(copy / "annotations.json"));
  // Other files in a sequence folder are outputs like any other.
  const auto written = runCli(plan + q(copy / "plan.json"));
  EXPECT_EQ(written.exit_code, 0) << written.err;
  EXPECT_TRUE(fs::exists(copy / "plan.json"));
}

TEST_F(CliOutputTest, ScoreNeverWritesIntoTheSequenceItReads) {
  TempDir out;
  const fs::path copy = out / "scene";
  fs::copy(scene(), copy, fs::copy_options::recursive);
  const std::string args = "score " + q(copy) + " --annotations " + q(copy / "annotations.json");
  expectUsage(runCli(args + " --out " + q(copy) + " --quiet"), "lies inside the input sequence");
  expectUsage(runCli(args + " --out " + q(copy / "reports") + " --quiet"),
              "lies inside the input sequence");
  EXPECT_FALSE(fs::exists(copy / "report.json"));
  EXPECT_FALSE(fs::exists(copy / "reports"));
  // Reports beside the annotations they would replace.
  fs::copy_file(copy / "annotations.json", out / "report.json");
  const auto r = runCli("score " + q(copy) + " --annotations " + q(out / "report.json") +
                        " --out " + q(out.path()) + " --quiet");
  expectUsage(r, "would overwrite the annotations file");
  EXPECT_EQ(slurp(out / "report.json"), slurp(copy / "annotations.json"));
  std::ofstream(out / "file") << "keep";
  expectUsage(runCli(args + " --out " + q(out / "file") + " --quiet"),
              "is an existing file; expected a folder");
}

TEST_F(CliOutputTest, RenderWritesOnlyPngFilesAndNeverItsInputs) {
  TempDir out;
  expectUsage(runCli("render " + q(map()) + " --out " + q(out / "view.jpg")), "ending in .png");
  fs::copy_file(scene() / "color" / "000001.png", out / "frame.png");
  fs::create_symlink(scene() / "color" / "000001.png", out / "link.png");
  expectUsage(runCli("render " + q(map()) + " --camera " + q(fs::path(scene().string() + ":1")) +
                     " --out " + q(out / "link.png")),
              "would overwrite a frame file");
  EXPECT_EQ(slurp(scene() / "color" / "000001.png"), slurp(out / "frame.png"));
}

TEST_F(CliOutputTest, ImportNeverWritesOverItsSource) {
  TempDir out;
  std::ofstream(out / "recording.bag") << "not a bag";
  expectUsage(
      runCli("import rosbag " + q(out / "recording.bag") + " --out " + q(out / "recording.bag")),
      "is an existing file; expected a folder");
  expectUsage(runCli("import frames " + q(scene()) + " --out " + q(scene())),
              "is the import source");
  EXPECT_EQ(slurp(out / "recording.bag"), "not a bag");
  // Nor into the source folder: not into one of its own image folders, nor a new one in it.
  for (const char* inside : {"depth", "converted"}) {
    SCOPED_TRACE(inside);
    expectUsage(runCli("import frames " + q(scene()) + " --out " + q(scene() / inside)),
                "lies inside the import source folder");
  }
  EXPECT_FALSE(fs::exists(scene() / "converted"));
  EXPECT_FALSE(fs::exists(scene() / "depth" / "sequence.json"));
}

// A folder that takes no new file (here /proc, even for root): one line in the
// program's words naming the output, not VTK's or PCL's complaint about a
// temporary file, and nothing left behind.
TEST_F(CliOutputTest, ExportIntoAFolderThatTakesNoFilesSaysSoInOneLine) {
  if (!fs::is_directory("/proc")) GTEST_SKIP() << "no /proc on this system";
  for (const std::string format : {"stl", "obj", "pcd", "ot", "ply --points", "ply"}) {
    SCOPED_TRACE(format);
    const std::string extension = format.substr(0, 3);
    const auto r =
        runCli("export " + q(map()) + " --format " + format + " --out /proc/map." + extension);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // (OBJ's material file, map.mtl, is written first and named.)
    EXPECT_NE(r.err.find("error: /proc/map."), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(": output path: expected a folder where files can be created"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find(".tmp"), std::string::npos) << r.err;
  }
}

// Outputs named relative to the working folder: a folder output that does not
// exist yet is created there (with its parents), as one given by an absolute
// path is; a file output goes beside the working folder's other files.
TEST_F(CliOutputTest, OutputsRelativeToTheWorkingFolderAreWritten) {
  TempDir work;
  const fs::path before = fs::current_path();
  fs::current_path(work.path());
  const std::string score = "score " + q(scene()) + " --annotations " +
                            q(scene() / "annotations.json") + " --map " + q(map()) + " --quiet";
  const auto in_report = runCli(score + " --out report");
  const auto in_trailing = runCli(score + " --out nested/report/");
  const auto fused = runCli("fuse " + q(scene()) + " --frames 0:1 --out map.ot --quiet");
  const auto exported = runCli("export " + q(map()) + " --format ply --per-label --out meshes");
  fs::current_path(before);
  EXPECT_EQ(in_report.exit_code, 0) << in_report.err;
  EXPECT_TRUE(fs::exists(work / "report" / "report.json"));
  EXPECT_EQ(in_trailing.exit_code, 0) << in_trailing.err;
  EXPECT_TRUE(fs::exists(work / "nested" / "report" / "report.json"));
  EXPECT_EQ(fused.exit_code, 0) << fused.err;
  EXPECT_TRUE(fs::exists(work / "map.ot"));
  EXPECT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_TRUE(fs::is_directory(work / "meshes"));
}

}  // namespace
