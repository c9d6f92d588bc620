// Option values: integers that do not fit, numbers that are not finite, settings that cannot
// work or would exhaust the machine, frame ranges past the end, switches that do not apply,
// and --help on every command. Mistakes in the call exit 2 before any work, naming the option.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_scene_fixture.hpp"
#include "lom/label_map.hpp"

namespace {

namespace fs = std::filesystem;
using lom::test::q;
using lom::test::runCli;
using lom::test::slurp;
using lom::test::TempDir;

class CliOptionTest : public lom::test::CliSceneTest {};

// Exit 2, the option named, the usage shown.
void expectUsage(const lom::test::CliResult& r, const std::string& option,
                 const std::string& text = {}) {
  EXPECT_EQ(r.exit_code, 2) << option << "\n" << r.err;
  EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
  if (!text.empty()) {
    EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
  }
  EXPECT_NE(r.err.find("usage: labeloctomap"), std::string::npos) << r.err;
}

// As the studio's: the build's version, for bug reports; no display needed.
TEST_F(CliOptionTest, VersionIsPrinted) {
  for (const char* option : {"--version", "-v"}) {
    const auto result = lom::test::runCli(option);
    EXPECT_EQ(result.exit_code, 0) << option << "\n" << result.out << result.err;
    EXPECT_EQ(result.out.rfind("labeloctomap ", 0), 0u) << result.out;
    EXPECT_NE(result.out.find_first_of("0123456789"), std::string::npos) << result.out;
    EXPECT_EQ(result.out.find("usage"), std::string::npos) << result.out;
  }
  // A word after it is no unknown command '--version'.
  const auto extra = lom::test::runCli("--version extra");
  EXPECT_EQ(extra.exit_code, 2);
  EXPECT_NE(extra.err.find("--version: takes no arguments, got 'extra'"), std::string::npos)
      << extra.err;
  EXPECT_EQ(extra.err.find("unknown command"), std::string::npos) << extra.err;
}

TEST_F(CliOptionTest, IntegersThatDoNotFitAreRefusedNotWrappedAround) {
  TempDir out;
  // 4294967302 = 2^32 + 6 would become label 6.
  expectUsage(
      runCli("export " + q(map()) + " --format ply --labels 4294967302 --out " + q(out / "m.ply")),
      "--labels", "4294967302");
  expectUsage(runCli("fuse " + q(scene()) + " --candidates 0,4294967302 --out " + q(out / "m.ot") +
                     " --quiet"),
              "--candidates", "4294967302");
  expectUsage(runCli("fuse " + q(scene()) + " --candidates 0,256 --out " + q(out / "m.ot")),
              "--candidates", "0 to 255");
  expectUsage(runCli("render " + q(map()) + " --labels -4294967290 --out " + q(out / "v.png")),
              "--labels");
  expectUsage(runCli("plan " + q(map()) + " --target " + target() +
                     " --approach 1,0,0 --min-cluster-voxels 18446744073709551617"),
              "--min-cluster-voxels");
  expectUsage(runCli("import frames " + q(scene()) + " --out " + q(out / "seq") +
                     " --flying-radius 4294967297"),
              "--flying-radius");
  expectUsage(runCli("import frames " + q(scene()) + " --out " + q(out / "seq") +
                     " --first 99999999999999999999"),
              "--first");
  expectUsage(runCli("synth --out " + q(out / "s") + " --objects 4294967300"), "--objects");
  expectUsage(
      runCli("fuse " + q(scene()) + " --frames 0:99999999999999999999 --out " + q(out / "m.ot")),
      "--frames expects frame indices of at most 9223372036854775807 (frame index "
      "99999999999999999999 is too large)");
  EXPECT_TRUE(fs::is_empty(out.path()));
}

TEST_F(CliOptionTest, NumbersMustBeFinite) {
  TempDir out;
  for (const std::string bad :
       {"--azimuth nan", "--azimuth inf", "--elevation nan", "--azimuth -inf --elevation 10"})
    expectUsage(runCli("render " + q(map()) + " " + bad + " --out " + q(out / "v.png")),
                bad.substr(0, bad.find(' ')), "finite");
  for (const std::string bad :
       {"--cluster-tolerance inf", "--overlap-margin inf", "--gap inf", "--gap nan"}) {
    const auto r =
        runCli("plan " + q(map()) + " --target " + target() + " --approach 1,0,0 " + bad);
    expectUsage(r, bad.substr(0, bad.find(' ')), "finite");
    EXPECT_EQ(r.err.find("_voxels"), std::string::npos) << r.err;  // no internal names
    EXPECT_EQ(r.err.find("placement_gap"), std::string::npos) << r.err;
  }
  expectUsage(runCli("fuse " + q(scene()) + " --max-range inf --out " + q(out / "m.ot")),
              "--max-range", "finite");
  EXPECT_TRUE(fs::is_empty(out.path()));
}

TEST_F(CliOptionTest, ApproachIsNormalisedWithoutOverflowOrUnderflow) {
  TempDir out;
  auto r = runCli("plan " + q(map()) + " --target " + target() +
                  " --approach 1e308,1e308,0 --out " + q(out / "huge.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto direction = nlohmann::json::parse(slurp(out / "huge.json"))["approach"]["direction"];
  EXPECT_NEAR(direction[0].get<double>(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(direction[1].get<double>(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(direction[2].get<double>(), 0.0, 1e-12);
  r = runCli("plan " + q(map()) + " --target " + target() + " --approach 0,-1e-310,0 --out " +
             q(out / "tiny.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  direction = nlohmann::json::parse(slurp(out / "tiny.json"))["approach"]["direction"];
  EXPECT_NEAR(direction[1].get<double>(), -1.0, 1e-12);
  expectUsage(runCli("plan " + q(map()) + " --target " + target() + " --approach 0,0,0"),
              "--approach", "not all zero");
  expectUsage(runCli("plan " + q(map()) + " --target " + target() + " --approach 1e309,0,0"),
              "--approach");
}

TEST_F(CliOptionTest, SwitchesThatDoNotApplyAreUsageMistakes) {
  TempDir out;
  const std::string e = "export " + q(map());
  expectUsage(runCli(e + " --format ply --native --out " + q(out / "a.ply")), "--native",
              "format ot");
  expectUsage(runCli(e + " --format stl --points --out " + q(out / "a.stl")), "--points");
  expectUsage(runCli(e + " --format pcd --smooth --out " + q(out / "a.pcd")), "--smooth");
  expectUsage(runCli(e + " --format objects --per-label --out " + q(out / "objects")),
              "--per-label");
  expectUsage(runCli(e + " --format ply --out " + q(out / "a.obj")), "--out", "ending in .ply");
  expectUsage(runCli(e + " --format ot --native --labels 1 --out " + q(out / "a.ot")), "--labels");
  // Found before the map is read: a missing map does not hide them.
  expectUsage(
      runCli("export " + q(out / "absent.ot") + " --format pcd --smooth --out " + q(out / "a.pcd")),
      "--smooth");
  EXPECT_TRUE(fs::is_empty(out.path()));
}

// A second --out or --labels used to replace the first without a word; an
// unknown option at the end was reported as missing its value.
TEST_F(CliOptionTest, OptionsGivenTwiceAndUnknownLastOptionsAreNamed) {
  TempDir out;
  const auto twice = runCli("fuse " + q(scene()) + " --out " + q(out / "a.ot") + " --out " +
                            q(out / "b.ot") + " --quiet");
  expectUsage(twice, "--out", "is given twice");
  EXPECT_TRUE(fs::is_empty(out.path()));
  expectUsage(runCli("export " + q(map()) + " --format ply --labels 4 --labels 6 --out " +
                     q(out / "m.ply")),
              "--labels", "give it once with a comma-separated list");
  expectUsage(runCli("fuse " + q(scene()) + " --out " + q(out / "a.ot") + " --bogus"),
              "unknown option --bogus");
  expectUsage(runCli("info " + q(scene()) + " --bogus"), "unknown option --bogus");
  expectUsage(runCli("fuse " + q(scene()) + " --out"), "option --out expects a value");
  EXPECT_TRUE(fs::is_empty(out.path()));
}

// A switch given a value (--native=1) used to be a value nobody read: the
// switch stayed off and the command succeeded.
TEST_F(CliOptionTest, SwitchesGivenAValueAreRefused) {
  TempDir out;
  expectUsage(runCli("export " + q(map()) + " --format ot --native=1 --out " + q(out / "a.ot")),
              "--native", "is a switch and takes no value");
  expectUsage(runCli("fuse " + q(scene()) + " --out " + q(out / "a.ot") + " --quiet=yes"),
              "--quiet", "is a switch and takes no value");
  EXPECT_TRUE(fs::is_empty(out.path()));
}

// An option whose value was forgotten took the next option for it: `synth
// --out --no-noise` wrote a scene with noise into a folder named --no-noise.
TEST_F(CliOptionTest, AnOptionIsNotTakenForTheValueOfTheOneBefore) {
  TempDir out;
  const fs::path before = fs::current_path();
  fs::current_path(out.path());  // where a folder named --no-noise was written
  const auto synth = runCli("synth --seed 3 --frames 2 --out --no-noise");
  const auto frames = runCli("fuse " + q(scene()) + " --out --frames 0:2");
  const auto resolution = runCli("fuse " + q(scene()) + " --out --resolution=0.02");
  fs::current_path(before);
  expectUsage(synth, "option --out expects a value, got the option --no-noise");
  expectUsage(frames, "option --out expects a value, got the option --frames");
  expectUsage(resolution, "option --out expects a value, got the option --resolution=0.02");
  EXPECT_TRUE(fs::is_empty(out.path()));
}

// Label lists and sizes take digits only: a trailing comma, blanks or a sign
// are mistakes, as in the other comma-separated options.
TEST_F(CliOptionTest, LabelListsAndSizesAreDigitsOnly) {
  TempDir out;
  const std::string e = "export " + q(map()) + " --format pcd --out " + q(out / "a.pcd");
  for (const std::string labels : {"4,", " 4", "+4", "4,,6", ","})
    expectUsage(runCli(e + " --labels '" + labels + "'"), "--labels", "comma-separated list");
  expectUsage(runCli(e + " --labels -3"), "--labels", "label ids from 0");
  EXPECT_TRUE(fs::is_empty(out.path()));
  const std::string r = "render " + q(map()) + " --out " + q(out / "a.png");
  for (const std::string size : {" 400x300", "+400x300", "400x300 ", "400x-3", "0x10"})
    expectUsage(runCli(r + " --size '" + size + "'"), "--size", "WIDTHxHEIGHT");
  expectUsage(runCli(r + " --size 16384x8193"), "--size", "at most 134217728 pixels");
  EXPECT_TRUE(fs::is_empty(out.path()));
}

TEST_F(CliOptionTest, EmptyValuesAreRefusedBeforeAnyWork) {
  TempDir out;
  const auto r = runCli("fuse " + q(scene()) + " --out= --quiet");
  expectUsage(r, "--out", "empty");
  EXPECT_EQ(r.out.find("fused"), std::string::npos) << r.out;
  expectUsage(runCli("plan " + q(map()) + " --target="), "--target");
  expectUsage(runCli("score " + q(scene()) + " --annotations= --out " + q(out / "r")),
              "--annotations");
  EXPECT_TRUE(fs::is_empty(out.path()));
}

TEST_F(CliOptionTest, MissingFilesGivenToOptionsAreInputProblems) {
  TempDir out;
  auto r = runCli("import frames " + q(scene()) + " --out " + q(out / "seq") + " --labels " +
                  q(out / "nonexist.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("nonexist.txt"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--labels"), std::string::npos) << r.err;
  r = runCli("import frames " + q(scene()) + " --out " + q(out / "seq") + " --intrinsics " +
             q(out / "nonexist_K.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("nonexist_K.txt"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--intrinsics"), std::string::npos) << r.err;
  // Numbers that do not make a camera stay a mistake in the call.
  expectUsage(
      runCli("import frames " + q(scene()) + " --out " + q(out / "seq") + " --intrinsics 1,2,3"),
      "--intrinsics");
  EXPECT_FALSE(fs::exists(out / "seq"));
}

TEST_F(CliOptionTest, FrameRangesPastTheEndAreUsageMistakes) {
  TempDir out;
  for (const std::string range : {"0:99", "3:5", "2:4", "3:", "7:"}) {
    const auto r = runCli("fuse " + q(scene()) + " --frames " + range + " --out " +
                          q(out / "m.ot") + " --quiet");
    expectUsage(r, "--frames", "has 3 frames");
    const auto s =
        runCli("score " + q(scene()) + " --annotations " + q(scene() / "annotations.json") +
               " --frames " + range + " --out " + q(out / "r") + " --quiet");
    expectUsage(s, "--frames", "has 3 frames");
  }
  EXPECT_TRUE(fs::is_empty(out.path()));
  const auto r =
      runCli("fuse " + q(scene()) + " --frames 1:3 --out " + q(out / "m.ot") + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("fused 2 frames"), std::string::npos) << r.out;
}

TEST_F(CliOptionTest, HelpPrintsTheUsageOfEveryCommand) {
  for (const std::string command : {"info", "validate", "synth", "fuse", "score", "export",
                                    "render", "import", "plan", "segment"}) {
    for (const std::string help : {"--help", "-h"}) {
      const auto r = runCli(command + " " + help);
      EXPECT_EQ(r.exit_code, 0) << command << " " << help << "\n" << r.err;
      // "help COMMAND" (git's habit) says the same.
      if (help == "--help") {
        EXPECT_EQ(runCli("help " + command).out, r.out) << command;
      }
      EXPECT_NE(r.out.find("usage: labeloctomap " + command), std::string::npos)
          << command << " " << help << "\n"
          << r.out;
      EXPECT_TRUE(r.err.empty()) << r.err;
    }
  }
  // help with no word is the general usage; with a word that is no command, or
  // with more words, an error and the general usage.
  const auto general = runCli("help");
  EXPECT_EQ(general.exit_code, 0);
  EXPECT_NE(general.out.find("usage: labeloctomap"), std::string::npos) << general.out;
  const auto unknown = runCli("help fusion");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("unknown command 'fusion'"), std::string::npos) << unknown.err;
  EXPECT_EQ(runCli("help fuse score").exit_code, 2);
  // Also after other arguments, and import gives every option.
  const auto r = runCli("fuse " + q(scene()) + " --help");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("--resolution"), std::string::npos) << r.out;
  EXPECT_NE(runCli("import -h").out.find("--flying-ratio"), std::string::npos);
  // Options that work are in the usage (score's fusion settings, export's variants).
  const std::string score = runCli("score --help").out, exported = runCli("export --help").out;
  for (const char* option : {"--max-range", "--p-miss", "--threshold", "--frames", "--quiet"})
    EXPECT_NE(score.find(option), std::string::npos) << option << "\n" << score;
  for (const char* option : {"--points", "--native", "--no-merge"})
    EXPECT_NE(exported.find(option), std::string::npos) << option << "\n" << exported;
}

TEST_F(CliOptionTest, ThresholdsAndMissProbabilitiesThatCannotWork) {
  TempDir out;
  const std::string fuse = "fuse " + q(scene()) + " --out " + q(out / "m.ot") + " --quiet ";
  expectUsage(runCli(fuse + "--threshold 0.98"), "--threshold", "0.97");
  expectUsage(runCli(fuse + "--threshold 0.1"), "--threshold", "0.12");
  // A value just past a limit is echoed as given, not rounded onto the limit.
  expectUsage(runCli(fuse + "--threshold 0.9700001"), "--threshold", "got 0.9700001");
  expectUsage(runCli(fuse + "--resolution 1.0000001"), "--resolution", "got 1.0000001");
  expectUsage(runCli(fuse + "--p-miss 0.7"), "--p-miss", "below 0.5");
  expectUsage(runCli(fuse + "--p-miss 0.5"), "--p-miss", "below 0.5");
  EXPECT_EQ(runCli(fuse + "--threshold 0.97 --p-miss 0.45").exit_code, 0);
  EXPECT_TRUE(fs::remove(out / "m.ot"));
  const std::string score = "score " + q(scene()) + " --annotations " +
                            q(scene() / "annotations.json") + " --out " + q(out / "r") +
                            " --quiet ";
  expectUsage(runCli(score + "--threshold 0.99"), "--threshold", "0.97");
  expectUsage(runCli(score + "--p-miss 0.7"), "--p-miss");
  // A given map: its own clamping applies, and the message names it.
  const auto r = runCli(score + "--map " + q(map()) + " --threshold 0.99");
  expectUsage(r, "--threshold", map().string());
  EXPECT_TRUE(fs::is_empty(out.path()));
}

TEST_F(CliOptionTest, ResolutionAndClusterToleranceHaveDocumentedBounds) {
  TempDir out;
  // Values that would take gigabytes and minutes if they were accepted: a failure here must
  // not take the machine with it.
  const lom::test::CliLimits guard{2L * 1024 * 1024, 60};
  const std::string fuse = "fuse " + q(scene()) + " --out " + q(out / "m.ot") + " --quiet ";
  for (const std::string r : {"0.0001", "0.0003", "0.001", "0.0019", "1e9", "1.5"})
    expectUsage(runCli(fuse + "--resolution " + r, guard), "--resolution", "from 0.002 to 1 m");
  expectUsage(runCli(fuse + "--resolution 0.002 --max-range 3", guard), "--max-range",
              "1000 voxels");
  expectUsage(runCli("score " + q(scene()) + " --annotations " + q(scene() / "annotations.json") +
                         " --out " + q(out / "r") + " --resolution 0.0003",
                     guard),
              "--resolution");
  EXPECT_TRUE(fs::is_empty(out.path()));
  const std::string plan = "plan " + q(map()) + " --target " + target() + " --approach 1,0,0 ";
  for (const std::string t : {"20.5", "1000", "10000"})
    expectUsage(runCli(plan + "--cluster-tolerance " + t, guard), "--cluster-tolerance",
                "at most 20");
  EXPECT_EQ(runCli(plan + "--cluster-tolerance 20").exit_code, 0);
}

}  // namespace
