// Cost of re-measuring during registration (docs/method.md, How a registration runs): a PairState that
// moves B by a solver-sized step and re-locates by walking from the previous
// locations must be at least 10x faster than a full Measure; a whole axial
// Align of two 1e5-point clouds should take less than 20 full measures.
//
// Input: two different random samplings (seeds kSeedA, kSeedB) of
// testing::SmoothTerrain on [0, 100]², N points each; B is moved by the
// inverse of a known motion (kAngleDeg about kAxis through B's centroid,
// then kShiftSpacings mean spacings), so θ_true brings it back onto A.
//
// Rows (N last before the suffixes, all wall time):
//   BM_Remeasure/<work>/<step>/<N>: a PairState located at θ_true, each
//     iteration Update to the other of θ_true and θ_true + δ (every Update
//     is a real move), then <work>;
//   BM_Scratch/<work>/<step>/<N>: a fresh PairState (built untimed) whose
//     first Update at θ_true + δ locates everything (LocateAll), then <work>;
//     B carries the mesh the located state has at θ_true, so nothing is
//     re-triangulated; BM_ScratchOwnMesh/update/...: the same from B's own
//     mesh, as each new state in Align starts (slivers that fold at the pose
//     make it re-triangulate B first: counter remeshes_per_update);
//   BM_Measure/<threads>/<N>: Measure(A, B moved by θ_true + δ_large),
//     default options (2t) and parallel = false (1t);
//   BM_Align/<cost>/<N>: Align from the identity, axial cost, the
//     defaults (volume cost after an axial prealign), or the defaults with
//     the information standard deviations (`information`: the sandwich's
//     own cost is the difference from `default`).
// <work>: update (Update only), axial (+ ComputeAxialResiduals with
// Jacobians), volume_1t / volume_2t (+ EvaluateVolumeCost with gradient),
// volinc_1t / volinc_2t (+ VolumeCostCache::Evaluate with gradient: the
// incremental re-measure Align's volume solver uses; counters
// searched_fraction = A triangles searched again / all, full_builds_per_eval),
// volval_1t (the same, value only: the re-measure proper, as Measure
// computes no gradient).
// <step>: small (δ = 1e-4 rad, 0.01 spacing), large (1e-3 rad, 0.1 spacing),
// solver (1e-6 rad, 1e-3 spacing; BM_Remeasure only).
//
// Checks (untimed; a failure prints ERROR and makes the exit status 2): every
// Update succeeds; the volume cost per area and the mean |r| of the axial
// residuals at θ_true + δ_large agree with Measure's mean |d| and ρ'd there
// (loosely: Measure re-triangulates B, the state keeps B's own mesh); Align
// ends within 0.1° and 0.5 spacing of the known motion (a verdict other than
// converged is only printed as a NOTE).
//
// N = 1e4 and 1e5; the flag --with_1e6 adds N = 1e6 (Align only at 1e5).
// The context line cell_kernel names the volume cost's cell kernel
// (SURFREG_CELL_KERNEL = scalar, avx2 or avx512 picks one; default the best
// this CPU runs).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "measure/measures.h"
#include "measure/surface.h"
#include "registration/align.h"
#include "registration/axial_cost.h"
#include "registration/gap_weight.h"
#include "registration/pair_state.h"
#include "registration/rigid_motion.h"
#include "registration/volume_cost/volume_cost.h"
#include "registration/volume_cost/volume_kernel_simd.h"
#include "tests/testing/surface_pairs.h"

namespace surfreg {

// The cell kernel benchmarked: SURFREG_CELL_KERNEL (scalar, avx2, avx512),
// else the best this CPU runs.
CellKernelChoice BenchKernel() {
  CellKernelChoice choice = CellKernelChoice::kBest;
  const char* name = std::getenv("SURFREG_CELL_KERNEL");
  if (name != nullptr && !ParseCellKernel(name, &choice)) std::fprintf(stderr, "unknown SURFREG_CELL_KERNEL=%s\n", name);
  return choice;
}

namespace {

// benchmark::DoNotOptimize on a non-const lvalue can clobber a double with
// GCC 12 and Google Benchmark 1.7.1 (see measure_bench.cc): always const.
template <class T>
BENCHMARK_ALWAYS_INLINE inline void Keep(const T& value) {
  benchmark::DoNotOptimize(value);
}

constexpr uint64_t kSeedA = 0xa1165eed;
constexpr uint64_t kSeedB = 0xb2265eed;
constexpr double kSide = 100.0;  // SmoothTerrain's square
constexpr double kAngleDeg = 2.0;
const Eigen::Vector3d kAxis(1.0, -2.0, 0.5);
const Eigen::Vector3d kShiftSpacings(3.0, -2.0, 1.0);
// Directions of δ: all six parameters move.
const Eigen::Vector3d kStepAxis = Eigen::Vector3d(1.0, -1.0, 0.5).normalized();
const Eigen::Vector3d kStepShift = Eigen::Vector3d(1.0, 2.0, -1.0).normalized();

struct Step {
  const char* name;
  double radians;   // |δω|
  double spacings;  // |δt| in mean spacings
};
// "solver": about 3× the median accepted step of the volume solver on the
// peer pairs (3–4e-4 spacing; README), BM_Remeasure rows only.
constexpr Step kSteps[] = {{"small", 1e-4, 0.01}, {"large", 1e-3, 0.1}, {"solver", 1e-6, 1e-3}};
constexpr int kNumSteps = 3;
constexpr int kSolverStep = 2;
constexpr int kMeasureStep = 1;  // BM_Measure's pose: θ_true + δ_large

enum class Work { kUpdate, kAxial, kVolume1, kVolume2, kIncremental1, kIncremental2, kValue1 };
const char* WorkName(Work w) {
  switch (w) {
    case Work::kUpdate: return "update";
    case Work::kAxial: return "axial";
    case Work::kVolume1: return "volume_1t";
    case Work::kVolume2: return "volume_2t";
    case Work::kIncremental1: return "volinc_1t";
    case Work::kIncremental2: return "volinc_2t";
    case Work::kValue1: return "volval_1t";
  }
  return "?";
}

bool g_failed = false;

void Fail(const std::string& message) {
  std::fprintf(stderr, "ERROR: %s\n", message.c_str());
  g_failed = true;
}

using Theta = std::array<double, 6>;

// One input pair, prepared as Align prepares its finest level.
struct Pair {
  int64_t n = 0;
  double spacing = 0;  // mean sample spacing, kSide / sqrt(N)
  Surface reference, moving;
  Eigen::Matrix4d truth;             // moving → reference, input coordinates
  Eigen::Vector3d moving_centroid;   // input coordinates
  ReferenceSide ref;
  MovingSide mov;
  // B with the mesh a state holds after its first Update at θ_true (B's own
  // mesh, re-triangulated there if slivers fold) and that mesh's EMST: fresh
  // states from it locate without re-triangulating.
  MovingSide mov_at_pose;
  Theta theta_true{};
  Theta theta_step[kNumSteps]{};     // θ_true + δ for each step
  Surface moved;                     // B moved by θ_true + δ_large (BM_Measure)
  int64_t nodes = 0;                 // A's and B's nodes
  std::string error;
};

Theta Plus(const Theta& theta, const Step& step, double spacing) {
  Theta out = theta;
  for (int k = 0; k < 3; ++k) {
    out[k] += step.radians * kStepAxis[k];
    out[3 + k] += step.spacings * spacing * kStepShift[k];
  }
  return out;
}

// θ as the moving → reference matrix in input coordinates (as align.cc).
Eigen::Matrix4d MatrixOf(const Pair& p, const Theta& theta) {
  const Eigen::Matrix3d r = RotationMatrix({theta[0], theta[1], theta[2]});
  const Eigen::Vector3d origin(p.reference.origin[0], p.reference.origin[1], p.reference.origin[2]);
  const Eigen::Vector3d centre = p.mov.centroid + origin;
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = centre + Eigen::Vector3d(theta[3], theta[4], theta[5]) - r * centre;
  return m;
}

Pair& GetPair(int64_t n) {
  static std::unique_ptr<Pair> cache;
  if (cache && cache->n == n) return *cache;
  cache.reset();
  cache = std::make_unique<Pair>();
  Pair& p = *cache;
  p.n = n;
  try {
    p.spacing = kSide / std::sqrt(static_cast<double>(n));
    const auto a = testing::SampleUniform(testing::SmoothTerrain, static_cast<std::size_t>(n), 0,
                                          kSide, 0, kSide, kSeedA);
    const auto b = testing::SampleUniform(testing::SmoothTerrain, static_cast<std::size_t>(n), 0,
                                          kSide, 0, kSide, kSeedB);
    p.truth = testing::TrueMotion(kAxis, kAngleDeg, kShiftSpacings * p.spacing, testing::Centroid(b));
    const auto moved = testing::MoveByInverse(b, p.truth);
    p.moving_centroid = testing::Centroid(moved);
    p.reference = MakeSurface(a, {}, "A");
    p.moving = MakeSurface(moved, {}, "B");
    const std::array<double, 3> shift = {p.moving.origin[0] - p.reference.origin[0],
                                         p.moving.origin[1] - p.reference.origin[1],
                                         p.moving.origin[2] - p.reference.origin[2]};
    p.ref = PrepareReference(p.reference);
    p.mov = PrepareMoving(p.moving, shift);
    p.nodes = static_cast<int64_t>(p.ref.xy.size() + p.mov.points.size());
    // θ_true about B's centroid c (A's local frame): ω = angle · axis,
    // t = T_true(c) − c.
    const Eigen::Vector3d omega = kAxis.normalized() * (kAngleDeg * M_PI / 180.0);
    const Eigen::Vector3d origin(p.reference.origin[0], p.reference.origin[1], p.reference.origin[2]);
    const Eigen::Vector3d c_input = p.mov.centroid + origin;
    const Eigen::Vector3d t =
        (p.truth * c_input.homogeneous()).head<3>() - c_input;
    p.theta_true = {omega[0], omega[1], omega[2], t[0], t[1], t[2]};
    for (int s = 0; s < kNumSteps; ++s) p.theta_step[s] = Plus(p.theta_true, kSteps[s], p.spacing);
    p.moved = TransformSurface(p.moving, MatrixOf(p, p.theta_step[kMeasureStep]));
    PairState at_pose(p.ref, p.mov);
    if (!at_pose.Update(p.theta_true)) throw std::runtime_error("Update to θ_true folds B");
    p.mov_at_pose = p.mov;
    p.mov_at_pose.mesh = at_pose.moving_mesh();
    p.mov_at_pose.tree = EuclideanMst(at_pose.moved_xy(), at_pose.moving_mesh());
  } catch (const std::exception& e) {
    p.error = "N=" + std::to_string(n) + ": preparing the pair threw: " + e.what();
    Fail(p.error);
  }
  return p;
}

Pair* Setup(benchmark::State& state, int64_t n) {
  Pair& p = GetPair(n);
  if (!p.error.empty()) {
    state.SkipWithError(p.error.c_str());
    return nullptr;
  }
  return &p;
}

// The work after an Update; returns something to keep.
double DoWork(Work work, const PairState& s, AxialResiduals* residuals, VolumeCostCache* cache) {
  switch (work) {
    case Work::kUpdate: return 0.0;
    case Work::kAxial:
      ComputeAxialResiduals(s, AxialSettings(), /*jacobians=*/true, residuals);
      return residuals->r.empty() ? 0.0 : residuals->r[0];
    case Work::kVolume1: return EvaluateVolumeCost(s, true, Execution{1}).abs;
    case Work::kVolume2: return EvaluateVolumeCost(s, true, Execution{2}).abs;
    case Work::kIncremental1: return cache->Evaluate(s, true, Execution{1}).abs;
    case Work::kIncremental2: return cache->Evaluate(s, true, Execution{2}).abs;
    case Work::kValue1: return cache->Evaluate(s, false, Execution{1}).abs;
  }
  return 0.0;
}

void SetCommonCounters(benchmark::State& state, const Pair& p, int64_t walk_steps,
                       int64_t updates, int64_t remeshes) {
  state.counters["nodes"] = static_cast<double>(p.nodes);
  state.counters["walk_steps_per_point"] =
      updates > 0 ? static_cast<double>(walk_steps) / updates / p.nodes : 0.0;
  state.counters["remeshes_per_update"] =
      updates > 0 ? static_cast<double>(remeshes) / updates : 0.0;
}

void BM_Remeasure(benchmark::State& state, int64_t n, int step, Work work) {
  Pair* p = Setup(state, n);
  if (!p) return;
  PairState s(p->ref, p->mov);
  if (!s.Update(p->theta_true)) {
    state.SkipWithError("Update to θ_true failed (fold)");
    Fail("N=" + std::to_string(n) + ": Update to θ_true failed");
    return;
  }
  const Theta poses[2] = {p->theta_true, p->theta_step[step]};
  AxialResiduals residuals;
  VolumeCostCache cache(0.25, BenchKernel());  // volinc_*: built in the warm-up, repaired in the timed loop
  // Untimed: one step there and back, so the result buffers exist before
  // timing, as in a solver's later evaluations.
  bool warm = s.Update(poses[1]);
  if (warm) {
    Keep(DoWork(work, s, &residuals, &cache));
    warm = s.Update(poses[0]);
    if (warm) Keep(DoWork(work, s, &residuals, &cache));
  }
  if (!warm) {
    state.SkipWithError("Update failed (fold)");
    Fail("N=" + std::to_string(n) + ": Update failed in BM_Remeasure's warm-up");
    return;
  }
  const int remeshes0 = s.remeshes();
  UpdateStats stats;
  int64_t walk = 0, updates = 0;
  int k = 0;
  for (auto _ : state) {
    k ^= 1;
    if (!s.Update(poses[k], &stats)) {
      state.SkipWithError("Update failed (fold)");
      Fail("N=" + std::to_string(n) + ": Update failed in BM_Remeasure");
      break;
    }
    walk += stats.walk_steps;
    ++updates;
    Keep(DoWork(work, s, &residuals, &cache));
    benchmark::ClobberMemory();
  }
  SetCommonCounters(state, *p, walk, updates, s.remeshes() - remeshes0);
  if (work == Work::kIncremental1 || work == Work::kIncremental2 || work == Work::kValue1) {
    // Over the warm-up and the timed loop: the share of A's triangles
    // searched again, of evaluations that rebuilt everything.
    const VolumeCostCacheStats& c = cache.stats();
    state.counters["searched_fraction"] =
        c.triangles > 0 ? static_cast<double>(c.triangles_searched) / c.triangles : 0.0;
    state.counters["full_builds_per_eval"] =
        c.evaluations > 0 ? static_cast<double>(c.full_builds - 1) / c.evaluations : 0.0;
    state.counters["fallbacks_per_eval"] =
        c.evaluations > 0 ? static_cast<double>(c.fallbacks) / c.evaluations : 0.0;
    state.counters["cells"] = c.evaluations > 0 ? static_cast<double>(c.cells) / c.evaluations : 0.0;
  }
}

// own_mesh: B's own mesh, as every new state in Align starts (its first
// Update re-triangulates B if slivers fold at the pose).
void Scratch(benchmark::State& state, int64_t n, int step, Work work, bool own_mesh) {
  Pair* p = Setup(state, n);
  if (!p) return;
  const MovingSide& moving = own_mesh ? p->mov : p->mov_at_pose;
  std::optional<PairState> s;
  AxialResiduals residuals;
  s.emplace(p->ref, moving);  // untimed: sizes the residual buffers
  std::optional<VolumeCostCache> cache;
  cache.emplace();
  if (s->Update(p->theta_step[step])) Keep(DoWork(work, *s, &residuals, &*cache));
  UpdateStats stats;
  int64_t walk = 0, updates = 0, remeshes = 0;
  for (auto _ : state) {
    state.PauseTiming();
    s.emplace(p->ref, moving);  // destroys the previous one, untimed
    cache.emplace();            // volinc_*: a fresh one builds the whole overlay
    stats = UpdateStats();      // Update sets `remeshed` only when it remeshes
    state.ResumeTiming();
    if (!s->Update(p->theta_step[step], &stats)) {
      state.SkipWithError("Update failed (fold)");
      Fail("N=" + std::to_string(n) + ": Update failed in BM_Scratch");
      break;
    }
    walk += stats.walk_steps;
    remeshes += stats.remeshed ? 1 : 0;
    ++updates;
    Keep(DoWork(work, *s, &residuals, &*cache));
    benchmark::ClobberMemory();
  }
  SetCommonCounters(state, *p, walk, updates, remeshes);
}

void BM_Scratch(benchmark::State& state, int64_t n, int step, Work work) {
  Scratch(state, n, step, work, /*own_mesh=*/false);
}

void BM_ScratchOwnMesh(benchmark::State& state, int64_t n, int step, Work work) {
  Scratch(state, n, step, work, /*own_mesh=*/true);
}

// Untimed: the state's costs at θ_true + δ_large against Measure's there.
void CrossCheck(const Pair& p, const MeasureSummary& m) {
  PairState s(p.ref, p.mov);
  if (!s.Update(p.theta_step[kMeasureStep])) return;  // reported by the other rows
  const VolumeCostValue v = EvaluateVolumeCost(s, false, Execution{1});
  AxialResiduals r;
  ComputeAxialResiduals(s, AxialSettings(), false, &r);
  double sum = 0;
  for (std::size_t k = 0; k < r.r.size(); ++k) sum += r.active[k] ? std::fabs(r.r[k]) : 0.0;
  const double axial = r.active_count > 0 ? sum / r.active_count : 0.0;
  const double volume = v.PerArea();
  char text[256];
  // Different meshes of B (own vs re-triangulated) give slightly different
  // interpolants; a factor 1.5 is far beyond that and catches a wrong pose.
  auto close = [](double x, double y) { return x > 0 && y > 0 && x < 1.5 * y && y < 1.5 * x; };
  if (!close(volume, m.mean_abs_dz) || !close(axial, m.rho_d_axial)) {
    std::snprintf(text, sizeof text,
                  "N=%lld: state volume cost %.6g vs Measure mean |d| %.6g; state mean |r| %.6g "
                  "vs Measure rho'd %.6g",
                  static_cast<long long>(p.n), volume, m.mean_abs_dz, axial, m.rho_d_axial);
    Fail(text);
  }
}

void BM_Measure(benchmark::State& state, int64_t n, bool parallel) {
  Pair* p = Setup(state, n);
  if (!p) return;
  MeasureOptions options;
  options.threads = parallel ? 2 : 1;
  MeasureSummary m;
  try {
    for (auto _ : state) {
      m = Measure(p->reference, p->moved, options);
      Keep(m.rho_d);
      benchmark::ClobberMemory();
    }
  } catch (const std::exception& e) {
    const std::string message = "N=" + std::to_string(n) + ": Measure threw: " + e.what();
    Fail(message);
    state.SkipWithError(message.c_str());
    return;
  }
  if (parallel) CrossCheck(*p, m);
  state.counters["nodes"] = static_cast<double>(p->nodes);
  state.counters["mean_abs_dz"] = m.mean_abs_dz;
  state.counters["rho_d_axial"] = m.rho_d_axial;
  state.counters["walk_steps_per_point"] =
      static_cast<double>(m.walk_steps) / static_cast<double>(m.n_points_a + m.n_points_b);
  // Measure's own stage timings (seconds, last iteration).
  state.counters["t_triangulate"] = m.timings.triangulate;
  state.counters["t_spanning_tree"] = m.timings.spanning_tree;
  state.counters["t_locate"] = m.timings.locate;
  state.counters["t_interpolate"] = m.timings.interpolate;
  state.counters["t_volume"] = m.timings.volume;
  state.counters["t_total"] = m.timings.total;
}

// The gap weight's per-node gaps on A's prepared side: the plane gaps (the
// `sampling_gap` report's) and the curvature gaps (the weight's, once per
// level of an alignment).
void BM_NodeGaps(benchmark::State& state, int64_t n, bool curvature) {
  Pair* p = Setup(state, n);
  if (!p) return;
  std::vector<Eigen::Vector3d> points(p->ref.xy.size());
  for (std::size_t v = 0; v < points.size(); ++v) points[v] = {p->ref.xy[v].x, p->ref.xy[v].y, p->ref.z[v]};
  for (auto _ : state) {
    const std::vector<double> gap = curvature ? CurvatureGaps(points, p->ref.mesh) : PlaneGaps(points, p->ref.mesh);
    Keep(gap[gap.size() / 2]);
  }
  state.counters["nodes"] = static_cast<double>(points.size());
}

// The BM_Align variants.
enum class AlignVariant { kAxial, kDefault, kInformation };
const char* VariantName(AlignVariant v) {
  return v == AlignVariant::kAxial ? "axial" : v == AlignVariant::kDefault ? "default" : "information";
}

void BM_Align(benchmark::State& state, int64_t n, AlignVariant variant) {
  const bool axial = variant == AlignVariant::kAxial;
  Pair* p = Setup(state, n);
  if (!p) return;
  AlignOptions options;
  options.cell_kernel = BenchKernel();
  if (axial) options.cost = CostKind::kAxial;
  if (variant == AlignVariant::kInformation) options.stddev_method = AlignOptions::StddevMethod::kInformation;
  AlignResult result;
  try {
    for (auto _ : state) {
      result = Align(p->reference, p->moving, options);
      Keep(result.matrix(0, 0));
      benchmark::ClobberMemory();
    }
  } catch (const std::exception& e) {
    const std::string message = "N=" + std::to_string(n) + ": Align threw: " + e.what();
    Fail(message);
    state.SkipWithError(message.c_str());
    return;
  }
  // Untimed: full measures of the same pair (as Align's own "before") in this
  // row, so the ratio does not depend on other rows.
  using Clock = std::chrono::steady_clock;
  constexpr int kMeasures = 3;
  const Clock::time_point t0 = Clock::now();
  for (int k = 0; k < kMeasures; ++k) Keep(Measure(p->reference, p->moving).rho_d);
  const double measure =
      std::chrono::duration<double>(Clock::now() - t0).count() / kMeasures;

  const testing::MotionError error = testing::CompareMotions(result.matrix, p->truth, p->moving_centroid);
  const double solve_start = result.log.empty() ? 0.0 : result.log.front().seconds;
  const double solve_end = result.log.empty() ? 0.0 : result.log.back().seconds;
  state.counters["align_s"] = result.seconds;
  state.counters["measure_s"] = measure;
  state.counters["full_measures"] = result.seconds / measure;
  state.counters["iterations"] = result.iterations;
  state.counters["rotation_error_deg"] = error.rotation_deg;
  state.counters["translation_error_spacings"] = error.translation / p->spacing;
  state.counters["remeshes"] = result.remeshes;
  // Where Align's time goes (seconds since its start, from its log): until
  // the solver's first iteration (prepare both sides, Measure before, first
  // evaluation), the solve, then the rest (Measure after, covariance).
  state.counters["t_before_solve"] = solve_start;
  state.counters["t_solve"] = solve_end - solve_start;
  state.counters["t_after_solve"] = result.seconds - solve_end;
  state.counters["t_covariance"] = result.covariance_seconds;
  state.counters["covariance_share"] = result.covariance_seconds / result.seconds;
  state.counters["t_measures_inside"] = result.before.timings.total + result.after.timings.total;
  state.counters["converged"] = result.verdict == Verdict::kConvergedImproved ? 1 : 0;
  char text[320];
  std::snprintf(text, sizeof text,
                "N=%lld %s Align: verdict %s (%s), rotation error %.3g deg, translation error "
                "%.3g spacings",
                static_cast<long long>(n), VariantName(variant), VerdictName(result.verdict),
                result.verdict_reason.c_str(), error.rotation_deg, error.translation / p->spacing);
  // Far from the known motion is an error; a verdict other than converged
  // (e.g. the iteration limit) with an accurate answer is only a note.
  if (error.rotation_deg > 0.1 || error.translation > 0.5 * p->spacing) {
    Fail(text);
  } else if (result.verdict != Verdict::kConvergedImproved) {
    std::fprintf(stderr, "NOTE: %s\n", text);
  }
}

void Configure(benchmark::internal::Benchmark* b, int64_t n) {
  b->Unit(benchmark::kMillisecond)->UseRealTime();
  // Seconds per iteration at 1e6 (the scratch rows and Measure): a short
  // minimum keeps the run within minutes.
  if (n >= 1000000) b->MinTime(0.2);
}

void RegisterAll(bool with_1e6) {
  std::vector<int64_t> sizes = {10000, 100000};
  if (with_1e6) sizes.push_back(1000000);
  const Work works[] = {Work::kUpdate,       Work::kAxial,        Work::kVolume1, Work::kVolume2,
                        Work::kIncremental1, Work::kIncremental2, Work::kValue1};
  // Input by input (GetPair keeps only the current one).
  for (int64_t n : sizes) {
    const std::string ns = "/" + std::to_string(n);
    for (bool parallel : {true, false}) {
      Configure(benchmark::RegisterBenchmark(
                    (std::string("BM_Measure/") + (parallel ? "2t" : "1t") + ns).c_str(),
                    BM_Measure, n, parallel),
                n);
    }
    for (int step = 0; step < kNumSteps; ++step) {
      for (Work w : works) {
        const std::string name = std::string(WorkName(w)) + "/" + kSteps[step].name + ns;
        Configure(benchmark::RegisterBenchmark(("BM_Remeasure/" + name).c_str(), BM_Remeasure,
                                               n, step, w),
                  n);
        if (step == kSolverStep) continue;  // from scratch, the step's size does not matter
        Configure(benchmark::RegisterBenchmark(("BM_Scratch/" + name).c_str(), BM_Scratch, n,
                                               step, w),
                  n);
      }
      if (step == kSolverStep) continue;
      const std::string name = std::string("update/") + kSteps[step].name + ns;
      Configure(benchmark::RegisterBenchmark(("BM_ScratchOwnMesh/" + name).c_str(),
                                             BM_ScratchOwnMesh, n, step, Work::kUpdate),
                n);
    }
    for (bool curvature : {false, true}) {
      Configure(benchmark::RegisterBenchmark(
                    (std::string("BM_NodeGaps/") + (curvature ? "curvature" : "plane") + ns).c_str(), BM_NodeGaps,
                    n, curvature),
                n);
    }
    if (n == 100000) {
      for (AlignVariant variant : {AlignVariant::kAxial, AlignVariant::kDefault, AlignVariant::kInformation}) {
        auto* b = benchmark::RegisterBenchmark((std::string("BM_Align/") + VariantName(variant) + ns).c_str(),
                                               BM_Align, n, variant);
        // Seconds each: one run.
        b->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
      }
    }
  }
}

}  // namespace
}  // namespace surfreg

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  // Our own flag (before GBench's check): also run N = 1e6.
  bool with_1e6 = false;
  int out = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--with_1e6") {
      with_1e6 = true;
    } else {
      argv[out++] = argv[i];
    }
  }
  argc = out;
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext(
      "cell_kernel", surfreg::volume_internal::CellKernelName(surfreg::volume_internal::ResolveCellKernel(
                         surfreg::BenchKernel())));
  surfreg::RegisterAll(with_1e6);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return surfreg::g_failed ? 2 : 0;
}
