// labeloctomap render: a picture of a map, rendered offscreen to a PNG.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "args.hpp"
#include "commands.hpp"
#include "lom/error.hpp"
#include "lom/evaluation.hpp"
#include "lom/height_colours.hpp"
#include "lom/render_limits.hpp"
#include "lom/sequence.hpp"
#include "output_paths.hpp"

#ifdef LOM_HAVE_RENDER
#include "lom/label_map.hpp"
#include "lom/render/map_render.hpp"
#include "lom/score_breakdown.hpp"
#endif

namespace lom::cli {

namespace {

namespace fs = std::filesystem;

// The command line of render, checked whether or not this build can render.
struct RenderRequest {
  fs::path map;
  fs::path out;
  double azimuth_deg = 210.0;
  double elevation_deg = 30.0;
  bool shading = true;
  std::optional<std::set<int>> labels;
  std::optional<Sequence> camera_sequence;  // --camera SEQ:INDEX
  size_t camera_frame = 0;
  std::optional<std::pair<int, int>> size;
  std::optional<Eigen::Vector3d> up;  // --up
  std::optional<VoxelColouring> colouring;  // --colour
  bool score = false;                       // --colour score
  std::optional<fs::path> annotations;      // --annotations (with --colour score)
  IouMode iou_mode = IouMode::Exact;        // --iou
  bool frame_all = false;                   // --frame all
};

// "1280x960" -> (1280, 960): digits only, each side 1 to 16384, at most
// 2^27 pixels in all.
std::pair<int, int> parseSize(const std::string& text) {
  const auto x = text.find('x');
  const auto digits = [](const std::string& part) {
    return !part.empty() && part.size() <= 5 &&
           std::all_of(part.begin(), part.end(), [](unsigned char c) { return std::isdigit(c); });
  };
  if (x != std::string::npos && digits(text.substr(0, x)) && digits(text.substr(x + 1))) {
    const long w = std::strtol(text.substr(0, x).c_str(), nullptr, 10);
    const long h = std::strtol(text.substr(x + 1).c_str(), nullptr, 10);
    if (w > 0 && h > 0 && w <= render::kMaxRenderSide && h <= render::kMaxRenderSide) {
      if (static_cast<long long>(w) * h > render::kMaxRenderPixels)
        throw UsageError("option --size expects at most 134217728 pixels (16384x8192), got '" +
                         text + "' (" + std::to_string(static_cast<long long>(w) * h) + ")");
      return {static_cast<int>(w), static_cast<int>(h)};
    }
  }
  throw UsageError(
      "option --size expects WIDTHxHEIGHT in pixels, each from 1 to 16384 (e.g. 1280x960), got '" +
      text + "'");
}

// "SEQ:INDEX": a sequence folder (or sequence.json) and a frame index.
std::pair<fs::path, size_t> parseCamera(const std::string& text) {
  const auto colon = text.rfind(':');
  // strtol's end pointer points into the string parsed: keep it alive.
  const std::string index_text = colon == std::string::npos ? "" : text.substr(colon + 1);
  char* end = nullptr;
  errno = 0;
  const long index = colon == std::string::npos ? -1 : std::strtol(index_text.c_str(), &end, 10);
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size() || *end != '\0' ||
      index < 0 || errno == ERANGE)
    throw UsageError(
        "option --camera expects SEQ:INDEX (a sequence folder and a frame index), got '" + text +
        "'");
  return {text.substr(0, colon), static_cast<size_t>(index)};
}

RenderRequest parseRequest(const Words& words) {
  const Args args(words, {"flat"});
  args.expectOnly({"out", "camera", "azimuth", "elevation", "up", "size", "labels", "flat",
                   "colour", "annotations", "iou", "frame"},
                  1);
  RenderRequest request;
  request.map = args.positional(0, "MAP.ot");
  request.out = args.required("out");
  if (args.option("camera") &&
      (args.option("azimuth") || args.option("elevation") || args.option("up")))
    throw UsageError("give either --camera SEQ:INDEX or --azimuth/--elevation/--up, not both");
  if (const auto up = args.option("up")) request.up = parseDirection(*up, "up");
  request.azimuth_deg = args.number("azimuth", request.azimuth_deg);
  request.elevation_deg = args.number("elevation", request.elevation_deg);
  if (request.elevation_deg < -90.0 || request.elevation_deg > 90.0)
    throw UsageError("option --elevation expects degrees from -90 to 90, got '" +
                     *args.option("elevation") + "'");
  request.shading = !args.flag("flat");
  if (const auto frame = args.option("frame")) {
    if (args.option("camera"))
      throw UsageError(
          "--frame is for the orbit view; --camera SEQ:INDEX shows what that "
          "camera saw");
    if (*frame != "bulk" && *frame != "all")
      throw UsageError("option --frame expects bulk or all, got '" + *frame + "'");
    request.frame_all = *frame == "all";
  }
  if (const auto colour = args.option("colour")) {
    if (*colour == "labels")
      request.colouring = VoxelColouring::Labels;
    else if (*colour == "height")
      request.colouring = VoxelColouring::Height;
    else if (*colour == "score")
      request.score = true;
    else
      throw UsageError("option --colour expects labels, height or score, got '" + *colour + "'");
  }
  if (const auto annotations = args.option("annotations")) request.annotations = *annotations;
  if (request.score && !request.annotations)
    throw UsageError(
        "--colour score needs --annotations BOXES.json (the boxes to score the voxels against)");
  if (!request.score && (request.annotations || args.option("iou")))
    throw UsageError(std::string(request.annotations ? "--annotations" : "--iou") +
                     " is for --colour score");
  if (const auto iou = args.option("iou")) {
    const auto mode = parseIouMode(*iou);
    if (!mode) throw UsageError("option --iou expects exact or center, got '" + *iou + "'");
    request.iou_mode = *mode;
  }
  if (const auto labels = args.option("labels")) {
    const auto list = parseLabelList(*labels, "labels");
    request.labels = std::set<int>(list.begin(), list.end());
  }
  std::optional<std::pair<fs::path, size_t>> camera;
  if (const auto text = args.option("camera")) camera = parseCamera(*text);
  if (const auto size = args.option("size")) request.size = parseSize(*size);

  CommandInputs inputs;
  inputs.addFile(request.map, "the input map");
  if (request.annotations) inputs.addFile(*request.annotations, "the annotations file");
  if (camera) inputs.addSequenceJson(camera->first);
  checkOutputFile(request.out, "out", ".png", "the picture", inputs);
  if (camera) {
    Sequence sequence = loadSequence(camera->first);
    const size_t count = sequence.frames.size();
    if (camera->second >= count)
      throw UsageError("option --camera: frame " + std::to_string(camera->second) +
                       " is past the end of " + (sequence.root / "sequence.json").string() +
                       ", which has " + std::to_string(count) +
                       (count == 1 ? " frame" : " frames") + " (a frame index below " +
                       std::to_string(count) + ")");
    if (request.size) {
      // A picture from a recorded camera keeps its shape: fy sets the field of
      // view, so another aspect ratio would crop or widen the view instead of
      // scaling it, and the picture would no longer line up with the frame.
      const CameraIntrinsics k = sequence.cameraOf(camera->second);
      const auto [width, height] = *request.size;
      const double ratio =
          (static_cast<double>(width) / height) / (static_cast<double>(k.width) / k.height);
      if (std::abs(ratio - 1.0) > 0.01)
        throw UsageError("option --size " + std::to_string(width) + "x" + std::to_string(height) +
                         " with --camera: the camera's images are " + std::to_string(k.width) +
                         "x" + std::to_string(k.height) +
                         " and its picture keeps that shape (e.g. --size " +
                         std::to_string(2 * k.width) + "x" + std::to_string(2 * k.height) + ")");
    }
    inputs.addSequenceFiles(sequence);
    checkOutputFile(request.out, "out", ".png", "the picture", inputs);
    request.camera_sequence = std::move(sequence);
    request.camera_frame = camera->second;
  }
  return request;
}

}  // namespace

#ifdef LOM_HAVE_RENDER

namespace {

// The labels to render must exist and hold occupied voxels.
void checkSomethingToRender(const LabelMap& map, const fs::path& map_path,
                            const std::optional<std::set<int>>& labels) {
  const auto counts = map.occupiedCountPerLabel();
  if (!labels) {
    if (counts.empty())
      throw Error(map_path.string(), "map", "at least one occupied voxel to render",
                  "no occupied voxel");
    return;
  }
  for (const int label : *labels)
    if (!map.labels().contains(label))
      throw Error(map_path.string(), "--labels",
                  "label ids of the map, 0 to " + std::to_string(map.numLabels() - 1),
                  std::to_string(label));
  for (const int label : *labels)
    if (counts.count(label)) return;
  throw Error(map_path.string(), "--labels", "labels with occupied voxels in the map",
              "no occupied voxel of the selected labels");
}

// What the score colours show: per boxed label drawn, its voxels inside its
// box, partly inside and outside, and the IU_3d they make.
void printScoreColours(const LabelMap& map, const render::RenderOptions& options) {
  const render::ScoreColours& score = *options.score;
  std::cout << "colours: each boxed label's voxels by how IU_3d (" << iouModeName(score.mode)
            << ") counts them: green wholly inside its box, red outside, from red through amber "
               "to green by the share inside when partly inside; the other labels grey\n";
  std::set<int> drawn;
  for (const GroundTruthBox& box : score.boxes)
    if (!options.labels || options.labels->count(box.label)) drawn.insert(box.label);
  // Every drawn label's voxels in one pass over the map.
  std::map<int, std::vector<VoxelKey>> voxels = map.voxelsByLabel(drawn);
  for (const GroundTruthBox& box : score.boxes) {
    if (!drawn.count(box.label)) continue;
    const ScoreBreakdown breakdown =
        scoreBreakdown(voxels[box.label], map.parameters().resolution, box, score.mode);
    std::cout << "  label " << box.label << " " << map.labels().at(box.label).name << ": ";
    if (breakdown.centres.empty()) {
      std::cout << "no voxels\n";
      continue;
    }
    char iou[32];
    std::snprintf(iou, sizeof iou, "%.2f", breakdown.volumes.iou() * 100.0);
    std::cout << breakdown.inside << " voxels inside, " << breakdown.partly << " partly, "
              << breakdown.outside << " outside; IU_3d " << iou << "\n";
  }
}

}  // namespace

int runRender(const Words& words) {
  const RenderRequest request = parseRequest(words);
  render::RenderOptions options;
  options.azimuth_deg = request.azimuth_deg;
  options.elevation_deg = request.elevation_deg;
  options.shading = request.shading;
  options.labels = request.labels;
  options.up = request.up;
  options.frame_all = request.frame_all;
  options.colouring = request.colouring;
  if (request.camera_sequence) {
    const Sequence& sequence = *request.camera_sequence;
    options.camera = render::PinholeView{};
    options.camera->intrinsics = sequence.cameraOf(request.camera_frame);
    options.camera->T_world_camera = sequence.frames[request.camera_frame].T_world_camera;
    options.width = options.camera->intrinsics.width;
    options.height = options.camera->intrinsics.height;
  }
  if (request.size) std::tie(options.width, options.height) = *request.size;

  // Say so before loading a large map when there is no display.
  if (const auto problem = render::displayProblem()) {
    std::cerr << "labeloctomap render: " << *problem << "\n";
    return 3;
  }
  const LabelMap map = LabelMap::load(request.map);
  checkSomethingToRender(map, request.map, options.labels);
  if (request.annotations) {
    const Annotations annotations = loadAnnotationsFor(*request.annotations, map.labels(), "world");
    checkBoxLabels(annotations, map.numLabels(), request.annotations->string(), "the map");
    // As score says: the colours are those of the box's label, whatever its name.
    for (const std::string& warning : boxNameWarnings(
             annotations, map.labels(), request.annotations->string(), request.map.string()))
      std::cerr << "warning: " << warning << "\n";
    options.score = render::ScoreColours{annotations.boxes, request.iou_mode};
  }
  render::OrbitFraming framing;
  try {
    render::renderMapToPng(map, options, request.out, &framing);
  } catch (const Error& e) {
    if (!e.problem().file.empty()) throw;
    Problem problem = e.problem();
    problem.file = request.map.string();
    throw Error(problem);
  }
  std::cout << "wrote " << options.width << "x" << options.height << " picture to "
            << request.out.string() << "\n";
  if (options.score) {
    printScoreColours(map, options);
  } else if (render::colouringFor(map, options) == VoxelColouring::Height) {
    const Eigen::Vector3d up = render::orbitUp(map, options);
    std::cout << "colours: height along (" << up.x() << ", " << up.y() << ", " << up.z()
              << "), blue lowest to red highest"
              << (options.colouring ? ""
                                    : " (the map has a single label; --colour labels paints it)")
              << "\n";
  }
  if (!options.camera) {
    const Eigen::Vector3d up = render::orbitUp(map, options);
    std::cout << "up in the picture: (" << up.x() << ", " << up.y() << ", " << up.z() << "), "
              << (options.up ? std::string("given with --up")
                  // orbitUp levelled the cameras' up when it differs from it (no second search).
                  : map.camerasUp() && up != *map.camerasUp()
                      ? "the normal of the map's largest level plane, near the mean up of its " +
                            std::to_string(map.cameraViews().views) + " camera views"
                  : map.camerasUp()
                      ? "the mean up direction of the map's " +
                            std::to_string(map.cameraViews().views) + " camera views"
                      : std::string("world +z (the map records no camera views that agree "
                                    "on up; --up x,y,z sets it)"))
              << "\n";
    if (framing.leftOut() > 0)
      std::cout << "framed: " << framing.framed.size() << " of " << framing.selected_voxels
                << " voxels; " << framing.leftOut() << " in specks of fewer than "
                << render::kFramedPartVoxels
                << " voxels may lie outside the picture (--frame all fits every voxel)\n";
  }
  return 0;
}

#else

int runRender(const Words& words) {
  (void)parseRequest(words);  // mistakes in the call are reported as everywhere else
  std::cerr << "labeloctomap render: unavailable: this labeloctomap was built without the VTK "
               "rendering library (configure with -DLOM_BUILD_UI=ON to get it)\n";
  return 3;
}

#endif

}  // namespace lom::cli
