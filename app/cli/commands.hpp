#pragma once
// One function per labeloctomap subcommand; each lives in its own cmd_*.cpp.
// They return the process exit code and may throw lom::Error,
// lom::ValidationError or cli::UsageError (handled in main.cpp).
#include <iosfwd>
#include <string>
#include <vector>

namespace lom {
class LabelMap;
struct FrameStats;
struct FusionOptions;
struct MapParameters;
struct Sequence;
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
const char* importHelp();             // cmd_import.cpp: every option of import
// Each option of `command` with its meaning and default (command_help.cpp;
// "" for info, validate and import, whose help is importHelp).
std::string commandOptionsHelp(const std::string& command);
int runPlan(const Words& words);      // cmd_plan.cpp
int runSegment(const Words& words);   // cmd_segment.cpp

// The warning about implausible depths (a wrong depth_scale) of the first,
// middle and last frames of `sequence` (cmd_info.cpp), "" when plausible or
// unreadable; `out`, when given, receives info's "depth (sampled):" line.
std::string sampledDepthWarning(const Sequence& sequence, std::ostream* out = nullptr);

// --resolution --max-range --p-miss --threshold --candidates --frames (cmd_fuse.cpp); throws
// UsageError for values out of range. The segmenter (--segmenter) is left to the caller.
FusionOptions fusionOptionsFromArgs(const Args& args);

// Throws UsageError unless clamp_min < threshold <= clamp_max of `map` (a threshold
// outside can never make a voxel occupied, or makes every observed voxel occupied).
// `map_file` names the map whose clamping applies, when there is one.
void checkOccupancyThreshold(double threshold, const MapParameters& map,
                             const std::string& map_file);

// Throws UsageError for --candidates not in the sequence and --frames past its end.
void checkFusionOptionsForSequence(const FusionOptions& options, const Sequence& sequence);

// What fuse and score say when fused frames had depth points outside the map's
// extent (FrameStats::outside_map_pixels; `frames` lists those frames):
// the warning, without its "warning: " prefix, or empty when there were none.
// `sequence_file` is the sequence's sequence.json.
// With `continued` (fuse --start-from, whose map keeps its own resolution and
// max range) the advice says to fuse again without it.
std::string outsideMapWarning(const std::string& sequence_file, const FrameStats& totals,
                              const std::vector<size_t>& frames, double resolution,
                              bool continued = false);

// What max range took of a fusion's valid depths: a warning when most, a note
// when a fifth or more (with how to map them), without the "warning: " or
// "note: " prefix; empty text when less.
struct RangeMessage {
  std::string text;
  bool warning = false;
};
RangeMessage maxRangeMessage(const FrameStats& totals, double max_range, double resolution,
                             const std::string& sequence_file, bool continued = false);

// "<heading> N" and one line per label (id, name, occupied voxels), as fuse and
// info print them; names line up by terminal columns (cmd_info.cpp). Returns N.
size_t printOccupiedPerLabel(const LabelMap& map, const std::string& heading, std::ostream& out);

// Object boxes of a map that records no camera up stand on the world's +z:
// the note export objects and plan print then (without "note: "), naming
// --sequence, which gives them its cameras' up; empty when the map records
// its up or `up_given` (a --sequence whose cameras agree on one; cmd_plan.cpp).
std::string boxesOnWorldZNote(const LabelMap& map, const std::string& map_file, bool up_given);

}  // namespace lom::cli
