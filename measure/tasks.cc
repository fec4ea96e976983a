#include "measure/tasks.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#ifndef SURFREG_TASKS_STD_THREADS
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#endif

namespace surfreg {
namespace {

// Region timing: a flag, and sums under a mutex (a region is far longer
// than the lock). Depth per thread, so nested regions do not count twice.
std::atomic<bool> timing_enabled{false};
std::mutex timing_mutex;
RegionTiming timing_sums;
thread_local int region_depth = 0;

using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

class RegionTimer {
 public:
  explicit RegionTimer(int width) : width_(width), outer_(region_depth++ == 0 && timing_enabled) {
    if (outer_) start_ = Clock::now();
  }
  ~RegionTimer() {
    --region_depth;
    if (!outer_) return;
    const double s = SecondsSince(start_);
    std::lock_guard<std::mutex> lock(timing_mutex);
    timing_sums.parallel_seconds += s;
    for (int k = 0; k < 4; ++k) {
      timing_sums.projected_seconds[k] += std::max(s / std::min(kProjectedCores[k], width_), longest_);
    }
    ++timing_sums.regions;
  }
  RegionTimer(const RegionTimer&) = delete;
  RegionTimer& operator=(const RegionTimer&) = delete;

  // Runs one chunk or task, timing it when this region is timed.
  template <typename F>
  void Task(F&& f) {
    if (!outer_) {
      f();
      return;
    }
    const Clock::time_point t = Clock::now();
    f();
    longest_ = std::max(longest_, SecondsSince(t));
  }

 private:
  int width_;
  bool outer_;
  double longest_ = 0.0;
  Clock::time_point start_;
};

#ifndef SURFREG_TASKS_STD_THREADS
// One arena per thread count, made on first use and kept: an arena bounds
// the concurrency of what runs inside it, nested regions included. More
// threads than cores would only take turns (and oneTBB warns): capped.
tbb::task_arena& ArenaFor(int threads) {
  threads = std::min(threads, std::max(1, tbb::info::default_concurrency()));
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<tbb::task_arena>& arena = arenas[threads];
  if (!arena) arena = std::make_unique<tbb::task_arena>(threads);
  return *arena;
}
#endif

}  // namespace

Execution ExecutionFor(int requested) {
  if (requested >= 1) return Execution{requested};
#ifndef SURFREG_TASKS_STD_THREADS
  return Execution{std::max(1, tbb::info::default_concurrency())};
#else
  return Execution{std::max(1u, std::thread::hardware_concurrency())};
#endif
}

int ChunksFor(int64_t n, int64_t min_items) {
  if (n <= 0 || min_items <= 0) return 1;
  return static_cast<int>(std::clamp<int64_t>(n / min_items, 1, kMaxChunks));
}

void ForEachChunk(const Execution& execution, int64_t n, int chunks,
                  const std::function<void(int, int64_t, int64_t)>& body) {
  chunks = std::max(1, chunks);
  RegionTimer timer(chunks);
  if (!execution.parallel() || chunks == 1) {
    for (int c = 0; c < chunks; ++c) {
      timer.Task([&] { body(c, ChunkBegin(n, chunks, c), ChunkBegin(n, chunks, c + 1)); });
    }
    return;
  }
#ifndef SURFREG_TASKS_STD_THREADS
  ArenaFor(execution.threads).execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& r) {
      for (int c = r.begin(); c < r.end(); ++c) body(c, ChunkBegin(n, chunks, c), ChunkBegin(n, chunks, c + 1));
    }, tbb::simple_partitioner());
  });
#else
  // Plain threads taking chunks in turn: the ThreadSanitizer build, which
  // cannot see oneTBB's own synchronization (uninstrumented).
  std::atomic<int> next{0};
  std::vector<std::exception_ptr> errors(chunks);
  const auto work = [&] {
    for (int c = next++; c < chunks; c = next++) {
      try {
        body(c, ChunkBegin(n, chunks, c), ChunkBegin(n, chunks, c + 1));
      } catch (...) {
        errors[c] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < std::min(execution.threads, chunks); ++t) workers.emplace_back(work);
  work();
  for (std::thread& w : workers) w.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
#endif
}

void RunOnTwoThreads(bool concurrent, const std::function<void()>& first,
                     const std::function<void()>& second) {
  RegionTimer timer(2);
  if (!concurrent) {
    timer.Task(first);
    timer.Task(second);
    return;
  }
  std::exception_ptr error;
  std::thread worker([&] {
    try {
      second();
    } catch (...) {
      error = std::current_exception();
    }
  });
  try {
    first();
  } catch (...) {
    worker.join();
    throw;
  }
  worker.join();
  if (error) std::rethrow_exception(error);
}

void RunBoth(const Execution& execution, const std::function<void()>& first,
             const std::function<void()>& second) {
#ifndef SURFREG_TASKS_STD_THREADS
  if (execution.parallel()) {
    RegionTimer timer(2);
    ArenaFor(execution.threads).execute([&] { tbb::parallel_invoke(first, second); });
    return;
  }
#endif
  RunOnTwoThreads(execution.parallel(), first, second);
}

void SetRegionTiming(bool enabled) { timing_enabled = enabled; }

RegionTiming TakeRegionTiming() {
  std::lock_guard<std::mutex> lock(timing_mutex);
  const RegionTiming t = timing_sums;
  timing_sums = RegionTiming{};
  return t;
}

}  // namespace surfreg
