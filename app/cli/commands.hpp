#pragma once
// One function per labeloctomap subcommand; each lives in its own cmd_*.cpp.
// They return the process exit code and may throw lom::Error,
// lom::ValidationError or cli::UsageError (handled in main.cpp).
#include <string>
#include <vector>

namespace lom {
struct FusionOptions;
}

namespace lom::cli {

class Args;

using Words = std::vector<std::string>;

int runInfo(const Words& words);      // cmd_info.cpp
int runValidate(const Words& words);  // cmd_info.cpp
int runSynth(const Words& words);     // cmd_synth.cpp
int runFuse(const Words& words);      // cmd_fuse.cpp
int runExport(const Words& words);    // cmd_export.cpp
int runScore(const Words& words);     // cmd_score.cpp
int runRender(const Words& words);    // cmd_render.cpp
int runImport(const Words& words);    // cmd_import.cpp
int runPlan(const Words& words);      // cmd_plan.cpp
int runSegment(const Words& words);   // cmd_segment.cpp

// --resolution --max-range --p-miss --threshold --candidates --frames (cmd_fuse.cpp).
FusionOptions fusionOptionsFromArgs(const Args& args);

}  // namespace lom::cli
