// Throughput of surfreg::Triangulate, and of CGAL's Delaunay_triangulation_2
// on the very same points when CGAL is available, for the point sets of
// tests/testing/point_sets.h (so tests and benchmarks share inputs).
//
// Names pair up by implementation: BM_Triangulate/<impl>/<distribution>/<N>,
// impl in {surfreg, cgal}, and surfreg-2threads at 1e6 (the slab build on
// two threads). N is the nominal size; grids use round(sqrt(N))^2 points
// (counter "points" holds the exact count).
//
// Before timing, each input is triangulated once by both and the results are
// compared (triangle count always; the triangles themselves where Delaunay is
// unique). A mismatch is printed to stderr and makes the exit status 2, so
// a filtered run doubles as a smoke test.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#ifdef SURFREG_HAVE_CGAL
#include <unordered_map>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#endif

#include "measure/delaunay.h"
#include "measure/surface.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

#ifdef SURFREG_HAVE_CGAL
using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalDelaunay = CGAL::Delaunay_triangulation_2<CgalKernel>;
#endif

enum class Distribution { kUniform, kJittered, kGrid };

constexpr uint64_t kSeed = 0x5eed2d;
constexpr double kJitter = 0.25;  // fraction of the grid step

const char* DistributionName(Distribution d) {
  switch (d) {
    case Distribution::kUniform:
      return "uniform";
    case Distribution::kJittered:
      return "jittered";
    case Distribution::kGrid:
      return "grid";
  }
  return "?";
}

int GridSide(int64_t n) { return static_cast<int>(std::lround(std::sqrt(static_cast<double>(n)))); }

// One input and what the one-off comparison found on it.
struct Input {
  std::vector<Point2> points;
#ifdef SURFREG_HAVE_CGAL
  std::vector<CgalKernel::Point_2> cgal_points;
#endif
  std::string description;  // names the exact input in messages
  bool checked = false;
  std::string error;  // set if our triangulation threw
  int64_t surfreg_triangles = -1;
  int64_t cgal_triangles = -1;
};

bool g_mismatch = false;  // any disagreement with CGAL: exit status 2

#ifdef SURFREG_HAVE_CGAL
// Triangle (a, b, c) rotated so the smallest index comes first; orientation
// is kept, so a flipped triangle does not compare equal.
std::array<int32_t, 3> Canonical(int32_t a, int32_t b, int32_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

// Compares the triangles themselves, by input index. CGAL vertices are
// mapped back to input points through their coordinates (the lowest index
// wins, as in ours for duplicates).
void CompareTriangles(const Input& input, const Triangulation& ours, const CgalDelaunay& dt,
                      bool delaunay_is_unique) {
  struct Hash {
    std::size_t operator()(const std::pair<double, double>& p) const {
      uint64_t x, y;
      std::memcpy(&x, &p.first, sizeof x);
      std::memcpy(&y, &p.second, sizeof y);
      return std::hash<uint64_t>()(x * 0x9e3779b97f4a7c15ULL ^ y);
    }
  };
  std::unordered_map<std::pair<double, double>, int32_t, Hash> index_of;
  index_of.reserve(input.points.size());
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    index_of.emplace(std::make_pair(input.points[i].x, input.points[i].y),
                     static_cast<int32_t>(i));
  }
  std::vector<std::array<int32_t, 3>> a, b;
  a.reserve(static_cast<std::size_t>(ours.num_triangles()));
  for (int32_t t = 0; t < ours.num_triangles(); ++t) {
    a.push_back(Canonical(ours.triangles[3 * t], ours.triangles[3 * t + 1],
                          ours.triangles[3 * t + 2]));
  }
  b.reserve(dt.number_of_faces());
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    std::array<int32_t, 3> v;
    for (int i = 0; i < 3; ++i) {
      const auto& p = f->vertex(i)->point();
      v[i] = index_of.at(std::make_pair(p.x(), p.y()));
    }
    b.push_back(Canonical(v[0], v[1], v[2]));
  }
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::vector<std::array<int32_t, 3>> only_ours, only_cgal;
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(only_ours));
  std::set_difference(b.begin(), b.end(), a.begin(), a.end(), std::back_inserter(only_cgal));
  if (only_ours.empty() && only_cgal.empty()) return;
  // Cocircular inputs have several Delaunay triangulations; differing
  // tie-breaking is then legitimate and only worth a note.
  if (delaunay_is_unique) g_mismatch = true;
  std::fprintf(stderr,
               "%s: %s: %zu triangles only in surfreg, %zu only in CGAL "
               "(e.g. surfreg (%d %d %d))\n",
               delaunay_is_unique ? "WARNING" : "note", input.description.c_str(),
               only_ours.size(), only_cgal.size(),
               only_ours.empty() ? -1 : only_ours[0][0], only_ours.empty() ? -1 : only_ours[0][1],
               only_ours.empty() ? -1 : only_ours[0][2]);
}
#endif

// Triangulates once with each implementation (untimed) and compares.
void CheckOnce(Distribution d, Input& input) {
  if (input.checked) return;
  input.checked = true;
  Triangulation ours;
  try {
    ours = Triangulate(input.points);
  } catch (const std::exception& e) {
    input.error = input.description + ": Triangulate threw: " + e.what();
    std::fprintf(stderr, "ERROR: %s\n", input.error.c_str());
    g_mismatch = true;
    return;
  }
  input.surfreg_triangles = ours.num_triangles();
#ifdef SURFREG_HAVE_CGAL
  CgalDelaunay dt;
  dt.insert(input.cgal_points.begin(), input.cgal_points.end());
  input.cgal_triangles = static_cast<int64_t>(dt.number_of_faces());
  if (input.surfreg_triangles != input.cgal_triangles) {
    g_mismatch = true;
    std::fprintf(stderr,
                 "WARNING: triangle count mismatch on %s: surfreg %lld (%d duplicates merged), "
                 "CGAL %lld (%zu vertices)\n",
                 input.description.c_str(), static_cast<long long>(input.surfreg_triangles),
                 ours.num_duplicates, static_cast<long long>(input.cgal_triangles),
                 dt.number_of_vertices());
  }
  // Random real coordinates have no four cocircular points (almost surely):
  // there the Delaunay triangulation is unique and must match exactly.
  CompareTriangles(input, ours, dt, /*delaunay_is_unique=*/d != Distribution::kGrid);
#endif
}

// Generated once per (distribution, N) and kept for the whole run, so both
// implementations see the same memory and generation is never timed.
Input& GetInput(Distribution d, int64_t n) {
  static std::map<std::pair<Distribution, int64_t>, std::unique_ptr<Input>> cache;
  std::unique_ptr<Input>& slot = cache[{d, n}];
  if (slot) return *slot;
  slot = std::make_unique<Input>();
  Input& input = *slot;
  const int side = GridSide(n);
  char description[160];
  switch (d) {
    case Distribution::kUniform:
      input.points = testing::UniformPoints(static_cast<std::size_t>(n), kSeed);
      std::snprintf(description, sizeof description, "UniformPoints(%lld, seed=%#llx)",
                    static_cast<long long>(n), static_cast<unsigned long long>(kSeed));
      break;
    case Distribution::kJittered:
      input.points = testing::JitteredGridPoints(side, side, kJitter, kSeed);
      std::snprintf(description, sizeof description,
                    "JitteredGridPoints(%d, %d, jitter=%g, seed=%#llx)", side, side, kJitter,
                    static_cast<unsigned long long>(kSeed));
      break;
    case Distribution::kGrid:
      input.points = testing::GridPoints(side, side);
      std::snprintf(description, sizeof description, "GridPoints(%d, %d)", side, side);
      break;
  }
  input.description = description;
#ifdef SURFREG_HAVE_CGAL
  input.cgal_points.reserve(input.points.size());
  for (const Point2& p : input.points) input.cgal_points.emplace_back(p.x, p.y);
#endif
  CheckOnce(d, input);
  return input;
}

void SetCounters(benchmark::State& state, const Input& input, int64_t triangles) {
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(input.points.size()));
  state.counters["points"] = static_cast<double>(input.points.size());
  state.counters["triangles"] = static_cast<double>(triangles);
}

void BM_Surfreg(benchmark::State& state, Distribution d, int64_t n, int threads) {
  const Input& input = GetInput(d, n);
  if (!input.error.empty()) {
    state.SkipWithError(input.error.c_str());
    return;
  }
  DelaunayOptions options;
  options.execution = Execution{threads};
  for (auto _ : state) {
    Triangulation t = Triangulate(input.points, options);
    benchmark::DoNotOptimize(t.triangles.data());
    benchmark::ClobberMemory();
  }
  SetCounters(state, input, input.surfreg_triangles);
}

#ifdef SURFREG_HAVE_CGAL
void BM_Cgal(benchmark::State& state, Distribution d, int64_t n) {
  const Input& input = GetInput(d, n);
  for (auto _ : state) {
    CgalDelaunay dt;
    // Range insertion spatially sorts first, like our Triangulate.
    dt.insert(input.cgal_points.begin(), input.cgal_points.end());
    benchmark::DoNotOptimize(dt.number_of_vertices());
    benchmark::ClobberMemory();
  }
  SetCounters(state, input, input.cgal_triangles);
}
#endif

void Configure(benchmark::internal::Benchmark* b, int64_t n) {
  b->Unit(benchmark::kMillisecond);
  // Wall time, but not at 1e4: UseRealTime appends "/real_time" to the name
  // and the smoke test selects the small rows with the filter '/10000$'.
  // Single-threaded, so CPU and wall time agree there anyway.
  if (n >= 100000) b->UseRealTime();
  // A second or more per iteration at 1e6: a few are enough, and keep the
  // full run within minutes.
  if (n >= 1000000) b->Iterations(3);
}

void RegisterAll() {
  const int64_t sizes[] = {10000, 100000, 1000000};
  const Distribution distributions[] = {Distribution::kUniform, Distribution::kJittered,
                                        Distribution::kGrid};
  for (Distribution d : distributions) {
    for (int64_t n : sizes) {
      const std::string suffix =
          std::string("/") + DistributionName(d) + "/" + std::to_string(n);
      Configure(benchmark::RegisterBenchmark(("BM_Triangulate/surfreg" + suffix).c_str(),
                                             BM_Surfreg, d, n, 1),
                n);
      // The slab build on two threads (large inputs only; the arrays are
      // the same as on one).
      if (n >= 1000000) {
        Configure(benchmark::RegisterBenchmark(("BM_Triangulate/surfreg-2threads" + suffix).c_str(),
                                               BM_Surfreg, d, n, 2),
                  n);
      }
#ifdef SURFREG_HAVE_CGAL
      Configure(benchmark::RegisterBenchmark(("BM_Triangulate/cgal" + suffix).c_str(),
                                             BM_Cgal, d, n),
                n);
#endif
    }
  }
}

}  // namespace
}  // namespace surfreg

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  surfreg::RegisterAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return surfreg::g_mismatch ? 2 : 0;
}
