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
// than the lock). Regions nest (a triangulation's slabs inside one of two
// sides): each task of a region gets its share of the projected machine's
// cores, and a region nested in a task counts as that task's time on them.
std::atomic<bool> timing_enabled{false};
std::mutex timing_mutex;
RegionTiming timing_sums;
thread_local int region_depth = 0;

using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// What one task of a timed region has seen of the regions nested in it.
struct TaskFrame {
  double cores[4];  // its share of each projected machine
  double nested_wall = 0.0;
  double nested_projected[4] = {0.0, 0.0, 0.0, 0.0};
};
thread_local TaskFrame* current_task = nullptr;

class RegionTimer {
 public:
  explicit RegionTimer(int width) : width_(width) {
    timed_ = timing_enabled && (region_depth == 0 || current_task != nullptr);
    ++region_depth;
    if (!timed_) return;
    for (int k = 0; k < 4; ++k) cores_[k] = current_task ? current_task->cores[k] : kProjectedCores[k];
    start_ = Clock::now();
  }
  ~RegionTimer() {
    --region_depth;
    if (!timed_) return;
    const double wall = SecondsSince(start_);
    double projected[4];
    for (int k = 0; k < 4; ++k) {
      const double spread = std::min(cores_[k], static_cast<double>(width_));
      // Tasks not timed one by one (run on several threads): the wall time.
      projected[k] = tasks_ == 0 ? wall / spread : std::max(task_sum_[k] / spread, longest_[k]);
    }
    if (current_task != nullptr) {
      current_task->nested_wall += wall;
      for (int k = 0; k < 4; ++k) current_task->nested_projected[k] += projected[k];
      return;
    }
    std::lock_guard<std::mutex> lock(timing_mutex);
    timing_sums.parallel_seconds += wall;
    for (int k = 0; k < 4; ++k) timing_sums.projected_seconds[k] += projected[k];
    ++timing_sums.regions;
  }
  RegionTimer(const RegionTimer&) = delete;
  RegionTimer& operator=(const RegionTimer&) = delete;

  // Runs one chunk or task, timing it when this region is timed: its own
  // time plus its nested regions' projected time.
  template <typename F>
  void Task(F&& f) {
    if (!timed_) {
      f();
      return;
    }
    TaskFrame frame;
    for (int k = 0; k < 4; ++k) frame.cores[k] = std::max(1.0, cores_[k] / width_);
    TaskFrame* const enclosing = current_task;
    current_task = &frame;
    const Clock::time_point t = Clock::now();
    try {
      f();
    } catch (...) {
      current_task = enclosing;
      throw;
    }
    current_task = enclosing;
    const double wall = SecondsSince(t);
    ++tasks_;
    for (int k = 0; k < 4; ++k) {
      const double p = std::max(0.0, wall - frame.nested_wall) + frame.nested_projected[k];
      task_sum_[k] += p;
      longest_[k] = std::max(longest_[k], p);
    }
  }

 private:
  int width_;
  bool timed_ = false;
  int tasks_ = 0;
  double cores_[4] = {1.0, 1.0, 1.0, 1.0};
  double task_sum_[4] = {0.0, 0.0, 0.0, 0.0};
  double longest_[4] = {0.0, 0.0, 0.0, 0.0};
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

void ForEachItem(const Execution& execution, int n, const std::function<void(int k)>& body) {
  if (n <= 0) return;
  std::vector<std::exception_ptr> errors(n);
  ForEachChunk(execution, n, n, [&](int k, int64_t, int64_t) {  // one item per chunk
    try {
      body(k);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  });
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

void RunSpreadByLibrary(int parts, const std::function<void()>& body) {
  RegionTimer timer(std::max(parts, 1));  // no tasks of its own: wall time over the parts
  body();
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
