#pragma once
// Status bar part for fusion: a progress bar and the fusion rate.
#include <QWidget>

class QLabel;
class QProgressBar;

namespace lom::ui {

class MapWorker;

class FusionStatus : public QWidget {
  Q_OBJECT

 public:
  explicit FusionStatus(MapWorker& worker, QWidget* parent = nullptr);
  [[nodiscard]] QString text() const;

 private:
  QProgressBar* progress_;
  QLabel* rate_;
  bool progressed_ = false;  // the current fusion has reported a frame
  bool failed_ = false;      // ... and reported an error
};

}  // namespace lom::ui
