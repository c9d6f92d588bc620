#pragma once
// The one thread that owns the LabelMap: fuses frames (the fast integration
// path), re-thresholds, answers voxel picks and runs the evaluation. The GUI
// thread only queues jobs and receives snapshots and results through queued
// calls, so it never waits for the map.
#include <QObject>
#include <QString>
#include <QStringList>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "lom/evaluation.hpp"
#include "lom/fusion.hpp"
#include "lom/ui/map_snapshot.hpp"

namespace lom::ui {

class MapWorker : public QObject {
  Q_OBJECT

 public:
  enum class State { Idle, Fusing, Paused };

  explicit MapWorker(QObject* parent = nullptr);
  ~MapWorker() override;  // cancels fusion and joins the thread

  // Fuses the option's frame range of `sequence` into a new map, replacing the
  // current one. Snapshots are published at most every `snapshot_interval_ms`.
  // Until its first frame is fused the current map is kept: a fusion that
  // fails or is cancelled before then leaves it (previousMapKept).
  void startFusion(std::shared_ptr<const Sequence> sequence, const FusionOptions& options);
  // Replaces the map with `map` (read from `source`, a .ot file), as a fusion
  // of `frames` frames that has just completed: a fusion in progress is
  // cancelled, fusionStarted, mapAdopted and fusionFinished(true) follow, and
  // the threshold becomes the map's. `fallback_up` (the sequence's cameras'
  // mean up) levels the views of a map that records no camera.
  void adoptMap(std::shared_ptr<LabelMap> map, size_t frames, const QString& source,
                std::optional<Eigen::Vector3d> fallback_up = std::nullopt);
  void setPaused(bool paused);
  void cancel();  // keeps what was fused so far
  void reset();   // cancels and drops the map
  // Applied between frames while fusing, at once otherwise.
  void setOccupancyThreshold(double threshold);
  void pick(const Eigen::Vector3d& point_world);
  // Newer requests supersede older ones that have not finished.
  void evaluate(std::shared_ptr<const Sequence> sequence, const Annotations& annotations,
                const EvaluationOptions& options);
  // Runs `job` with the map (null when there is none) on the worker thread,
  // after the fusion in progress (also a paused one) has ended. A non-empty
  // `description` ("export to map.ply") lists the job in pendingWork() until it
  // has run: work the user asked for that closing the window would drop.
  void withMap(std::function<void(const LabelMap*)> job, const QString& description = {});
  // The same for a job with something to say when it is done: the function it
  // returns runs in the GUI thread once the job is off pendingWork() (so that
  // what it announces never finds its own work still listed).
  void withMapThen(std::function<std::function<void()>(const LabelMap*)> job,
                   const QString& description = {});
  // Runs `job` on the worker thread with the map as it is now: between two
  // fused frames (also while paused) when fusing, at once otherwise. `final`
  // is false while a fusion is in progress; a job that then returns false
  // (the map has nothing for it yet) runs again with `final` true once the
  // fusion has ended. Listed in pendingWork() as withMap's jobs are.
  void withCurrentMap(std::function<bool(const LabelMap* map, bool final)> job,
                      const QString& description = {});
  [[nodiscard]] QStringList pendingWork() const;
  // Changes whenever a fusion starts or the map is reset: a job queued behind a
  // fusion compares it with the value it was queued with to tell whether the
  // map it was asked for was replaced meanwhile (re-fused, another sequence).
  [[nodiscard]] unsigned mapGeneration() const { return map_generation_; }
  // Whether the map shown was fused here (in whole or in part) and not
  // saved since (File ▸ Save Map…, the map's own .ot): work that closing the window or
  // replacing the map would lose. A map opened from a file is not, nor a map
  // without voxels (a fusion that failed or has fused nothing yet).
  [[nodiscard]] bool hasUnsavedMap() const {
    return unsaved_map_ && snapshot_ && !snapshot_->empty();
  }
  // The map of `generation` was written whole, as its own tree, to a .ot file.
  void markMapSaved(unsigned generation) {
    if (generation == map_generation_) unsaved_map_ = false;
  }

  [[nodiscard]] State state() const { return state_; }
  [[nodiscard]] bool isFusing() const { return state_ != State::Idle; }
  [[nodiscard]] MapSnapshotPtr snapshot() const { return snapshot_; }
  [[nodiscard]] bool isEvaluating() const { return evaluations_pending_ > 0; }
  void setSnapshotInterval(int ms) { snapshot_interval_ms_ = ms; }
  // For tests: called on the worker thread after every fused frame with the
  // number of frames fused so far (taken when a fusion starts).
  void setFrameFusedHook(std::function<void(size_t frames_fused)> hook);

 signals:
  void stateChanged(lom::ui::MapWorker::State state);
  // Every startFusion, also one that replaces a fusion still running.
  void fusionStarted();
  void snapshotChanged();
  void fusionProgress(int done, int total, double frames_per_second);
  void fusionFinished(bool completed);
  // A fusion that failed or was cancelled before fusing its first frame left
  // the map it was to replace in place (read from `source`, empty when fused
  // here); fusionFinished(false) follows.
  void previousMapKept(const QString& source);
  // adoptMap began taking the map read from `source` (after fusionStarted:
  // the worker is busy with it, though nothing is fused).
  void adoptionStarted(const QString& source);
  // A map read from `source` replaced the fused one (adoptMap).
  void mapAdopted(const QString& source);
  // reset() emptied the map (after the end of the fusion it stopped, unless
  // another fusion started meanwhile).
  void mapReset();
  // After a fusion (also a stopped one): the fused frames' totals, with their
  // depths beyond the map's max range (which map nothing) and the farthest.
  void depthRangesMeasured(const lom::FrameStats& totals, double max_range);
  void voxelPicked(const Eigen::Vector3d& point, const lom::VoxelState& voxel);
  void evaluationStarted();
  void evaluationFinished(const lom::EvaluationReport& report);
  void evaluationFailed(const QString& message);
  void errorOccurred(const QString& title, const QString& message);
  // Other work on the map (a box fit, an export) failed with an unexpected
  // error; the worker goes on.
  void workFailed(const QString& title, const QString& message);

 private:
  struct Job {
    std::function<void()> run;
    bool quick = true;  // may run between two fused frames
  };
  void post(std::function<void()> run, bool quick);
  void loop();
  void runQuickJobs();
  void runGuarded(Job& job);
  struct Start {
    unsigned id = 0;           // the fusion's (fusion_id_)
    unsigned generation = 0;   // the map's it makes (map_generation_)
    bool was_unsaved = false;  // whether the map it replaces was (unsaved_map_)
  };
  void fuse(const std::shared_ptr<const Sequence>& sequence, const FusionOptions& options,
            const Start& start, const std::shared_ptr<std::atomic<bool>>& cancelled);
  void publish(MapSnapshotPtr snapshot);
  void applyPendingThreshold();
  void inGui(std::function<void()> call);
  void setState(State state);
  // A new map is on its way (fused or adopted): the map changes generation,
  // the fusion in progress is cancelled; returns the new fusion's id.
  unsigned beginNewMap();
  // Lists a described job in pendingWork() (0 when not listed); forget removes it.
  unsigned listWork(const QString& description);
  // Takes job `id` off pendingWork() in the GUI thread, then runs `then`.
  void forgetWork(unsigned id, std::function<void()> then = {});

  // Worker thread only.
  std::unique_ptr<LabelMap> map_;
  // Worker thread: the file the map was read from (empty when fused here),
  // and what fusing it here measured (FrameStats summed; frames with depths
  // outside the map's extent), for the reports of its scores.
  std::string map_file_;
  std::optional<Eigen::Vector3d> fallback_up_;  // worker thread: for an adopted map (adoptMap)
  FrameStats fused_totals_;
  std::vector<size_t> frames_outside_map_;
  size_t frames_fused_ = 0;
  // Of a map fused here: its first frame (it holds frames_fused_ from there)
  // and the segmenter model its frames without a proba image ran through.
  size_t first_fused_frame_ = 0;
  std::string fused_segmenter_;
  bool fusing_now_ = false;  // inside fuse(): quick jobs run between its frames

  // Shared.
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> jobs_;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> paused_{false};
  std::atomic<bool> threshold_pending_{false};
  std::atomic<double> threshold_{0.5};
  bool unsaved_map_ = false;  // GUI thread
  std::atomic<unsigned> evaluation_generation_{0};
  std::atomic<int> snapshot_interval_ms_{200};
  // Snapshots the GUI has not taken yet are merged: only the newest is
  // shown, so a GUI slower than the worker never falls behind (publish).
  std::mutex snapshot_mutex_;
  MapSnapshotPtr next_snapshot_;  // guarded by snapshot_mutex_
  bool snapshot_posted_ = false;  // guarded by snapshot_mutex_
  // How long the GUI took to show the last snapshot: fusion publishes no
  // faster than every two of these, so the GUI stays free half the time.
  std::atomic<int> gui_snapshot_ms_{0};
  std::function<void(size_t)> frame_fused_hook_;  // guarded by mutex_

  // GUI thread only.
  State state_ = State::Idle;
  MapSnapshotPtr snapshot_;
  unsigned fusion_id_ = 0;                          // latest started fusion
  std::atomic<unsigned> map_generation_{0};
  std::shared_ptr<std::atomic<bool>> fusion_cancel_;  // its cancel flag
  int evaluations_pending_ = 0;
  unsigned map_job_id_ = 0;
  std::vector<std::pair<unsigned, QString>> pending_work_;  // described withMap jobs

  std::thread thread_;
};

}  // namespace lom::ui
