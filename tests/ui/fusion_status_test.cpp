// The status bar's fusion indicator: the rate of a slow fusion, and Cancel's
// word that the stop is coming.
#include "lom/ui/fusion_status.hpp"

#include <gtest/gtest.h>

#include <QAction>
#include <QStatusBar>
#include <QTest>

#include "lom/ui/fusion_reactions.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "test_support.hpp"
#include "tiny_sequence.hpp"

namespace lom::ui {
namespace {

// A frame every 22 s (a fine room-scale map) is no "0.0 frames/s".
TEST(FusionStatusTest, ASlowFusionShowsSecondsPerFrame) {
  MapWorker worker;
  FusionStatus status(worker);
  emit worker.fusionProgress(1, 5, 2.5);
  EXPECT_TRUE(status.text().contains("2.5 frames/s")) << status.text().toStdString();
  emit worker.fusionProgress(2, 5, 1.0 / 22.0);
  EXPECT_TRUE(status.text().contains("22 s/frame")) << status.text().toStdString();
  EXPECT_FALSE(status.text().contains("frames/s")) << status.text().toStdString();
}

// Cancel during a frame: the status bar says the stop is coming at once, and
// the line goes when the fusion has stopped.
TEST(FusionStatusTest, CancelSaysAtOnceThatTheFusionStops) {
  lom::test::TempDir temp;
  const auto tiny = lom::test::writeTinySequence(temp / "tiny_shelf");
  MainWindow window;
  window.setErrorReporter([](const QString&, const QString&) {});
  window.setWarningReporter([](const QString&, const QString&) {});
  window.setMapDiscardQuestion([](const QString&) { return true; });
  window.session().setAutoFuse(false);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  ASSERT_TRUE(window.controller().openSequence(QString::fromStdString(tiny.folder.string())));
  MapWorker& worker = window.session().worker();
  window.session().fuse();
  ASSERT_TRUE(worker.isFusing());
  worker.setPaused(true);  // holds the fusion between frames, as a long frame would
  window.findAction("Cancel Fusion")->trigger();
  EXPECT_EQ(window.statusBar()->currentMessage(), FusionReaction::stoppingNote());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !worker.isFusing(); }, 10000));
  QTest::qWait(50);
  EXPECT_TRUE(window.statusBar()->currentMessage().isEmpty())
      << window.statusBar()->currentMessage().toStdString();

  // Pause says the frame being fused comes first.
  window.session().fuse();
  ASSERT_TRUE(worker.isFusing());
  QAction* pause = window.findAction("Pause Fusion");
  ASSERT_NE(pause, nullptr);
  pause->trigger();
  EXPECT_TRUE(window.statusBar()->currentMessage().startsWith("Pausing"))
      << window.statusBar()->currentMessage().toStdString();
  // Cancel, then Fuse again before the stop is heard: the new fusion does not
  // keep saying the fusion is stopping.
  window.findAction("Cancel Fusion")->trigger();
  ASSERT_EQ(window.statusBar()->currentMessage(), FusionReaction::stoppingNote());
  window.session().fuse();
  EXPECT_NE(window.statusBar()->currentMessage(), FusionReaction::stoppingNote());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !worker.isFusing(); }, 10000));
}

}  // namespace
}  // namespace lom::ui
