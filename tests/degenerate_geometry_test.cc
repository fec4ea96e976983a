// Degenerate geometry for the triangulation and the overlay (issue 7): regular
// grids, rotated grids, cocircular points, a fan of thin triangles over one
// line, clouds sharing all their xy, clouds whose edges overlap exactly, and
// coordinates offset by 1e6. For each pair of surfaces A, B:
//  - each triangulation Measure() builds (same local coordinates) is checked
//    against the definition by brute force in exact arithmetic
//    (tests/testing/delaunay_checks.h: counter-clockwise, empty circles with
//    the documented tie rule, 2n − 2 − h triangles, boundary = convex hull);
//  - ρd, the signed volume, above/below and |Ω| from Measure() are compared
//    with two oracles that never call the overlay or the walk
//    (tests/testing/overlay_oracle.h), on the same triangulations:
//    (1) every pair (T_A, T_B) clipped directly (O(N_A·N_B)), each piece
//        integrated by the long-double reference of volume_reference.h, and
//        |Ω| as the area of the clipped hulls;
//    (2) a centroid rule of |F̂_B − F̂_A| on Ω (~4e4 points), each point
//        located by brute force (exact orientation);
//  - ρd(A, B) = ρd(B, A), and surfaces that agree give exactly 0.
// The oracles integrate over Ω = Conv(A) ∩ Conv(B), so Measure() runs with
// DomainKind::kHull here (the data domain has domain_test and
// measure_domain_test; on these sets, e.g. points on a circle, it is not
// meant to be the hull).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "measure/delaunay.h"
#include "measure/input_error.h"
#include "measure/measures.h"
#include "measure/surface.h"
#include "tests/testing/delaunay_checks.h"
#include "tests/testing/exact_rational.h"
#include "tests/testing/overlay_oracle.h"
#include "tests/testing/point_sets.h"
#include "tests/testing/predicate_oracle.h"
#include "tests/testing/volume_reference.h"

namespace surfreg {
namespace {

using Height = std::function<double(double, double)>;
using testing::Area;
using testing::ClipConvex;
using testing::ClippedIntegrals;
using testing::Hull;
using testing::Integrals;
using testing::Mesh;
using testing::Polygon;
using testing::Quadrature;
using testing::QuadratureResult;

// Two smooth, non-planar heights that cross (so |d| has zero lines).
double F1(double x, double y) {
  return 0.5 * std::sin(2.1 * x + 0.3) * std::cos(1.7 * y) + 0.2 * x * y;
}
double F2(double x, double y) { return 0.4 * std::cos(1.3 * x - 0.9 * y) + 0.1 - 0.3 * y * y; }

// ---------------------------------------------------------------------------
// Point sets (input coordinates).

std::vector<Point2> Moved(std::vector<Point2> p, double dx, double dy) {
  for (Point2& q : p) q = {q.x + dx, q.y + dy};
  return p;
}

std::vector<Point2> Rotated(std::vector<Point2> p, double degrees, Point2 c) {
  const double a = degrees * M_PI / 180.0, co = std::cos(a), si = std::sin(a);
  for (Point2& q : p) {
    const double x = q.x - c.x, y = q.y - c.y;
    q = {c.x + co * x - si * y, c.y + si * x + co * y};
  }
  return p;
}

std::vector<Point2> Joined(std::vector<Point2> a, const std::vector<Point2>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Integer points of x² + y² = r², scaled by 2^-6: exactly cocircular.
std::vector<Point2> LatticeCircle(int r) {
  std::vector<Point2> p;
  for (const auto& [x, y] : testing::LatticeCircle(r)) p.push_back({x / 64.0, y / 64.0});
  return p;
}

// n points on y = 0, x = 0, 1/(n−1), …, 1, and one apex above.
std::vector<Point2> LineFan(int n, Point2 apex) {
  std::vector<Point2> p;
  for (int i = 0; i < n; ++i) p.push_back({static_cast<double>(i) / (n - 1), 0.0});
  p.push_back(apex);
  return p;
}

// `n` uniform points in the unit square plus its corners and `edge_points`
// points on its bottom and top edges (collinear hull points).
std::vector<Point2> SquareCloud(int n, int edge_points, uint64_t seed) {
  std::vector<Point2> p = testing::UniformPoints(n, seed);
  p.insert(p.end(), {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  for (int i = 1; i <= edge_points; ++i) {
    const double x = static_cast<double>(i) / (edge_points + 1);
    p.push_back({x, 0.0});
    p.push_back({x, 1.0});
  }
  return p;
}

std::vector<Point2> Grid(int n, double step) { return testing::GridPoints(n, n, step); }

// ---------------------------------------------------------------------------
// One configuration, checked end to end.

struct Case {
  std::string name;
  std::vector<Point2> xy_a, xy_b;
  Height fa, fb;
  double offset = 0.0;  // added to every input x and y (heights see x − offset)
  // kExact: the same samples, so the same origin and mesh: ρd must be 0.0.
  // kRounding: F̂_A = F̂_B on Ω, but z is stored relative to different
  // origins, so the gaps are rounding noise (≤ a few ulps of z).
  enum Zero { kNo, kExact, kRounding } zero = kNo;
  // Relative tolerance of the quadrature (see CheckCase).
  double quadrature_tolerance = 1e-3;
};

Surface MakeCloud(const std::vector<Point2>& xy, const Height& f, double offset,
                  const std::string& name) {
  std::vector<std::array<double, 3>> points;
  for (const Point2& p : xy) points.push_back({p.x + offset, p.y + offset, f(p.x, p.y)});
  return MakeSurface(points, {}, name, 1.0);
}

struct Worst {  // the largest relative errors over all cases, for the report
  double clip = 0, signed_volume = 0, area = 0, quadrature = 0, symmetry = 0;
  ~Worst() {
    std::printf(
        "max relative errors: rho_d vs clipping %.2e, signed/above/below %.2e, |Omega| %.2e, "
        "rho_d vs quadrature %.2e, symmetry %.2e\n",
        clip, signed_volume, area, quadrature, symmetry);
  }
};
Worst worst;

double Rel(long double got, long double want, long double scale) {
  return static_cast<double>(std::fabs(got - want) / std::max<long double>(scale, 1e-300L));
}

void CheckCase(const Case& c) {
  SCOPED_TRACE(c.name);
  const Surface sa = MakeCloud(c.xy_a, c.fa, c.offset, c.name + " A");
  const Surface sb = MakeCloud(c.xy_b, c.fb, c.offset, c.name + " B");
  // What Measure() works on (measures.cc): B shifted into A's frame.
  Mesh a{sa.xy, sa.z, {}}, b{sb.xy, sb.z, {}};
  for (Point2& p : b.xy)
    p = {p.x + (sb.origin[0] - sa.origin[0]), p.y + (sb.origin[1] - sa.origin[1])};
  for (double& z : b.z) z += sb.origin[2] - sa.origin[2];
  a.tri = Triangulate(a.xy);
  b.tri = Triangulate(b.xy);
  EXPECT_TRUE(testing::IsPerturbedDelaunay(a.xy, a.tri)) << "A";
  EXPECT_TRUE(testing::IsPerturbedDelaunay(b.xy, b.tri)) << "B";

  MeasureOptions hull;
  hull.domain.kind = DomainKind::kHull;
  const MeasureSummary ab = Measure(sa, sb, hull), ba = Measure(sb, sa, hull);
  const Integrals clip = ClippedIntegrals(a, b);
  const Polygon omega_polygon = ClipConvex(Hull(a.xy), Hull(b.xy));
  const long double omega = Area(omega_polygon);

  // Tolerances. Both sides sum the same non-negative cell integrals from
  // corners rounded to a few ulps, so they agree to ~1e-15 of the volume
  // scale |Ω|·max|z| (∫|F̂_A| + ∫|F̂_B| bounds every term); 1e-12 of it
  // leaves room for ~1e4 cells' rounding without hiding a lost or doubled
  // cell (which would cost ≥ 1/N of ρd ≫ 1e-12).
  double zmax = 0.0;
  for (double z : a.z) zmax = std::max(zmax, std::fabs(z));
  for (double z : b.z) zmax = std::max(zmax, std::fabs(z));
  const long double scale = omega * 2 * zmax;
  const double tol = 1e-12;
  const double e_clip = Rel(ab.rho_d, clip.abs, scale);
  const double e_signed =
      std::max({Rel(ab.signed_volume, clip.signed_volume, scale),
                Rel(ab.volume_above, clip.above, scale), Rel(ab.volume_below, clip.below, scale)});
  // |Ω|: the clipped hulls (exact up to rounded crossing corners) and the
  // sum of the clipped cells agree to ulps of the area.
  const double e_area = std::max(Rel(ab.overlap_area, omega, omega), Rel(clip.area, omega, omega));
  const double e_sym =
      std::max({Rel(ba.rho_d, ab.rho_d, scale), Rel(-ba.signed_volume, ab.signed_volume, scale),
                Rel(ba.overlap_area, ab.overlap_area, omega)});
  EXPECT_LT(e_clip, tol) << "rho_d " << ab.rho_d << " clipping " << static_cast<double>(clip.abs);
  EXPECT_LT(e_signed, tol) << "signed " << ab.signed_volume << " above " << ab.volume_above
                           << " below " << ab.volume_below;
  EXPECT_LT(e_area, 1e-12) << "overlap area " << ab.overlap_area << " hulls "
                           << static_cast<double>(omega);
  EXPECT_LT(e_sym, tol) << "rho_d(B, A) " << ba.rho_d;

  // Quadrature with ~4e4 points. Its own error is O(h²) from the τ that a
  // kink of |d| crosses; the bound of Quadrature() adds those errors up
  // with one sign, which at this h is 10–100 times the actual error (kinks
  // cut τ at all offsets and the errors largely cancel): it is checked, but
  // too loose alone. Measured errors: ≤ 5e-4 of ρd where F1 and F2 differ
  // (|d| ~ 0.3, kinks are a small part of it): tolerance 1e-3; up to 2e-2
  // where both sample F1 (d is the interpolation error itself, of size
  // O(H²) with gradient jumps O(H) at every edge of both meshes, so the
  // kinks are all of it): tolerance 5e-2. A lost or doubled overlay cell is
  // caught far more tightly by the clipping oracle above.
  const QuadratureResult quad = Quadrature(a, b, omega_polygon, 40000, zmax);
  EXPECT_EQ(quad.outside, 0) << "quadrature points of Ω outside a mesh";
  const double q2 = quad.value;
  const double e_quad = c.zero != Case::kNo ? 0.0 : Rel(ab.rho_d, q2, ab.rho_d);
  const double noise = 1e-15 * static_cast<double>(scale);  // ~ulps of z over Ω
  switch (c.zero) {
    case Case::kExact:
      EXPECT_EQ(ab.rho_d, 0.0);
      EXPECT_EQ(ab.signed_volume, 0.0);
      EXPECT_EQ(ba.rho_d, 0.0);
      EXPECT_LT(q2, noise);  // shared edges: either triangle, to rounding
      break;
    case Case::kRounding:
      EXPECT_LT(ab.rho_d, noise);
      EXPECT_LT(ba.rho_d, noise);
      EXPECT_LT(q2, noise);
      break;
    case Case::kNo:
      EXPECT_GT(ab.rho_d, 100 * noise);
      EXPECT_LE(std::fabs(ab.rho_d - q2), quad.bound + noise)
          << "rho_d " << ab.rho_d << " quadrature " << q2 << " ± " << quad.bound;
      EXPECT_LT(e_quad, c.quadrature_tolerance) << "rho_d " << ab.rho_d << " quadrature " << q2;
      break;
  }
  std::printf(
      "%-44s nA %4zu nB %4zu  rho_d %-12.6g |Omega| %-9.5g clip %.1e sgn %.1e area %.1e "
      "sym %.1e quad %.1e (bound %.1e)\n",
      c.name.c_str(), c.xy_a.size(), c.xy_b.size(), ab.rho_d, ab.overlap_area, e_clip, e_signed,
      e_area, e_sym, e_quad, c.zero != Case::kNo ? 0.0 : quad.bound / ab.rho_d);
  worst.clip = std::max(worst.clip, e_clip);
  worst.signed_volume = std::max(worst.signed_volume, e_signed);
  worst.area = std::max(worst.area, e_area);
  worst.symmetry = std::max(worst.symmetry, e_sym);
  worst.quadrature = std::max(worst.quadrature, e_quad);
}

// The same point sets with F1/F2, and with F1 on both (`zero`: what F1/F1 gives).
void CheckPair(const std::string& name, const std::vector<Point2>& a, const std::vector<Point2>& b,
               double offset = 0.0, Case::Zero zero = Case::kNo) {
  CheckCase({name + " F1/F2", a, b, F1, F2, offset});
  CheckCase({name + " F1/F1", a, b, F1, F1, offset, zero, 5e-2});
}

const Point2 kCentre{0.5, 0.5};

// ---------------------------------------------------------------------------

TEST(DegenerateGeometryTest, RegularGrids) {
  CheckPair("grid 17² h=1/16 vs 21² h=0.05", Grid(17, 1.0 / 16), Grid(21, 0.05));
  CheckPair("grid 17² h=1/16 vs 9² h=1/8 (shared)", Grid(17, 1.0 / 16), Grid(9, 1.0 / 8));
  CheckCase({"same grid 17², F1/F2", Grid(17, 1.0 / 16), Grid(17, 1.0 / 16), F1, F2});
  CheckCase(
      {"same grid 17², F1/F1", Grid(17, 1.0 / 16), Grid(17, 1.0 / 16), F1, F1, 0.0, Case::kExact});
}

TEST(DegenerateGeometryTest, RotatedGrids) {
  CheckPair("grid vs grid rotated 45°", Grid(17, 1.0 / 16),
            Rotated(Grid(17, 1.0 / 16), 45, kCentre));
  CheckPair("grid vs grid rotated 30°", Grid(17, 1.0 / 16),
            Rotated(Grid(15, 1.0 / 14), 30, kCentre));
  CheckPair("rotated 45° vs rotated 30°", Rotated(Grid(17, 1.0 / 16), 45, kCentre),
            Rotated(Grid(17, 1.0 / 16), 30, kCentre));
  CheckPair("1e6: grid vs grid rotated 45°", Grid(17, 1.0 / 16),
            Rotated(Grid(17, 1.0 / 16), 45, kCentre), 1e6);
}

TEST(DegenerateGeometryTest, LargeOffsetCostsOnlyTheRoundingOfTheInput) {
  // At 1e6 the inputs are rounded to 2^-33 ≈ 1.2e-10. That alone changes
  // which diagonal each nearly cocircular cell of a rotated grid gets (and
  // ρd with it: 6e-5 relative for F1/F2 and 2% for F1/F1 here);
  // the same rounded points measured near 0 give the same ρd.
  const std::vector<Point2> grid = Grid(17, 1.0 / 16), rotated = Rotated(grid, 45, kCentre);
  std::vector<Point2> rounded = rotated;
  for (Point2& p : rounded) p = {(p.x + 1e6) - 1e6, (p.y + 1e6) - 1e6};
  for (const Height& fb : {Height(F1), Height(F2)}) {
    // rounded + 1e6 is rotated + 1e6 exactly; heights from the same points.
    const MeasureSummary far =
        Measure(MakeCloud(grid, F1, 1e6, "A"), MakeCloud(rounded, fb, 1e6, "B"));
    const MeasureSummary near =
        Measure(MakeCloud(grid, F1, 0.0, "A"), MakeCloud(rounded, fb, 0.0, "B"));
    const MeasureSummary unrounded =
        Measure(MakeCloud(grid, F1, 0.0, "A"), MakeCloud(rotated, fb, 0.0, "B"));
    EXPECT_NEAR(far.rho_d, near.rho_d, 1e-12 * near.rho_d);
    std::printf(
        "rotated 45° grid at 1e6: rho_d %.12g, near 0 with the same rounding %.12g, unrounded "
        "%.12g\n",
        far.rho_d, near.rho_d, unrounded.rho_d);
    EXPECT_NEAR(far.overlap_area, near.overlap_area, 1e-12);
  }
}

TEST(DegenerateGeometryTest, PointsOnACircle) {
  const std::vector<Point2> centre = {{0.0, 0.0}};
  const std::vector<Point2> circle = Joined(LatticeCircle(65), centre);  // 36 + 1, cocircular
  const std::vector<Point2> rings = Joined(LatticeCircle(25), circle);   // + 20 on r = 25/64
  const std::vector<Point2> snapped =
      Joined(testing::CirclePoints(64), centre);  // nearly cocircular
  CheckPair("circle r=65/64 vs two concentric circles", circle, rings);
  CheckPair("circle vs 64 snapped points on a circle", circle, snapped);
  CheckCase({"circle, same points, F1/F2", circle, circle, F1, F2});
  CheckCase({"circle, same points, F1/F1", circle, circle, F1, F1, 0.0, Case::kExact});
  CheckPair("1e6: circle vs two concentric circles", circle, rings, 1e6);
}

TEST(DegenerateGeometryTest, ManyPointsOnALinePlusOne) {
  const std::vector<Point2> fan = LineFan(65, {0.5, 0.125});
  CheckPair("fan 64 vs fan 40 (other apex)", fan, LineFan(41, {0.3, 0.1}));
  CheckPair("fan 64 vs fan 32 (same hull)", fan, LineFan(33, {0.5, 0.125}));
  CheckPair("fan 64 vs grid over it", fan, testing::GridPoints(17, 3, 1.0 / 16));
  CheckCase({"fan, same points, F1/F1", fan, fan, F1, F1, 0.0, Case::kExact});
}

TEST(DegenerateGeometryTest, CloudsSharingAllTheirXy) {
  std::vector<Point2> cloud = SquareCloud(300, 5, 41), shuffled = cloud;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937_64(3));
  CheckCase({"shared xy (random), F1/F2", cloud, shuffled, F1, F2});
  CheckCase({"shared xy (random), F1/F1", cloud, shuffled, F1, F1, 0.0, Case::kExact});
  CheckCase({"shared xy (rotated grid), F1/F2", Rotated(Grid(17, 1.0 / 16), 30, kCentre),
             Rotated(Grid(17, 1.0 / 16), 30, kCentre), F1, F2});
}

TEST(DegenerateGeometryTest, CloudsWhoseEdgesOverlapExactly) {
  const std::vector<Point2> grid = Grid(17, 1.0 / 16);
  CheckPair("grid vs grid + half a cell in y", grid, Moved(grid, 0.0, 1.0 / 32));
  CheckPair("grid vs grid + half a cell in x", grid, Moved(grid, 1.0 / 32, 0.0));
  CheckPair("grid vs grid + 1/2 (shared half)", grid, Moved(grid, 0.5, 0.0), 0.0, Case::kRounding);
  const std::vector<Point2> cloud = SquareCloud(200, 3, 42);
  CheckPair("cloud vs its copy shifted along a hull edge", cloud, Moved(cloud, 0.375, 0.0));
  CheckPair("1e6: grid vs grid + half a cell in y", grid, Moved(grid, 0.0, 1.0 / 32), 1e6);
}

TEST(DegenerateGeometryTest, SquaresSharingOnlyABoundaryEdgeDoNotOverlap) {
  // Ω is the common edge: area exactly 0, reported as bad input.
  const std::vector<Point2> grid = Grid(9, 1.0 / 8), right = Moved(grid, 1.0, 0.0);
  EXPECT_EQ(Area(ClipConvex(Hull(grid), Hull(right))), 0.0L);
  const Surface a = MakeCloud(grid, F1, 0.0, "left"), b = MakeCloud(right, F2, 0.0, "right");
  EXPECT_THROW(Measure(a, b), InputError);
  EXPECT_THROW(Measure(b, a), InputError);
  // Touching at one corner only.
  const Surface c = MakeCloud(Moved(grid, 1.0, 1.0), F2, 0.0, "corner");
  EXPECT_THROW(Measure(a, c), InputError);
}

}  // namespace
}  // namespace surfreg
