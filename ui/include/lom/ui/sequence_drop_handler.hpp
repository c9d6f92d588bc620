#pragma once
// Opens what is dropped onto the watched widget: a sequence folder or its
// sequence.json, a dataset folder, or a ROS bag (.bag), just after the drop.
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

  // The local folder, .json or .bag of a drag, empty when it holds none.
  [[nodiscard]] static QString droppedSequencePath(const QMimeData* mime);

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  SequenceController& controller_;
};

}  // namespace lom::ui
