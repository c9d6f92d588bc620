#pragma once
// The 3D view: the map's voxels coloured by label, the current frame's
// back-projected points, the camera frustums of all frames with the current
// one highlighted, and the ground-truth boxes with handles on the selected one.
// VTK stays behind this header (see scene_adapters.hpp in src/).
#include <QImage>
#include <QPoint>
#include <QRect>
#include <QSize>
#include <QString>
#include <QWidget>
#include <cstddef>
#include <memory>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "lom/annotations.hpp"
#include "lom/height_colours.hpp"
#include "lom/objects.hpp"
#include "lom/planning.hpp"
#include "lom/score_breakdown.hpp"
#include "lom/sequence.hpp"
#include "lom/ui/map_snapshot.hpp"

class QTimer;
class QVTKOpenGLNativeWidget;

namespace lom::ui {

// Must run before the QApplication is created: VTK needs an OpenGL 3.2 core
// context, which Qt only gives when it is the default surface format.
void setDefaultSurfaceFormat();

class SceneView : public QWidget {
  Q_OBJECT

 public:
  explicit SceneView(QWidget* parent = nullptr);
  ~SceneView() override;

  // Draws the frustums of all frames and frames the view on the trajectory.
  void showSequence(const Sequence& sequence);
  // `frame` may be null when the frame's files could not be read.
  void showFrame(const Sequence& sequence, size_t index, const FrameData* frame,
                 const std::optional<LabelImage>& labels);
  void clear();
  // Whether the view says how to open a sequence (until one is shown).
  [[nodiscard]] bool emptyHintShown() const;
  // Frames everything shown: the frame's points, the cameras, the boxes and
  // the bulk of the map (mapBounds).
  void resetCamera();
  // What the view frames of the map, as VTK bounds (xmin, xmax, ymin, ...):
  // the box of the shown voxels' bulk (bulkBounds: specks of fewer than
  // kBulkPartVoxels connected voxels, such as flying pixels, left out).
  // False when no voxel is shown.
  bool mapBounds(double bounds[6]) const;
  // Keeps the view direction and frames the map's voxels (mapBounds), and with
  // `with_current_camera` the current frame's camera too (screenshots).
  void zoomToMap(bool with_current_camera = false);
  // Whether the current frame's camera (its frustum) is wholly in the picture.
  [[nodiscard]] bool currentCameraInView() const;
  // How far the cubes of the shown map's bulk reach across the view: the
  // largest |x| or |y| of their corners in normalised view coordinates, 1 at
  // the picture's edge (0 without a map).
  [[nodiscard]] double mapExtentInView() const;
  // How far the corners of `bounds` (VTK bounds) reach across the view: the
  // largest |x| or |y| in normalised view coordinates, 1 at the picture's
  // edge (infinity when a corner lies behind the camera).
  [[nodiscard]] double boxExtentInView(const double bounds[6]) const;
  // Puts the 3D camera where frame `index`'s camera was.
  void lookFromFrame(const Sequence& sequence, size_t index);
  // Standard views of the map (of the whole scene before there is one),
  // levelled with the map's up (the cameras' mean up; else the first
  // camera's): from above, with the first camera's viewing direction pointing
  // up the picture; from the front, looking as the first camera looked; from
  // the side, from the first camera's right. Each frames what it looks at.
  enum class StandardView { Above, Front, Side };
  void lookFrom(StandardView view);
  // The 3D camera's viewing direction and view up (unit vectors).
  [[nodiscard]] Eigen::Vector3d cameraDirection() const;
  [[nodiscard]] Eigen::Vector3d cameraViewUp() const;
  // Where a world point is drawn in the view, in its pixels (x right, y up,
  // as VTK's display coordinates), and the view's size in pixels.
  [[nodiscard]] Eigen::Vector2d displayPointOf(const Eigen::Vector3d& world) const;
  [[nodiscard]] QSize viewPixels() const;

  void showVoxels(const MapSnapshot& snapshot, const LabelSet& labels, const std::set<int>& hidden);
  void setOpacityByProbability(bool on);
  // Voxels in their label colours or by height along the map's up (blue low, red high).
  void setVoxelColouring(VoxelColouring colouring);
  [[nodiscard]] VoxelColouring voxelColouring() const;
  // Extra, smaller cubes (e.g. a single view's projection); null hides them.
  void showProjectionVoxels(const MapSnapshot* voxels, const LabelSet& labels);
  [[nodiscard]] size_t projectionVoxelCount() const;
  // Boxes' labels' voxels coloured by how much of each lies inside its box
  // (scoreShareColour), over the map's; none hides them.
  void showScoreBreakdown(const std::vector<ScoreBreakdown>& breakdowns);
  [[nodiscard]] size_t scoreBreakdownCount() const;
  void setFrameCloudVisible(bool on);
  // What a figure may leave out (View menu): the camera frustums, the
  // orientation axes in the corner, the boxes' outlines (ground truth, with
  // the selected box's handles, and the objects' of the Objects panel).
  // Hidden parts are not framed by Reset Camera either.
  void setCamerasVisible(bool on);
  void setAxesVisible(bool on);
  void setBoxesVisible(bool on);
  [[nodiscard]] bool camerasVisible() const;
  [[nodiscard]] bool axesVisible() const;
  [[nodiscard]] bool boxesVisible() const;
  void showBoxes(const Annotations& boxes, int selected, const LabelSet& labels);
  [[nodiscard]] size_t voxelCount() const;
  // Where the 3D drawing lies in the view (inside the focus frame), in the
  // view's coordinates: what renderToImage shows.
  [[nodiscard]] QRect drawingRect() const;
  [[nodiscard]] bool boxHandlesVisible() const;
  // Wireframe boxes of extracted objects in their label colours (empty hides them).
  void showObjectBoxes(const std::vector<ObjectInstance>& objects, const LabelSet& labels);
  [[nodiscard]] size_t objectBoxCount() const;
  [[nodiscard]] bool objectBoxesVisible() const;
  // A pick plan: the occluders' boxes thick and red, the target's thick and
  // green, one grasp arrow per step (yellow first to green last) with its step
  // number. Null hides it.
  void showPickPlan(const PickPlan* plan);
  [[nodiscard]] bool pickPlanVisible() const;
  [[nodiscard]] size_t pickPlanBoxCount() const;    // occluders + target
  [[nodiscard]] size_t pickPlanArrowCount() const;  // one per step

  // A measurement: a marker at each point, a line between two points and
  // `label` beside the line's middle, drawn over everything else so that the
  // voxels never hide it. No points hide it.
  void showMeasurement(const std::vector<Eigen::Vector3d>& points, const QString& label);
  [[nodiscard]] size_t measurementPointCount() const;
  [[nodiscard]] QString measurementLabel() const;

  // Points of the current frame's cloud (one per valid depth pixel).
  [[nodiscard]] size_t framePointCount() const;
  // Renders now and returns the 3D view's pixels (same size as this widget).
  // With a magnification of 2 to 4, a picture that many times as wide and as
  // high, rendered in tiles (for figures): the same view, lines and points
  // as thin as on screen, on a plain background of the gradient's middle
  // colour and without the corner axes (both would repeat in every tile).
  [[nodiscard]] QImage renderToImage(int magnification = 1);
  // Redraws of the view so far (a frame step is one: software GL redraws slowly).
  [[nodiscard]] size_t renderCount() const;

  // What the tooltip says of the voxel under the resting mouse: its label,
  // probability, size and centre; empty over no voxel.
  [[nodiscard]] QString hoverText() const { return hover_text_; }

  // The orientation axes in the bottom-left corner: a square of this many
  // pixels (a quarter of the view's shorter side, within these bounds), its
  // X, Y and Z drawn in a fixed font size just beyond the axes' tips.
  static constexpr int kAxesMarkerMinPixels = 120;
  static constexpr int kAxesMarkerMaxPixels = 160;
  static constexpr int kAxesLabelFontSize = 14;
  // Where the axes are drawn, and where their X, Y and Z were drawn at the
  // last render, in this widget's coordinates.
  [[nodiscard]] QRect axesMarkerRect() const;
  [[nodiscard]] std::vector<QRect> axesLabelRects() const;

 signals:
  // A click (press and release without dragging) hit the scene at this point,
  // nudged a little along the view ray so that it lies inside the voxel hit.
  void pointPicked(const Eigen::Vector3d& point_world);
  // The same click: the point on the visible surface (a voxel's face), for measuring.
  void surfacePicked(const Eigen::Vector3d& point_world);
  // The 3D handles changed the selected box.
  void boxEdited(const lom::OrientedBox& box);
  // After the map's voxels were drawn: the heights (metres along the map's up)
  // that the height colours' blue and red ends stand for, or none when the
  // voxels are in label colours (or there are none).
  void heightColoursShown(std::optional<std::pair<double, double>> range);

 protected:
  void resizeEvent(QResizeEvent* event) override;
  // A frame in the highlight colour while the view has the keyboard focus
  // (Tab there selects boxes, Ctrl+Tab leaves it: the focus must be seen).
  void paintEvent(QPaintEvent* event) override;
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  void restoreViewAngle();  // the overview's 30 degrees, vertical
  void render();
  void placeAxesMarker();
  [[nodiscard]] std::optional<VoxelHit> voxelAt(int x, int y) const;  // VTK display pixels
  // The frame point drawn under the pixel nearest the eye (the frame's
  // points shown), found by a ray through it: the depth buffer is not always readable.
  [[nodiscard]] std::optional<Eigen::Vector3d> framePointAt(int x, int y) const;
  void pickAt(int x, int y);
  void hoverAt(int x, int y);
  // The bulk of the voxels shown (mapBulk), worked out once per snapshot and
  // hidden labels; null without one.
  [[nodiscard]] const MapBulk* shownBulk() const;
  // Keeps the camera's direction and view up, and moves it to where the
  // bulk's cubes fill 90 % of the view across or up, centred.
  void frameCubes(const MapBulk& bulk);
  // How far the boxes of half edges `half` centred on `centres` (axis-aligned)
  // reach across the view (see boxExtentInView).
  [[nodiscard]] double boxesExtentInView(const std::vector<Eigen::Vector3d>& centres,
                                         const Eigen::Vector3d& half) const;

  struct Scene;
  std::unique_ptr<Scene> scene_;
  QVTKOpenGLNativeWidget* vtk_widget_;
  QTimer* hover_timer_ = nullptr;
  QPoint hover_at_;
  QString hover_text_;
};

}  // namespace lom::ui
