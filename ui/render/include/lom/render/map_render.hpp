#pragma once
// Offscreen pictures of a labelled map: the voxel surfaces of its labels in
// their label colours, seen from an orbit around the map or from a recorded
// camera. Debian's VTK renders through X: a display (or Xvfb) is needed.
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>

#include "lom/annotations.hpp"
#include "lom/box_fit.hpp"
#include "lom/camera.hpp"
#include "lom/evaluation.hpp"
#include "lom/height_colours.hpp"
#include "lom/images.hpp"
#include "lom/label_map.hpp"
#include "lom/labels.hpp"
#include "lom/render_limits.hpp"

namespace lom::render {

// Rendering is impossible here (no X display); the message says what to do.
class RenderUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A pinhole camera: the picture is what that camera would have seen.
struct PinholeView {
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
};

// Score colours (render --colour score): each voxel of a boxed label in the
// colour of its share inside that label's box as IU_3d counts it
// (scoreShareColour: green inside, red outside, blends between); the voxels of
// labels without a box in grey.
struct ScoreColours {
  std::vector<GroundTruthBox> boxes;  // at most one per label (checkBoxLabels)
  IouMode mode = IouMode::Exact;
};

struct RenderOptions {
  int width = 1280;
  int height = 960;
  // Orbit view: the camera looks at the centre of the rendered voxels from
  // this direction, with `up` (see orbitUp) up in the picture; azimuth
  // counter-clockwise about up, from the world x axis (z when x is up or
  // down) laid flat; elevation above the plane across up; distance such that
  // everything fits. With up = +z: azimuth about +z from +x, elevation above
  // the x-y plane.
  double azimuth_deg = 210.0;
  double elevation_deg = 30.0;
  // Up in the orbit view; when absent, the map's own (LabelMap::upDirection:
  // the cameras it was fused from, levelled by its largest level plane), else +z.
  std::optional<Eigen::Vector3d> up;
  // What the orbit view fits in the picture: false, the bulk of the map (the
  // voxels in connected parts of at least kFramedPartVoxels voxels; specks
  // such as flying pixels far from the scene may then fall outside); true,
  // every voxel. See orbitFraming.
  bool frame_all = false;
  // Replaces the orbit view. Its intrinsics are scaled to width x height.
  std::optional<PinholeView> camera;
  std::optional<std::set<int>> labels;  // default: every label
  // Headlight shading; false paints every pixel exactly in its voxel face's colour.
  bool shading = true;
  // Label colours, or height along the orbit's up (orbitUp, also with a
  // camera view); when absent, see colouringFor.
  std::optional<VoxelColouring> colouring;
  // Replaces `colouring` when set.
  std::optional<ScoreColours> score;
  Rgb background{255, 255, 255};
};

// The orbit view's up direction for `map` (unit length): options.up, else the
// map's cameras' up, else +z. Throws lom::Error (field "up") for a zero or
// non-finite options.up.
[[nodiscard]] Eigen::Vector3d orbitUp(const LabelMap& map, const RenderOptions& options);

// The orbit view frames connected parts (26-neighbours, over the selected
// labels together) of at least this many voxels, unless frame_all is set or
// no part is that large.
inline constexpr size_t kFramedPartVoxels = kBulkPartVoxels;

// Which of the selected labels' occupied voxels the orbit view fits in the
// picture (VoxelKeys, sorted) and how many voxels the selection holds.
struct OrbitFraming {
  std::vector<VoxelKey> framed;
  size_t selected_voxels = 0;
  [[nodiscard]] size_t leftOut() const { return selected_voxels - framed.size(); }
};
[[nodiscard]] OrbitFraming orbitFraming(const LabelMap& map, const RenderOptions& options);

// options.colouring, else height for a map with a single label (geometry
// without labels: one colour would hide its shape), else label colours.
[[nodiscard]] VoxelColouring colouringFor(const LabelMap& map, const RenderOptions& options);

// Empty when an X display can be opened; otherwise the reason, with the
// xvfb-run command line that works around it.
[[nodiscard]] std::optional<std::string> displayProblem();

// Whether the X display `name` accepts a connection (kept open for the life of
// the process, which also keeps a virtual X server from resetting).
[[nodiscard]] bool canOpenDisplay(const std::string& name);

// Whether the X display `name` opens and offers GLX, through which VTK draws
// (without it VTK aborts the process, or draws nothing in the studio).
[[nodiscard]] bool displayHasGlx(const std::string& name);
// The sentence saying that `who` ("render", "the studio's 3D view") finds no
// GLX on display `name`.
[[nodiscard]] std::string missingGlxProblem(const std::string& who, const std::string& name);

// Throws RenderUnavailable without a display, lom::Error when the selection
// has no occupied voxel or the size is not positive.
// `framing`, when given, receives the orbit view's framing (untouched with a camera).
[[nodiscard]] ColorImage renderMap(const LabelMap& map, const RenderOptions& options,
                                   OrbitFraming* framing = nullptr);

// renderMap, then a PNG written atomically.
void renderMapToPng(const LabelMap& map, const RenderOptions& options,
                    const std::filesystem::path& png, OrbitFraming* framing = nullptr);

}  // namespace lom::render
