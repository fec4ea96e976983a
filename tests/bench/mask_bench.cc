// The cost of a mask's size: Measure of two clouds with a 4-vertex mask and
// with a 2,000-vertex one covering about the same area. The mask's triangles
// are found per overlay cell through a grid of buckets (measure/mask_region.h),
// so the two should take about the same time.
// Run: build/tests/bench/mask_bench [--benchmark_filter=/100000]
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "measure/measures.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

Surface Cloud(int64_t n, uint64_t seed, double lift) {
  std::vector<std::array<double, 3>> points;
  for (const Point2& p : testing::UniformPoints(static_cast<std::size_t>(n), seed)) {
    points.push_back({p.x, p.y, std::sin(6 * p.x) * std::cos(5 * p.y) + lift * (1 + p.x)});
  }
  return MakeSurface(points, {}, "cloud");
}

// A wavy ring of `vertices` vertices about (0.5, 0.5), radius 0.4 ± 0.02.
MaskRing Ring(int vertices) {
  MaskRing ring;
  if (vertices == 4) return {{0.15, 0.15}, {0.85, 0.15}, {0.85, 0.85}, {0.15, 0.85}};
  for (int k = 0; k < vertices; ++k) {
    const double a = 2 * M_PI * k / vertices, r = 0.4 + 0.02 * std::sin(37 * a);
    ring.push_back({0.5 + r * std::cos(a), 0.5 + r * std::sin(a)});
  }
  return ring;
}

void BM_MeasureMask(benchmark::State& state) {
  const int vertices = static_cast<int>(state.range(0));
  const int64_t n = state.range(1);
  const Surface a = Cloud(n, 0x5eed, 0.0), b = Cloud(n, 0xb0b, 0.01);
  MeasureOptions options;
  options.weight = WeightMode::kMask;
  options.mask = {Ring(vertices)};
  options.threads = 1;
  for (auto _ : state) {
    MeasureSummary s = Measure(a, b, options);
    benchmark::DoNotOptimize(s);
  }
  state.SetItemsProcessed(state.iterations() * 2 * n);
}
BENCHMARK(BM_MeasureMask)
    ->ArgsProduct({{4, 2000}, {10000, 100000}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace surfreg

BENCHMARK_MAIN();
