#include "lom/ui/save_screenshot_reaction.hpp"

#include <QFileDialog>
#include <QMessageBox>
#include <QWidget>

#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/window_capture.hpp"

namespace lom::ui {

SaveScreenshotReaction::SaveScreenshotReaction(QAction* action, QWidget& window, SceneView& scene,
                                               const SequenceController& controller)
    : Reaction(action), window_(window), scene_(scene), controller_(controller) {}

void SaveScreenshotReaction::onTriggered() {
  const QString path = QFileDialog::getSaveFileName(&window_, tr("Save Screenshot"),
                                                    "labeloctomap-studio.png",
                                                    tr("Images (*.png *.jpg)"));
  if (path.isEmpty()) return;
  const QString error = saveTo(path);
  if (!error.isEmpty()) QMessageBox::warning(&window_, tr("Save Screenshot"), error);
}

QString SaveScreenshotReaction::saveTo(const QString& path) {
  // A frame's colour image is a PNG too: never replaced by a picture of the window.
  if (const QString input = controller_.sequenceFileAt(path); !input.isEmpty())
    return tr("%1 is a file of the sequence (%2): a screenshot never replaces it. Choose another "
              "name.")
        .arg(path, input);
  return saveImageAtomically(captureWindow(window_, scene_), path);
}

}  // namespace lom::ui
