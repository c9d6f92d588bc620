#pragma once
// Reads .ot map files on threads of their own, so that a large map does not
// hold up the window, and hands each result back on the GUI thread.
#include <QObject>
#include <QString>
#include <memory>
#include <set>

class QThread;

namespace lom {
class LabelMap;
struct Sequence;
}

namespace lom::ui {

class MapFileReader : public QObject {
  Q_OBJECT

 public:
  explicit MapFileReader(QObject* parent = nullptr);
  ~MapFileReader() override;  // waits for the reads still running

  // Starts reading `path`; finished() follows with the ticket returned. With
  // `sequence`, the map's fit to its depths is measured too (lom::mapFitOf,
  // off the GUI thread: it reads three depth images).
  unsigned read(const QString& path, std::shared_ptr<const lom::Sequence> sequence = nullptr);
  // The ticket of the latest read() (results of earlier ones are stale).
  [[nodiscard]] unsigned latestTicket() const { return ticket_; }
  // Makes every read started so far stale.
  void forget() { ++ticket_; }
  [[nodiscard]] bool isReading() const { return !threads_.empty(); }

 signals:
  // The map, or null and why it could not be read (file, field, expected);
  // `fit_warning`: lom::poorMapFitWarning for the sequence given to read().
  void finished(unsigned ticket, const QString& path, std::shared_ptr<lom::LabelMap> map,
                const QString& error, const QString& fit_warning);

 private:
  unsigned ticket_ = 0;
  std::set<QThread*> threads_;
};

}  // namespace lom::ui
