// Measure() against analytic answers (planes, a paraboloid), brute-force
// quadrature, and its own invariances (symmetry, shuffling, rigid xy motion).
#include "measure/measures.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "measure/delaunay.h"
#include "measure/input_error.h"
#include "measure/locator.h"
#include "measure/volume.h"
#include "tests/testing/hull_golden_pairs.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

using Height = std::function<double(double, double)>;

// Random points in [0, side]^2 plus the four corners (so the hull is the square).
std::vector<Point2> SquareCloud(std::size_t n, double side, uint64_t seed) {
  std::vector<Point2> p = testing::UniformPoints(n, seed);
  for (Point2& q : p) q = {q.x * side, q.y * side};
  p.push_back({0, 0});
  p.push_back({side, 0});
  p.push_back({side, side});
  p.push_back({0, side});
  return p;
}

Surface Sample(const std::vector<Point2>& xy, const Height& f, double dx = 0.0, double dy = 0.0) {
  std::vector<std::array<double, 3>> points;
  for (const Point2& p : xy) points.push_back({p.x + dx, p.y + dy, f(p.x, p.y)});
  return MakeSurface(points, {}, "test");
}

double Rel(double value, double truth) { return std::fabs(value - truth) / std::fabs(truth); }

// The analytic answers below are integrals over the square [0, side]², the
// hull of SquareCloud (its corners are samples). Its data domain leaves out
// the long thin fans from the corners along the square's edges (edges of up
// to a side's length), so those tests measure over the hull, the integrator
// being what they test; measure_domain_test covers the data domain.
MeasureOptions OnHull(MeasureOptions options = MeasureOptions()) {
  options.domain.kind = DomainKind::kHull;
  return options;
}

TEST(MeasureTest, ParallelPlanes) {
  const Height a = [](double x, double y) { return 1.0 + 0.5 * x - 0.2 * y; };
  const Height b = [&](double x, double y) { return a(x, y) + 2.0; };
  const MeasureSummary s =
      Measure(Sample(SquareCloud(500, 10, 1), a), Sample(SquareCloud(700, 10, 2), b), OnHull());
  EXPECT_LT(Rel(s.rho_d, 200.0), 1e-9);
  EXPECT_LT(Rel(s.overlap_area, 100.0), 1e-12);
  EXPECT_LT(Rel(s.signed_volume, 200.0), 1e-9);
  EXPECT_LT(Rel(s.volume_above, 200.0), 1e-9);
  EXPECT_NEAR(s.volume_below, 0.0, 1e-9);
  EXPECT_LT(Rel(s.rho_d_axial, 2.0), 1e-9);
  EXPECT_LT(Rel(s.mean_abs_dz, 2.0), 1e-9);
  EXPECT_LT(Rel(s.rho_s, 1.0 / 200.0), 1e-9);
  EXPECT_EQ(s.n_overlap_nodes, 504 + 704 - 4);  // G1 ∪ G2 as a set: shared corners once
}

// on_progress: every stage once, in order, with shares and times that grow,
// from the calling thread; and the same measures as without it.
TEST(MeasureTest, ProgressNamesEveryStageInOrder) {
  const Height a = [](double x, double y) { return std::sin(x) + 0.1 * y; };
  const Surface sa = Sample(SquareCloud(800, 10, 3), a), sb = Sample(SquareCloud(900, 10, 4), a, 0.01);
  std::vector<MeasureProgress> seen;
  MeasureOptions options;
  options.on_progress = [&seen](const MeasureProgress& p) { seen.push_back(p); };
  const MeasureSummary with = Measure(sa, sb, options);
  const MeasureSummary without = Measure(sa, sb);
  const std::vector<std::string> stages = {"triangulating", "data domains and spanning trees",
                                           "locating each cloud in the other", "volume"};
  ASSERT_EQ(seen.size(), stages.size());
  for (std::size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].stage, stages[i]);
    EXPECT_GE(seen[i].done, 0.0);
    EXPECT_LT(seen[i].done, 1.0);
    if (i > 0) {
      EXPECT_GT(seen[i].done, seen[i - 1].done);
      EXPECT_GE(seen[i].seconds, seen[i - 1].seconds);
    }
  }
  EXPECT_EQ(with.rho_d, without.rho_d);
  EXPECT_EQ(with.n_cells, without.n_cells);
}

TEST(MeasureTest, CrossingPlanes) {
  // d = x − 5 on [0, 10]^2: ∫|d| = 10·2·(5²/2) = 250, half above, half below.
  const Height zero = [](double, double) { return 0.0; };
  const Height ramp = [](double x, double) { return x - 5.0; };
  for (VolumeMode mode : {VolumeMode::kOverlay}) {
    MeasureOptions options = OnHull();
    options.volume = mode;
    const MeasureSummary s =
        Measure(Sample(SquareCloud(400, 10, 3), zero), Sample(SquareCloud(600, 10, 4), ramp), options);
    EXPECT_LT(Rel(s.rho_d, 250.0), 1e-9);
    EXPECT_LT(Rel(s.volume_above, 125.0), 1e-9);
    EXPECT_LT(Rel(s.volume_below, 125.0), 1e-9);
    EXPECT_NEAR(s.signed_volume, 0.0, 1e-9);
  }
}

TEST(MeasureTest, ObliquePlanes) {
  // d = x − 2y + 1 on [0, 10]^2. Per x-slice ∫|d|dy = (x+1)²/2 + 90 − 10x,
  // so ρd = [(x+1)³/6]₀¹⁰ + 400 = 1330/6 + 400 = 1865/3; signed = 500 − 1000 + 100.
  const Height a = [](double x, double y) { return x + y; };
  const Height b = [](double x, double y) { return 2.0 * x - y + 1.0; };
  const MeasureSummary s =
      Measure(Sample(SquareCloud(800, 10, 5), a), Sample(SquareCloud(300, 10, 6), b), OnHull());
  EXPECT_LT(Rel(s.rho_d, 1865.0 / 3.0), 1e-9);
  EXPECT_LT(Rel(s.signed_volume, -400.0), 1e-9);
  EXPECT_LT(Rel(s.volume_above - s.volume_below, -400.0), 1e-9);
}

TEST(MeasureTest, SamePlaneOnTwoSamplingsIsZero) {
  const Height f = [](double x, double y) { return 3.0 - 0.7 * x + 0.1 * y; };
  const MeasureSummary s = Measure(Sample(SquareCloud(900, 10, 7), f), Sample(SquareCloud(500, 10, 8), f));
  EXPECT_LT(s.rho_d, 1e-10);
  EXPECT_LT(s.rho_d_axial, 1e-12);
}

TEST(MeasureTest, SurfaceAgainstItselfIsExactlyZero) {
  const Surface a = Sample(SquareCloud(300, 10, 9), [](double x, double y) { return std::sin(x) * y; });
  const MeasureSummary s = Measure(a, a);
  EXPECT_EQ(s.rho_d, 0.0);
  EXPECT_EQ(s.rho_d_axial, 0.0);
  EXPECT_EQ(s.rho_s, 1.0);
}

TEST(MeasureTest, ParaboloidConvergesToTheIntegral) {
  // ∫∫_{[0,1]²} (x² + y²) = 2/3 against the plane z = 0; piecewise-linear
  // interpolation error is O(h²), so the error must fall ~10× per 10× points.
  const Height bowl = [](double x, double y) { return x * x + y * y; };
  const Height flat = [](double, double) { return 0.0; };
  double previous = 1.0;
  for (std::size_t n : {1000u, 10000u, 100000u}) {
    const MeasureSummary s =
        Measure(Sample(SquareCloud(n, 1, 10 + n), bowl), Sample(SquareCloud(n, 1, 20 + n), flat),
                OnHull());
    const double error = Rel(s.rho_d, 2.0 / 3.0);
    EXPECT_LT(error, previous / 4.0) << n;
    previous = error;
  }
  EXPECT_LT(previous, 1e-4);
}

TEST(MeasureTest, SymmetricInItsArguments) {
  const Surface a = Sample(SquareCloud(600, 10, 30), [](double x, double y) { return std::cos(x) + 0.1 * y * y; });
  const Surface b = Sample(SquareCloud(450, 10, 31), [](double x, double y) { return std::sin(y) + 0.05 * x; });
  const MeasureSummary ab = Measure(a, b), ba = Measure(b, a);
  EXPECT_LT(Rel(ab.rho_d, ba.rho_d), 1e-12);
  EXPECT_LT(Rel(ab.rho_d_axial, ba.rho_d_axial), 1e-12);
  EXPECT_LT(Rel(ab.volume_above, ba.volume_below), 1e-12);
  EXPECT_LT(Rel(ab.overlap_area, ba.overlap_area), 1e-12);
}

TEST(MeasureTest, ShufflingLeavesEveryMeasureUnchanged) {
  const Height fa = [](double x, double y) { return std::cos(0.7 * x) * std::sin(0.3 * y); };
  const Height fb = [](double x, double y) { return 0.2 + 0.1 * x - 0.03 * y * y; };
  std::vector<Point2> pa = SquareCloud(2000, 10, 40), pb = testing::GridPoints(31, 31, 1.0 / 3.0);
  const MeasureSummary before = Measure(Sample(pa, fa), Sample(pb, fb));
  std::mt19937_64 rng(41);
  std::shuffle(pa.begin(), pa.end(), rng);
  std::shuffle(pb.begin(), pb.end(), rng);
  const MeasureSummary after = Measure(Sample(pa, fa), Sample(pb, fb));
  EXPECT_LT(Rel(after.rho_d, before.rho_d), 1e-12);
  EXPECT_LT(Rel(after.rho_d_axial, before.rho_d_axial), 1e-12);
  EXPECT_LT(Rel(after.signed_volume, before.signed_volume), 1e-12);
  EXPECT_LT(Rel(after.overlap_area, before.overlap_area), 1e-12);
  EXPECT_EQ(after.n_cells, before.n_cells);
}

TEST(MeasureTest, ParallelAndSerialAgree) {
  const Height fa = [](double x, double y) { return std::cos(0.7 * x) * std::sin(0.3 * y); };
  const Height fb = [](double x, double y) { return 0.2 + 0.1 * x - 0.03 * y * y; };
  const Surface a = Sample(SquareCloud(20000, 10, 42), fa), b = Sample(SquareCloud(15000, 10, 43), fb);
  MeasureOptions serial;
  serial.threads = 1;
  const MeasureSummary p = Measure(a, b), s = Measure(a, b, serial);
  EXPECT_LT(Rel(p.rho_d, s.rho_d), 1e-12);
  EXPECT_LT(Rel(p.overlap_area, s.overlap_area), 1e-12);
  EXPECT_LT(Rel(p.volume_above, s.volume_above), 1e-12);
  EXPECT_EQ(p.rho_d_axial, s.rho_d_axial);  // per-node work: bit-identical
  EXPECT_EQ(p.n_cells, s.n_cells);
  EXPECT_EQ(p.walk_steps, s.walk_steps);
}

TEST(MeasureTest, InvariantUnderACommonRigidMotionOfXy) {
  const Height fa = [](double x, double y) { return std::cos(0.5 * x) + 0.2 * y; };
  const Height fb = [](double x, double y) { return 0.3 * std::sin(x * y / 10.0); };
  const std::vector<Point2> pa = SquareCloud(1500, 10, 50), pb = SquareCloud(1200, 10, 51);
  const MeasureSummary base = Measure(Sample(pa, fa), Sample(pb, fb));
  const double c = std::cos(0.5), s = std::sin(0.5);
  auto move = [&](const std::vector<Point2>& p, const Height& f) {
    std::vector<std::array<double, 3>> out;
    for (const Point2& q : p) out.push_back({c * q.x - s * q.y + 500000.0, s * q.x + c * q.y + 4.5e6, f(q.x, q.y)});
    return MakeSurface(out, {}, "moved");
  };
  const MeasureSummary moved = Measure(move(pa, fa), move(pb, fb));
  EXPECT_LT(Rel(moved.rho_d, base.rho_d), 1e-9);
  EXPECT_LT(Rel(moved.overlap_area, base.overlap_area), 1e-9);
  EXPECT_LT(Rel(moved.rho_d_axial, base.rho_d_axial), 1e-9);
}

TEST(MeasureTest, UnionEqualsOverlayOnIdenticalSamplings) {
  // Same xy: the union triangulation is each one's, so both are exact.
  const std::vector<Point2> xy = SquareCloud(500, 10, 60);
  const Surface a = Sample(xy, [](double x, double y) { return std::sin(x) + y; });
  const Surface b = Sample(xy, [](double x, double y) { return 0.5 * x - std::cos(y); });
  MeasureOptions options;
  options.volume = VolumeMode::kUnion;
  const MeasureSummary u = Measure(a, b, options), o = Measure(a, b);
  EXPECT_LT(Rel(u.rho_d, o.rho_d), 1e-12);
  EXPECT_LT(Rel(u.signed_volume, o.signed_volume), 1e-9);
}

TEST(MeasureTest, UnionApproximatesOverlay) {
  const Height fa = [](double x, double y) { return std::sin(0.5 * x) * std::cos(0.4 * y); };
  const Height fb = [](double x, double y) { return 0.3 + 0.02 * x * y; };
  MeasureOptions options;
  options.volume = VolumeMode::kUnion;
  const Surface a = Sample(SquareCloud(3000, 10, 61), fa), b = Sample(SquareCloud(2500, 10, 62), fb);
  const MeasureSummary u = Measure(a, b, options), o = Measure(a, b);
  EXPECT_LT(Rel(u.rho_d, o.rho_d), 0.02);
  EXPECT_NE(u.rho_d, o.rho_d);
}

// Union mode assembled independently: nodes of A in Conv(B) and of B in
// Conv(A) found by brute-force location, the gap there by barycentric
// interpolation, the Delaunay triangulation of those nodes, and the paper's
// closed form per triangle.
TEST(MeasureTest, UnionModeIsThePapersFormulaOnTheUnionTriangulation) {
  const Height fa = [](double x, double y) { return std::sin(0.5 * x) + 0.1 * y; };
  const Height fb = [](double x, double y) { return 0.2 * x - std::cos(0.3 * y); };
  std::vector<Point2> pa = testing::UniformPoints(150, 63), pb = testing::UniformPoints(120, 64);
  for (Point2& p : pa) p = {10 * p.x, 10 * p.y};
  for (Point2& p : pb) p = {10 * p.x + 1.0, 10 * p.y - 0.5};
  const Triangulation ma = Triangulate(pa), mb = Triangulate(pb);
  auto height_at = [](const std::vector<Point2>& p, const Triangulation& m, const Height& f,
                      const Location& l) {
    double z = 0.0;
    for (int i = 0; i < 3; ++i) {
      const Point2& v = p[m.triangles[3 * l.triangle + i]];
      z += l.barycentric[i] * f(v.x, v.y);
    }
    return z;
  };
  std::vector<Point2> nodes;
  std::vector<double> gap;
  for (const Point2& p : pa) {
    const Location l = LocatePointBruteForce(pb, mb, p);
    if (!l.found()) continue;
    nodes.push_back(p);
    gap.push_back(height_at(pb, mb, fb, l) - fa(p.x, p.y));
  }
  for (const Point2& p : pb) {
    const Location l = LocatePointBruteForce(pa, ma, p);
    if (!l.found()) continue;
    nodes.push_back(p);
    gap.push_back(fb(p.x, p.y) - height_at(pa, ma, fa, l));
  }
  const Triangulation mu = Triangulate(nodes);
  double expected = 0.0;
  for (int32_t t = 0; t < mu.num_triangles(); ++t) {
    const int32_t* v = &mu.triangles[3 * t];
    const Point2 &a = nodes[v[0]], &b = nodes[v[1]], &c = nodes[v[2]];
    const double area = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    expected += AbsVolumePaper(area, gap[v[0]], gap[v[1]], gap[v[2]]);
  }
  MeasureOptions options = OnHull();  // the paper's Ω, as assembled above
  options.volume = VolumeMode::kUnion;
  const MeasureSummary s = Measure(Sample(pa, fa), Sample(pb, fb), options);
  EXPECT_LT(Rel(s.rho_d, expected), 1e-12);
  EXPECT_EQ(s.n_cells, mu.num_triangles());
}

TEST(MeasureTest, ConstantPerPointWeightScalesTheVolume) {
  const std::vector<Point2> pa = SquareCloud(300, 10, 70);
  std::vector<std::array<double, 3>> points;
  for (const Point2& p : pa) points.push_back({p.x, p.y, 0.0});
  const Surface a = MakeSurface(points, std::vector<double>(points.size(), 2.0), "weighted");
  const Surface b = Sample(SquareCloud(400, 10, 71), [](double x, double) { return x - 5.0; });
  MeasureOptions options = OnHull();
  options.weight = WeightMode::kPerPoint;
  const MeasureSummary s = Measure(a, b, options);
  EXPECT_LT(Rel(s.rho_d, 500.0), 1e-9);
  EXPECT_LT(Rel(s.weight_integral, 200.0), 1e-9);
  EXPECT_LT(Rel(s.mean_abs_dz, 2.5), 1e-9);
}

TEST(MeasureTest, LinearPerPointWeight) {
  // μ = x/10 on A (exactly linear), d = 1: ∫μ = 50 over the square.
  std::vector<std::array<double, 3>> points;
  std::vector<double> weight;
  for (const Point2& p : SquareCloud(300, 10, 72)) {
    points.push_back({p.x, p.y, 0.0});
    weight.push_back(p.x / 10.0);
  }
  const Surface a = MakeSurface(points, weight, "weighted");
  const Surface b = Sample(SquareCloud(200, 10, 73), [](double, double) { return 1.0; });
  MeasureOptions options = OnHull();
  options.weight = WeightMode::kPerPoint;
  const MeasureSummary s = Measure(a, b, options);
  EXPECT_LT(Rel(s.rho_d, 50.0), 1e-9);
  EXPECT_LT(Rel(s.weight_integral, 50.0), 1e-9);
}

TEST(MeasureTest, MaskPolygonRestrictsTheIntegral) {
  // d = x − 5; an L-shaped (non-convex) mask: [0,5]x[0,10] ∪ [5,10]x[0,2].
  // ∫_mask |x − 5| = 10·(5²/2) + 2·(5²/2) = 150; mask area 50 + 10 = 60.
  const Height zero = [](double, double) { return 0.0; };
  const Height ramp = [](double x, double) { return x - 5.0; };
  MeasureOptions options = OnHull();
  options.weight = WeightMode::kMask;
  options.mask = {{{0, 0}, {10, 0}, {10, 2}, {5, 2}, {5, 10}, {0, 10}}};
  const MeasureSummary s =
      Measure(Sample(SquareCloud(500, 10, 80), zero), Sample(SquareCloud(500, 10, 81), ramp), options);
  EXPECT_LT(Rel(s.rho_d, 150.0), 1e-9);
  EXPECT_LT(Rel(s.weight_integral, 60.0), 1e-9);
  EXPECT_LT(Rel(s.overlap_area, 100.0), 1e-12);  // |Ω| itself is unweighted
}

TEST(MeasureTest, PartialOverlap) {
  // B covers [5, 15] x [0, 10]: Ω = [5, 10] x [0, 10].
  const Height a = [](double, double) { return 0.0; };
  const Height b = [](double, double) { return 1.0; };
  const MeasureSummary s = Measure(Sample(SquareCloud(400, 10, 90), a),
                                   Sample(SquareCloud(400, 10, 91), b, 5.0, 0.0), OnHull());
  EXPECT_LT(Rel(s.overlap_area, 50.0), 1e-12);
  EXPECT_LT(Rel(s.rho_d, 50.0), 1e-12);
}

TEST(MeasureTest, DisjointOrSliverOverlapIsAnError) {
  const Height f = [](double, double) { return 0.0; };
  const Surface a = Sample(SquareCloud(100, 10, 92), f);
  EXPECT_THROW(Measure(a, Sample(SquareCloud(100, 10, 93), f, 20.0, 0.0)), InputError);
  // Touching along the edge x = 10 only.
  EXPECT_THROW(Measure(a, Sample(SquareCloud(100, 10, 94), f, 10.0, 0.0)), InputError);
  MeasureOptions bad;
  bad.min_overlap_fraction = 2.0;
  EXPECT_THROW(Measure(a, a, bad), InputError);
  MeasureOptions no_weights;
  no_weights.weight = WeightMode::kPerPoint;
  EXPECT_THROW(Measure(a, a, no_weights), InputError);
  MeasureOptions bow_tie;
  bow_tie.weight = WeightMode::kMask;
  bow_tie.mask = {{{0, 0}, {10, 10}, {10, 0}, {0, 10}}};
  EXPECT_THROW(Measure(a, a, bow_tie), InputError);
}

TEST(MeasureTest, DuplicatePointsAreAveraged) {
  // Two samples at each xy with heights 0 and 2: the surface is z = 1.
  std::vector<std::array<double, 3>> points;
  for (const Point2& p : SquareCloud(200, 10, 95)) {
    points.push_back({p.x, p.y, 0.0});
    points.push_back({p.x, p.y, 2.0});
  }
  const Surface a = MakeSurface(points, {}, "dup");
  const Surface b = Sample(SquareCloud(300, 10, 96), [](double, double) { return 1.0; });
  const MeasureSummary s = Measure(a, b);
  EXPECT_EQ(s.n_duplicates_a, 204);
  EXPECT_LT(s.rho_d, 1e-10);
}

// A prepared once (MeasureReference) gives, for every B, the very summary
// Measure(a, b) gives: every golden case (serial and parallel, union, per
// point weights, a mask, nodata lattices), on the data domain and the hull,
// B also from another origin and as a raster, and one A for two Bs.
TEST(MeasureTest, PreparedReferenceGivesTheSameSummary) {
  std::vector<testing::GoldenCase> cases = testing::GoldenCases();
  testing::GoldenCase shifted = cases[0];
  shifted.b.origin = {0.25, -0.5, 0.125};
  cases.push_back(shifted);
  testing::GoldenCase raster{{}, {}, MeasureOptions()};
  std::vector<std::array<double, 3>> points;
  std::vector<RasterCell> cells;
  for (int r = 0; r < 15; ++r) {
    for (int c = 0; c < 20; ++c) {
      if ((3 * c + 5 * r) % 17 == 0) continue;  // nodata
      points.push_back({0.5 * c, 0.5 * r, std::sin(0.3 * c) + 0.02 * r});
      cells.push_back({c, r});
    }
  }
  raster.a = MakeSurface(points, {}, "raster");
  raster.a.raster_cell = cells;
  raster.b = testing::GoldenCloud(400, 0.2, 9.3, 0.1, 6.8, 1, 5, false);
  raster.options.keep_node_gaps = true;
  cases.push_back(raster);
  std::swap(raster.a, raster.b);
  cases.push_back(raster);
  for (std::size_t k = 0; k < cases.size(); ++k) {
    for (DomainKind kind : {DomainKind::kData, DomainKind::kHull}) {
      MeasureOptions options = cases[k].options;
      options.domain.kind = kind;
      const MeasureReference prepared(cases[k].a, options);
      for (int repeat = 0; repeat < 2; ++repeat) {
        const MeasureSummary direct = Measure(cases[k].a, cases[k].b, options);
        const MeasureSummary reused = Measure(prepared, cases[k].b, options);
        EXPECT_EQ(testing::GoldenFingerprint(direct), testing::GoldenFingerprint(reused)) << "case " << k;
        EXPECT_EQ(direct.domain_area_a, reused.domain_area_a) << "case " << k;
        EXPECT_EQ(direct.domain_area_b, reused.domain_area_b) << "case " << k;
        EXPECT_EQ(direct.n_duplicates_a, reused.n_duplicates_a) << "case " << k;
        ASSERT_EQ(direct.dz_a.size(), reused.dz_a.size());
        for (std::size_t i = 0; i < direct.dz_a.size(); ++i) {
          if (!(std::isnan(direct.dz_a[i]) && std::isnan(reused.dz_a[i]))) {
            EXPECT_EQ(direct.dz_a[i], reused.dz_a[i]) << "case " << k << " node " << i;
          }
        }
        ASSERT_EQ(direct.dz_b.size(), reused.dz_b.size());
      }
    }
  }
}

// The reference is prepared for one domain rule; another is refused, and an
// A without data domain is refused when it is prepared, as Measure would.
TEST(MeasureTest, PreparedReferenceRefusesAnotherRuleAndAnEmptyDomain) {
  const testing::GoldenCase c = testing::GoldenCases()[0];
  MeasureOptions options;
  const MeasureReference prepared(c.a, options);
  MeasureOptions hull = options;
  hull.domain.kind = DomainKind::kHull;
  EXPECT_THROW(Measure(prepared, c.b, hull), std::invalid_argument);
  MeasureOptions longer = options;
  longer.domain.max_edge_spacings = 6.0;
  EXPECT_THROW(Measure(prepared, c.b, longer), std::invalid_argument);
  // One sliver of a triangle: an outline sliver, no data domain.
  const Surface empty = MakeSurface({{0, 0, 0}, {4, 0, 0}, {2, 0.05, 0}}, {}, "sliver");
  MeasureOptions data;
  EXPECT_THROW(MeasureReference(empty, data), InputError);
  EXPECT_THROW(Measure(empty, c.b, data), InputError);
}

}  // namespace
}  // namespace surfreg
