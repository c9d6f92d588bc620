#pragma once
// Opens a sequence folder or sequence.json dropped onto the watched widget.
#include <QObject>
#include <QString>

class QMimeData;

namespace lom::ui {

class SequenceController;

class SequenceDropHandler : public QObject {
  Q_OBJECT

 public:
  // Installs itself as an event filter of `target` and enables drops on it.
  SequenceDropHandler(QWidget* target, SequenceController& controller);

  // The local folder or .json of a drag, empty when it holds none.
  [[nodiscard]] static QString droppedSequencePath(const QMimeData* mime);

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  SequenceController& controller_;
};

}  // namespace lom::ui
