// COMMAND --help and help COMMAND explain every option a command takes (its
// Args::expectOnly list), with the defaults and limits the code enforces
// (app/cli/command_help.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace {

using lom::test::runCli;

struct CommandOptions {
  std::string command;
  // The command's Args::expectOnly list, as in app/cli/cmd_<command>.cpp.
  std::vector<std::string> options;
};

const std::vector<CommandOptions>& commands() {
  static const std::vector<CommandOptions> list = {
      {"info", {}},
      {"validate", {}},
      {"synth",
       {"out", "seed", "objects", "frames", "views", "width", "height", "no-noise",
        "perfect-segmenter"}},
      {"fuse",
       {"out", "resolution", "max-range", "p-miss", "threshold", "candidates", "frames",
        "frame-memory", "quiet", "start-from", "segmenter"}},
      {"score",
       {"annotations", "out", "map", "batch", "iou", "resolution", "max-range", "p-miss",
        "threshold", "candidates", "frames", "frame-memory", "quiet", "segmenter"}},
      {"export",
       {"voxels", "format", "out", "labels", "per-label", "smooth", "points", "native", "no-merge",
        "sequence", "level"}},
      {"render",
       {"out", "camera", "azimuth", "elevation", "up", "size", "labels", "flat", "colour",
        "annotations", "iou", "frame"}},
      {"plan",
       {"target", "approach", "sequence", "out", "empty-bin", "all-clusters", "candidates",
        "cluster-tolerance", "min-cluster-voxels", "overlap-margin", "transitive", "gap",
        "threshold", "occluders"}},
      {"segment", {"segmenter", "all", "dtype", "out-dir", "quiet"}},
  };
  return list;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) result.push_back(line);
  return result;
}

// The text after "options:" (empty when there is no such section).
std::string optionsSection(const std::string& help) {
  const auto start = help.find("\noptions:\n");
  return start == std::string::npos ? std::string() : help.substr(start + 10);
}

// The entry of `option` ("--resolution") in the options section: its first line
// ("  --resolution R  ...") and its continuation lines, blanks collapsed so that
// a phrase wrapped across lines reads as one; empty when the option has no entry.
std::string entry(const std::string& help, const std::string& option) {
  std::string text;
  bool inside = false;
  for (const std::string& line : lines(optionsSection(help))) {
    const std::string head = "  " + option;
    const bool starts =
        line.rfind(head, 0) == 0 && (line.size() == head.size() || line[head.size()] == ' ');
    if (starts) {
      inside = true;
    } else if (inside && line.rfind("   ", 0) != 0) {
      break;  // the next option, or the details line
    }
    if (inside) text += " " + line;
  }
  std::string collapsed;
  std::istringstream words(text);
  for (std::string word; words >> word;) collapsed += (collapsed.empty() ? "" : " ") + word;
  return collapsed;
}

std::string helpOf(const std::string& command) {
  const auto r = runCli(command + " --help");
  EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.err;
  EXPECT_TRUE(r.err.empty()) << command << "\n" << r.err;
  return r.out;
}

TEST(CliHelpTest, EveryOptionOfEveryCommandIsExplained) {
  for (const auto& [command, options] : commands()) {
    const auto help = runCli(command + " --help");
    const auto word = runCli("help " + command);
    EXPECT_EQ(help.exit_code, 0) << command << "\n" << help.err;
    EXPECT_EQ(word.exit_code, 0) << command << "\n" << word.err;
    EXPECT_TRUE(help.err.empty()) << command << "\n" << help.err;
    EXPECT_EQ(word.out, help.out) << command;
    EXPECT_EQ(help.out.rfind("usage: labeloctomap " + command, 0), 0u) << help.out;
    const std::string section = optionsSection(help.out);
    if (options.empty()) {
      EXPECT_TRUE(section.empty()) << command << " takes no option\n" << help.out;
      continue;
    }
    ASSERT_FALSE(section.empty()) << command << " has no options section\n" << help.out;
    for (const std::string& option : options) {
      const std::string name = "--" + option;
      EXPECT_NE(help.out.find(name), std::string::npos) << command << " " << name;
      // Its own entry, with a description, not only a mention in the usage.
      const std::string text = entry(help.out, name);
      EXPECT_GT(text.size(), name.size() + 10) << command << ": no entry for " << name << "\n"
                                               << help.out;
    }
  }
}

TEST(CliHelpTest, OptionsArePlainAsciiWithinNinetyFiveColumnsAndNameExistingDocs) {
  for (const auto& [command, options] : commands()) {
    const std::string help = helpOf(command);
    for (const std::string& line : lines(help))
      for (const char c : line)
        EXPECT_TRUE(c >= ' ' && c <= '~') << command << ": not plain ASCII: " << line;
    // (The usage lines of main.cpp's kCommands table are wider; the options are wrapped.)
    for (const std::string& line : lines(optionsSection(help)))
      EXPECT_LE(line.size(), 95u) << command << ": " << line;
    if (options.empty()) continue;
    bool details = false;
    for (const std::string& line : lines(help)) {
      if (line.rfind("details: ", 0) != 0) continue;
      details = true;
      const auto start = line.find("docs/");
      ASSERT_NE(start, std::string::npos) << line;
      const auto end = line.find(".md", start);
      ASSERT_NE(end, std::string::npos) << line;
      const std::string doc = line.substr(start, end + 3 - start);
      EXPECT_TRUE(std::filesystem::is_regular_file(std::filesystem::path(LOM_SOURCE_DIR) / doc))
          << command << ": " << doc;
    }
    EXPECT_TRUE(details) << command << " names no doc\n" << help;
  }
}

// Each expectation: the entry of `option` of `command` holds `text` (blanks
// collapsed, so wrapping does not matter).
struct Expected {
  const char* command;
  const char* option;
  const char* text;
};

TEST(CliHelpTest, DefaultsAndLimitsAreTheOnesTheCodeUses) {
  const Expected expected[] = {
      // MapParameters, kMinFusionResolution, kMaxFusionResolution (fuse and score alike).
      {"fuse", "--resolution", "default 0.01; 0.002 to 1"},
      {"fuse", "--max-range", "default 1;"},
      {"fuse", "--max-range", "0 or less: unlimited"},
      {"fuse", "--max-range", "1000 voxels"},
      {"fuse", "--p-miss", "default 0.3; above 0 and below 0.5"},
      {"fuse", "--threshold", "default 0.5; above 0.12 and at most 0.97"},
      {"fuse", "--candidates", "0 to 255"},
      {"fuse", "--frame-memory", "GiB"},
      {"score", "--resolution", "default 0.01; 0.002 to 1"},
      {"score", "--threshold", "default 0.5; above 0.12 and at most 0.97"},
      {"score", "--iou", "exact, the default"},
      // SynthOptions and the kSynth* limits.
      {"synth", "--seed", "default 1;"},
      {"synth", "--objects", "default 6; 1 to 39"},
      {"synth", "--frames", "default 15; 3 to 10000"},
      {"synth", "--views", "default 3; 3 to F"},
      {"synth", "--width", "default 640; 32 to 2048"},
      {"synth", "--height", "default 480; 24 to 2048"},
      // PlanOptions, ObjectOptions, kMaxClusterTolerance, kDefaultMinObjectVoxels.
      {"plan", "--overlap-margin", "default 1;"},
      {"plan", "--gap", "default 0.01;"},
      {"plan", "--cluster-tolerance", "default 2; above 0, at most 20"},
      {"plan", "--min-cluster-voxels", "default 8; 1 to 2147483647"},
      {"plan", "--occluders", "path (the default)"},
      // cmd_render.cpp and lom/render_limits.hpp.
      {"render", "--size", "default 1280x960"},
      {"render", "--size", "1 to 16384"},
      {"render", "--azimuth", "default 210"},
      {"render", "--elevation", "default 30; -90 to 90"},
      {"render", "--iou", "default exact"},
      // cmd_segment.cpp.
      {"segment", "--dtype", "default float32"},
      {"segment", "--out-dir", "proba-MODEL"},
      // cmd_export.cpp's checkSwitches.
      {"export", "--native", "ot"},
      {"export", "--points", "ply"},
  };
  std::string command;
  std::string help;
  for (const auto& e : expected) {
    if (command != e.command) {
      command = e.command;
      help = helpOf(command);
    }
    const std::string text = entry(help, e.option);
    EXPECT_NE(text.find(e.text), std::string::npos)
        << command << " " << e.option << ": expected \"" << e.text << "\" in\n"
        << text;
  }
}

// import keeps its own complete help, without a second options section.
TEST(CliHelpTest, ImportKeepsItsOwnHelp) {
  const std::string help = helpOf("import");
  EXPECT_NE(help.find("--flying-ratio"), std::string::npos) << help;
  EXPECT_EQ(help.find("\noptions:\n"), std::string::npos) << help;
}

}  // namespace
