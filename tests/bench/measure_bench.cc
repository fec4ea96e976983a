// Throughput of the whole comparison, surfreg::Measure, stage by stage, and
// against CGAL's Delaunay_triangulation_2 of the union A ∪ B when CGAL is
// available (the peer: the whole measure should take at most 3x the
// time CGAL needs to triangulate the 2N points of both clouds, at N = 1e6).
//
// Inputs: two clouds A and B of N points each in the unit square,
//   uniform:  UniformPoints(N), A and B with different seeds;
//   jittered: JitteredGridPoints(sqrt(N), sqrt(N), 0.25), scaled to the unit
//             square; B with another seed and shifted by half a cell in x and
//             y, so that no two grids share their nodes.
// Heights: A z = sin(6x) cos(5y); B the same + 0.01 + 0.02 x, so the gap
// d = F̂_B − F̂_A is about 0.01 + 0.02 x (mean about 0.02 over the square).
//
// Names: BM_Stage/<stage>/<distribution>/<N> for the stages of Measure in
// its order (triangulate, domain, spanning_tree, locate, interpolate,
// overlay, union), each on both clouds, with the inputs and every earlier stage
// prepared outside the timed loop exactly as Measure prepares them (points
// in A's frame, sorted by SpatialOrder(xy, false, 0));
// BM_Measure/<impl>/<distribution>/<N>, impl surfreg (the whole
// Measure(a, b) on Surfaces from MakeSurface of the unsorted points: what a
// user calls) or cgal_union_triangulation. items_per_second counts the 2N
// input points of both clouds in every row, so all rows are comparable.
//
// Checks (untimed): Measure's mean |d| must be about 0.02, and its ρd must
// equal the overlay stage's on the same input. A failure is printed to
// stderr and makes the exit status 2, so a filtered run doubles as a smoke
// test.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#ifdef SURFREG_HAVE_CGAL
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#endif

#include "measure/delaunay.h"
#include "measure/gap_volume.h"
#include "measure/locator.h"
#include "measure/measures.h"
#include "measure/spanning_tree.h"
#include "measure/spatial_sort.h"
#include "measure/surface.h"
#include "measure/weights.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

#ifdef SURFREG_HAVE_CGAL
using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalDelaunay = CGAL::Delaunay_triangulation_2<CgalKernel>;
#endif

enum class Distribution { kUniform, kJittered };

constexpr uint64_t kSeedA = 0x5eed2d;  // A's as in delaunay_bench
constexpr uint64_t kSeedB = 0xb0b2d;
constexpr double kJitter = 0.25;  // fraction of the grid step
constexpr double kExpectedMeanGap = 0.02;
constexpr double kMeanGapTolerance = 0.05;  // relative

// benchmark::DoNotOptimize on a non-const lvalue uses the asm constraint
// "+m,r", with which GCC 12 and Google Benchmark 1.7.1 can clobber a double
// (seen here: a VolumeResult's ρd read back as garbage). The const overload
// only reads its argument, so every use goes through this.
template <class T>
BENCHMARK_ALWAYS_INLINE inline void Keep(const T& value) {
  benchmark::DoNotOptimize(value);
}

const char* DistributionName(Distribution d) {
  return d == Distribution::kUniform ? "uniform" : "jittered";
}

int GridSide(int64_t n) { return static_cast<int>(std::lround(std::sqrt(static_cast<double>(n)))); }

double HeightA(double x, double y) { return std::sin(6.0 * x) * std::cos(5.0 * y); }
double HeightB(double x, double y) { return HeightA(x, y) + 0.01 + 0.02 * x; }

// One cloud in input coordinates, as a user would hand it to MakeSurface.
std::vector<std::array<double, 3>> MakeCloud(Distribution d, int64_t n, bool is_b) {
  std::vector<Point2> xy;
  if (d == Distribution::kUniform) {
    xy = testing::UniformPoints(static_cast<std::size_t>(n), is_b ? kSeedB : kSeedA);
  } else {
    const int side = GridSide(n);
    const double h = 1.0 / side;
    const double offset = is_b ? 0.75 : 0.25;  // half a cell apart, both inside [0, 1]
    xy = testing::JitteredGridPoints(side, side, kJitter, is_b ? kSeedB : kSeedA);
    for (Point2& p : xy) p = {(p.x + offset) * h, (p.y + offset) * h};
  }
  std::vector<std::array<double, 3>> points(xy.size());
  for (std::size_t i = 0; i < xy.size(); ++i) {
    points[i] = {xy[i].x, xy[i].y, is_b ? HeightB(xy[i].x, xy[i].y) : HeightA(xy[i].x, xy[i].y)};
  }
  return points;
}

// A surface as Measure prepares it (measures.cc, Prepared): in A's frame,
// sorted spatially, then its mesh, data domain and EMST.
struct Prepared {
  std::vector<Point2> xy;
  std::vector<double> z;
  Triangulation mesh;
  MeshDomain domain;
  SpanningTree tree;
};

// The same permutation as measures.cc's SortSpatially.
void SortSpatially(Prepared& s) {
  const std::vector<int32_t> order = SpatialOrder(s.xy, /*brio=*/false, 0);
  std::vector<Point2> xy(s.xy.size());
  std::vector<double> z(s.z.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    xy[k] = s.xy[order[k]];
    z[k] = s.z[order[k]];
  }
  s.xy.swap(xy);
  s.z.swap(z);
}

// F̂ at a located point, as in measures.cc.
double Interpolate(const Triangulation& mesh, const std::vector<double>& values, const Location& l) {
  const int32_t* v = &mesh.triangles[3 * l.triangle];
  return l.barycentric[0] * values[v[0]] + l.barycentric[1] * values[v[1]] +
         l.barycentric[2] * values[v[2]];
}

// Measure's interpolate stage: μ, the nodes in Ω, then the gap at every
// node inside Ω (each distinct vertex once) and ρ'd. Same loop as measures.cc.
double NodeGapsAndAxial(const Surface& a, const Prepared& pa, const Prepared& pb,
                        const std::vector<Location>& a_in_b, const std::vector<Location>& b_in_a,
                        const MeasureOptions& options, WeightField* mu, NodeGaps* gaps,
                        std::vector<uint8_t>* omega_a, std::vector<uint8_t>* omega_b) {
  static const std::vector<double> kNoWeights;
  *mu = MakeWeightField(options, a, pa.xy, pa.mesh, kNoWeights, pb.xy, pb.mesh, kNoWeights, a_in_b,
                        b_in_a);
  gaps->a.assign(pa.xy.size(), 0.0);
  gaps->b.assign(pb.xy.size(), 0.0);
  omega_a->assign(pa.xy.size(), 0);
  omega_b->assign(pb.xy.size(), 0);
  for (std::size_t i = 0; i < pa.xy.size(); ++i) {
    (*omega_a)[i] = a_in_b[i].found() && pa.domain.vertices[pa.mesh.vertex_of_input[i]] &&
                    pb.domain.Contains(pb.mesh, a_in_b[i]);
  }
  for (std::size_t j = 0; j < pb.xy.size(); ++j) {
    (*omega_b)[j] = b_in_a[j].found() && pb.domain.vertices[pb.mesh.vertex_of_input[j]] &&
                    pa.domain.Contains(pa.mesh, b_in_a[j]);
  }
  double gap_sum = 0.0, node_weight = 0.0;
  int64_t overlap_nodes = 0;
  for (std::size_t i = 0; i < pa.xy.size(); ++i) {
    if (!a_in_b[i].found()) continue;
    gaps->a[i] = Interpolate(pb.mesh, pb.z, a_in_b[i]) - pa.z[i];
    if (!(*omega_a)[i] || pa.mesh.vertex_of_input[i] != static_cast<int32_t>(i)) continue;
    const double w = mu->AtNodeA(i);
    gap_sum += w * std::fabs(gaps->a[i]);
    node_weight += w;
    ++overlap_nodes;
  }
  for (std::size_t j = 0; j < pb.xy.size(); ++j) {
    if (!b_in_a[j].found()) continue;
    gaps->b[j] = pb.z[j] - Interpolate(pa.mesh, pa.z, b_in_a[j]);
    if (!(*omega_b)[j] || pb.mesh.vertex_of_input[j] != static_cast<int32_t>(j)) continue;
    if (b_in_a[j].where == Where::kOnVertex) continue;
    const double w = mu->AtNodeB(j);
    gap_sum += w * std::fabs(gaps->b[j]);
    node_weight += w;
    ++overlap_nodes;
  }
  Keep(overlap_nodes);
  return node_weight > 0.0 ? gap_sum / node_weight : 0.0;
}

// One input pair and the stages prepared on it so far.
struct Input {
  Distribution distribution = Distribution::kUniform;
  int64_t n = 0;
  std::string description;  // names the exact input in messages
  Surface a, b;             // MakeSurface of the unsorted clouds
  int64_t total_points = 0;
#ifdef SURFREG_HAVE_CGAL
  std::vector<CgalKernel::Point_2> cgal_union;  // A's points then B's, input coordinates
#endif
  // Stages prepared as in Measure, each on demand, in this order.
  enum Level { kSorted, kMeshes, kDomains, kTrees, kLocations, kGaps };
  int level = kSorted;
  Prepared pa, pb;
  std::vector<Location> a_in_b, b_in_a;
  WeightField mu;
  NodeGaps gaps;
  std::vector<uint8_t> omega_a, omega_b;  // the nodes in Ω
  MeasureOptions options;  // defaults: overlay volume, uniform μ
  double overlay_rho_d = -1.0;  // from the overlay stage, for the cross-check
  std::string error;            // a stage threw: the rows of this input are skipped
};

bool g_failed = false;  // a check failed: exit status 2

void Fail(const std::string& message) {
  std::fprintf(stderr, "ERROR: %s\n", message.c_str());
  g_failed = true;
}

// Builds (untimed) the stages up to `level`.
void Prepare(Input& input, int level) {
  if (!input.error.empty()) return;
  try {
    if (input.level < Input::kMeshes && level >= Input::kMeshes) {
      input.pa.mesh = Triangulate(input.pa.xy);
      input.pb.mesh = Triangulate(input.pb.xy);
      // Random real coordinates: no duplicates, so Measure's height merge
      // (MergeDuplicateHeights) is a no-op and is not repeated here.
      if (input.pa.mesh.num_duplicates != 0 || input.pb.mesh.num_duplicates != 0) {
        Fail(input.description + ": unexpected duplicate points");
      }
      input.level = Input::kMeshes;
    }
    if (input.level < Input::kDomains && level >= Input::kDomains) {
      input.pa.domain = MakeMeshDomain(input.pa.xy, input.pa.mesh, input.options.domain);
      input.pb.domain = MakeMeshDomain(input.pb.xy, input.pb.mesh, input.options.domain);
      input.level = Input::kDomains;
    }
    if (input.level < Input::kTrees && level >= Input::kTrees) {
      input.pa.tree = EuclideanMst(input.pa.xy, input.pa.mesh);
      input.pb.tree = EuclideanMst(input.pb.xy, input.pb.mesh);
      input.level = Input::kTrees;
    }
    if (input.level < Input::kLocations && level >= Input::kLocations) {
      const Prepared& pa = input.pa;
      const Prepared& pb = input.pb;
      input.a_in_b = LocateAll(pb.xy, pb.mesh, pa.xy, pa.mesh, pa.tree);
      input.b_in_a = LocateAll(pa.xy, pa.mesh, pb.xy, pb.mesh, pb.tree);
      input.level = Input::kLocations;
    }
    if (input.level < Input::kGaps && level >= Input::kGaps) {
      NodeGapsAndAxial(input.a, input.pa, input.pb, input.a_in_b, input.b_in_a, input.options,
                       &input.mu, &input.gaps, &input.omega_a, &input.omega_b);
      input.level = Input::kGaps;
    }
  } catch (const std::exception& e) {
    input.error = input.description + ": preparing a stage threw: " + e.what();
    Fail(input.error);
  }
}

// Generated once per (distribution, N). Benchmarks are registered input by
// input, so only the current input is kept: at 1e6 one input with all its
// stages and a Measure running on it bring the process to about 0.7 GB.
Input& GetInput(Distribution d, int64_t n) {
  static std::unique_ptr<Input> cache;
  if (cache && cache->distribution == d && cache->n == n) return *cache;
  cache.reset();
  cache = std::make_unique<Input>();
  Input& input = *cache;
  input.distribution = d;
  input.n = n;
  char description[160];
  if (d == Distribution::kUniform) {
    std::snprintf(description, sizeof description,
                  "uniform: UniformPoints(%lld) seeds %#llx (A), %#llx (B)",
                  static_cast<long long>(n), static_cast<unsigned long long>(kSeedA),
                  static_cast<unsigned long long>(kSeedB));
  } else {
    const int side = GridSide(n);
    std::snprintf(description, sizeof description,
                  "jittered: JitteredGridPoints(%d, %d, %g) seeds %#llx (A), %#llx (B, shifted "
                  "half a cell)",
                  side, side, kJitter, static_cast<unsigned long long>(kSeedA),
                  static_cast<unsigned long long>(kSeedB));
  }
  input.description = description;
  {
    const std::vector<std::array<double, 3>> cloud_a = MakeCloud(d, n, false);
    const std::vector<std::array<double, 3>> cloud_b = MakeCloud(d, n, true);
    input.a = MakeSurface(cloud_a, {}, "A");
    input.b = MakeSurface(cloud_b, {}, "B");
    input.total_points = static_cast<int64_t>(cloud_a.size() + cloud_b.size());
#ifdef SURFREG_HAVE_CGAL
    input.cgal_union.reserve(cloud_a.size() + cloud_b.size());
    for (const auto& p : cloud_a) input.cgal_union.emplace_back(p[0], p[1]);
    for (const auto& p : cloud_b) input.cgal_union.emplace_back(p[0], p[1]);
#endif
  }
  // As Measure: B in A's frame, then both in Hilbert order.
  input.pa.xy = input.a.xy;
  input.pa.z = input.a.z;
  input.pb.xy = input.b.xy;
  input.pb.z = input.b.z;
  const double shift[3] = {input.b.origin[0] - input.a.origin[0],
                           input.b.origin[1] - input.a.origin[1],
                           input.b.origin[2] - input.a.origin[2]};
  for (Point2& p : input.pb.xy) p = {p.x + shift[0], p.y + shift[1]};
  for (double& z : input.pb.z) z += shift[2];
  SortSpatially(input.pa);
  SortSpatially(input.pb);
  return input;
}

// Looks up the input, prepares the stages before the timed one, and reports
// whether the benchmark can run.
Input* Setup(benchmark::State& state, Distribution d, int64_t n, int level) {
  Input& input = GetInput(d, n);
  Prepare(input, level);
  if (!input.error.empty()) {
    state.SkipWithError(input.error.c_str());
    return nullptr;
  }
  return &input;
}

void SetCounters(benchmark::State& state, const Input& input) {
  // Both clouds' points in every row, so items_per_second compares across rows.
  state.SetItemsProcessed(state.iterations() * input.total_points);
  state.counters["points"] = static_cast<double>(input.total_points);
}

void BM_Triangulate(benchmark::State& state, Distribution d, int64_t n) {
  Input* input = Setup(state, d, n, Input::kSorted);
  if (!input) return;
  for (auto _ : state) {
    Triangulation ta = Triangulate(input->pa.xy);
    Triangulation tb = Triangulate(input->pb.xy);
    Keep(ta.triangles.data());
    Keep(tb.triangles.data());
    benchmark::ClobberMemory();
  }
  SetCounters(state, *input);
}

void BM_Domain(benchmark::State& state, Distribution d, int64_t n) {
  Input* input = Setup(state, d, n, Input::kMeshes);
  if (!input) return;
  for (auto _ : state) {
    MeshDomain da = MakeMeshDomain(input->pa.xy, input->pa.mesh, input->options.domain);
    MeshDomain db = MakeMeshDomain(input->pb.xy, input->pb.mesh, input->options.domain);
    Keep(da.triangles.data());
    Keep(db.triangles.data());
    benchmark::ClobberMemory();
  }
  SetCounters(state, *input);
}

void BM_SpanningTree(benchmark::State& state, Distribution d, int64_t n) {
  Input* input = Setup(state, d, n, Input::kDomains);
  if (!input) return;
  for (auto _ : state) {
    SpanningTree ta = EuclideanMst(input->pa.xy, input->pa.mesh);
    SpanningTree tb = EuclideanMst(input->pb.xy, input->pb.mesh);
    Keep(ta.order.data());
    Keep(tb.order.data());
    benchmark::ClobberMemory();
  }
  SetCounters(state, *input);
}

void BM_Locate(benchmark::State& state, Distribution d, int64_t n) {
  Input* input = Setup(state, d, n, Input::kTrees);
  if (!input) return;
  const Prepared& pa = input->pa;
  const Prepared& pb = input->pb;
  int64_t steps = 0;
  for (auto _ : state) {
    LocateAllStats stats_a, stats_b;
    std::vector<Location> a_in_b = LocateAll(pb.xy, pb.mesh, pa.xy, pa.mesh, pa.tree, &stats_a);
    std::vector<Location> b_in_a = LocateAll(pa.xy, pa.mesh, pb.xy, pb.mesh, pb.tree, &stats_b);
    Keep(a_in_b.data());
    Keep(b_in_a.data());
    benchmark::ClobberMemory();
    steps = stats_a.steps + stats_b.steps;
  }
  SetCounters(state, *input);
  // Triangles visited per located point: O(1) means the EMST order works.
  state.counters["steps_per_point"] = static_cast<double>(steps) / input->total_points;
}

void BM_Interpolate(benchmark::State& state, Distribution d, int64_t n) {
  Input* input = Setup(state, d, n, Input::kLocations);
  if (!input) return;
  double axial = 0.0;
  for (auto _ : state) {
    WeightField mu;
    NodeGaps gaps;
    std::vector<uint8_t> omega_a, omega_b;
    axial = NodeGapsAndAxial(input->a, input->pa, input->pb, input->a_in_b, input->b_in_a,
                             input->options, &mu, &gaps, &omega_a, &omega_b);
    Keep(axial);
    Keep(gaps.a.data());
    Keep(gaps.b.data());
    benchmark::ClobberMemory();
  }
  SetCounters(state, *input);
  state.counters["rho_d_axial"] = axial;
}

OmegaDomains Omega(const Input& input) {
  return {&input.pa.domain, &input.pb.domain, &input.omega_a, &input.omega_b};
}

void BM_Overlay(benchmark::State& state, Distribution d, int64_t n) {
  Input* input = Setup(state, d, n, Input::kGaps);
  if (!input) return;
  const Prepared& pa = input->pa;
  const Prepared& pb = input->pb;
  VolumeResult volume;
  for (auto _ : state) {
    volume = OverlayVolume(pa.xy, pa.mesh, pa.z, input->a_in_b, pb.xy, pb.mesh, pb.z,
                           input->b_in_a, input->mu, Execution{1}, -1.0, Omega(*input));
    Keep(volume.gap.abs);
    benchmark::ClobberMemory();
  }
  input->overlay_rho_d = volume.gap.abs;
  SetCounters(state, *input);
  state.counters["cells"] = static_cast<double>(volume.cells);
  state.counters["rho_d"] = volume.gap.abs;
}

void BM_Union(benchmark::State& state, Distribution d, int64_t n) {
  Input* input = Setup(state, d, n, Input::kGaps);
  if (!input) return;
  const Prepared& pa = input->pa;
  const Prepared& pb = input->pb;
  VolumeResult volume;
  for (auto _ : state) {
    volume = UnionVolume(pa.xy, pa.mesh, input->a_in_b, input->gaps.a, pb.xy, pb.mesh,
                         input->b_in_a, input->gaps.b, input->mu, Omega(*input));
    Keep(volume.gap.abs);
    benchmark::ClobberMemory();
  }
  SetCounters(state, *input);
  state.counters["cells"] = static_cast<double>(volume.cells);
  state.counters["rho_d"] = volume.gap.abs;
}

// Untimed checks of a whole Measure result.
void CheckSummary(const Input& input, const MeasureSummary& s) {
  char text[320];
  if (!(std::fabs(s.mean_abs_dz - kExpectedMeanGap) <= kMeanGapTolerance * kExpectedMeanGap)) {
    std::snprintf(text, sizeof text,
                  "%s N=%lld: Measure's mean |d| = %.6g, expected about %g (+-%g%%)",
                  input.description.c_str(), static_cast<long long>(input.n), s.mean_abs_dz,
                  kExpectedMeanGap, 100.0 * kMeanGapTolerance);
    Fail(text);
  }
  if (s.n_points_a + s.n_points_b != input.total_points) {
    Fail(input.description + ": Measure counted a different number of points");
  }
  // Same data, same order, same code: the overlay stage must agree exactly
  // (up to the last bits, if the compiler reassociates nothing).
  if (input.overlay_rho_d >= 0.0 &&
      !(std::fabs(s.rho_d - input.overlay_rho_d) <= 1e-12 * std::fabs(input.overlay_rho_d))) {
    std::snprintf(text, sizeof text,
                  "%s N=%lld: Measure's rho_d = %.17g but the overlay stage gave %.17g",
                  input.description.c_str(), static_cast<long long>(input.n), s.rho_d,
                  input.overlay_rho_d);
    Fail(text);
  }
}

void MeasureSurfreg(benchmark::State& state, Distribution d, int64_t n, bool parallel) {
  Input* input = Setup(state, d, n, Input::kSorted);
  if (!input) return;
  MeasureSummary summary;
  MeasureOptions options;
  options.threads = parallel ? 2 : 1;
  try {
    for (auto _ : state) {
      summary = Measure(input->a, input->b, options);
      Keep(summary.rho_d);
      benchmark::ClobberMemory();
    }
  } catch (const std::exception& e) {
    const std::string message = input->description + ": Measure threw: " + e.what();
    Fail(message);
    state.SkipWithError(message.c_str());
    return;
  }
  CheckSummary(*input, summary);
  SetCounters(state, *input);
  state.counters["rho_d"] = summary.rho_d;
  state.counters["mean_abs_dz"] = summary.mean_abs_dz;
  // Measure's own stage timings (last iteration, seconds), to compare with
  // the BM_Stage rows.
  state.counters["t_triangulate"] = summary.timings.triangulate;
  state.counters["t_domain"] = summary.timings.domain;
  state.counters["t_spanning_tree"] = summary.timings.spanning_tree;
  state.counters["t_locate"] = summary.timings.locate;
  state.counters["t_interpolate"] = summary.timings.interpolate;
  state.counters["t_volume"] = summary.timings.volume;
  state.counters["t_total"] = summary.timings.total;
}

// The default: two threads (A's and B's stages side by side, the overlay in
// two halves). Wall time is what a user waits; CPU time here is the calling
// thread's only.
void BM_MeasureSurfreg(benchmark::State& state, Distribution d, int64_t n) {
  MeasureSurfreg(state, d, n, /*parallel=*/true);
}

// One thread, like the CGAL row.
void BM_MeasureSurfregSerial(benchmark::State& state, Distribution d, int64_t n) {
  MeasureSurfreg(state, d, n, /*parallel=*/false);
}

#ifdef SURFREG_HAVE_CGAL
void BM_MeasureCgal(benchmark::State& state, Distribution d, int64_t n) {
  Input* input = Setup(state, d, n, Input::kSorted);
  if (!input) return;
  std::size_t faces = 0;
  for (auto _ : state) {
    CgalDelaunay dt;
    // Range insertion spatially sorts first, like our Triangulate.
    dt.insert(input->cgal_union.begin(), input->cgal_union.end());
    faces = dt.number_of_faces();
    Keep(faces);
    benchmark::ClobberMemory();
  }
  SetCounters(state, *input);
  state.counters["triangles"] = static_cast<double>(faces);
}
#endif

void Configure(benchmark::internal::Benchmark* b, int64_t n) {
  b->Unit(benchmark::kMillisecond);
  // Wall time, but not at 1e4: UseRealTime appends "/real_time" to the name
  // and the smoke test selects the small rows with the filter '/10000$'.
  // Single-threaded, so CPU and wall time agree there anyway.
  if (n >= 100000) b->UseRealTime();
  // Seconds per iteration at 1e6: a few are enough, and keep the full run
  // within minutes.
  if (n >= 1000000) b->Iterations(3);
}

using Function = void (*)(benchmark::State&, Distribution, int64_t);

void RegisterAll() {
  const int64_t sizes[] = {10000, 100000, 1000000};
  const Distribution distributions[] = {Distribution::kUniform, Distribution::kJittered};
  const std::pair<const char*, Function> stages[] = {
      {"BM_Stage/triangulate", BM_Triangulate}, {"BM_Stage/domain", BM_Domain},
      {"BM_Stage/spanning_tree", BM_SpanningTree},
      {"BM_Stage/locate", BM_Locate},           {"BM_Stage/interpolate", BM_Interpolate},
      {"BM_Stage/overlay", BM_Overlay},         {"BM_Stage/union", BM_Union},
      {"BM_Measure/surfreg", BM_MeasureSurfreg},
      {"BM_Measure/surfreg_serial", BM_MeasureSurfregSerial},
#ifdef SURFREG_HAVE_CGAL
      {"BM_Measure/cgal_union_triangulation", BM_MeasureCgal},
#endif
  };
  // Input by input (GetInput keeps only the current one), stages in order.
  for (Distribution d : distributions) {
    for (int64_t n : sizes) {
      const std::string suffix =
          std::string("/") + DistributionName(d) + "/" + std::to_string(n);
      for (const auto& [name, function] : stages) {
        Configure(benchmark::RegisterBenchmark((name + suffix).c_str(), function, d, n), n);
      }
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
  return surfreg::g_failed ? 2 : 0;
}
