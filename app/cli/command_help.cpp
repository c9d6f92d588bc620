// The options of each labeloctomap command, for COMMAND --help and help COMMAND
// (import has its own full help, importHelp() in cmd_import.cpp).
//
// Defaults and limits are taken from the constants the parsing code uses
// (MapParameters, kMinFusionResolution, SynthOptions, PlanOptions, ...) where
// the code has one, so that the help cannot drift from what is enforced; the
// others (render's view, --size) are the literals of cmd_render.cpp.
#include <climits>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include "args.hpp"
#include "lom/box_fit.hpp"
#include "lom/fusion.hpp"
#include "lom/label_map.hpp"
#include "lom/objects.hpp"
#include "lom/planning.hpp"
#include "lom/render_limits.hpp"
#include "lom/synth.hpp"
#include "segmenter_option.hpp"

namespace lom::cli {

namespace {

// Where the descriptions start, and the widest line.
constexpr size_t kDescriptionColumn = 23;
constexpr size_t kMaxColumns = 95;

struct OptionHelp {
  std::string spec;  // "--resolution R"
  std::string text;  // what it does, its default and its range
};

// A number as the options take it: "0.01", "1", "0.97".
std::string num(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

std::string num(long long value) { return std::to_string(value); }

// "  --spec     text", the text wrapped at word boundaries to kMaxColumns, its
// continuation lines indented to kDescriptionColumn. A spec too long for the
// column is followed by two blanks, as import's help does.
std::string formatOption(const OptionHelp& option) {
  std::string out;
  std::string line = "  " + option.spec;
  if (line.size() + 2 <= kDescriptionColumn)
    line.append(kDescriptionColumn - line.size(), ' ');
  else
    line += "  ";
  bool line_has_text = false;
  std::istringstream words(option.text);
  std::string word;
  while (words >> word) {
    const size_t needed = word.size() + (line_has_text ? 1 : 0);
    if (line_has_text && line.size() + needed > kMaxColumns) {
      out += line + "\n";
      line = std::string(kDescriptionColumn, ' ');
      line_has_text = false;
    }
    if (line_has_text) line += ' ';
    line += word;
    line_has_text = true;
  }
  return out + line + "\n";
}

// "\noptions:\n" and one entry per option, then "details: DOC" when given.
std::string section(const std::vector<OptionHelp>& options, const std::string& details) {
  std::string out = "\noptions:\n";
  for (const auto& option : options) out += formatOption(option);
  if (!details.empty()) out += "details: " + details + "\n";
  return out;
}

std::string segmenterSpec() { return std::string("--") + kSegmenterOption + " MODEL.onnx"; }

// fuse's and score's fusion settings (fusionOptionsFromArgs in cmd_fuse.cpp).
std::vector<OptionHelp> fusionOptions(bool score) {
  const MapParameters map;
  // With --map, the map keeps the settings it was fused with (noteResolution in cmd_score.cpp).
  const std::string map_note = score ? "; with --map, the map's own" : "";
  std::vector<OptionHelp> options = {
      {"--resolution R", "voxel edge in metres (default " + num(map.resolution) + "; " +
                             num(kMinFusionResolution) + " to " + num(kMaxFusionResolution) +
                             map_note + ")"},
      {"--max-range M",
       "depths farther than M metres from the camera map nothing, they only clear free space "
       "up to M (default " +
           num(map.max_range) + "; 0 or less: unlimited" + map_note +
           "); a ray may cross at most " + num(kMaxFusionVoxelsPerRay) + " voxels: M/R at most " +
           num(kMaxFusionVoxelsPerRay)},
      {"--p-miss P", "probability given to every label of a voxel a ray passes through (default " +
                         num(map.p_miss) + "; above 0 and below 0.5" + map_note + ")"},
      {"--threshold T",
       "a voxel is occupied by its most probable label when that label's probability reaches T "
       "(default " +
           num(map.occupancy_threshold) + "; above " + num(map.clamp_min) + " and at most " +
           num(map.clamp_max) + ", the clamping bounds" +
           (score ? "; with --map, the map's threshold and bounds, and T re-thresholds it)"
                  : "; with --start-from, the map's threshold and bounds)")},
      {"--candidates 0,8,19|none",
       "labels known to be present: the probabilities of the other labels are set to 0 and each "
       "pixel is renormalised over these (label ids of the sequence, 0 to " +
           num(static_cast<long long>(kMaxLabelId)) + "; default none: every label" +
           (score ? "; with --map, the candidates the map records, for the baselines too)"
                  : "; with --start-from, the candidates the map records)")},
      {"--frames A:B",
       std::string("frames A to B-1 (A: from A to the end, :B the first B; default every frame)") +
           (score ? "; with --map, only the frames projected for the baselines and the 2D "
                    "metrics"
                  : "")},
      {"--frame-memory GIB",
       "the most memory a frame may take while it is fused, in GiB (more than 0; default: the "
       "memory the system has available); a frame that would take more is refused"},
      {segmenterSpec(),
       "run this ONNX network on the colour image of every frame without a proba (or with one "
       "made from its label image); MODEL.json beside it configures it"},
  };
  return options;
}

std::string synthHelp() {
  const SynthOptions d;
  const auto range = [](long long low, const std::string& high) {
    return num(low) + " to " + high;
  };
  return section(
      {
          {"--out DIR",
           "folder to write the scene to (required; created when missing; it must be empty or "
           "an earlier synth output)"},
          {"--seed S", "everything random derives from it (default " + std::to_string(d.seed) +
                           "; 0 to 2^64-1)"},
          {"--objects N", "number of objects, each of another label (default " +
                              num(static_cast<long long>(d.objects)) + "; " +
                              range(1, num(static_cast<long long>(kSynthMaxObjects))) + ")"},
          {"--frames F",
           "frames along the camera path (default " + num(static_cast<long long>(d.frames)) + "; " +
               range(kSynthMinViews, num(static_cast<long long>(kSynthMaxFrames))) + ")"},
          {"--views V", "frames marked view: true, evenly spaced (default " +
                            num(static_cast<long long>(d.views)) + "; " +
                            range(kSynthMinViews, "F") + ")"},
          {"--width W", "image width in pixels (default " + num(static_cast<long long>(d.width)) +
                            "; " +
                            range(kSynthMinWidth, num(static_cast<long long>(kSynthMaxImageSide))) +
                            "); the intrinsics scale with it"},
          {"--height H",
           "image height in pixels (default " + num(static_cast<long long>(d.height)) + "; " +
               range(kSynthMinHeight, num(static_cast<long long>(kSynthMaxImageSide))) + ")"},
          {"--no-noise",
           "perfect depth: no noise, dropouts or holes at depth edges and grazing angles (the "
           "transparent object still has no depth)"},
          {"--perfect-segmenter",
           "no look-alike patches and no false positives in the probability images"},
      },
      "docs/synthetic-scenes.md");
}

std::string fuseHelp() {
  std::vector<OptionHelp> options = {
      {"--out MAP.ot", "the map to write (required; a .ot file)"},
  };
  for (auto& option : fusionOptions(false)) options.push_back(std::move(option));
  options.push_back({"--start-from EARLIER.ot",
                     "fuse the frames into a copy of this earlier map, which keeps its own "
                     "resolution, max range and p_miss (--resolution, --max-range and --p-miss "
                     "are then refused); EARLIER.ot is only read"});
  options.push_back({"--quiet", "no progress bar and no notes (warnings are always printed)"});
  return section(options, "docs/fusion.md (--segmenter: docs/segmenter.md)");
}

std::string scoreHelp() {
  std::vector<OptionHelp> options = {
      {"--annotations BOXES.json|BOXES.yaml",
       "the ground-truth boxes (required, except with --batch)"},
      {"--out DIR",
       "folder for report.json, .csv, .md and .svg (required; created when missing); with "
       "--batch, one report folder per sequence and aggregate.{json,csv,md,svg}"},
      {"--map MAP.ot",
       "score this map, fused earlier, instead of fusing the sequence; it must have the "
       "sequence's labels"},
      {"--batch LIST.txt",
       "score every line of the list, SEQ ANNOTATIONS [MAP.ot] (paths relative to the list's "
       "folder); no SEQ, --annotations or --map with it"},
      {"--iou exact|center",
       "how a voxel counts in IU_3d: the volume of its cube inside the box (exact, the "
       "default) or all of it when its centre is inside (center)"},
  };
  for (auto& option : fusionOptions(true)) options.push_back(std::move(option));
  options.push_back({"--quiet", "no progress line and no notes (warnings are always printed)"});
  return section(options, "docs/evaluation.md (fusion settings: docs/fusion.md)");
}

std::string exportHelp() {
  return section(
      {
          {"--format F",
           "ply, obj or stl (voxel surface meshes), pcd (voxel centres), ot (colour octree), bt "
           "(occupied/free octree) or objects (fitted boxes, JSON); required unless --voxels"},
          {"--out PATH",
           "the file to write, ending in the format's extension (.json for objects); with "
           "--per-label a folder"},
          {"--voxels OUT.pcd", "the same as --format pcd --out OUT.pcd"},
          {"--labels 8,19", "only these labels (ids of the map's labels, 0 to " +
                                num(static_cast<long long>(kMaxLabelId)) +
                                "; default every label, for objects every label but 0)"},
          {"--per-label",
           "one file per label, <id>_<name>.<ext>, in the folder --out (ply, obj, stl, pcd)"},
          {"--smooth",
           "meshes (ply, obj, stl): smoothed surfaces instead of voxel faces; not exact, for "
           "collision checks use the voxel mesh"},
          {"--points", "ply: the voxel centres as points instead of a mesh"},
          {"--native",
           "ot: the labelled map itself (every label's probabilities) instead of a colour "
           "octree; not with --labels"},
          {"--no-merge",
           "voxel meshes (ply, obj, stl without --smooth or --points): two triangles per voxel "
           "face instead of merged rectangles"},
          {"--level",
           "meshes and point clouds: rotate about the origin so that the map's up lies along "
           "+z (the rotation is printed and written in the PLY and OBJ headers)"},
          {"--sequence SEQ",
           "the sequence the map was fused from, whose cameras give the up of a map that "
           "records none (only with --format objects or --level)"},
      },
      "docs/export.md");
}

std::string renderHelp() {
  const std::string max_side = num(static_cast<long long>(render::kMaxRenderSide));
  return section(
      {
          {"--out view.png", "the picture to write (required; a .png file)"},
          {"--camera SEQ:INDEX",
           "the view of frame INDEX (from 0) of the sequence SEQ, with its pose and intrinsics, "
           "instead of the orbit view (not with --azimuth, --elevation, --up or --frame)"},
          {"--azimuth A",
           "orbit view: degrees counter-clockwise about the up direction (default 210)"},
          {"--elevation E",
           "orbit view: degrees above the plane across up (default 30; -90 to 90)"},
          {"--up X,Y,Z",
           "orbit view: the direction up in the picture (default: the map's own, from its "
           "cameras and level plane, else +z)"},
          {"--frame bulk|all", "what the orbit view fits in the picture: the parts of at least " +
                                   num(static_cast<long long>(kBulkPartVoxels)) +
                                   " voxels (bulk, the default) or every voxel (all)"},
          {"--size WxH",
           "picture size in pixels (default 1280x960, with --camera its image size, whose shape "
           "it must keep; each side 1 to " +
               max_side + ", at most " + num(render::kMaxRenderPixels) + " pixels)"},
          {"--labels 8,19", "only these labels (ids of the map's labels, 0 to " +
                                num(static_cast<long long>(kMaxLabelId)) +
                                "; default every label)"},
          {"--flat",
           "no lighting: every face exactly its colour, a white background, no anti-aliasing"},
          {"--colour labels|height|score",
           "label colours, or height along up (default: height for a map with a single label, "
           "else labels); score: how IU_3d counts each voxel against --annotations"},
          {"--annotations BOXES.json",
           "the boxes of --colour score (required with it, only with it)"},
          {"--iou exact|center",
           "how --colour score counts a voxel, as score does (default exact; only with --colour "
           "score)"},
      },
      "docs/export.md (\"Rendering\")");
}

std::string planHelp() {
  const PlanOptions d;
  return section(
      {
          {"--target LABEL",
           "the object to pick: a label id or name of the map, not the background 0 (required)"},
          {"--approach X,Y,Z",
           "the direction the gripper moves in (default: the mean viewing direction of the "
           "cameras the map records, else guessed from its free space); not with --sequence"},
          {"--sequence SEQ",
           "the approach is the mean viewing direction of this sequence's cameras (the "
           "recording the map was fused from); their up levels the boxes of a map that records "
           "none; not with --approach"},
          {"--out plan.json", "also write the plan as JSON"},
          {"--empty-bin CX,CY,CZ,DX,DY,DZ",
           "axis-aligned box (centre and sizes in metres, map frame, z up) to place the removed "
           "objects in (default: none, every removed object is placed outside)"},
          {"--gap M", "metres between placed objects and from the bin's walls (default " +
                          num(d.placement_gap) + "; 0 or more)"},
          {"--candidates 8,19,NAME",
           "only these labels are objects, ids or names (the target is always among them; "
           "default every label but 0)"},
          {"--all-clusters",
           "every cluster of a label is an object, not only its largest (the others are "
           "outliers)"},
          {"--cluster-tolerance VOXELS",
           "voxels whose centres are at most this many voxel edges apart are in the same "
           "cluster (default " +
               num(d.objects.cluster_tolerance_voxels) + "; above 0, at most " +
               num(kMaxClusterTolerance) + ")"},
          {"--min-cluster-voxels N", "clusters of fewer voxels are never objects (default " +
                                         num(static_cast<long long>(kDefaultMinObjectVoxels)) +
                                         "; 1 to " + std::to_string(INT_MAX) + ")"},
          {"--overlap-margin VOXELS",
           "a box is in the target's path when it overlaps the path by more than this many "
           "voxel edges (default " +
               num(d.overlap_margin_voxels) + "; 0 or more)"},
          {"--transitive",
           "also remove the objects in front of each object to be removed, recursively"},
          {"--threshold T",
           "read the voxels as occupied at probability T (default: the map's own threshold; "
           "above the map's lower clamping bound and at most its upper)"},
          {"--occluders path|centroid",
           "path (the default): remove only the objects whose box is in the target's path; "
           "centroid (the paper's rule): every object whose centroid is nearer the cameras "
           "than the target's"},
      },
      "docs/planning.md");
}

std::string segmentHelp() {
  return section(
      {
          {segmenterSpec(),
           "the ONNX network to run on the colour images (required); MODEL.json beside it "
           "configures it"},
          {"--all",
           "segment every frame, replacing their proba (default: the frames without a "
           "network's proba)"},
          {"--dtype float32|float16|uint8",
           "how the probability images are stored (default float32; float16 halves the size, "
           "uint8 quarters it)"},
          {"--out-dir DIR",
           "folder for the probability images, relative to the sequence folder unless absolute "
           "(default proba-MODEL, MODEL the model's file name without .onnx)"},
          {"--quiet", "no progress line"},
      },
      "docs/segmenter.md");
}

}  // namespace

// The options section of `command`'s help, beginning with an empty line so that
// it follows the usage line directly; "" for a command without options (info,
// validate) and for import, whose importHelp() is complete.
std::string commandOptionsHelp(const std::string& command) {
  if (command == "synth") return synthHelp();
  if (command == "fuse") return fuseHelp();
  if (command == "score") return scoreHelp();
  if (command == "export") return exportHelp();
  if (command == "render") return renderHelp();
  if (command == "plan") return planHelp();
  if (command == "segment") return segmentHelp();
  return {};
}

}  // namespace lom::cli
