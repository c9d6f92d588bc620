#include "lom/ui/save_screenshot_reaction.hpp"

#include <QFileDialog>
#include <QMessageBox>
#include <QWidget>

#include "lom/ui/window_capture.hpp"

namespace lom::ui {

SaveScreenshotReaction::SaveScreenshotReaction(QAction* action, QWidget& window, SceneView& scene)
    : Reaction(action), window_(window), scene_(scene) {}

void SaveScreenshotReaction::onTriggered() {
  const QString path = QFileDialog::getSaveFileName(&window_, tr("Save Screenshot"),
                                                    "labeloctomap-studio.png",
                                                    tr("Images (*.png *.jpg)"));
  if (path.isEmpty()) return;
  const QImage shot = captureWindow(window_, scene_);
  const QString error = saveImageAtomically(shot, path);
  if (!error.isEmpty()) QMessageBox::warning(&window_, tr("Save Screenshot"), error);
}

}  // namespace lom::ui
