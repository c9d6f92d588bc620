// Work queued behind fusion on the demo scene: a box fit during fusion uses
// the voxels fused so far, keeps one box per label and belongs to the map it
// was asked for; the status bar says when work waits, closing the window asks
// before dropping it, and reports and objects of a map that is gone cannot be
// used.
#include <gtest/gtest.h>

#include <QAction>
#include <QPushButton>
#include <QStatusBar>
#include <QTest>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>

#include "demo_window_fixture.hpp"
#include "dialog_answerer.hpp"
#include "lom/iou.hpp"
#include "lom/ui/annotations_model.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/export_map_reaction.hpp"
#include "lom/ui/objects_panel.hpp"

namespace lom::ui {
namespace {

using fixture::kTimeoutMs;
using fixture::qPath;
using fixture::smallDemo;

class QueuedWorkTest : public fixture::DemoWindowTest {
 protected:
  void TearDown() override {
    session().worker().setPaused(false);
    session().annotations().undoStack().setClean();
  }
  StudioSession& session() { return window_.session(); }
  AnnotationsModel& boxes() { return session().annotations(); }
  // Opens `folder` with its fusion paused before the first frame. (The small
  // demo fuses faster than the window opens it, so the worker is held until
  // the pause is in place.)
  void openPaused(const std::filesystem::path& folder) {
    session().setAutoFuse(false);
    ASSERT_TRUE(window_.controller().openSequence(qPath(folder)));
    auto gate = std::make_shared<std::atomic<bool>>(false);
    session().worker().withMap([gate](const LabelMap*) {
      while (!*gate) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
    session().fuse();
    session().worker().setPaused(true);
    *gate = true;
    session().setAutoFuse(true);
    ASSERT_EQ(session().worker().state(), MapWorker::State::Paused);
    QTest::qWait(200);
    ASSERT_EQ(session().worker().state(), MapWorker::State::Paused);
    ASSERT_EQ(session().worker().snapshot()->frames_fused, 0u);
  }
  void removeBoxOf(int label) {
    for (int i = boxes().boxCount() - 1; i >= 0; --i)
      if (boxes().box(i).label == label) boxes().removeBox(i);
  }
  [[nodiscard]] int boxesOf(int label) {
    int count = 0;
    for (int i = 0; i < boxes().boxCount(); ++i) count += boxes().box(i).label == label;
    return count;
  }
  void waitForQueuedWork() {
    ASSERT_TRUE(
        QTest::qWaitFor([&] { return session().worker().pendingWork().isEmpty(); }, kTimeoutMs));
    QTest::qWait(50);  // the result arrives through the event loop
  }
};

TEST_F(QueuedWorkTest, BoxFitAskedTwiceDuringFusionAddsOneBox) {
  openPaused(folder_);
  const int label = *visibleObjectLabels().begin();
  removeBoxOf(label);
  session().setSelectedLabel(label);
  QAction* add = window_.findAction("Add Box from Label Voxels");
  ASSERT_NE(add, nullptr);
  add->trigger();
  EXPECT_TRUE(window_.statusBar()->currentMessage().contains("when fusion finishes"))
      << window_.statusBar()->currentMessage().toStdString();
  add->trigger();
  // Paused before the first frame: no voxels yet, so both fits wait for the fusion's end.
  QTest::qWait(200);
  EXPECT_EQ(session().worker().pendingWork().size(), 2);
  EXPECT_EQ(boxesOf(label), 0);

  session().worker().setPaused(false);
  waitForFusion();
  waitForQueuedWork();
  EXPECT_EQ(boxesOf(label), 1);
  EXPECT_TRUE(std::any_of(errors_.begin(), errors_.end(),
                          [](const QString& e) { return e.contains("already"); }));
}

TEST_F(QueuedWorkTest, BoxesForAllLabelsWaitForTheFusionAndBoxEachLabelOnce) {
  openPaused(folder_);
  // The demo's ground truth is loaded with it: keep one label's box, drop the others.
  const int kept = *visibleObjectLabels().begin();
  ASSERT_EQ(boxesOf(kept), 1);
  GroundTruthBox kept_box;
  for (int i = boxes().boxCount() - 1; i >= 0; --i) {
    if (boxes().box(i).label == kept)
      kept_box = boxes().box(i);
    else
      boxes().removeBox(i);
  }
  const int steps_before = boxes().undoStack().index();
  QAction* add_all = window_.findAction("Add Boxes for All Labels");
  ASSERT_NE(add_all, nullptr);
  EXPECT_EQ(add_all->shortcut(), QKeySequence(Qt::CTRL + Qt::Key_B));
  add_all->trigger();
  EXPECT_TRUE(window_.statusBar()->currentMessage().contains("when fusion finishes"))
      << window_.statusBar()->currentMessage().toStdString();
  // Paused before the first frame: the fit waits for the whole map.
  QTest::qWait(200);
  EXPECT_EQ(session().worker().pendingWork().size(), 1);
  EXPECT_EQ(boxes().boxCount(), 1);

  session().worker().setPaused(false);
  waitForFusion();
  waitForQueuedWork();
  // Every object label of the map has one box; the kept one is as it was.
  std::set<int> mapped;
  for (const auto& [label, count] : session().worker().snapshot()->counts)
    if (label > 0 && count > 0) mapped.insert(label);
  ASSERT_GE(mapped.size(), 2u);
  for (const int label : mapped) EXPECT_EQ(boxesOf(label), 1) << label;
  EXPECT_EQ(boxes().boxCount(), static_cast<int>(mapped.size()));
  for (int i = 0; i < boxes().boxCount(); ++i) {
    const GroundTruthBox& box = boxes().box(i);
    if (box.label == kept) {
      EXPECT_EQ(box.box.center, kept_box.box.center);
      EXPECT_EQ(box.box.size, kept_box.box.size);
      continue;
    }
    // Fitted to the label's voxels, which cover only the sides the cameras
    // saw (box IU 0.2 to 0.7 in this small demo): overlapping the object's
    // true box, its centre inside it, or within half a voxel edge of it for
    // an object thinner than a voxel (a 9 mm mailer on the floor gets the
    // box of the voxel layers it touches, standing on the floor).
    for (const GroundTruthBox& truth : truth_.boxes) {
      if (truth.label != box.label) continue;
      EXPECT_GT(boxIoU(box.box, truth.box), 0.1) << box.name;
      const Eigen::Vector3d local =
          truth.box.rotation.inverse() * (box.box.center - truth.box.center);
      const double half_edge = 0.5 * session().worker().snapshot()->resolution;
      EXPECT_TRUE(
          (local.cwiseAbs().array() <= 0.5 * truth.box.size.array() + half_edge + 1e-9).all())
          << box.name;
    }
  }
  EXPECT_TRUE(window_.statusBar()->currentMessage().contains("1 label boxed already kept"))
      << window_.statusBar()->currentMessage().toStdString();

  // One undo step takes them all back.
  EXPECT_EQ(boxes().undoStack().index(), steps_before + 1);
  boxes().undoStack().undo();
  EXPECT_EQ(boxes().boxCount(), 1);
  boxes().undoStack().redo();
  EXPECT_EQ(boxes().boxCount(), static_cast<int>(mapped.size()));

  // Asked again, with every label boxed: nothing to add, and it says why.
  errors_.clear();
  add_all->trigger();
  waitForQueuedWork();
  EXPECT_EQ(boxes().boxCount(), static_cast<int>(mapped.size()));
  ASSERT_EQ(errors_.size(), 1u);
  EXPECT_TRUE(errors_.front().contains("has a box already")) << errors_.front().toStdString();
}

TEST_F(QueuedWorkTest, BoxFitDuringFusionUsesTheVoxelsFusedSoFar) {
  // The worker waits after each of its first three frames until released.
  struct Gate {
    std::atomic<size_t> reached{0};
    std::atomic<size_t> released{0};
  };
  auto gate = std::make_shared<Gate>();
  session().worker().setFrameFusedHook([gate](size_t frames) {
    gate->reached = frames;
    while (frames <= 3 && gate->released < frames)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  // Whatever happens below, the worker is not left waiting.
  const std::shared_ptr<void> open_gate(nullptr, [gate](void*) { gate->released = 1000; });
  auto waitUntilReached = [&](size_t frames) {
    return QTest::qWaitFor([&] { return gate->reached == frames; }, kTimeoutMs);
  };

  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(waitUntilReached(1));
  gate->released = 1;
  ASSERT_TRUE(waitUntilReached(2));
  // Held after two frames: the fit is asked for now and runs before the third.
  const int label = *visibleObjectLabels().begin();
  removeBoxOf(label);
  session().setSelectedLabel(label);
  window_.findAction("Add Box from Label Voxels")->trigger();
  EXPECT_TRUE(window_.statusBar()->currentMessage().contains("voxels fused so far"))
      << window_.statusBar()->currentMessage().toStdString();
  gate->released = 2;
  ASSERT_TRUE(waitUntilReached(3));
  // Held after the third frame: the box has arrived while fusion still runs.
  EXPECT_TRUE(QTest::qWaitFor([&] { return boxesOf(label) == 1; }, 10'000));
  EXPECT_TRUE(session().worker().isFusing());
  EXPECT_TRUE(session().worker().pendingWork().isEmpty());
  gate->released = 3;
  waitForFusion();
  session().worker().setFrameFusedHook({});
  EXPECT_EQ(boxesOf(label), 1);
}

TEST_F(QueuedWorkTest, BoxFittedToAPreviousSequencesMapIsDropped) {
  const int label = *visibleObjectLabels().begin();
  // Another scene whose boxes lack that label, so only the map tells them apart.
  const auto other = temp_.path() / "other_shelf";
  prepareDemoScene(qPath(other), smallDemo());
  Annotations other_boxes = loadAnnotations(other / "annotations.json");
  other_boxes.boxes.erase(
      std::remove_if(other_boxes.boxes.begin(), other_boxes.boxes.end(),
                     [&](const GroundTruthBox& box) { return box.label == label; }),
      other_boxes.boxes.end());
  saveAnnotations(other_boxes, other / "annotations.json");

  window_.controller().setDiscardGuard([] { return true; });
  openAndFuse();
  removeBoxOf(label);
  session().setSelectedLabel(label);
  // The fit runs on this map; its result arrives after the other scene opened.
  window_.findAction("Add Box from Label Voxels")->trigger();
  ASSERT_TRUE(window_.controller().openSequence(qPath(other)));
  waitForFusion();
  waitForQueuedWork();
  EXPECT_EQ(boxes().boxCount(), static_cast<int>(other_boxes.boxes.size()));
  EXPECT_FALSE(boxes().isDirty());
  EXPECT_TRUE(window_.statusBar()->currentMessage().contains("dropped"))
      << window_.statusBar()->currentMessage().toStdString();
}

TEST_F(QueuedWorkTest, ClosingDuringFusionOrAPendingExportAsksFirst) {
  openPaused(folder_);
  auto* exporter = window_.findAction("Point Cloud (PCD)…")->findChild<ExportMapReaction*>();
  ASSERT_NE(exporter, nullptr);
  const auto pcd = temp_.path() / "map.pcd";
  exporter->exportTo(qPath(pcd));
  EXPECT_TRUE(window_.statusBar()->currentMessage().contains("queued"));
  {
    test::DialogAnswerer answer("Cancel");
    EXPECT_FALSE(window_.close());
    ASSERT_EQ(answer.questions.size(), 1);
    EXPECT_TRUE(answer.questions.front().contains("fusion of demo_shelf"))
        << answer.questions.front().toStdString();
    EXPECT_TRUE(answer.questions.front().contains("map.pcd"))
        << answer.questions.front().toStdString();
  }
  EXPECT_TRUE(window_.isVisible());
  EXPECT_TRUE(session().worker().isFusing());  // Cancel keeps working

  // Once everything has finished, closing does not ask.
  session().worker().setPaused(false);
  waitForFusion();
  waitForQueuedWork();
  EXPECT_TRUE(std::filesystem::exists(pcd));
  test::DialogAnswerer answer("Cancel");
  EXPECT_TRUE(window_.close());
  EXPECT_TRUE(answer.questions.isEmpty());
}

TEST_F(QueuedWorkTest, AnExportWaitingForAFusionThatIsReplacedIsDropped) {
  openPaused(folder_);
  auto* exporter = window_.findAction("Point Cloud (PCD)…")->findChild<ExportMapReaction*>();
  ASSERT_NE(exporter, nullptr);
  QStringList results;
  QObject::connect(exporter, &ExportMapReaction::finished, &window_,
                   [&](const QString& message, bool) { results << message; });
  const auto pcd = temp_.path() / "map.pcd";
  exporter->exportTo(qPath(pcd));
  // Fused again before the first fusion finished: the map the export waited
  // for never comes, and the partial one is not written in its place. (The
  // new fusion cancels the paused one; unpausing it first would let it finish
  // on a fast machine before the new one starts.)
  window_.findAction("Fuse Sequence")->trigger();
  waitForFusion();
  waitForQueuedWork();
  ASSERT_EQ(results.size(), 1);
  EXPECT_TRUE(results.front().contains("dropped: the map it waited for was replaced"))
      << results.front().toStdString();
  EXPECT_FALSE(std::filesystem::exists(pcd));

  // Cancel Fusion ends the wait: the export writes the map fused so far (the
  // worker holds after its second frame until then).
  auto reached = std::make_shared<std::atomic<size_t>>(0);
  auto released = std::make_shared<std::atomic<bool>>(false);
  session().worker().setFrameFusedHook([reached, released](size_t frames) {
    *reached = frames;
    while (frames == 2 && !*released) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  const std::shared_ptr<void> release(nullptr, [released](void*) { *released = true; });
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return *reached == 2; }, kTimeoutMs));
  exporter->exportTo(qPath(pcd));
  window_.findAction("Cancel Fusion")->trigger();
  *released = true;
  waitForQueuedWork();
  session().worker().setFrameFusedHook({});
  ASSERT_EQ(results.size(), 2);
  EXPECT_TRUE(results.back().startsWith("Wrote ")) << results.back().toStdString();
  EXPECT_TRUE(std::filesystem::exists(pcd));
}

TEST_F(QueuedWorkTest, ClosingAnywayStopsTheWork) {
  openPaused(folder_);
  test::DialogAnswerer answer("Close Anyway");
  EXPECT_TRUE(window_.close());
  EXPECT_EQ(answer.questions.size(), 1);
}

// Closing during a fusion can keep the frames fused so far: the fusion
// stops, and the map is asked about as a finished one (Save Map…).
TEST_F(QueuedWorkTest, ClosingDuringFusionCanKeepTheMapSoFar) {
  auto reached = std::make_shared<std::atomic<size_t>>(0);
  session().worker().setFrameFusedHook([reached](size_t frames) {
    *reached = frames;
    // Long enough for the question to be answered on a loaded machine (the
    // fusion then stops here); the remaining frames fuse in milliseconds.
    if (frames == 2) std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  });
  QStringList map_questions;
  window_.setMapDiscardQuestion([&](const QString& replaced_by) {
    map_questions << replaced_by;
    return false;  // Cancel: the window stays
  });
  ASSERT_TRUE(window_.controller().openSequence(qPath(folder_)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return *reached >= 2; }, kTimeoutMs));
  ASSERT_TRUE(session().worker().isFusing());
  test::DialogAnswerer answer("Stop Fusion and Keep the Map…");
  EXPECT_FALSE(window_.close());
  session().worker().setFrameFusedHook({});
  EXPECT_EQ(answer.questions.size(), 1);
  EXPECT_FALSE(session().worker().isFusing());
  ASSERT_EQ(map_questions.size(), 1);
  EXPECT_GE(session().worker().snapshot()->frames_fused, 2u);
  EXPECT_LT(session().worker().snapshot()->frames_fused,
            static_cast<size_t>(window_.controller().frameCount()));
  EXPECT_TRUE(session().worker().hasUnsavedMap());
}

TEST_F(QueuedWorkTest, ReportAndObjectsOfAMapThatIsGoneCannotBeUsed) {
  openAndFuse();
  EvaluationPanel& scores = window_.evaluationPanel();
  ObjectsPanel& objects = window_.objectsPanel();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !scores.isBusy() && scores.canExport(); }, kTimeoutMs))
      << scores.summaryText().toStdString();
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return !objects.isBusy() && !objects.objects().empty(); }, kTimeoutMs));
  EXPECT_TRUE(objects.planButton().isEnabled());

  window_.findAction("Reset Map")->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return session().worker().snapshot()->frames_fused == 0; },
                              kTimeoutMs));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !scores.isBusy(); }, kTimeoutMs));
  const auto out = temp_.path() / "report";
  EXPECT_FALSE(scores.canExport());
  EXPECT_NE(scores.exportReport(qPath(out)), QString());
  EXPECT_FALSE(std::filesystem::exists(out / "report.json"));
  EXPECT_TRUE(objects.objects().empty());
  EXPECT_FALSE(objects.planButton().isEnabled());
  EXPECT_FALSE(objects.plan().has_value());

  // Fused again, then another sequence opens: the old report goes at once.
  window_.findAction("Fuse Sequence")->trigger();
  waitForFusion();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !scores.isBusy() && scores.canExport(); }, kTimeoutMs));
  const auto tiny = temp_.path() / "tiny";
  prepareDemoScene(qPath(tiny), smallDemo());
  ASSERT_TRUE(window_.controller().openSequence(qPath(tiny)));
  EXPECT_FALSE(scores.canExport());
  EXPECT_NE(scores.exportReport(qPath(out)), QString());
  EXPECT_TRUE(objects.objects().empty());
  waitForFusion();
}

}  // namespace
}  // namespace lom::ui
