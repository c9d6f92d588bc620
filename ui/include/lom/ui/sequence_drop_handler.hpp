#pragma once
// Opens what is dropped onto the watched widget: a sequence folder or its
// sequence.json, a dataset folder, or a ROS bag (.bag), just after the drop;
// and a fused map (.ot), when given a way to open one.
#include <QObject>
#include <QString>
#include <functional>

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
  // The local .ot file of a drag, empty when it holds none.
  [[nodiscard]] static QString droppedMapPath(const QMimeData* mime);
  // What a dropped map is given to (none: maps are not accepted).
  void setMapOpener(std::function<void(const QString&)> open_map) {
    open_map_ = std::move(open_map);
  }

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  SequenceController& controller_;
  std::function<void(const QString&)> open_map_;
};

}  // namespace lom::ui
