#include "lom/ui/window_capture.hpp"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QImageWriter>
#include <QPainter>
#include <QThread>
#include <QWidget>
#include <QWindow>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/ui/scene_view.hpp"

namespace lom::ui {

bool waitUntilExposed(QWidget& window, int timeout_ms) {
  QElapsedTimer timer;
  timer.start();
  while (timer.elapsed() < timeout_ms) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
    if (window.windowHandle() && window.windowHandle()->isExposed()) {
      // One more round so pending layout and paint events settle.
      QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
      return true;
    }
    QThread::msleep(10);
  }
  return false;
}

QImage captureWindow(QWidget& window, SceneView& scene) {
  QImage shot = window.grab().toImage().convertToFormat(QImage::Format_RGB32);
  const QImage rendered = scene.renderToImage();
  if (!rendered.isNull() && scene.isVisible()) {
    QPainter painter(&shot);
    const QRect area(scene.mapTo(&window, QPoint(0, 0)), scene.size());
    painter.drawImage(area, rendered);
  }
  return shot;
}

QString saveImageAtomically(const QImage& image, const QString& path) {
  const QString target = path;
  try {
    lom::writePathAtomically(std::filesystem::path(path.toStdString()),
                             [&](const std::filesystem::path& temporary) {
                               QImageWriter writer(QString::fromStdString(temporary.string()));
                               if (!writer.write(image))
                                 throw Error(target.toStdString(), "image",
                                             "an image format such as .png or .jpg and a "
                                             "writable folder",
                                             writer.errorString().toStdString());
                             });
  } catch (const std::exception& error) {
    return QString::fromStdString(error.what());
  }
  return {};
}

}  // namespace lom::ui
