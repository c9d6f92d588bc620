#pragma once
// Screenshots of the whole studio window, 3D view included.
#include <QImage>
#include <QString>

class QWidget;

namespace lom::ui {

class SceneView;

// Processes events until `window` is shown on screen (or the timeout passes).
bool waitUntilExposed(QWidget& window, int timeout_ms = 5000);

// QWidget::grab() of `window` with the OpenGL content of `scene` painted in
// from its framebuffer (grab() alone may leave the GL area black).
[[nodiscard]] QImage captureWindow(QWidget& window, SceneView& scene);

// Writes `image` to `path` in the format its extension names, through a
// temporary file renamed into place (an existing file is only replaced by a
// complete picture). Returns an empty string on success, else a message
// naming the file.
[[nodiscard]] QString saveImageAtomically(const QImage& image, const QString& path);
// Whether saveImageAtomically can write an image format named by `path`'s
// extension (.png, .jpg, ...), the check a caller makes before any work.
[[nodiscard]] bool namesWritableImageFormat(const QString& path);

}  // namespace lom::ui
