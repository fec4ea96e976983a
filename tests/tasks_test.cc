// The task primitives (measure/tasks.h): fixed chunks whatever the thread
// count, every item once, exceptions carried back (for independent items the
// lowest failing one's), and the two-thread runner
// for tasks that wait on each other.
#include "measure/tasks.h"

#include <atomic>
#include <chrono>
#include <future>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace surfreg {
namespace {

TEST(Tasks, ChunkCountDependsOnSizeOnly) {
  EXPECT_EQ(ChunksFor(0, 100), 1);
  EXPECT_EQ(ChunksFor(-5, 100), 1);
  EXPECT_EQ(ChunksFor(99, 100), 1);
  EXPECT_EQ(ChunksFor(250, 100), 2);
  EXPECT_EQ(ChunksFor(int64_t{1} << 40, 100), kMaxChunks);
  EXPECT_EQ(ChunksFor(1000, 0), 1);
}

TEST(Tasks, ChunksCoverTheRangeInOrder) {
  for (const int64_t n : {0, 1, 7, 64, 1000003}) {
    for (const int chunks : {1, 3, 64}) {
      EXPECT_EQ(ChunkBegin(n, chunks, 0), 0);
      EXPECT_EQ(ChunkBegin(n, chunks, chunks), n);
      for (int c = 0; c < chunks; ++c) EXPECT_LE(ChunkBegin(n, chunks, c), ChunkBegin(n, chunks, c + 1));
    }
  }
}

TEST(Tasks, EveryItemOnceWithTheSameBoundsOnAnyThreadCount) {
  const int64_t n = 100000;
  const int chunks = 37;
  std::vector<std::pair<int64_t, int64_t>> bounds_one(chunks);
  ForEachChunk(Execution{1}, n, chunks, [&](int c, int64_t b, int64_t e) { bounds_one[c] = {b, e}; });
  for (const int threads : {1, 2, 8}) {
    std::vector<std::atomic<int>> seen(n);
    std::vector<std::pair<int64_t, int64_t>> bounds(chunks);
    ForEachChunk(Execution{threads}, n, chunks, [&](int c, int64_t b, int64_t e) {
      bounds[c] = {b, e};
      for (int64_t i = b; i < e; ++i) ++seen[i];
    });
    for (int64_t i = 0; i < n; ++i) ASSERT_EQ(seen[i].load(), 1) << i << " on " << threads;
    EXPECT_EQ(bounds, bounds_one) << threads;
  }
}

TEST(Tasks, ExceptionComesBackAfterTheOthersStop) {
  for (const int threads : {1, 4}) {
    std::atomic<int> ran{0};
    EXPECT_THROW(ForEachChunk(Execution{threads}, 64, 16,
                              [&](int c, int64_t, int64_t) {
                                ++ran;
                                if (c == 5) throw std::runtime_error("chunk 5");
                              }),
                 std::runtime_error);
    EXPECT_GE(ran.load(), 1);
    EXPECT_THROW(RunBoth(Execution{threads}, [] {}, [] { throw std::invalid_argument("second"); }),
                 std::invalid_argument);
    EXPECT_THROW(RunBoth(Execution{threads}, [] { throw std::invalid_argument("first"); }, [] {}),
                 std::invalid_argument);
  }
}

TEST(Tasks, EveryItemRunsAndTheLowestFailingItemsErrorComesBack) {
  for (const int threads : {1, 2, 8}) {
    for (int repeat = 0; repeat < 20; ++repeat) {
      std::vector<std::atomic<int>> ran(12);
      try {
        ForEachItem(Execution{threads}, 12, [&](int k) {
          ++ran[k];
          if (k == 9) throw std::runtime_error("item 9");
          if (k == 4) {  // the lowest failing item, made to finish last
            std::this_thread::sleep_for(std::chrono::milliseconds(repeat % 3));
            throw std::runtime_error("item 4");
          }
          if (k == 7) throw std::invalid_argument("item 7");
        });
        ADD_FAILURE() << "no exception";
      } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "item 4") << threads << " threads";
      }
      for (int k = 0; k < 12; ++k) EXPECT_EQ(ran[k].load(), 1) << "item " << k;
    }
  }
  int calls = 0;
  ForEachItem(Execution{4}, 0, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
}

TEST(Tasks, TwoThreadsLetOneTaskWaitForTheOther) {
  // The second waits for a value the first gives: needs two threads (or
  // the order first, second).
  for (const bool concurrent : {false, true}) {
    std::promise<int> given;
    std::future<int> value = given.get_future();
    int got = 0;
    RunOnTwoThreads(concurrent, [&] { given.set_value(42); }, [&] { got = value.get(); });
    EXPECT_EQ(got, 42);
  }
}

TEST(Tasks, NestedRegionsRun) {
  std::atomic<int64_t> sum{0};
  ForEachChunk(Execution{2}, 8, 8, [&](int, int64_t b, int64_t) {
    RunBoth(Execution{2}, [&] { sum += b; }, [&] {
      ForEachChunk(Execution{2}, 10, 5, [&](int, int64_t lo, int64_t hi) { sum += hi - lo; });
    });
  });
  EXPECT_EQ(sum.load(), 28 + 8 * 10);
}

TEST(Tasks, ExecutionForResolvesEveryCore) {
  EXPECT_EQ(ExecutionFor(3).threads, 3);
  EXPECT_GE(ExecutionFor(0).threads, 1);
  EXPECT_FALSE(Execution{1}.parallel());
  EXPECT_TRUE(Execution{2}.parallel());
}

TEST(Tasks, RegionTimingCountsNestedRegionsOnTheirTasksShare) {
  TakeRegionTiming();
  SetRegionTiming(true);
  // Two sides, one with eight 2 ms chunks inside: on 16 cores each side has
  // 8, so the chunks take 2 ms; on 2 cores each side has one, so 16 ms.
  RunBoth(Execution{1}, [] {
    ForEachChunk(Execution{1}, 8, 8, [](int, int64_t, int64_t) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    });
  }, [] {});
  SetRegionTiming(false);
  const RegionTiming t = TakeRegionTiming();
  EXPECT_EQ(t.regions, 1);
  EXPECT_GE(t.parallel_seconds, 0.016);
  EXPECT_GE(t.projected_seconds[0], 0.016);  // 2 cores
  EXPECT_LT(t.projected_seconds[2], 0.5 * t.projected_seconds[0]);  // 16 cores (8 ideally)
  EXPECT_GE(t.projected_seconds[2], 0.002);
}

TEST(Tasks, RegionTimingCountsOutermostRegionsOnly) {
  TakeRegionTiming();
  SetRegionTiming(true);
  ForEachChunk(Execution{1}, 4, 4, [&](int, int64_t, int64_t) {
    RunBoth(Execution{1}, [] { std::this_thread::sleep_for(std::chrono::milliseconds(2)); }, [] {});
  });
  RunBoth(Execution{1}, [] { std::this_thread::sleep_for(std::chrono::milliseconds(4)); }, [] {});
  SetRegionTiming(false);
  const RegionTiming t = TakeRegionTiming();
  EXPECT_EQ(t.regions, 2);
  EXPECT_GE(t.parallel_seconds, 0.012);
  // On 8 or more cores: the first region's longest chunk (2 ms of 8), the
  // second's longest task (all of its 4 ms): about half the time.
  EXPECT_LT(t.projected_seconds[1], t.parallel_seconds * 0.7);
  EXPECT_GE(t.projected_seconds[1], 0.006);
  EXPECT_DOUBLE_EQ(t.projected_seconds[1], t.projected_seconds[3]);
  EXPECT_GE(t.projected_seconds[0], t.projected_seconds[1]);
  EXPECT_EQ(TakeRegionTiming().regions, 0);
}

// Work a library spreads over its own threads: its wall time over
// min(cores, parts), alone or as one of two sides.
TEST(Tasks, RegionTimingSpreadsALibrarysPartsOverTheCores) {
  TakeRegionTiming();
  SetRegionTiming(true);
  RunSpreadByLibrary(8, [] { std::this_thread::sleep_for(std::chrono::milliseconds(16)); });
  SetRegionTiming(false);
  RegionTiming t = TakeRegionTiming();
  EXPECT_EQ(t.regions, 1);
  EXPECT_GE(t.parallel_seconds, 0.016);
  EXPECT_DOUBLE_EQ(t.projected_seconds[0], t.parallel_seconds / 2);  // 2 cores
  EXPECT_DOUBLE_EQ(t.projected_seconds[1], t.parallel_seconds / 8);  // 8 cores
  EXPECT_DOUBLE_EQ(t.projected_seconds[3], t.parallel_seconds / 8);  // 64 cores, 8 parts
  SetRegionTiming(true);
  RunBoth(Execution{1}, [] {}, [] {
    RunSpreadByLibrary(0, [] { std::this_thread::sleep_for(std::chrono::milliseconds(4)); });  // one part
  });
  SetRegionTiming(false);
  t = TakeRegionTiming();
  EXPECT_EQ(t.regions, 1);
  EXPECT_GE(t.projected_seconds[3], 0.004);  // one part is serial on any machine
}

}  // namespace
}  // namespace surfreg
