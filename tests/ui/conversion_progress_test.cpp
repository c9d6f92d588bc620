// Opening a recording that needs converting: the conversion runs beside the
// event loop with a modal progress dialog, Cancel keeps the open sequence,
// errors are reported as ever, a second open and closing the window while it
// runs are handled, and without a window it still converts.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QEvent>
#include <QProgressBar>
#include <QProgressDialog>
#include <QPushButton>
#include <QSignalSpy>
#include <QSlider>
#include <QStatusBar>
#include <QTest>
#include <QTimer>
#include <QWindow>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "dialog_answerer.hpp"
#include "lom/error.hpp"
#include "lom/import.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "lom/ui/timeline_widget.hpp"
#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

namespace fs = std::filesystem;

QString qPath(const fs::path& path) { return QString::fromStdString(path.string()); }

// Holds a conversion after its first frame until the test lets it go on, so
// that what the window does meanwhile is certain (not a matter of speed). A
// test that never lets go is let go after a while instead of hanging.
class FirstFrameGate {
 public:
  // Converts into the default import cache as the studio does, holding at
  // the first frame.
  SequenceController::SourceOpener opener() {
    return [this](const fs::path& source, const ImportOptions& options,
                  const ImportProgressCallback& progress) {
      return openSource(source, options, {}, [this, &progress](const ImportProgress& step) {
        const bool go_on = progress(step);
        if (step.done == 1) hold();
        return go_on;
      });
    };
  }
  // The same, reporting first that a quarter of the recording has been
  // read (as a bag is read through before its frames) and holding there.
  SequenceController::SourceOpener readingOpener() {
    return [this](const fs::path& source, const ImportOptions& options,
                  const ImportProgressCallback& progress) {
      ImportProgress reading;
      reading.read = 250;
      reading.read_total = 1000;
      if (progress(reading)) hold();
      return openSource(source, options, {}, progress);
    };
  }
  [[nodiscard]] bool holding() const { return holding_; }
  void release() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      released_ = true;
    }
    released_changed_.notify_all();
  }

 private:
  void hold() {
    std::unique_lock<std::mutex> lock(mutex_);
    holding_ = true;
    released_changed_.wait_for(lock, std::chrono::seconds(60), [this] { return released_; });
    holding_ = false;
  }

  std::mutex mutex_;
  std::condition_variable released_changed_;
  bool released_ = false;
  std::atomic<bool> holding_{false};
};

// The progress dialog on screen, null when there is none.
QProgressDialog* visibleProgressDialog() {
  for (QWidget* widget : QApplication::topLevelWidgets())
    if (auto* dialog = qobject_cast<QProgressDialog*>(widget); dialog && dialog->isVisible())
      return dialog;
  return nullptr;
}

QString barText(const QProgressDialog& dialog) {
  const auto* bar = dialog.findChild<QProgressBar*>();
  return bar ? bar->text() : QString();
}

QPushButton* cancelButton(const QProgressDialog& dialog) {
  for (QPushButton* button : dialog.findChildren<QPushButton*>())
    if (button->text().remove('&') == "Cancel") return button;
  return nullptr;
}

// Calls `step` every 10 ms (while an open waits, too) until it returns true.
class Poller {
 public:
  explicit Poller(std::function<bool()> step) : step_(std::move(step)) {
    timer_.setInterval(10);
    QObject::connect(&timer_, &QTimer::timeout, [this] {
      ++ticks;
      if (step_()) timer_.stop();
    });
    timer_.start();
  }
  int ticks = 0;

 private:
  std::function<bool()> step_;
  QTimer timer_;
};

// Counts the paint events a widget receives.
class PaintCounter : public QObject {
 public:
  explicit PaintCounter(QWidget* widget) { widget->installEventFilter(this); }
  int paints = 0;

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (event->type() == QEvent::Paint) ++paints;
    return QObject::eventFilter(watched, event);
  }
};

class ConversionProgressTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tiny_ = lom::test::writeTinySequence(temp_ / "tiny_shelf");
    window_.setErrorReporter([this](const QString& title, const QString& message) {
      errors_.push_back({title, message});
    });
    window_.setWarningReporter([this](const QString& title, const QString& message) {
      warnings_.push_back({title, message});
    });
    window_.setRecoveryOffer([](const QString&) { return false; });
    window_.setMapDiscardQuestion([](const QString&) { return true; });  // see unsaved_map_test.cpp
    window_.resize(1280, 800);
    window_.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&window_));
    // The sequence a conversion would replace.
    ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
    controller().setCurrentFrame(1);
  }
  void TearDown() override { gate_.release(); }

  SequenceController& controller() { return window_.controller(); }
  fs::path framesLayout(const std::string& name) {
    const fs::path folder = temp_ / name;
    lom::test::writeFramesLayout(tiny_, folder);
    return folder;
  }
  // Whether the previous sequence is still the open one, on its frame.
  void expectTinyStillOpen() {
    EXPECT_FALSE(controller().isConverting());
    EXPECT_EQ(controller().sequenceName(), "tiny_shelf");
    EXPECT_EQ(controller().currentFrame(), 1);
    EXPECT_EQ(controller().frameCount(), lom::test::kTinyFrames);
    EXPECT_TRUE(window_.windowTitle().contains("tiny_shelf"))
        << window_.windowTitle().toStdString();
  }
  // Entries of the import cache that belong to the source folder `name`, and
  // conversions that were never finished.
  static std::vector<std::string> cacheLeftovers(const std::string& name) {
    std::vector<std::string> found;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(defaultImportCacheRoot(), ec)) {
      const std::string file = entry.path().filename().string();
      if (file.rfind(name + "-", 0) == 0 || file.rfind(".partial-", 0) == 0) found.push_back(file);
    }
    return found;
  }

  struct ReportedError {
    QString title;
    QString message;
  };
  lom::test::TempDir temp_;
  lom::test::TinySequence tiny_;
  MainWindow window_;
  std::vector<ReportedError> errors_;
  std::vector<ReportedError> warnings_;
  FirstFrameGate gate_;
};

TEST_F(ConversionProgressTest, ShowsProgressWhileTheWindowKeepsRunning) {
  const fs::path folder = framesLayout("frames_layout");
  controller().setSourceOpener(gate_.opener());
  std::vector<std::pair<int, int>> progress;
  QObject::connect(&controller(), &SequenceController::conversionProgress,
                   [&](int done, int total) { progress.emplace_back(done, total); });

  // Runs while the open waits: without its own event loop the conversion
  // would wait for the gate in vain.
  QString label, bar;
  bool input_kept_out = false;
  int paints_before = -1;
  PaintCounter status_paints(window_.statusBar());
  Poller poll([&] {
    QProgressDialog* dialog = visibleProgressDialog();
    if (!gate_.holding() || !dialog || dialog->value() != 1) return false;
    if (paints_before < 0) {
      label = dialog->labelText();
      bar = barText(*dialog);
      // As under a modal dialog, the window takes no input meanwhile: neither
      // its shortcuts (End, the last frame) nor a click on the timeline.
      window_.activateWindow();
      QTest::keyClick(&window_, Qt::Key_End);
      QSlider& slider = window_.timeline().slider();
      QTest::mouseClick(&slider, Qt::LeftButton, {},
                        QPoint(slider.width() - 2, slider.height() / 2));
      input_kept_out =
          controller().currentFrame() == 1 && controller().sequenceName() == "tiny_shelf";
      // The window under the dialog must still repaint (when uncovered, say).
      paints_before = status_paints.paints;
      window_.statusBar()->showMessage("changed while converting");
      return false;
    }
    if (status_paints.paints == paints_before) return false;
    gate_.release();
    return true;
  });
  ASSERT_TRUE(controller().openSequence(qPath(folder)))
      << (errors_.empty() ? std::string() : errors_.back().message.toStdString());
  EXPECT_GT(poll.ticks, 0);
  EXPECT_EQ(label, "Converting frames_layout…");
  EXPECT_EQ(bar, "1 of 3 frames");
  EXPECT_TRUE(input_kept_out);
  EXPECT_GT(status_paints.paints, paints_before);
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), std::make_pair(lom::test::kTinyFrames, lom::test::kTinyFrames));

  EXPECT_TRUE(errors_.empty());
  EXPECT_FALSE(controller().isConverting());
  EXPECT_TRUE(controller().isConverted());
  EXPECT_EQ(controller().frameCount(), lom::test::kTinyFrames);
  EXPECT_EQ(controller().currentFrame(), 0);
  EXPECT_EQ(visibleProgressDialog(), nullptr);
}

TEST_F(ConversionProgressTest, CancelKeepsTheOpenSequenceAndReportsNoError) {
  const fs::path folder = framesLayout("cancelled_frames");
  controller().setSourceOpener(gate_.opener());
  QSignalSpy changed(&controller(), &SequenceController::sequenceChanged);
  QString label_after_cancel;
  bool still_shown = false;
  Poller poll([&] {
    QProgressDialog* dialog = visibleProgressDialog();
    if (!gate_.holding() || !dialog) return false;
    QPushButton* cancel = cancelButton(*dialog);
    if (!cancel) return false;
    cancel->click();
    // Until the importer has stopped, the dialog says so.
    label_after_cancel = dialog->labelText();
    still_shown = dialog->isVisible() && !cancel->isEnabled();
    gate_.release();
    return true;
  });

  EXPECT_FALSE(controller().openSequence(qPath(folder)));
  EXPECT_EQ(label_after_cancel, "Cancelling…");
  EXPECT_TRUE(still_shown);
  EXPECT_TRUE(errors_.empty()) << errors_.front().message.toStdString();
  EXPECT_EQ(changed.count(), 0);
  expectTinyStillOpen();
  EXPECT_EQ(visibleProgressDialog(), nullptr);
  EXPECT_TRUE(window_.statusBar()->currentMessage().contains("cancelled"))
      << window_.statusBar()->currentMessage().toStdString();
  // Nothing of the cancelled conversion is left in the cache ...
  EXPECT_EQ(cacheLeftovers("cancelled_frames"), std::vector<std::string>());

  // ... and the recording opens normally afterwards.
  controller().setSourceOpener({});
  ASSERT_TRUE(controller().openSequence(qPath(folder)));
  EXPECT_EQ(controller().sequenceName(), "cancelled_frames");
  EXPECT_TRUE(errors_.empty());
}

// A dataset folder without its camera: the importer's message, with the
// studio's hint on how to give the camera, as when the studio converted on
// the GUI thread.
TEST_F(ConversionProgressTest, ConversionErrorIsReportedAsBefore) {
  const fs::path folder = framesLayout("no_camera");
  fs::remove(folder / "intrinsics.K.txt");
  std::string core_message;
  try {
    (void)openSource(folder, {}, temp_ / "direct_cache");
  } catch (const Error& error) {
    core_message = error.what();
  }
  ASSERT_FALSE(core_message.empty());
  QSignalSpy finished(&controller(), &SequenceController::conversionFinished);

  EXPECT_FALSE(controller().openSequence(qPath(folder)));
  ASSERT_EQ(errors_.size(), 1u);
  EXPECT_EQ(errors_[0].title, "Cannot open sequence");
  EXPECT_TRUE(errors_[0].message.startsWith(QString::fromStdString(core_message)))
      << errors_[0].message.toStdString();
  EXPECT_TRUE(errors_[0].message.contains("labeloctomap-studio --intrinsics"))
      << errors_[0].message.toStdString();
  ASSERT_EQ(finished.count(), 1);
  EXPECT_FALSE(finished.front().at(1).toBool());  // not a cancel
  expectTinyStillOpen();
  EXPECT_EQ(visibleProgressDialog(), nullptr);
  EXPECT_EQ(cacheLeftovers("no_camera"), std::vector<std::string>());
}

TEST_F(ConversionProgressTest, SecondOpenWhileConvertingIsRefused) {
  const fs::path folder = framesLayout("first_frames");
  const auto other = lom::test::writeTinySequence(temp_ / "other_shelf");
  controller().setSourceOpener(gate_.opener());
  bool second_opened = true, asked = false;
  Poller poll([&] {
    if (!gate_.holding()) return false;
    asked = true;
    second_opened = controller().openSequence(qPath(other.folder));
    gate_.release();
    return true;
  });

  ASSERT_TRUE(controller().openSequence(qPath(folder)));
  EXPECT_TRUE(asked);
  EXPECT_FALSE(second_opened);
  EXPECT_TRUE(errors_.empty());
  EXPECT_EQ(controller().sequenceName(), "first_frames");
}

TEST_F(ConversionProgressTest, ClosingTheWindowWhileConvertingAsksAndStopsIt) {
  const fs::path folder = framesLayout("closing_frames");
  controller().setSourceOpener(gate_.opener());
  test::DialogAnswerer answer("Close Anyway");
  bool closed = false;
  Poller poll([&] {
    if (!gate_.holding() || !visibleProgressDialog()) return false;
    closed = window_.close();
    gate_.release();
    return true;
  });

  EXPECT_FALSE(controller().openSequence(qPath(folder)));
  EXPECT_TRUE(closed);
  EXPECT_FALSE(window_.isVisible());
  ASSERT_EQ(answer.questions.size(), 1);
  EXPECT_TRUE(answer.questions[0].contains("conversion of closing_frames"))
      << answer.questions[0].toStdString();
  EXPECT_TRUE(errors_.empty());
  expectTinyStillOpen();
  EXPECT_EQ(visibleProgressDialog(), nullptr);
  EXPECT_EQ(cacheLeftovers("closing_frames"), std::vector<std::string>());
}

// Closing the window from its title bar (the window manager's close, not
// QWidget::close) while the progress shows asks as well: a modal dialog made
// Qt drop it without a word.
TEST_F(ConversionProgressTest, ClosingTheWindowFromTheWindowManagerWhileConvertingAsks) {
  const fs::path folder = framesLayout("wm_closing_frames");
  controller().setSourceOpener(gate_.opener());
  test::DialogAnswerer answer("Cancel");
  bool closed = true;
  Poller poll([&] {
    if (!gate_.holding() || !visibleProgressDialog()) return false;
    // As the window manager's close button does (through Qt's platform layer).
    closed = window_.windowHandle()->close();
    gate_.release();
    return true;
  });

  ASSERT_TRUE(controller().openSequence(qPath(folder))) << "Cancel: the conversion went on";
  EXPECT_FALSE(closed);
  ASSERT_EQ(answer.questions.size(), 1) << "closing asked nothing";
  EXPECT_TRUE(answer.questions[0].contains("conversion of wm_closing_frames"))
      << answer.questions[0].toStdString();
  EXPECT_TRUE(window_.isVisible());
  EXPECT_EQ(controller().sequenceName(), "wm_closing_frames");
}

// A recording is read through before its frames (a compressed bag for a
// minute): the bar says how far, instead of a busy indicator.
TEST_F(ConversionProgressTest, ReadingTheRecordingMovesTheBar) {
  const fs::path folder = framesLayout("read_frames");
  controller().setSourceOpener(gate_.readingOpener());
  QString reading;
  Poller poll([&] {
    QProgressDialog* dialog = visibleProgressDialog();
    if (!gate_.holding() || !dialog || barText(*dialog).isEmpty()) return false;
    reading = barText(*dialog);
    gate_.release();
    return true;
  });
  ASSERT_TRUE(controller().openSequence(qPath(folder)));
  EXPECT_EQ(reading, "Reading the recording: 25%");
  EXPECT_EQ(controller().sequenceName(), "read_frames");
}

// A damaged frame is left out of the conversion: the user is told which and
// why, also when the cached conversion is opened again, and the recording
// goes by its own name, not the cache folder's.
TEST_F(ConversionProgressTest, FramesLeftOutOfAConversionAreReportedEveryTimeItOpens) {
  const fs::path folder = framesLayout("damaged_frames");
  const fs::path damaged = folder / "frame-000001.depth.png";
  const auto size = fs::file_size(damaged);
  fs::resize_file(damaged, size / 2);
  for (int open = 0; open < 2; ++open) {
    SCOPED_TRACE(open == 0 ? "converted" : "from the cache");
    warnings_.clear();
    ASSERT_TRUE(controller().openSequence(qPath(folder)));
    EXPECT_TRUE(errors_.empty());
    EXPECT_EQ(controller().frameCount(), lom::test::kTinyFrames - 1);
    EXPECT_EQ(controller().sequenceName(), "damaged_frames");
    ASSERT_EQ(warnings_.size(), 1u);
    EXPECT_EQ(warnings_.front().title, "Frames left out");
    const std::string message = warnings_.front().message.toStdString();
    EXPECT_NE(message.find("1 of " + std::to_string(lom::test::kTinyFrames) + " frames"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("frame-000001"), std::string::npos) << message;
    EXPECT_NE(message.find("PNG ends inside"), std::string::npos) << message;
    ASSERT_TRUE(controller().openSequence(qPath(tiny_.folder)));
  }
  // A complete recording opens without a word.
  warnings_.clear();
  ASSERT_TRUE(controller().openSequence(qPath(framesLayout("complete_frames"))));
  EXPECT_TRUE(warnings_.empty());
}

// A recording converted without label images or probabilities has the
// background label only: nothing to box or score, and the window says so
// instead of offering boxes it cannot make.
TEST_F(ConversionProgressTest, ARecordingWithoutObjectLabelsOffersNoBoxes) {
  ASSERT_TRUE(
      window_.findAction("Add Boxes for All Labels")->isEnabled());  // the tiny shelf has a label
  ASSERT_TRUE(controller().openSequence(qPath(framesLayout("geometry_only"))));
  ASSERT_TRUE(errors_.empty());
  ASSERT_EQ(controller().sequence().labels.size(), 1u);
  EXPECT_FALSE(window_.findAction("Add Boxes for All Labels")->isEnabled());
  EvaluationPanel& evaluation = window_.evaluationPanel();
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return !window_.session().worker().isFusing() && !evaluation.isBusy(); }, 60'000));
  QTest::qWait(300);  // the panel's update is debounced
  EXPECT_TRUE(evaluation.summaryText().contains("only the background label"))
      << evaluation.summaryText().toStdString();
}

TEST_F(ConversionProgressTest, PlainSequenceOpensWithoutConversion) {
  const auto other = lom::test::writeTinySequence(temp_ / "other_shelf");
  QSignalSpy started(&controller(), &SequenceController::conversionStarted);
  QSignalSpy finished(&controller(), &SequenceController::conversionFinished);
  controller().setProgressDelay(0);  // a conversion would show its dialog at once
  ASSERT_TRUE(controller().openSequence(qPath(other.folder)));
  EXPECT_EQ(controller().sequenceName(), "other_shelf");
  EXPECT_EQ(started.count(), 0);
  EXPECT_EQ(finished.count(), 0);
  EXPECT_FALSE(controller().isConverted());
}

// Batch use without a window: the conversion still runs (and ends) with no
// one to show a dialog to.
TEST(ConversionWithoutWindowTest, ControllerAloneConverts) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "tiny_shelf");
  lom::test::writeFramesLayout(tiny, temp / "headless_frames");
  SequenceController controller;
  controller.setProgressDelay(0);
  QSignalSpy started(&controller, &SequenceController::conversionStarted);
  bool dialog_seen = false;
  Poller poll([&] {
    dialog_seen = dialog_seen || visibleProgressDialog() != nullptr;
    return false;
  });
  ASSERT_TRUE(controller.openSequence(qPath(temp / "headless_frames")));
  EXPECT_EQ(started.count(), 1);
  EXPECT_FALSE(dialog_seen);
  EXPECT_TRUE(controller.isConverted());
  EXPECT_EQ(controller.frameCount(), lom::test::kTinyFrames);
}

}  // namespace
}  // namespace lom::ui
