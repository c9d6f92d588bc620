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

 protected:
  void onTriggered() override;

 private:
  QWidget& window_;
  SceneView& scene_;
  const SequenceController& controller_;
  Kind kind_;
};

}  // namespace lom::ui
