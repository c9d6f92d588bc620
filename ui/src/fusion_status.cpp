#include "lom/ui/fusion_status.hpp"

#include <QFileInfo>
#include <QFontMetrics>
#include <QHBoxLayout>
#include <QLabel>
#include <QProgressBar>
#include <algorithm>

#include "lom/ui/map_worker.hpp"

namespace lom::ui {

namespace {

// As wide as its longest text needs in its font ("fused 12000/12000"), no
// wider: QProgressBar's own size fits about four digits, so a count of a
// long sequence or a large desktop font wrapped and clipped the text.
class CountBar : public QProgressBar {
 public:
  [[nodiscard]] QSize sizeHint() const override { return widened(QProgressBar::sizeHint()); }
  [[nodiscard]] QSize minimumSizeHint() const override {
    return widened(QProgressBar::minimumSizeHint());
  }

 private:
  [[nodiscard]] QSize widened(QSize size) const {
    const QFontMetrics metrics(font());
    const int longest =
        std::max(metrics.horizontalAdvance(FusionStatus::tr("fused %1/%1").arg(88888)),
                 metrics.horizontalAdvance(text()));
    size.setWidth(std::max(size.width(), longest + 4 * metrics.averageCharWidth()));
    return size;
  }
};

// Frames per second; a fusion slower than a frame in ten seconds (a fine
// room-scale map) in seconds per frame, which "0.0 frames/s" would hide.
QString rateText(double frames_per_second) {
  if (frames_per_second >= 0.1 || !(frames_per_second > 0.0))
    return FusionStatus::tr("%1 frames/s").arg(frames_per_second, 0, 'f', 1);
  return FusionStatus::tr("%1 s/frame").arg(1.0 / frames_per_second, 0, 'f', 0);
}

}  // namespace

FusionStatus::FusionStatus(MapWorker& worker, QWidget* parent)
    : QWidget(parent), progress_(new CountBar), rate_(new QLabel) {
  setObjectName("fusionStatus");
  progress_->setSizePolicy(QSizePolicy::Fixed, QSizePolicy::Fixed);
  // Its own width, never more: while a message hides the frame text, the
  // status bar's free space goes to the message, not here (which would
  // move the indicator from the right edge to the middle).
  setSizePolicy(QSizePolicy::Maximum, QSizePolicy::Preferred);
  // Until a fusion reports its first frame the frame count is unknown: say
  // "not fused" rather than a made-up "0/1".
  progress_->setFormat(tr("not fused"));
  progress_->setRange(0, 1);
  progress_->setValue(0);
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(progress_);
  layout->addWidget(rate_);
  connect(&worker, &MapWorker::fusionProgress, this,
          [this, &worker](int done, int total, double rate) {
            progressed_ = true;
            progress_->setFormat(tr("fused %v/%m"));
            progress_->setRange(0, std::max(1, total));
            progress_->setValue(done);
            // The frame being fused when Pause came reports after it: the
            // count moves on, "paused" stays.
            rate_->setText(worker.state() == MapWorker::State::Paused ? tr("paused")
                                                                      : rateText(rate));
          });
  // A new fusion: the last one's count is not this one's, also when it fails
  // on its first frame or replaces a fusion still running.
  connect(&worker, &MapWorker::fusionStarted, this, [this] {
    before_fusion_ =
        before_opening_.value_or(Shown{progress_->format(), rate_->text(), progress_->toolTip(),
                                       progress_->maximum(), progress_->value()});
    before_opening_.reset();
    progressed_ = failed_ = kept_ = false;
    progress_->setFormat(tr("fusing"));
    progress_->setRange(0, 1);
    progress_->setValue(0);
    rate_->clear();
  });
  // Taking in a map read from a file (a snapshot of a large map takes a while):
  // nothing is being fused.
  connect(&worker, &MapWorker::adoptionStarted, this, [this](const QString& source) {
    progress_->setFormat(tr("opening map"));
    rate_->setText(QFileInfo(source).fileName());
  });
  // A map read from a file: nothing was fused here.
  connect(&worker, &MapWorker::mapAdopted, this, [this](const QString& source) {
    before_opening_.reset();
    progress_->setFormat(tr("map from file"));
    progress_->setRange(0, 1);
    progress_->setValue(1);
    rate_->clear();
    progress_->setToolTip(source);
  });
  connect(&worker, &MapWorker::fusionStarted, this, [this] { progress_->setToolTip(QString()); });
  // Reset Map: nothing fused, also when it stopped a fusion (whose end says
  // where it stopped just before).
  connect(&worker, &MapWorker::mapReset, this, [this] {
    before_opening_.reset();
    progressed_ = failed_ = false;
    progress_->setFormat(tr("not fused"));
    progress_->setRange(0, 1);
    progress_->setValue(0);
    progress_->setToolTip(QString());
    rate_->clear();
  });
  connect(&worker, &MapWorker::stateChanged, this, [this](MapWorker::State state) {
    if (state == MapWorker::State::Paused) rate_->setText(tr("paused"));
  });
  // A fusion that failed (the error was reported first) or was stopped; one
  // that ended before its first frame fused nothing and has no count to show.
  connect(&worker, &MapWorker::errorOccurred, this, [this] { failed_ = true; });
  connect(&worker, &MapWorker::previousMapKept, this, [this] {
    kept_ = true;
    progress_->setFormat(before_fusion_.format);
    progress_->setRange(0, before_fusion_.maximum);
    progress_->setValue(before_fusion_.value);
    progress_->setToolTip(before_fusion_.tool_tip);
    rate_->setText(failed_ ? tr("re-fuse failed, map kept") : tr("re-fuse stopped, map kept"));
  });
  connect(&worker, &MapWorker::fusionFinished, this, [this](bool completed) {
    if (completed || kept_) return;
    if (!progressed_) {
      progress_->setFormat(tr("not fused"));
      rate_->setText(failed_ ? tr("failed before the first frame")
                             : tr("stopped before the first frame"));
      return;
    }
    const QString count = QStringLiteral("%1/%2").arg(progress_->value()).arg(progress_->maximum());
    rate_->setText(failed_ ? tr("failed after %1").arg(count) : tr("stopped at %1").arg(count));
  });
  connect(&worker, &MapWorker::snapshotChanged, this, [this, &worker] {
    if (worker.snapshot()->frames_fused == 0 && !worker.isFusing()) {
      progress_->setFormat(tr("not fused"));
      progress_->setValue(0);
      rate_->clear();
    }
  });
}

void FusionStatus::showOpeningMap(const QString& file_name) {
  if (!before_opening_)
    before_opening_ = Shown{progress_->format(), rate_->text(), progress_->toolTip(),
                            progress_->maximum(), progress_->value()};
  progress_->setFormat(tr("reading map"));
  progress_->setRange(0, 1);
  progress_->setValue(0);
  rate_->setText(file_name);
  progress_->setToolTip(QString());
}

void FusionStatus::endOpeningMap() {
  if (!before_opening_) return;
  const Shown shown = *before_opening_;
  before_opening_.reset();
  progress_->setFormat(shown.format);
  progress_->setRange(0, shown.maximum);
  progress_->setValue(shown.value);
  rate_->setText(shown.rate);
  progress_->setToolTip(shown.tool_tip);
}

QString FusionStatus::text() const { return progress_->text() + " " + rate_->text(); }

}  // namespace lom::ui
