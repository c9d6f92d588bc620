#include "lom/ui/map_worker.hpp"

#include <malloc.h>

#include <QMetaObject>
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "lom/error.hpp"
#include "lom/segmenter.hpp"

namespace lom::ui {

namespace {

// What the scores of a map fused here do not cover, one sentence each, as
// `score` warns about them: depths outside the map's extent, and most depths
// beyond the max range.
std::vector<std::string> fusionWarnings(const FrameStats& totals,
                                        const std::vector<size_t>& frames_outside_map,
                                        const MapParameters& map) {
  std::vector<std::string> warnings;
  char text[512];
  const size_t measured = measuredPixels(totals);
  if (totals.outside_map_pixels > 0 && measured > 0) {
    std::snprintf(text, sizeof text,
                  "%zu of %zu measured depth pixels (%.1f%%), in %zu frames, lie outside the "
                  "map's extent, %s: the map leaves them out, free space and all (coarser "
                  "voxels extend it).",
                  totals.outside_map_pixels, measured,
                  100.0 * static_cast<double>(totals.outside_map_pixels) / measured,
                  frames_outside_map.size(), describeMapExtent(map.resolution).c_str());
    warnings.emplace_back(text);
  }
  if (mostDepthsBeyondMaxRange(totals, map.max_range)) {
    std::snprintf(text, sizeof text,
                  "%.1f%% of the measured depths lay beyond the max range of %.2f m and mapped "
                  "nothing (the farthest lies %.1f m from the camera): the scores cover the "
                  "nearer surfaces only.",
                  100.0 * static_cast<double>(totals.beyond_range_pixels) / measured, map.max_range,
                  totals.farthest_range);
    warnings.emplace_back(text);
  }
  return warnings;
}

}  // namespace

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}
}  // namespace

MapWorker::MapWorker(QObject* parent)
    : QObject(parent), snapshot_(std::make_shared<MapSnapshot>()) {
  thread_ = std::thread([this] { loop(); });
}

MapWorker::~MapWorker() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    jobs_.clear();
  }
  if (fusion_cancel_) *fusion_cancel_ = true;
  paused_ = false;
  evaluation_generation_ += 1;
  wake_.notify_all();
  thread_.join();
}

void MapWorker::post(std::function<void()> run, bool quick) {
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back({std::move(run), quick});
  }
  wake_.notify_all();
}

void MapWorker::inGui(std::function<void()> call) {
  QMetaObject::invokeMethod(this, std::move(call), Qt::QueuedConnection);
}

void MapWorker::loop() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (stopping_) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    runGuarded(job);
    // A fusion, a reset or an adopted map may have freed a large map (a fine
    // room-scale one takes gigabytes): the allocator keeps freed memory for
    // the process unless asked to give it back, and this process is the
    // studio, open for hours beside other programs.
    if (!job.quick) {
      job = Job();
      malloc_trim(0);
    }
  }
}

void MapWorker::runGuarded(Job& job) {
  // An exception leaving a job would end the whole program (it runs on a
  // std::thread), losing unsaved boxes and maps: it is reported instead.
  try {
    job.run();
  } catch (const std::exception& error) {
    const QString message = QString::fromStdString(error.what());
    inGui([this, message] { emit workFailed(tr("Map work failed"), message); });
  } catch (...) {
    inGui([this] { emit workFailed(tr("Map work failed"), tr("an unknown error")); });
  }
}

void MapWorker::runQuickJobs() {
  std::deque<Job> quick;
  {
    std::lock_guard lock(mutex_);
    for (auto it = jobs_.begin(); it != jobs_.end();) {
      if (it->quick) {
        quick.push_back(std::move(*it));
        it = jobs_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (Job& job : quick) runGuarded(job);
}

void MapWorker::setState(State state) {
  if (state_ == state) return;
  state_ = state;
  emit stateChanged(state);
}

void MapWorker::publish(MapSnapshotPtr snapshot) {
  {
    std::lock_guard lock(snapshot_mutex_);
    next_snapshot_ = std::move(snapshot);
    if (snapshot_posted_) return;  // the call already on its way takes this one
    snapshot_posted_ = true;
  }
  // Queued behind the GUI calls posted before it, ahead of those posted
  // after: whatever the worker reports next finds this snapshot or a newer one.
  inGui([this] {
    {
      std::lock_guard lock(snapshot_mutex_);
      snapshot_ = std::move(next_snapshot_);
      snapshot_posted_ = false;
    }
    const auto start = Clock::now();
    emit snapshotChanged();
    gui_snapshot_ms_ = static_cast<int>(secondsSince(start) * 1000.0);
  });
}

unsigned MapWorker::beginNewMap() {
  // The map changes generation before the running fusion is cancelled: the
  // worker may end that fusion and run the work queued behind it (an export
  // waiting for the map) at once, and that work must see the map replaced.
  ++map_generation_;
  // An evaluation still running scores the map being replaced: it stops.
  evaluation_generation_ += 1;
  cancel();
  paused_ = false;
  fusion_cancel_ = std::make_shared<std::atomic<bool>>(false);
  return ++fusion_id_;
}

void MapWorker::startFusion(std::shared_ptr<const Sequence> sequence,
                            const FusionOptions& options) {
  const bool was_unsaved = unsaved_map_;
  const unsigned id = beginNewMap();
  unsaved_map_ = true;
  const Start start{id, map_generation_, was_unsaved};
  post([this, sequence, options, start,
        cancelled = fusion_cancel_] { fuse(sequence, options, start, cancelled); },
       false);
  setState(State::Fusing);
  emit fusionStarted();
}

void MapWorker::adoptMap(std::shared_ptr<LabelMap> map, size_t frames, const QString& source,
                         std::optional<Eigen::Vector3d> fallback_up) {
  const unsigned id = beginNewMap();
  unsaved_map_ = false;
  threshold_ = map->parameters().occupancy_threshold;
  threshold_pending_ = false;
  post(
      [this, map = std::move(map), frames, source, id, fallback_up] {
        map_ = std::make_unique<LabelMap>(std::move(*map));
        fallback_up_ = fallback_up;
        map_file_ = source.toStdString();
        fused_totals_ = {};
        frames_outside_map_.clear();
        frames_fused_ = frames;
        publish(takeSnapshot(*map_, frames_fused_, fallback_up_));
        inGui([this, id, source] {
          if (id != fusion_id_) return;  // superseded meanwhile
          setState(State::Idle);
          emit mapAdopted(source);
          emit fusionFinished(true);
        });
      },
      false);
  setState(State::Fusing);
  emit fusionStarted();
  emit adoptionStarted(source);
}

void MapWorker::fuse(const std::shared_ptr<const Sequence>& sequence, const FusionOptions& options,
                     const Start& start_of, const std::shared_ptr<std::atomic<bool>>& cancelled) {
  const unsigned id = start_of.id;
  auto finish = [this, id](bool completed) {
    inGui([this, id, completed] {
      if (id != fusion_id_) return;  // superseded by a newer fusion
      setState(State::Idle);
      emit fusionFinished(completed);
    });
  };
  // The map shown stays until this fusion has fused a frame: a Re-fuse that
  // fails on its first frame (a segmenter that cannot run on the frames, a
  // missing image) or is cancelled before it keeps the map the user had,
  // rather than leave an empty one. Not for a map replaced meanwhile (another
  // fusion, Reset Map, another sequence: the generation moved on).
  struct Previous {
    std::unique_ptr<LabelMap> map;
    std::string file;
    std::optional<Eigen::Vector3d> up;
    FrameStats totals;
    std::vector<size_t> outside;
    size_t frames = 0, first = 0;
    std::string segmenter;
  } previous;
  auto keepPrevious = [this, start_of] {
    inGui([this, start_of, source = QString::fromStdString(map_file_)] {
      if (start_of.id != fusion_id_ || start_of.generation != map_generation_) return;
      unsaved_map_ = start_of.was_unsaved;
      emit previousMapKept(source);
    });
  };
  const bool had_map = map_ && (frames_fused_ > 0 || !map_file_.empty());
  FusionOptions fusion = options;
  fusion.map.occupancy_threshold = threshold_;
  // Cancel also stops within a frame, before the frame changes the map.
  fusion.integration.cancelled = [cancelled] { return cancelled->load(); };
  try {
    // As fuseSequence: a camera outside the map fails before any frame is
    // fused, naming sequence.json and the frame.
    checkCamerasInsideMap(*sequence, fusion.map.resolution, fusion.first_frame, fusion.last_frame);
    auto fresh = std::make_unique<LabelMap>(sequence->labels, fusion.map);
    noteSequenceWorldFrame(*fresh, *sequence);
    // Named in reports only when it runs: frames with a proba image of their own
    // are fused as they are (segmenterRunsOn).
    const size_t first_fused = std::min(fusion.first_frame, sequence->frames.size());
    const size_t last_fused = std::min(fusion.last_frame, sequence->frames.size());
    std::string segmenter;
    for (size_t i = first_fused; fusion.segmenter && i < last_fused; ++i)
      if (segmenterRunsOn(*sequence, i, fusion.segmenter.get())) {
        segmenter = fusion.segmenter->modelPath().string();
        break;
      }
    if (had_map)
      previous = {std::move(map_),    std::move(map_file_),       fallback_up_,
                  fused_totals_,      frames_outside_map_,        frames_fused_,
                  first_fused_frame_, std::move(fused_segmenter_)};
    map_ = std::move(fresh);
    map_file_.clear();
    fused_totals_ = {};
    frames_outside_map_.clear();
    first_fused_frame_ = first_fused;
    fused_segmenter_ = std::move(segmenter);
  } catch (const std::exception& error) {
    QString message = QString::fromStdString(error.what());
    if (had_map) message += " " + tr("Nothing was fused: the map shown before is kept.");
    inGui([this, message] { emit errorOccurred(tr("Cannot fuse"), message); });
    if (had_map) keepPrevious();  // not replaced yet
    return finish(false);
  }
  frames_fused_ = 0;
  fallback_up_.reset();  // a fused map records its cameras
  publish(takeSnapshot(*map_, 0));
  std::function<void(size_t)> frame_fused_hook;
  {
    std::lock_guard lock(mutex_);
    frame_fused_hook = frame_fused_hook_;
  }
  fusing_now_ = true;
  const size_t first = std::min(fusion.first_frame, sequence->frames.size());
  const size_t last = std::min(fusion.last_frame, sequence->frames.size());
  const int total = static_cast<int>(last > first ? last - first : 0);
  const auto start = Clock::now();
  auto last_snapshot = Clock::now();
  double paused_seconds = 0.0;
  bool completed = true;
  FrameStats totals;
  for (size_t i = first; i < last; ++i) {
    runQuickJobs();
    applyPendingThreshold();
    if (paused_) {
      const auto pause_start = Clock::now();
      publish(takeSnapshot(*map_, frames_fused_, fallback_up_));
      std::unique_lock lock(mutex_);
      while (paused_ && !*cancelled && !stopping_) {
        wake_.wait_for(lock, std::chrono::milliseconds(50));
        lock.unlock();
        runQuickJobs();
        applyPendingThreshold();
        lock.lock();
      }
      paused_seconds += secondsSince(pause_start);
    }
    if (*cancelled || stopping_) {
      completed = false;
      break;
    }
    try {
      const FrameData frame = loadFusionFrame(*sequence, i, fusion.segmenter.get());
      const FrameEvidence evidence = makeEvidence(*sequence, i, frame, fusion);
      FrameStats stats =
          integrateFrame(*map_, sequence->cameraOf(i), sequence->frames[i].T_world_camera,
                         frame.depth, evidence, fusion.integration);
      map_->noteFusedEvidence(evidenceSourceOf(*sequence, i, fusion.segmenter.get()));
      noteDepthRanges(stats, sequence->cameraOf(i), frame.depth, fusion.map.max_range);
      addFrameStats(totals, stats);
      fused_totals_ = totals;
      if (stats.outside_map_pixels > 0) frames_outside_map_.push_back(i);
    } catch (const FrameCancelled&) {  // the frame left the map as it was
      completed = false;
      break;
    } catch (const std::exception& error) {
      // Errors about a frame's files name the frame already (frames[5].depth).
      const QString what = QString::fromStdString(error.what());
      const QString frame = QString("frames[%1]").arg(i);
      QString message = what.contains(frame) ? what : frame + ": " + what;
      if (previous.map && frames_fused_ == 0 && start_of.generation == map_generation_)
        message += " " + tr("Nothing was fused: the map shown before is kept.");
      inGui([this, message] { emit errorOccurred(tr("Fusion stopped"), message); });
      completed = false;
      break;
    }
    ++frames_fused_;
    if (previous.map) previous = {};  // this fusion's map is the one kept now
    if (frame_fused_hook) frame_fused_hook(frames_fused_);
    const int done = static_cast<int>(i + 1 - first);
    const double busy = std::max(1e-6, secondsSince(start) - paused_seconds);
    const double rate = done / busy;
    const bool last_frame = i + 1 == last;
    const int interval = std::max(snapshot_interval_ms_.load(), 2 * gui_snapshot_ms_.load());
    if (!last_frame && secondsSince(last_snapshot) * 1000.0 >= interval) {
      publish(takeSnapshot(*map_, frames_fused_, fallback_up_));
      last_snapshot = Clock::now();
    }
    inGui([this, done, total, rate] { emit fusionProgress(done, total, rate); });
  }
  fusing_now_ = false;
  if (!completed && previous.map && frames_fused_ == 0 && !stopping_ &&
      start_of.generation == map_generation_) {
    map_ = std::move(previous.map);
    map_file_ = std::move(previous.file);
    fallback_up_ = previous.up;
    fused_totals_ = previous.totals;
    frames_outside_map_ = std::move(previous.outside);
    frames_fused_ = previous.frames;
    first_fused_frame_ = previous.first;
    fused_segmenter_ = std::move(previous.segmenter);
    // A threshold changed while this fusion ran is the one the view shows.
    if (map_->parameters().occupancy_threshold != threshold_)
      map_->setOccupancyThreshold(threshold_);
    publish(takeSnapshot(*map_, frames_fused_, fallback_up_));
    keepPrevious();
    return finish(false);
  }
  // As fuseSequence does: the studio's map, its exports and .ot files are
  // then the command line's for the same frames.
  map_->prune();
  publish(takeSnapshot(*map_, frames_fused_, fallback_up_));
  const double max_range = fusion.map.max_range;
  inGui([this, id, totals, max_range] {
    if (id == fusion_id_) emit depthRangesMeasured(totals, max_range);
  });
  finish(completed);
}

void MapWorker::setPaused(bool paused) {
  if (!isFusing()) return;
  paused_ = paused;
  wake_.notify_all();
  setState(paused ? State::Paused : State::Fusing);
}

void MapWorker::cancel() {
  if (!isFusing()) return;
  if (fusion_cancel_) *fusion_cancel_ = true;
  paused_ = false;
  wake_.notify_all();
}

void MapWorker::reset() {
  unsaved_map_ = false;
  evaluation_generation_ += 1;
  ++map_generation_;  // before the cancel, as in startFusion
  cancel();
  const unsigned id = fusion_id_;
  post(
      [this, id] {
        map_.reset();
        fallback_up_.reset();
        frames_fused_ = 0;
        publish(std::make_shared<MapSnapshot>());
        // After the stopped fusion's end (queued before this): the status
        // says "not fused", not where that fusion stopped.
        inGui([this, id] {
          if (id == fusion_id_ && !isFusing()) emit mapReset();
        });
      },
      false);
}

void MapWorker::applyPendingThreshold() {
  if (!threshold_pending_.exchange(false) || !map_) return;
  map_->setOccupancyThreshold(threshold_);
  publish(takeSnapshot(*map_, frames_fused_, fallback_up_));
}

void MapWorker::setOccupancyThreshold(double threshold) {
  // A map re-thresholded differs from the file it was saved to or read from
  // (a .ot keeps its threshold): it is unsaved again.
  if (threshold != threshold_) unsaved_map_ = true;
  threshold_ = threshold;
  threshold_pending_ = true;
  post([this] { applyPendingThreshold(); }, true);
}

void MapWorker::pick(const Eigen::Vector3d& point_world) {
  post(
      [this, point_world] {
        VoxelState state;
        if (map_) {
          try {
            state = map_->voxelAt(point_world);
          } catch (const std::exception&) {
            // outside the map's key range: unknown
          }
        }
        inGui([this, point_world, state] { emit voxelPicked(point_world, state); });
      },
      true);
}

void MapWorker::evaluate(std::shared_ptr<const Sequence> sequence, const Annotations& annotations,
                         const EvaluationOptions& options) {
  const unsigned generation = ++evaluation_generation_;
  ++evaluations_pending_;
  emit evaluationStarted();
  post(
      [this, sequence, annotations, options, generation] {
        auto finish = [this](std::function<void()> emit_result) {
          inGui([this, emit_result] {
            --evaluations_pending_;
            emit_result();
          });
        };
        if (generation != evaluation_generation_) return finish([] {});
        if (!map_) {
          return finish([this] { emit evaluationFailed(tr("Fuse the sequence first.")); });
        }
        // What a score of an empty map would fail with names no file here.
        if (map_->occupiedCountPerLabel().empty())
          return finish([this] {
            emit evaluationFailed(
                tr("Nothing to score: the map holds no occupied voxel. Its frames put no depth "
                   "within the max range, or no label's probability reached the occupancy "
                   "threshold (Fusion panel)."));
          });
        try {
          EvaluationReport report = lom::evaluate(
              *sequence, annotations, *map_, options,
              [this, generation](const EvaluationProgress&) {
                return generation == evaluation_generation_ && !stopping_;
              });
          // What `score` reports besides the scores: a map file's fit and
          // candidates, or what fusing it here left out.
          if (!map_file_.empty()) {
            describeMapFile(report, *map_, *sequence, map_file_, false, options.fusion.first_frame,
                            options.fusion.last_frame, options.fusion.segmenter.get());
          } else {
            report.fusion_totals = fused_totals_;
            if (frames_fused_ > 0)
              report.fused_frames =
                  std::make_pair(first_fused_frame_, first_fused_frame_ + frames_fused_ - 1);
            report.segmenter = fused_segmenter_;
            report.frames_outside_map = frames_outside_map_;
            for (std::string& warning :
                 fusionWarnings(fused_totals_, frames_outside_map_, map_->parameters()))
              report.warnings.push_back(std::move(warning));
            if (std::string near =
                    nearDepthWarning(*sequence, first_fused_frame_,
                                     first_fused_frame_ + frames_fused_, fused_totals_);
                !near.empty())
              report.warnings.push_back(std::move(near));
          }
          finish([this, report] { emit evaluationFinished(report); });
        } catch (const EvaluationCancelled&) {
          finish([] {});
        } catch (const std::exception& error) {
          const QString message = QString::fromStdString(error.what());
          finish([this, message] { emit evaluationFailed(message); });
        }
      },
      false);
}

unsigned MapWorker::listWork(const QString& description) {
  if (description.isEmpty()) return 0;
  const unsigned id = ++map_job_id_;
  pending_work_.emplace_back(id, description);
  return id;
}

void MapWorker::forgetWork(unsigned id, std::function<void()> then) {
  if (id == 0 && !then) return;
  inGui([this, id, then = std::move(then)] {
    pending_work_.erase(std::remove_if(pending_work_.begin(), pending_work_.end(),
                                       [id](const auto& work) { return work.first == id; }),
                        pending_work_.end());
    if (then) then();
  });
}

void MapWorker::withMap(std::function<void(const LabelMap*)> job, const QString& description) {
  withMapThen(
      [job = std::move(job)](const LabelMap* map) {
        job(map);
        return std::function<void()>();
      },
      description);
}

void MapWorker::withMapThen(std::function<std::function<void()>(const LabelMap*)> job,
                            const QString& description) {
  const unsigned id = listWork(description);
  post(
      [this, id, job = std::move(job)] {
        std::function<void()> then;
        try {
          then = job(map_.get());
        } catch (...) {  // reported by runGuarded; no longer pending either way
          forgetWork(id);
          throw;
        }
        forgetWork(id, std::move(then));
      },
      false);
}

void MapWorker::withCurrentMap(std::function<bool(const LabelMap*, bool)> job,
                               const QString& description) {
  const unsigned id = listWork(description);
  post(
      [this, id, job = std::move(job)] {
        // The work is forgotten (no longer listed as pending) however it ends.
        struct Forget {
          MapWorker* worker;
          unsigned id;
          bool armed = true;
          ~Forget() {
            if (armed) worker->forgetWork(id);
          }
        } forget{this, id};
        if (!fusing_now_) {
          job(map_.get(), true);
          return;
        }
        if (job(map_.get(), false)) return;
        forget.armed = false;
        post(  // nothing to work on yet: again once the fusion has ended
            [this, id, job] {
              Forget again{this, id};
              job(map_.get(), true);
            },
            false);
      },
      true);
}

void MapWorker::setFrameFusedHook(std::function<void(size_t)> hook) {
  std::lock_guard lock(mutex_);
  frame_fused_hook_ = std::move(hook);
}

QStringList MapWorker::pendingWork() const {
  QStringList work;
  for (const auto& entry : pending_work_) work << entry.second;
  return work;
}

}  // namespace lom::ui
