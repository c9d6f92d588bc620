#include "lom/ui/sequence_drop_handler.hpp"

#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileInfo>
#include <QMimeData>
#include <QTimer>
#include <QUrl>
#include <QWidget>

#include "lom/import.hpp"
#include "lom/ui/sequence_controller.hpp"

namespace lom::ui {

SequenceDropHandler::SequenceDropHandler(QWidget* target, SequenceController& controller)
    : QObject(target), controller_(controller) {
  target->setAcceptDrops(true);
  target->installEventFilter(this);
}

namespace {

// A file named sequence.json, or a JSON file whose beginning names the
// sequence format (a sequence.json saved under another name).
bool isSequenceJson(const QFileInfo& info) {
  if (info.fileName() == QLatin1String("sequence.json")) return true;
  QFile file(info.absoluteFilePath());
  if (!file.open(QIODevice::ReadOnly)) return false;
  return file.read(4096).contains("\"labeloctomap-sequence\"");
}

}  // namespace

QString SequenceDropHandler::droppedSequencePath(const QMimeData* mime) {
  if (!mime || !mime->hasUrls()) return {};
  for (const QUrl& url : mime->urls()) {
    if (!url.isLocalFile()) continue;
    const QFileInfo info(url.toLocalFile());
    // A sequence folder or its sequence.json, a dataset folder, or a ROS bag.
    // Another JSON file (boxes, a report) is no sequence, nor is a folder of
    // no layout the importer knows (the folder that holds the sequences, say):
    // the drop is refused rather than trying an open that cannot succeed.
    if ((info.isDir() && detectSource(info.absoluteFilePath().toStdString()).kind) ||
        info.suffix().compare("bag", Qt::CaseInsensitive) == 0 ||
        (info.suffix().compare("json", Qt::CaseInsensitive) == 0 && isSequenceJson(info)))
      return info.absoluteFilePath();
  }
  return {};
}

QString SequenceDropHandler::droppedMapPath(const QMimeData* mime) {
  if (!mime || !mime->hasUrls()) return {};
  for (const QUrl& url : mime->urls()) {
    if (!url.isLocalFile()) continue;
    const QFileInfo info(url.toLocalFile());
    if (!info.isDir() && info.suffix().compare("ot", Qt::CaseInsensitive) == 0)
      return info.absoluteFilePath();
  }
  return {};
}

bool SequenceDropHandler::eventFilter(QObject* watched, QEvent* event) {
  if (event->type() == QEvent::DragEnter) {
    auto* drag = static_cast<QDragEnterEvent*>(event);
    if (!droppedSequencePath(drag->mimeData()).isEmpty() ||
        (open_map_ && !droppedMapPath(drag->mimeData()).isEmpty()))
      drag->acceptProposedAction();
    return true;
  }
  if (event->type() == QEvent::Drop) {
    auto* drop = static_cast<QDropEvent*>(event);
    const QString path = droppedSequencePath(drop->mimeData());
    if (const QString map = droppedMapPath(drop->mimeData());
        path.isEmpty() && open_map_ && !map.isEmpty()) {
      drop->acceptProposedAction();
      QTimer::singleShot(0, this, [this, map] { open_map_(map); });
      return true;
    }
    if (path.isEmpty()) return false;
    drop->acceptProposedAction();
    // Opened once the drop has been answered: a recording's conversion shows
    // a modal dialog, and the application the drag came from must not wait
    // for it.
    QTimer::singleShot(0, this, [this, path] { controller_.openSequence(path); });
    return true;
  }
  return QObject::eventFilter(watched, event);
}

}  // namespace lom::ui
