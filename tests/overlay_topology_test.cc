// The overlay kept as combinatorics (registration/volume_cost/overlay_topology.h) and
// the incremental volume cost built on it (VolumeCostCache), against
// independent truth: hand-computed crossings of a hexagram, the full
// overlay's own cells (measure/overlay.h), and the full evaluation
// (EvaluateVolumeCost) after moves that change locations, re-mesh B after a
// fold, overlap B only partly, with weights and with a mask.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <gtest/gtest.h>

#include "measure/delaunay.h"
#include "measure/domain.h"
#include "measure/locator.h"
#include "measure/overlay.h"
#include "measure/weights.h"
#include "registration/volume_cost/overlay_topology.h"
#include "registration/pair_state.h"
#include "registration/volume_cost/volume_accumulator.h"
#include "registration/volume_cost/volume_cost.h"
#include "testing/registration_sides.h"

namespace surfreg {
namespace {

// The cell kernel these tests run: SURFREG_CELL_KERNEL (ctest runs them
// once per kernel, tests/CMakeLists.txt), else the best.
CellKernelChoice KernelUnderTest() {
  CellKernelChoice choice = CellKernelChoice::kBest;
  if (const char* name = std::getenv("SURFREG_CELL_KERNEL")) {
    EXPECT_TRUE(ParseCellKernel(name, &choice)) << name;
  }
  return choice;
}

std::vector<Location> LocateBrute(const std::vector<Point2>& points, const Triangulation& mesh,
                                  const std::vector<Point2>& queries) {
  std::vector<Location> out;
  for (const Point2& q : queries) out.push_back(LocatePointBruteForce(points, mesh, q));
  return out;
}

// The corners of T_A ∩ T_B for one cell of `topology`.
std::vector<Point2> Corners(const OverlayTopology& topology, int32_t ta, int c,
                            const std::vector<Point2>& pa, const Triangulation& ma,
                            const std::vector<Point2>& pb, const Triangulation& mb) {
  const TopologyCell& cell = topology.cells_of(ta)[c];
  const int32_t* ia = &ma.triangles[3 * ta];
  const int32_t* ib = &mb.triangles[3 * cell.triangle_b];
  const Point2 a[3] = {pa[ia[0]], pa[ia[1]], pa[ia[2]]};
  const Point2 b[3] = {pb[ib[0]], pb[ib[1]], pb[ib[2]]};
  std::vector<Point2> out(cell.num_corners);
  CellCorners(cell, a, ia, b, ib, out.data());
  return out;
}

// Whether two corner lists are the same cycle (any start), within `tol`.
bool SameCycle(const std::vector<Point2>& x, const std::vector<Point2>& y, double tol) {
  if (x.size() != y.size()) return false;
  for (std::size_t shift = 0; shift < y.size(); ++shift) {
    bool same = true;
    for (std::size_t k = 0; k < x.size() && same; ++k) {
      const Point2& q = y[(k + shift) % y.size()];
      same = std::fabs(x[k].x - q.x) <= tol && std::fabs(x[k].y - q.y) <= tol;
    }
    if (same) return true;
  }
  return false;
}

// A hexagram: no corner of either triangle inside the other; the cell is a
// hexagon of six edge crossings, computed by hand from the edge lines
// (A: y = 0, y = 2x, y = 12 − 2x; B shifted by (dx, dy): y = 4, y = 4 − 2x,
// y = 2x − 8).
TEST(OverlayTopologyTest, HexagramCornersAreTheEdgeCrossings) {
  const std::vector<Point2> pa = {{0, 0}, {6, 0}, {3, 6}};
  const Triangulation ma = Triangulate(pa);
  for (const double shift : {0.0, 0.1}) {
    const double dx = shift, dy = 0.5 * shift;
    const std::vector<Point2> pb = {{0 + dx, 4 + dy}, {3 + dx, -2 + dy}, {6 + dx, 4 + dy}};
    const Triangulation mb = Triangulate(pb);
    OverlayTopology topology;
    topology.Build(pa, ma, LocateBrute(pb, mb, pa), pb, mb, LocateBrute(pa, ma, pb), Execution{1});
    ASSERT_EQ(topology.num_cells(), 1);
    ASSERT_EQ(topology.count_of(0), 1);
    const TopologyCell& cell = topology.cells_of(0)[0];
    ASSERT_EQ(cell.num_corners, 6);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(cell.corner[k] & 3, kCornerCross) << k;
    // B's lines moved by (dx, dy): y − dy = 4, y − dy = 4 − 2(x − dx), y − dy = 2(x − dx) − 8.
    const double top = 4 + dy, c_left = 4 + dy + 2 * dx, c_right = -8 + dy - 2 * dx;
    const std::vector<Point2> truth = {
        {(0 - c_right) / 2, 0},                                  // bottom ∩ B right
        {(12 - c_right) / 4, (12 - c_right) / 4 * 2 + c_right},  // A right ∩ B right
        {(12 - top) / 2, top},                                   // A right ∩ top
        {top / 2, top},                                          // A left ∩ top
        {c_left / 4, c_left / 2},                                // A left ∩ B left
        {c_left / 2, 0}};                                        // bottom ∩ B left
    const std::vector<Point2> got = Corners(topology, 0, 0, pa, ma, pb, mb);
    EXPECT_TRUE(SameCycle(got, truth, 1e-13)) << "shift " << shift;
  }
}

// After Build, every cell of the full overlay is a cell of the topology with
// the same corners; on random clouds (crossings everywhere) and on grids
// (vertices on edges and on vertices: collinear, degenerate).
void CheckAgainstFullOverlay(const std::vector<Point2>& pa, const std::vector<Point2>& pb,
                             bool parallel) {
  const Triangulation ma = Triangulate(pa), mb = Triangulate(pb);
  const auto a_in_b = LocateBrute(pb, mb, pa), b_in_a = LocateBrute(pa, ma, pb);
  OverlayTopology topology;
  topology.Build(pa, ma, a_in_b, pb, mb, b_in_a, Execution{parallel ? 2 : 1});
  int64_t full = 0;
  ForEachOverlayCell(pa, ma, a_in_b, pb, mb, b_in_a, [&](const OverlayCell& cell) {
    ++full;
    const std::vector<Point2> want(cell.vertices.begin(), cell.vertices.begin() + cell.num_vertices);
    int found = 0;
    for (int c = 0; c < topology.count_of(cell.triangle_a); ++c) {
      if (topology.cells_of(cell.triangle_a)[c].triangle_b != cell.triangle_b) continue;
      ++found;
      EXPECT_TRUE(SameCycle(Corners(topology, cell.triangle_a, c, pa, ma, pb, mb), want, 1e-11))
          << "cell " << cell.triangle_a << " x " << cell.triangle_b;
    }
    EXPECT_EQ(found, 1) << "cell " << cell.triangle_a << " x " << cell.triangle_b;
  });
  EXPECT_EQ(topology.num_cells(), full);
}

TEST(OverlayTopologyTest, BuildHasTheFullOverlaysCells) {
  std::vector<Point2> pa, pb, ga, gb;
  for (const auto& p : testing::SampleUniform(testing::SmoothTerrain, 700, 0, 100, 0, 100, 5)) pa.push_back({p[0], p[1]});
  for (const auto& p : testing::SampleUniform(testing::SmoothTerrain, 600, 20, 120, 10, 110, 6)) pb.push_back({p[0], p[1]});
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 9; ++j) {
      ga.push_back({10.0 * i, 10.0 * j});
      gb.push_back({5.0 + 10.0 * i, 10.0 * j});  // B's vertices on A's edges
    }
  }
  for (bool parallel : {false, true}) {
    CheckAgainstFullOverlay(pa, pb, parallel);
    CheckAgainstFullOverlay(ga, gb, parallel);
    CheckAgainstFullOverlay(ga, ga, parallel);  // every vertex on a vertex
  }
}

// ---------------------------------------------------------- VolumeCostCache

struct Compared {
  double worst = 0;  // worst relative difference over value, area and gradients
};

void ExpectSame(const VolumeCostValue& got, const VolumeCostValue& want, double tol,
                const char* what, Compared* c) {
  auto rel = [](double x, double y, double scale) { return std::fabs(x - y) / std::max(scale, 1e-300); };
  double worst = std::max(rel(got.abs, want.abs, std::fabs(want.abs)),
                          rel(got.area, want.area, std::fabs(want.area)));
  worst = std::max(worst, (got.d_abs - want.d_abs).norm() / std::max(want.d_abs.norm(), 1e-300));
  if (want.d_area.norm() > 0) {
    worst = std::max(worst, (got.d_area - want.d_area).norm() / want.d_area.norm());
  }
  c->worst = std::max(c->worst, worst);
  EXPECT_LE(worst, tol) << what << ": abs " << got.abs << " vs " << want.abs << ", area " << got.area
                        << " vs " << want.area << ", |Δ∇abs| " << (got.d_abs - want.d_abs).norm();
}

Theta Step(const Theta& t, double radians, double shift, int k) {
  // Directions that vary with k: all six parameters move.
  const double s[6] = {std::sin(1.0 + k), std::cos(2.0 + 3 * k), std::sin(0.5 * k - 1),
                       std::cos(0.7 * k), std::sin(1.3 * k + 2), std::cos(k - 0.4)};
  Theta out = t;
  for (int i = 0; i < 3; ++i) out[i] += radians * s[i];
  for (int i = 3; i < 6; ++i) out[i] += shift * s[i];
  return out;
}

// A walk of θ: small, large and very large steps, each evaluated by the
// cache and by the full path. Returns the cache's stats.
VolumeCostCacheStats Walk(const Sides& sides, bool parallel,
                          const MaskRegion* mask, const char* label,
                          double spacing, int* remeshes = nullptr) {
  PairState state(sides.reference, sides.moving);
  VolumeCostCache cache(0.25, KernelUnderTest());
  Compared compared;
  Theta theta = {0.01, -0.02, 0.03, 0.2, -0.1, 0.05};
  const double steps[][2] = {{1e-4, 0.01}, {1e-3, 0.1}, {1e-2, 1.0}, {1e-4, 0.01}, {1e-3, 0.1}};
  int k = 0;
  for (const auto& step : steps) {
    for (int rep = 0; rep < 4; ++rep, ++k) {
      const Theta next = Step(theta, step[0], step[1] * spacing, k);
      if (!state.Update(next)) continue;
      theta = next;
      for (bool gradient : {true, false}) {
        const VolumeCostValue want = EvaluateVolumeCost(state, gradient, Execution{parallel ? 2 : 1}, mask);
        const VolumeCostValue got = cache.Evaluate(state, gradient, Execution{parallel ? 2 : 1}, mask);
        EXPECT_GT(want.area, 0);
        ExpectSame(got, want, 1e-11, label, &compared);
      }
    }
  }
  if (remeshes != nullptr) *remeshes = state.remeshes();
  const VolumeCostCacheStats& st = cache.stats();
  std::printf("%s%s: %lld evaluations, %lld full builds, searched %.2f%% of A's triangles, "
              "worst relative difference %.2e\n",
              label, parallel ? " (2 threads)" : "", static_cast<long long>(st.evaluations),
              static_cast<long long>(st.full_builds),
              100.0 * st.triangles_searched / std::max<int64_t>(1, st.triangles), compared.worst);
  return st;
}

TEST(VolumeCostCacheTest, MatchesFullEvaluationAlongAWalk) {
  const auto sides = TerrainSides(3000, 2500, 0, 100);
  const double spacing = 100.0 / std::sqrt(3000.0);
  for (bool parallel : {false, true}) {
    const VolumeCostCacheStats st = Walk(*sides, parallel, nullptr, "plain", spacing);
    EXPECT_LT(st.full_builds, st.evaluations / 2);     // mostly repaired, not rebuilt
    EXPECT_LT(st.triangles_searched, st.triangles / 4);  // and locally
  }
}

TEST(VolumeCostCacheTest, MatchesWithPartialOverlap) {
  const auto sides = TerrainSides(2500, 2000, 40, 140);  // B overlaps A on [40, 100]²
  Walk(*sides, true, nullptr, "partial overlap", 100.0 / std::sqrt(2500.0));
  Walk(*sides, false, nullptr, "partial overlap", 100.0 / std::sqrt(2500.0));
}

TEST(VolumeCostCacheTest, MatchesWithWeightsAndMask) {
  const auto weighted = TerrainSides(2000, 1800, 0, 100, SmoothWeight);
  Walk(*weighted, true, nullptr, "weights", 100.0 / std::sqrt(2000.0));
  Walk(*weighted, false, nullptr, "weights", 100.0 / std::sqrt(2000.0));
  const auto plain = TerrainSides(2000, 1800, 0, 100);
  // In A's local frame.
  const MaskRegion shifted = MakeMaskRegion({{{20, 15}, {80, 25}, {70, 60}, {45, 40}, {25, 75}}},
                                            MaskMode::kInclude, {plain->a.origin[0], plain->a.origin[1]});
  Walk(*plain, false, &shifted, "mask", 100.0 / std::sqrt(2000.0));
  Walk(*weighted, true, &shifted, "weights and mask", 100.0 / std::sqrt(2000.0));
}

// The data domain: cells of either surface's junk (here the triangles that
// bridge a void in each) are left out by the incremental path exactly as by
// the full one, through repairs and B's junk re-meshes.
TEST(VolumeCostCacheTest, MatchesWithDataDomain) {
  const auto sides = VoidSides(2500, 2200);
  for (bool parallel : {false, true}) Walk(*sides, parallel, nullptr, "data domain", 100.0 / std::sqrt(2500.0));
}

// At the identity with B's data covering A's, Ω is A's data domain: the
// cost's area is DomainArea(A), not A's hull (which includes its void).
TEST(VolumeCostCacheTest, AreaIsTheDataDomainsIntersection) {
  const auto points = testing::SampleUniform(testing::SmoothTerrain, 2500, 0, 100, 0, 100, 11);
  // B: a lattice over [−10, 110]² (no junk inside A's hull).
  std::vector<std::array<double, 3>> lattice;
  for (int i = 0; i <= 80; ++i) {
    for (int j = 0; j <= 80; ++j) {
      const double x = -10 + 1.5 * i, y = -10 + 1.5 * j;
      lattice.push_back({x, y, testing::SmoothTerrain(x, y)});
    }
  }
  const auto sides = MakeSides(WithoutDisc(points, 50, 50, 15), lattice, nullptr, DomainRule());
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update({0, 0, 0, 0, 0, 0}));
  const ReferenceSide& a = sides->reference;
  const double domain = DomainArea(a.xy, a.mesh, a.domain);
  const double hull = MeshArea(a.xy, a.mesh);
  std::printf("A: hull %.1f, data domain %.1f (void of radius 15: %.1f)\n", hull, domain, M_PI * 225);
  // The empty region is the disc and its ragged rim: a little more than the disc.
  EXPECT_GT(hull - domain, 0.95 * M_PI * 225);
  EXPECT_LT(hull - domain, 1.4 * M_PI * 225);
  VolumeCostCache cache(0.25, KernelUnderTest());
  EXPECT_NEAR(cache.Evaluate(state, true, Execution{1}).area, domain, 1e-9 * domain);
  EXPECT_NEAR(EvaluateVolumeCost(state, false, Execution{2}).area, domain, 1e-9 * domain);
}

// A step too large to repair takes the plain full path and keeps the
// overlay for its pose; coming back repairs it; another pose too far right
// after builds it again. Equal to the full evaluation throughout.
TEST(VolumeCostCacheTest, FallsBackToTheFullPathForLargeSteps) {
  const auto sides = TerrainSides(1500, 1500, 0, 100);
  const double spacing = 100.0 / std::sqrt(1500.0);
  PairState state(sides->reference, sides->moving);
  VolumeCostCache cache(0.25, KernelUnderTest());
  Compared compared;
  const Theta near = {1e-3, -1e-3, 2e-3, 0.1, 0.0, 0.0};
  const Theta far = Step(near, 1e-2, 2 * spacing, 3);
  const Theta farther = Step(far, 1e-2, 2 * spacing, 5);
  const int64_t want_builds[] = {1, 1, 1, 1, 2};
  const int64_t want_fallbacks[] = {0, 2, 2, 4, 4};
  int k = 0;
  for (const Theta& theta : {near, far, near, far, farther}) {
    ASSERT_TRUE(state.Update(theta));
    for (bool gradient : {true, false}) {  // the same pose twice: one decision
      ExpectSame(cache.Evaluate(state, gradient, Execution{1}), EvaluateVolumeCost(state, gradient, Execution{1}),
                 1e-11, "fallback", &compared);
    }
    EXPECT_EQ(cache.stats().full_builds, want_builds[k]) << k;
    EXPECT_EQ(cache.stats().fallbacks, want_fallbacks[k]) << k;
    ++k;
  }
}

// Where B coincides with A exactly (d ≡ 0 on whole cells, hull cells
// included), those cells add nothing inside but still move the boundary:
// ∇|Ω| must match the full path's.
TEST(VolumeCostCacheTest, CellsWithZeroGapStillMoveTheBoundary) {
  std::vector<std::array<double, 3>> pa, pb;
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      const double x = i + 0.3 * std::sin(7.0 * j), y = j + 0.3 * std::cos(5.0 * i);
      pa.push_back({x, y, 0.0});
      pb.push_back({x, y, x > 10 ? 0.05 * (x - 10) * (x - 10) : 0.0});  // equal to A on x ≤ 10
    }
  }
  const auto sides = MakeSides(pa, pb);
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update({0, 0, 0, 0, 0, 0}));
  VolumeCostCache cache(0.25, KernelUnderTest());
  const VolumeCostValue want = EvaluateVolumeCost(state, true, Execution{1});
  const VolumeCostValue got = cache.Evaluate(state, true, Execution{1});
  ASSERT_GT(want.abs, 0);
  ASSERT_GT(want.d_area.norm(), 0);
  EXPECT_LE((got.d_area - want.d_area).norm(), 1e-12 * want.d_area.norm());
  EXPECT_LE((got.d_abs - want.d_abs).norm(), 1e-12 * want.d_abs.norm());
  EXPECT_NEAR(got.abs, want.abs, 1e-12 * want.abs);
}

// A 5° tilt folds slivers: B is re-triangulated and the cache rebuilds.
TEST(VolumeCostCacheTest, RebuildsAfterARemesh) {
  const auto sides = TerrainSides(1500, 1500, 0, 100);
  PairState state(sides->reference, sides->moving);
  VolumeCostCache cache(0.25, KernelUnderTest());
  Compared compared;
  const Theta thetas[] = {{0, 0, 0, 0, 0, 0},
                          {1e-4, 0, 0, 0.01, 0, 0},
                          {5 * M_PI / 180, 0, 0, 0.5, -0.5, 0},
                          {5.0001 * M_PI / 180, 1e-4, 0, 0.51, -0.5, 0},
                          {5.001 * M_PI / 180, 2e-4, 1e-4, 0.55, -0.45, 0.01}};
  for (const Theta& theta : thetas) {
    ASSERT_TRUE(state.Update(theta));
    ExpectSame(cache.Evaluate(state, true, Execution{2}), EvaluateVolumeCost(state, true, Execution{2}), 1e-11,
               "remesh", &compared);
  }
  EXPECT_EQ(state.remeshes(), 1);
  EXPECT_EQ(cache.stats().full_builds, 2);  // the first evaluation and after the re-mesh
  // Another state (new locations, B's own mesh again): rebuilt, still equal.
  PairState other(sides->reference, sides->moving);
  ASSERT_TRUE(other.Update(thetas[1]));
  ExpectSame(cache.Evaluate(other, true, Execution{1}), EvaluateVolumeCost(other, true, Execution{1}), 1e-11,
             "new state", &compared);
  EXPECT_EQ(cache.stats().full_builds, 3);
  cache.Reset();
  ExpectSame(cache.Evaluate(other, false, Execution{1}), EvaluateVolumeCost(other, false, Execution{1}), 1e-11,
             "after Reset", &compared);
  EXPECT_EQ(cache.stats().full_builds, 4);
}

}  // namespace
}  // namespace surfreg

namespace surfreg {
namespace {

// The gradient's shares per bin (GradientBins) against brute force: every
// cell of the full overlay through the full path's accumulator, its share
// put in the bin of its B triangle's centroid. With partial overlap, so that
// the boundary terms (and ∇∫μ) are in play; one and two threads.
using Vector6 = Eigen::Matrix<double, 6, 1>;

TEST(VolumeCostCacheTest, GradientBinsAreEachBTrianglesShare) {
  const auto sides = TerrainSides(2500, 2000, 40, 140);  // B overlaps A on [40, 100]²
  for (bool parallel : {false, true}) {
    PairState state(sides->reference, sides->moving);
    ASSERT_TRUE(state.Update({0.01, -0.02, 0.03, 0.2, -0.1, 0.05}));
    // 8 × 8 bins over A's nodes (in A's local frame).
    GradientBins bins;
    bins.x0 = bins.y0 = 1e300;
    double hi = -1e300;
    for (const Point2& p : state.reference().xy) {
      bins.x0 = std::min(bins.x0, p.x), bins.y0 = std::min(bins.y0, p.y);
      hi = std::max({hi, p.x, p.y});
    }
    bins.side = (hi - std::min(bins.x0, bins.y0)) / 8, bins.n = 8;
    VolumeCostCache cache(0.25, KernelUnderTest());
    const VolumeCostValue value = cache.Evaluate(state, true, Execution{parallel ? 2 : 1}, nullptr, &bins);
    ASSERT_EQ(bins.used.size(), 64u);

    std::vector<Vector6> want_abs(64, Vector6::Zero()), want_area(64, Vector6::Zero());
    std::vector<uint8_t> want_used(64, 0);
    volume_internal::VolumeAccumulator accumulator(state, true, nullptr);
    const auto& xb = state.moved_xy();
    const auto& mb = state.moving_mesh();
    ForEachOverlayCell(state.reference().xy, state.reference().mesh, state.a_in_b(), xb, mb,
                       state.b_in_a(), [&](const OverlayCell& cell) {
      const VolumeCostValue before = accumulator.value;
      accumulator(cell);
      if (accumulator.value.cells == before.cells) return;
      const int32_t* v = &mb.triangles[3 * cell.triangle_b];
      const int b = bins.Index((xb[v[0]].x + xb[v[1]].x + xb[v[2]].x) / 3,
                               (xb[v[0]].y + xb[v[1]].y + xb[v[2]].y) / 3);
      want_abs[b] += accumulator.value.d_abs - before.d_abs;
      want_area[b] += accumulator.value.d_area - before.d_area;
      want_used[b] = 1;
    });
    const double scale_abs = value.d_abs.norm(), scale_area = value.d_area.norm();
    ASSERT_GT(scale_area, 0);  // the boundary moves: its terms are in the shares
    Vector6 sum_abs = Vector6::Zero(), sum_area = Vector6::Zero();
    int used = 0;
    for (int b = 0; b < 64; ++b) {
      used += bins.used[b];
      sum_abs += bins.d_abs[b], sum_area += bins.d_area[b];
      // A bin with cells of zero share may be used on one side only.
      EXPECT_LE((bins.d_abs[b] - want_abs[b]).norm(), 1e-10 * scale_abs) << "bin " << b;
      EXPECT_LE((bins.d_area[b] - want_area[b]).norm(), 1e-10 * scale_area) << "bin " << b;
      if (want_abs[b].norm() > 1e-6 * scale_abs) {
        EXPECT_TRUE(bins.used[b]) << "bin " << b;
      }
    }
    std::printf("gradient bins%s: %d of 64 used\n", parallel ? " (2 threads)" : "", used);
    EXPECT_GE(used, 12);  // the overlap, [40, 100]² of [0, 100]², spans about 5 × 5 bins
    EXPECT_LE((sum_abs - value.d_abs).norm(), 1e-11 * scale_abs);
    EXPECT_LE((sum_area - value.d_area).norm(), 1e-11 * scale_area);
  }
}

}  // namespace
}  // namespace surfreg
