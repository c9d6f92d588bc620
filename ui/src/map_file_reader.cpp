#include "lom/ui/map_file_reader.hpp"

#include <QMetaObject>
#include <QThread>
#include <string>

#include "lom/evaluation.hpp"
#include "lom/label_map.hpp"

namespace lom::ui {

MapFileReader::MapFileReader(QObject* parent) : QObject(parent) {}

MapFileReader::~MapFileReader() {
  for (QThread* thread : threads_) {
    thread->wait();
    delete thread;
  }
}

unsigned MapFileReader::read(const QString& path, std::shared_ptr<const Sequence> sequence) {
  const unsigned ticket = ++ticket_;
  QThread* thread = QThread::create([this, ticket, path, sequence] {
    std::shared_ptr<LabelMap> map;
    QString error, fit_warning;
    try {
      map = std::make_shared<LabelMap>(LabelMap::load(path.toStdString()));
      if (sequence)
        fit_warning = QString::fromStdString(
            poorMapFitWarning(mapFitOf(*map, *sequence), path.toStdString()));
    } catch (const std::exception& e) {
      error = QString::fromStdString(e.what());
    }
    // Delivered by this object's event loop: dropped with it when it is gone.
    QMetaObject::invokeMethod(
        this,
        [this, ticket, path, map, error, fit_warning] {
          emit finished(ticket, path, map, error, fit_warning);
        },
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
