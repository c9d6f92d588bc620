// The map worker fuses on a thread of its own: the GUI thread only queues
// work and hears back through its event loop, so fusion never blocks it.
#include "lom/ui/map_worker.hpp"

#include <gtest/gtest.h>

#include <QTest>
#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "demo_window_fixture.hpp"
#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/label_map.hpp"
#include "lom/sequence.hpp"
#include "lom/synth.hpp"
#include "test_support.hpp"

namespace lom::ui {
namespace {

TEST(MapWorkerTest, FusesOffTheGuiThreadAndReportsThroughItsEventLoop) {
  test::TempDir temp;
  const auto folder = temp.path() / "scene";
  (void)writeSyntheticScene(fixture::smallDemo(), folder);
  const auto sequence = std::make_shared<const Sequence>(loadSequence(folder));
  const size_t frames = sequence->frames.size();
  ASSERT_GT(frames, 1u);

  MapWorker worker;
  const std::thread::id gui_thread = std::this_thread::get_id();
  std::vector<std::thread::id> progress_threads;
  bool finished = false, completed = false;
  QObject::connect(&worker, &MapWorker::fusionProgress, [&](int, int, double) {
    progress_threads.push_back(std::this_thread::get_id());
  });
  QObject::connect(&worker, &MapWorker::fusionFinished, [&](bool done) {
    finished = true;
    completed = done;
  });
  std::atomic<std::thread::id> map_thread{};

  worker.startFusion(sequence, FusionOptions{});
  worker.withMap([&](const LabelMap*) { map_thread = std::this_thread::get_id(); });
  // startFusion returned at once: nothing has been reported, since reports
  // wait for this thread's event loop.
  EXPECT_TRUE(worker.isFusing());
  EXPECT_TRUE(progress_threads.empty());
  EXPECT_FALSE(finished);

  ASSERT_TRUE(QTest::qWaitFor([&] { return finished; }, fixture::kTimeoutMs));
  EXPECT_TRUE(completed);
  EXPECT_EQ(progress_threads.size(), frames);  // one report per frame ...
  for (const std::thread::id id : progress_threads)
    EXPECT_EQ(id, gui_thread);  // ... heard on the GUI thread
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return map_thread.load() != std::thread::id{}; }, fixture::kTimeoutMs));
  EXPECT_NE(map_thread.load(), gui_thread);  // the map lives on the worker's thread
  QTest::qWait(50);                          // the last snapshot arrives through the event loop
  EXPECT_EQ(worker.snapshot()->frames_fused, frames);
  EXPECT_FALSE(worker.isFusing());
}

// Work that fails on the worker's thread is reported, not the end of the
// program (an exception leaving a std::thread terminates it, losing unsaved
// boxes and maps), and is no longer listed as pending; later work still runs.
// A GUI that takes longer to show a snapshot (a large map drawn) than the
// worker takes to fuse a frame never falls behind: snapshots it has not
// taken yet are merged into the newest, which it then shows.
TEST(MapWorkerTest, AGuiSlowerThanFusionSeesOnlyTheNewestSnapshot) {
  test::TempDir temp;
  const auto folder = temp.path() / "scene";
  SynthOptions options = fixture::smallDemo();
  options.frames = 8;
  (void)writeSyntheticScene(options, folder);
  const auto sequence = std::make_shared<const Sequence>(loadSequence(folder));
  const size_t frames = sequence->frames.size();

  MapWorker worker;
  worker.setSnapshotInterval(0);  // a snapshot after every frame
  std::atomic<size_t> fused{0};
  worker.setFrameFusedHook([&](size_t count) {
    fused = count;
    // Frames fused while the GUI draws the first snapshot each publish one.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  });
  std::vector<size_t> shown;
  bool finished = false;
  QObject::connect(&worker, &MapWorker::snapshotChanged, [&] {
    shown.push_back(worker.snapshot()->frames_fused);
    if (shown.size() == 1) std::this_thread::sleep_for(std::chrono::milliseconds(600));
  });
  QObject::connect(&worker, &MapWorker::fusionFinished, [&](bool) { finished = true; });
  worker.startFusion(sequence, FusionOptions{});
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished; }, fixture::kTimeoutMs));
  ASSERT_FALSE(shown.empty());
  EXPECT_EQ(shown.back(), frames) << "the last snapshot shown is the whole map";
  EXPECT_EQ(worker.snapshot()->frames_fused, frames);
  // While the GUI drew the first snapshot, the worker fused the other frames:
  // their snapshots were merged, not queued one by one.
  EXPECT_LE(shown.size(), 3u);
  for (size_t i = 1; i < shown.size(); ++i) EXPECT_GT(shown[i], shown[i - 1]);
}

TEST(MapWorkerTest, WorkThatThrowsIsReportedAndTheWorkerGoesOn) {
  MapWorker worker;
  QString title, message;
  QObject::connect(&worker, &MapWorker::workFailed, [&](const QString& t, const QString& m) {
    title = t;
    message = m;
  });
  worker.withMap([](const LabelMap*) { throw std::runtime_error("too many voxels to expand"); },
                 "failing work");
  worker.withCurrentMap(
      [](const LabelMap*, bool) -> bool { throw std::runtime_error("a fit that fails"); },
      "failing fit");
  std::atomic<bool> later{false};
  worker.withMap([&](const LabelMap*) { later = true; });
  ASSERT_TRUE(QTest::qWaitFor([&] { return later.load(); }, fixture::kTimeoutMs));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !message.isEmpty(); }, fixture::kTimeoutMs));
  EXPECT_EQ(title, "Map work failed");
  ASSERT_TRUE(QTest::qWaitFor([&] { return worker.pendingWork().isEmpty(); }, fixture::kTimeoutMs))
      << worker.pendingWork().join(", ").toStdString();
}

TEST(MapWorkerTest, TheFusedMapIsTheCommandLinesMapForTheSameFrames) {
  test::TempDir temp;
  const auto folder = temp.path() / "scene";
  (void)writeSyntheticScene(fixture::smallDemo(), folder);
  const auto sequence = std::make_shared<const Sequence>(loadSequence(folder));
  const LabelMap expected = fuseSequence(*sequence, FusionOptions{});

  MapWorker worker;
  bool finished = false;
  QObject::connect(&worker, &MapWorker::fusionFinished, [&](bool) { finished = true; });
  worker.startFusion(sequence, FusionOptions{});
  std::atomic<size_t> leaves{0}, nodes{0};
  worker.withMap([&](const LabelMap* map) {
    nodes = map->numNodes();
    leaves = map->numLeaves();
  });
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished && leaves > 0; }, fixture::kTimeoutMs));
  // Pruned as fuseSequence prunes: the same tree, so the same exports and .ot files.
  EXPECT_EQ(leaves.load(), expected.numLeaves());
  EXPECT_EQ(nodes.load(), expected.numNodes());
}

TEST(MapWorkerTest, ACameraOutsideTheMapStopsFusionBeforeAnyFrame) {
  test::TempDir temp;
  const auto folder = temp.path() / "scene";
  (void)writeSyntheticScene(fixture::smallDemo(), folder);
  Sequence far = loadSequence(folder);
  far.frames.back().T_world_camera.translation().x() += 1000.0;  // beyond 327.68 m at 1 cm
  const auto sequence = std::make_shared<const Sequence>(far);

  MapWorker worker;
  bool finished = false, completed = true;
  QString error;
  QObject::connect(&worker, &MapWorker::errorOccurred,
                   [&](const QString&, const QString& message) { error = message; });
  QObject::connect(&worker, &MapWorker::fusionFinished, [&](bool done) {
    finished = true;
    completed = done;
  });
  std::atomic<size_t> fused{1};
  worker.startFusion(sequence, FusionOptions{});
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished; }, fixture::kTimeoutMs));
  EXPECT_FALSE(completed);
  const std::string frame = "frames[" + std::to_string(far.frames.size() - 1) + "].pose";
  EXPECT_TRUE(error.contains("sequence.json")) << error.toStdString();
  EXPECT_TRUE(error.contains(QString::fromStdString(frame))) << error.toStdString();
  worker.withMap([&](const LabelMap* map) { fused = map ? map->numLeaves() : 0; });
  ASSERT_TRUE(QTest::qWaitFor([&] { return fused.load() != 1; }, fixture::kTimeoutMs));
  EXPECT_EQ(fused.load(), 0u);  // no frame was fused
}

// A map fused without any occupied voxel (every depth beyond the max range)
// cannot be scored: the panel is told why in the studio's words, not in a
// file validator's about a "(map)" that names no file.
TEST(MapWorkerTest, AnEmptyMapIsNotScoredAndTheMessageSaysWhy) {
  test::TempDir temp;
  const SynthScene scene = writeSyntheticScene(fixture::smallDemo(), temp.path() / "scene");
  const auto sequence = std::make_shared<const Sequence>(loadSequence(temp.path() / "scene"));
  MapWorker worker;
  bool finished = false;
  QObject::connect(&worker, &MapWorker::fusionFinished, [&](bool) { finished = true; });
  EvaluationOptions options;
  options.fusion.map.max_range = 0.05;  // the scene's depths are all farther
  worker.startFusion(sequence, options.fusion);
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished; }, fixture::kTimeoutMs));
  ASSERT_TRUE(worker.snapshot()->counts.empty());

  QString failure;
  bool scored = false;
  QObject::connect(&worker, &MapWorker::evaluationFailed, [&](const QString& m) { failure = m; });
  QObject::connect(&worker, &MapWorker::evaluationFinished, [&] { scored = true; });
  worker.evaluate(sequence, scene.annotations, options);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !failure.isEmpty() || scored; }, fixture::kTimeoutMs));
  EXPECT_FALSE(scored);
  EXPECT_TRUE(failure.startsWith("Nothing to score: the map holds no occupied voxel"))
      << failure.toStdString();
  EXPECT_FALSE(failure.contains("(map)")) << failure.toStdString();
}

}  // namespace
}  // namespace lom::ui
