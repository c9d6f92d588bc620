#pragma once
// File > Save Screenshot…: the whole window, 3D view included, as an image;
// File > Save 3D View…: the 3D view alone, as it is shown (for figures).
#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class SceneView;
class SequenceController;

class SaveScreenshotReaction : public Reaction {
  Q_OBJECT

 public:
  enum class Kind { Window, SceneView };
  SaveScreenshotReaction(QAction* action, QWidget& window, SceneView& scene,
                         const SequenceController& controller, Kind kind = Kind::Window);
  // Writes the picture to `path`; an error message, empty on success.
  QString saveTo(const QString& path);
  // The 3D view's picture this many times its size on screen (1 to 4; File ▸
  // 3D View Picture Size).
  void setMagnification(int magnification) { magnification_ = magnification; }

 protected:
  void onTriggered() override;

 private:
  QWidget& window_;
  SceneView& scene_;
  const SequenceController& controller_;
  Kind kind_;
  int magnification_ = 1;
};

}  // namespace lom::ui
