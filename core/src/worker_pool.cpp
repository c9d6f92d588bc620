#include "worker_pool.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace lom {

namespace {

// A few workers that wait for jobs: they spin briefly after a job (the next
// phase of the frame usually follows within microseconds), then sleep.
class WorkerPool {
 public:
  ~WorkerPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
      ++generation_;
    }
    wake_.notify_all();
    for (auto& worker : workers_) worker.join();
  }

  // False when busy with another caller's job.
  bool tryRun(int parts, const std::function<void(int)>& work) {
    std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
    if (!busy.owns_lock()) return false;
    while (static_cast<int>(workers_.size()) < parts - 1) {
      const int index = static_cast<int>(workers_.size()) + 1;
      // The worker starts from the current generation: the job set below is new to it.
      const unsigned long seen = generation_.load(std::memory_order_acquire);
      workers_.emplace_back([this, index, seen] { loop(index, seen); });
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      work_ = &work;
      parts_ = parts;
      error_ = nullptr;
      remaining_.store(parts - 1, std::memory_order_relaxed);
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    std::exception_ptr own_error;
    try {
      work(0);
    } catch (...) {
      own_error = std::current_exception();
    }
    while (remaining_.load(std::memory_order_acquire) > 0) std::this_thread::yield();
    {
      std::lock_guard<std::mutex> lock(mutex_);  // workers not in this job may be reading it
      work_ = nullptr;
    }
    if (own_error) std::rethrow_exception(own_error);
    if (error_) std::rethrow_exception(error_);
    return true;
  }

 private:
  void loop(int index, unsigned long seen) {
    while (true) {
      // Spin a little for the next phase, then sleep until woken.
      const auto spin_until = std::chrono::steady_clock::now() + std::chrono::microseconds(300);
      while (generation_.load(std::memory_order_acquire) == seen &&
             std::chrono::steady_clock::now() < spin_until)
        std::this_thread::yield();
      // The job is read under the lock, with the generation it belongs to: a
      // worker that takes no part in a job must not read its fields after the
      // lock, when the next caller may already be setting them.
      const std::function<void(int)>* work = nullptr;
      int parts = 0;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
        if (stop_) return;
        seen = generation_.load(std::memory_order_relaxed);
        work = work_;
        parts = parts_;
      }
      if (index < parts) {
        try {
          (*work)(index);
        } catch (...) {
          std::lock_guard<std::mutex> lock(mutex_);
          if (!error_) error_ = std::current_exception();
        }
        remaining_.fetch_sub(1, std::memory_order_acq_rel);
      }
    }
  }

  std::mutex busy_;   // held by the caller whose job runs
  std::mutex mutex_;  // guards the job fields and the sleeping workers
  std::condition_variable wake_;
  std::vector<std::thread> workers_;
  std::atomic<unsigned long> generation_{0};
  std::atomic<int> remaining_{0};
  const std::function<void(int)>* work_ = nullptr;
  int parts_ = 0;
  std::exception_ptr error_;
  bool stop_ = false;
};

WorkerPool& pool() {
  static WorkerPool workers;
  return workers;
}

}  // namespace

void runParts(int parts, const std::function<void(int)>& work) {
  if (parts <= 1) {
    work(0);
    return;
  }
  if (pool().tryRun(parts, work)) return;
  std::vector<std::thread> threads;
  std::exception_ptr error;
  std::mutex error_mutex;
  auto guarded = [&](int t) {
    try {
      work(t);
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  };
  for (int t = 1; t < parts; ++t) threads.emplace_back(guarded, t);
  guarded(0);
  for (auto& thread : threads) thread.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace lom
