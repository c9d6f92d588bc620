#include "lom/ui/map_file_reader.hpp"

#include <QMetaObject>
#include <QThread>
#include <string>

#include "lom/label_map.hpp"

namespace lom::ui {

MapFileReader::MapFileReader(QObject* parent) : QObject(parent) {}

MapFileReader::~MapFileReader() {
  for (QThread* thread : threads_) {
    thread->wait();
    delete thread;
  }
}

unsigned MapFileReader::read(const QString& path) {
  const unsigned ticket = ++ticket_;
  QThread* thread = QThread::create([this, ticket, path] {
    std::shared_ptr<LabelMap> map;
    QString error;
    try {
      map = std::make_shared<LabelMap>(LabelMap::load(path.toStdString()));
    } catch (const std::exception& e) {
      error = QString::fromStdString(e.what());
    }
    // Delivered by this object's event loop: dropped with it when it is gone.
    QMetaObject::invokeMethod(
        this, [this, ticket, path, map, error] { emit finished(ticket, path, map, error); },
        Qt::QueuedConnection);
  });
  threads_.insert(thread);
  connect(thread, &QThread::finished, this, [this, thread] {
    threads_.erase(thread);
    thread->deleteLater();
  });
  thread->start();
  return ticket;
}

}  // namespace lom::ui
