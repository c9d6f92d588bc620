#pragma once
// The 3D view: the current frame's back-projected points coloured by label,
// and the camera frustums of all frames with the current one highlighted.
// VTK stays behind this header (see scene_adapters.hpp in src/).
#include <QImage>
#include <QWidget>
#include <cstddef>
#include <memory>
#include <optional>

#include "lom/sequence.hpp"

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
  void resetCamera();

  // Points of the current frame's cloud (one per valid depth pixel).
  [[nodiscard]] size_t framePointCount() const;
  // Renders now and returns the 3D view's pixels (same size as this widget).
  [[nodiscard]] QImage renderToImage();

 private:
  void render();

  struct Scene;
  std::unique_ptr<Scene> scene_;
  QVTKOpenGLNativeWidget* vtk_widget_;
};

}  // namespace lom::ui
