#pragma once
// File > Save Screenshot…: the whole window, 3D view included, as an image.
#include "lom/ui/reaction.hpp"

class QWidget;

namespace lom::ui {

class SceneView;

class SaveScreenshotReaction : public Reaction {
  Q_OBJECT

 public:
  SaveScreenshotReaction(QAction* action, QWidget& window, SceneView& scene);

 protected:
  void onTriggered() override;

 private:
  QWidget& window_;
  SceneView& scene_;
};

}  // namespace lom::ui
