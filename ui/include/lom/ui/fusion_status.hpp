#pragma once
// Status bar part for fusion: a progress bar and the fusion rate.
#include <QWidget>
#include <optional>

class QLabel;
class QProgressBar;

namespace lom::ui {

class MapWorker;

class FusionStatus : public QWidget {
  Q_OBJECT

 public:
  explicit FusionStatus(MapWorker& worker, QWidget* parent = nullptr);
  [[nodiscard]] QString text() const;
  // While a map file is read (StudioSession::openMap): says so instead of
  // nothing; the next fusion, reset or the map's adoption replace it, and
  // endOpeningMap (the map was refused) brings back what was shown before.
  void showOpeningMap(const QString& file_name);
  void endOpeningMap();

 private:
  struct Shown {
    QString format, rate, tool_tip;
    int maximum = 1, value = 0;
  };
  std::optional<Shown> before_opening_;  // set while a map file is read
  // What was shown as the current fusion started: shown again, with why, when
  // that fusion keeps the map before it (MapWorker::previousMapKept).
  Shown before_fusion_;
  bool kept_ = false;  // the current fusion kept the map before it
  QProgressBar* progress_;
  QLabel* rate_;
  bool progressed_ = false;  // the current fusion has reported a frame
  bool failed_ = false;      // ... and reported an error
};

}  // namespace lom::ui
