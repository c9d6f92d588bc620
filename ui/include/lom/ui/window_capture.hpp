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

}  // namespace lom::ui
