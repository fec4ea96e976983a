#pragma once
// How the library runs work on several threads: an execution context (how
// many threads a computation may use) passed down through every stage, and
// two primitives over oneTBB. Results never depend on the thread count:
// work is cut into chunks whose bounds depend only on the input's size, each
// chunk accumulates on its own, and callers add the chunks' sums in chunk
// order (docs/speed.md, Threads).
#include <cstdint>
#include <functional>

namespace surfreg {

struct Execution {
  int threads = 1;  // >= 1
  bool parallel() const { return threads > 1; }
};

// `requested` threads, 0 meaning every core the process may use.
Execution ExecutionFor(int requested);

// The number of chunks for n items of which each chunk should hold at least
// `min_items` (1 to kMaxChunks): a function of n only.
constexpr int kMaxChunks = 64;
int ChunksFor(int64_t n, int64_t min_items);

// Items per chunk for cheap per-item loops: a face scan's 3e4 triangles
// still spread over several threads, and a chunk's few µs of overhead stay
// well under its work (as any ChunksFor, a function of n only).
constexpr int64_t kItemChunk = 4096;

// Chunk c's half-open range of [0, n) cut into `chunks` near-equal parts.
inline int64_t ChunkBegin(int64_t n, int chunks, int c) { return n * c / chunks; }

// body(c, begin, end) for every chunk c of [0, n) cut into `chunks` parts,
// on up to `execution.threads` threads (in order on the calling thread with
// one). An exception from a body is rethrown here once all have stopped.
void ForEachChunk(const Execution& execution, int64_t n, int chunks,
                  const std::function<void(int chunk, int64_t begin, int64_t end)>& body);

// body(k) for every k in [0, n), up to `execution.threads` items at once,
// for independent jobs (pairs of a series, rows of a batch). Every item runs
// even when another throws; then the exception of the lowest k that threw
// is rethrown, so the error a user sees does not depend on the order the
// items ran in.
void ForEachItem(const Execution& execution, int n, const std::function<void(int k)>& body);

// first() and second(), side by side when parallel. They must not wait on
// each other: a task library may run both on one thread, one after the other.
void RunBoth(const Execution& execution, const std::function<void()>& first,
             const std::function<void()>& second);

// first() here and second() on a thread of its own when `concurrent` (else
// in order): for two tasks of which one may wait for the other (a promise),
// which RunBoth does not allow.
void RunOnTwoThreads(bool concurrent, const std::function<void()>& first,
                     const std::function<void()>& second);

// body() on this thread, where a library spreads its work over `parts`
// independent parts on threads of its own (GDAL compressing a GeoTIFF's
// blocks: NUM_THREADS): timed as a region of that width.
void RunSpreadByLibrary(int parts, const std::function<void()>& body);

// Time spent inside ForEachChunk, RunBoth and RunOnTwoThreads regions, for
// the serial-fraction measurement (docs/speed.md, Threads): enabled by
// SetRegionTiming(true), read and reset by TakeRegionTiming. Meant for
// one-thread runs, where each chunk is timed too. A region nested in a
// chunk or task counts inside it: each of a region's W tasks has P / W of
// the P projected cores (at least one) for the regions nested in it.
constexpr int kProjectedCores[4] = {2, 8, 16, 64};
struct RegionTiming {
  double parallel_seconds = 0.0;  // wall time inside outermost regions
  // What the regions would take on P = kProjectedCores[k] cores, summed:
  // each region's tasks' projected times over min(P, its chunks), but never
  // less than its longest (a lower bound, as a perfect scheduler would
  // reach); a task's projected time is its own time outside nested regions
  // plus theirs projected on its share of the cores.
  double projected_seconds[4] = {0.0, 0.0, 0.0, 0.0};
  int64_t regions = 0;
};
void SetRegionTiming(bool enabled);
RegionTiming TakeRegionTiming();

}  // namespace surfreg
