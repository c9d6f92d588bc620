#pragma once
// File > Save Screenshot…: the whole window, 3D view included, as an image.
#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class SceneView;
class SequenceController;

class SaveScreenshotReaction : public Reaction {
  Q_OBJECT

 public:
  SaveScreenshotReaction(QAction* action, QWidget& window, SceneView& scene,
                         const SequenceController& controller);
  // Writes the picture to `path`; an error message, empty on success.
  QString saveTo(const QString& path);

 protected:
  void onTriggered() override;

 private:
  QWidget& window_;
  SceneView& scene_;
  const SequenceController& controller_;
};

}  // namespace lom::ui
