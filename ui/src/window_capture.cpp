#include "lom/ui/window_capture.hpp"

#include <QBuffer>
#include <QCoreApplication>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QImageWriter>
#include <QPainter>
#include <QThread>
#include <QWidget>
#include <QWindow>
#include <ostream>

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
    // The view's drawing, inside its focus frame.
    const QRect drawing = scene.drawingRect();
    const QRect area(scene.mapTo(&window, drawing.topLeft()), drawing.size());
    painter.drawImage(area, rendered);
  }
  return shot;
}

namespace {
QByteArray imageFormatOf(const QString& path) {
  return QFileInfo(path).suffix().toLower().toLatin1();
}
}  // namespace

bool namesWritableImageFormat(const QString& path) {
  const QByteArray format = imageFormatOf(path);
  return !format.isEmpty() && QImageWriter::supportedImageFormats().contains(format);
}

QString saveImageAtomically(const QImage& image, const QString& path) {
  try {
    // Encoded in memory and written by the atomic writer, which names a full
    // disk as such; the image library writing to the file itself would only
    // print its own message on the terminal.
    const QByteArray format = imageFormatOf(path);
    QByteArray bytes;
    QBuffer buffer(&bytes);
    buffer.open(QIODevice::WriteOnly);
    QImageWriter writer(&buffer, format);
    if (format.isEmpty() || !writer.write(image))
      throw Error(path.toStdString(), "image",
                  "an image format such as .png or .jpg and a writable folder",
                  format.isEmpty() ? std::string("a file name without an extension")
                                   : writer.errorString().toStdString());
    lom::writeFileAtomically(std::filesystem::path(path.toStdString()), [&](std::ostream& out) {
      out.write(bytes.constData(), static_cast<std::streamsize>(bytes.size()));
    });
  } catch (const std::exception& error) {
    return QString::fromStdString(error.what());
  }
  return {};
}

}  // namespace lom::ui
