#include "lom/ui/save_screenshot_reaction.hpp"

#include <QDir>
#include <QImageWriter>
#include <QMainWindow>
#include <QMessageBox>
#include <QStatusBar>
#include <QWidget>

#include "lom/ui/save_file_dialog.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/window_capture.hpp"

namespace lom::ui {

SaveScreenshotReaction::SaveScreenshotReaction(QAction* action, QWidget& window, SceneView& scene,
                                               const SequenceController& controller, Kind kind)
    : Reaction(action), window_(window), scene_(scene), controller_(controller), kind_(kind) {}

void SaveScreenshotReaction::onTriggered() {
  const bool view = kind_ == Kind::SceneView;
  const QString title = view ? tr("Save 3D View") : tr("Save Screenshot");
  // A name without an image format gets .png; any format Qt writes is kept.
  QStringList formats{QStringLiteral("png")};
  for (const QByteArray& format : QImageWriter::supportedImageFormats())
    formats << QString::fromLatin1(format);
  // Beside the sequence and named after it, as the map and the report are.
  const QString suffix = view ? "-3d-view.png" : ".png";
  QString start = controller_.proposedOutput(suffix);
  if (start.isEmpty()) start = view ? "labeloctomap-3d-view.png" : "labeloctomap-studio.png";
  const QString path = askSaveFileName(&window_, title, start, tr("Images (*.png *.jpg)"), formats);
  if (path.isEmpty()) return;
  const QString error = saveTo(path);
  if (!error.isEmpty()) {
    QMessageBox::warning(&window_, title, error);
    return;
  }
  // Said where it went, as the exports say what they wrote.
  if (auto* main = qobject_cast<QMainWindow*>(&window_))
    main->statusBar()->showMessage(tr("Saved %1.").arg(QDir::toNativeSeparators(path)), 8000);
}

QString SaveScreenshotReaction::saveTo(const QString& path) {
  // A frame's colour image is a PNG too: never replaced by a picture of the window.
  if (const QString input = controller_.sequenceFileAt(path); !input.isEmpty())
    return tr("%1 is a file of the sequence (%2): a screenshot never replaces it. Choose another "
              "name.")
        .arg(path, input);
  if (kind_ == Kind::SceneView) {
    if (!scene_.isVisible())
      return tr("The 3D view is not shown, so there is no picture of it to save.");
    const QImage view = scene_.renderToImage(magnification_);
    if (view.isNull())
      return tr("The 3D view could not be drawn at %1 times its size; a smaller picture size "
                "may work.")
          .arg(magnification_);
    return saveImageAtomically(view, path);
  }
  return saveImageAtomically(captureWindow(window_, scene_), path);
}

}  // namespace lom::ui
