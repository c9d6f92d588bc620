// labeloctomap render: a picture of a map, rendered offscreen to a PNG.
#include <cstdlib>
#include <iostream>
#include <set>
#include <tuple>

#include "args.hpp"
#include "commands.hpp"
#include "lom/error.hpp"

#ifdef LOM_HAVE_RENDER
#include "lom/label_map.hpp"
#include "lom/render/map_render.hpp"
#include "lom/sequence.hpp"
#endif

namespace lom::cli {

#ifdef LOM_HAVE_RENDER

namespace {

// "1280x960" -> (1280, 960).
std::pair<int, int> parseSize(const std::string& text) {
  const auto x = text.find('x');
  char* end = nullptr;
  if (x != std::string::npos) {
    const long w = std::strtol(text.substr(0, x).c_str(), &end, 10);
    if (*end == '\0' && x > 0) {
      const long h = std::strtol(text.substr(x + 1).c_str(), &end, 10);
      if (*end == '\0' && x + 1 < text.size() && w > 0 && h > 0 && w <= 16384 && h <= 16384)
        return {static_cast<int>(w), static_cast<int>(h)};
    }
  }
  throw UsageError("option --size expects WIDTHxHEIGHT in pixels (e.g. 1280x960), got '" + text +
                   "'");
}

// "SEQ:INDEX": the camera of frame INDEX of the sequence folder (or sequence.json) SEQ.
render::PinholeView parseCamera(const std::string& text) {
  const auto colon = text.rfind(':');
  char* end = nullptr;
  const long index =
      colon == std::string::npos ? -1 : std::strtol(text.substr(colon + 1).c_str(), &end, 10);
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size() || *end != '\0' ||
      index < 0)
    throw UsageError(
        "option --camera expects SEQ:INDEX (a sequence folder and a frame index), got '" + text +
        "'");
  const std::string folder = text.substr(0, colon);
  const Sequence sequence = loadSequence(folder);
  if (static_cast<size_t>(index) >= sequence.frames.size())
    throw Error((sequence.root / "sequence.json").string(), "frames",
                "a frame index below " + std::to_string(sequence.frames.size()),
                std::to_string(index));
  render::PinholeView view;
  view.intrinsics = sequence.cameraOf(static_cast<size_t>(index));
  view.T_world_camera = sequence.frames[static_cast<size_t>(index)].T_world_camera;
  return view;
}

}  // namespace

int runRender(const Words& words) {
  const Args args(words, {"flat"});
  args.expectOnly({"out", "camera", "azimuth", "elevation", "size", "labels", "flat"}, 1);
  const std::filesystem::path map_path = args.positional(0, "MAP.ot");
  const std::filesystem::path out = args.required("out");
  if (args.option("camera") && (args.option("azimuth") || args.option("elevation")))
    throw UsageError("give either --camera SEQ:INDEX or --azimuth/--elevation, not both");

  render::RenderOptions options;
  options.azimuth_deg = args.number("azimuth", options.azimuth_deg);
  options.elevation_deg = args.number("elevation", options.elevation_deg);
  if (options.elevation_deg < -90.0 || options.elevation_deg > 90.0)
    throw UsageError("option --elevation expects degrees from -90 to 90");
  options.shading = !args.flag("flat");
  if (const auto labels = args.option("labels")) {
    const auto list = parseIntList(*labels, "labels");
    options.labels = std::set<int>(list.begin(), list.end());
  }
  if (const auto camera = args.option("camera")) {
    options.camera = parseCamera(*camera);
    options.width = options.camera->intrinsics.width;
    options.height = options.camera->intrinsics.height;
  }
  if (const auto size = args.option("size"))
    std::tie(options.width, options.height) = parseSize(*size);

  // Say so before loading a large map when there is no display.
  if (const auto problem = render::displayProblem()) {
    std::cerr << "labeloctomap render: " << *problem << "\n";
    return 3;
  }
  const LabelMap map = LabelMap::load(map_path);
  if (options.labels)
    for (const int label : *options.labels)
      if (!map.labels().contains(label))
        throw Error(map_path.string(), "labels",
                    "label ids of the map, 0 to " + std::to_string(map.numLabels() - 1),
                    std::to_string(label));
  render::renderMapToPng(map, options, out);
  std::cout << "wrote " << options.width << "x" << options.height << " picture to " << out.string()
            << "\n";
  return 0;
}

#else

int runRender(const Words&) {
  std::cerr << "labeloctomap render: unavailable: this labeloctomap was built without the VTK "
               "rendering library (configure with -DLOM_BUILD_UI=ON to get it)\n";
  return 3;
}

#endif

}  // namespace lom::cli
