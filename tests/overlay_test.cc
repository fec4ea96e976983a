// The overlay against brute force: every pair of triangles clipped directly,
// and ρd against midpoint quadrature of |F̂_B − F̂_A| (with a Richardson
// estimate of the quadrature's own error), on random smooth pairs and on a
// real DEM against an irregular resampling of itself.
#include "measure/overlay.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "measure/locator.h"
#include "measure/measures.h"
#include "measure/overlay_clip.h"
#include "measure/predicates.h"
#include "measure/spanning_tree.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

// Area of triangle P ∩ triangle Q by an independent convex clip.
double IntersectionArea(const std::array<Point2, 3>& p, const std::array<Point2, 3>& q) {
  std::vector<Point2> poly(p.begin(), p.end());
  for (int i = 0; i < 3; ++i) {
    const Point2 a = q[i], b = q[(i + 1) % 3];
    auto side = [&](const Point2& r) { return (b.x - a.x) * (r.y - a.y) - (b.y - a.y) * (r.x - a.x); };
    std::vector<Point2> out;
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const Point2 r = poly[k], s = poly[(k + 1) % poly.size()];
      const double sr = side(r), ss = side(s);
      if (sr >= 0) out.push_back(r);
      if ((sr > 0 && ss < 0) || (sr < 0 && ss > 0)) {
        const double t = sr / (sr - ss);
        out.push_back({r.x + t * (s.x - r.x), r.y + t * (s.y - r.y)});
      }
    }
    poly = out;
    if (poly.empty()) return 0.0;
  }
  double twice = 0.0;
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    twice += (poly[k].x - poly[0].x) * (poly[k + 1].y - poly[0].y) -
             (poly[k].y - poly[0].y) * (poly[k + 1].x - poly[0].x);
  }
  return 0.5 * twice;
}

std::array<Point2, 3> Corners(const std::vector<Point2>& p, const Triangulation& m, int32_t t) {
  return {p[m.triangles[3 * t]], p[m.triangles[3 * t + 1]], p[m.triangles[3 * t + 2]]};
}

struct Pair {
  std::vector<Point2> a, b;
  Triangulation ma, mb;
  std::vector<Location> a_in_b, b_in_a;
};

Pair MakePair(std::vector<Point2> a, std::vector<Point2> b) {
  Pair s{std::move(a), std::move(b), {}, {}, {}, {}};
  s.ma = Triangulate(s.a);
  s.mb = Triangulate(s.b);
  s.a_in_b = LocateAll(s.b, s.mb, s.a, s.ma, EuclideanMst(s.a, s.ma));
  s.b_in_a = LocateAll(s.a, s.ma, s.b, s.mb, EuclideanMst(s.b, s.mb));
  return s;
}

void ExpectCellsMatchBruteForce(const Pair& s) {
  std::map<std::pair<int32_t, int32_t>, double> cells;
  ForEachOverlayCell(s.a, s.ma, s.a_in_b, s.b, s.mb, s.b_in_a, [&](const OverlayCell& c) {
    const auto key = std::make_pair(c.triangle_a, c.triangle_b);
    EXPECT_EQ(cells.count(key), 0u) << "cell visited twice";
    cells[key] = c.area;
  });
  int missing = 0;
  double total = 0.0;
  for (int32_t ta = 0; ta < s.ma.num_triangles(); ++ta) {
    for (int32_t tb = 0; tb < s.mb.num_triangles(); ++tb) {
      const double area = IntersectionArea(Corners(s.a, s.ma, ta), Corners(s.b, s.mb, tb));
      const auto it = cells.find({ta, tb});
      if (area > 1e-9) {
        if (it == cells.end()) {
          ++missing;
          continue;
        }
        EXPECT_NEAR(it->second, area, 1e-12 + 1e-9 * area);
      } else if (it != cells.end()) {
        EXPECT_LT(it->second, 1e-9) << "spurious cell " << ta << " " << tb;
      }
      total += std::max(area, 0.0);
    }
  }
  EXPECT_EQ(missing, 0);
  double sum = 0.0;
  for (const auto& kv : cells) sum += kv.second;
  EXPECT_NEAR(sum, total, 1e-9 * total);
}

// The overlay in chunks visits exactly the serial overlay's cells, each
// once, and each chunk the same cells in the same order on 1, 2 and 8
// threads.
void ExpectSameCellsInTwo(const Pair& s) {
  std::map<std::pair<int32_t, int32_t>, double> serial;
  ForEachOverlayCell(s.a, s.ma, s.a_in_b, s.b, s.mb, s.b_in_a,
                     [&](const OverlayCell& c) { serial[{c.triangle_a, c.triangle_b}] = c.area; });
  for (const int chunks : {2, 7}) {
    std::vector<std::vector<std::pair<int32_t, int32_t>>> order_one;
    for (const int threads : {1, 2, 8}) {
      SCOPED_TRACE(::testing::Message() << chunks << " chunks, " << threads << " threads");
      std::vector<std::vector<std::pair<int32_t, int32_t>>> order(chunks);
      std::vector<std::map<std::pair<int32_t, int32_t>, double>> parts(chunks);
      const OverlayStats stats = ForEachOverlayCellInChunks(
          s.a, s.ma, s.a_in_b, s.b, s.mb, s.b_in_a, chunks,
          [&](int c, const OverlayCell& cell) {
            parts[c][{cell.triangle_a, cell.triangle_b}] = cell.area;
            order[c].push_back({cell.triangle_a, cell.triangle_b});
          },
          Execution{threads});
      std::map<std::pair<int32_t, int32_t>, double> all;
      for (const auto& part : parts) {
        for (const auto& kv : part) EXPECT_TRUE(all.insert(kv).second) << "cell visited by two chunks";
      }
      EXPECT_EQ(all, serial);
      EXPECT_EQ(stats.cells, static_cast<int64_t>(serial.size()));
      if (order_one.empty()) {
        order_one = order;
      } else {
        EXPECT_EQ(order, order_one);
      }
    }
  }
}

TEST(OverlayTest, TwoThreadsVisitTheSerialCells) {
  ExpectSameCellsInTwo(MakePair(testing::UniformPoints(3000, 21), testing::UniformPoints(2000, 22)));
  ExpectSameCellsInTwo(MakePair(testing::GridPoints(40, 40, 1.0), testing::GridPoints(20, 20, 2.0)));
  std::vector<Point2> strip = testing::UniformPoints(500, 23);
  for (Point2& p : strip) p = {p.x * 40.0, 18.0 + p.y * 2.0};  // a thin strip across the grid
  ExpectSameCellsInTwo(MakePair(testing::GridPoints(40, 40, 1.0), strip));
  ExpectSameCellsInTwo(MakePair(strip, testing::GridPoints(40, 40, 1.0)));
}

TEST(OverlayTest, RandomMeshesMatchBruteForcePairs) {
  for (uint64_t seed : {1, 2, 3}) {
    ExpectCellsMatchBruteForce(MakePair(testing::UniformPoints(120, seed), testing::UniformPoints(90, seed + 10)));
  }
}

TEST(OverlayTest, SharedGridVerticesAndEdges) {
  // Both on grids that share vertices and whole edges: every contact is degenerate.
  std::vector<Point2> a = testing::GridPoints(9, 9, 1.0);
  std::vector<Point2> b = testing::GridPoints(5, 5, 2.0);
  ExpectCellsMatchBruteForce(MakePair(a, b));
  ExpectCellsMatchBruteForce(MakePair(a, a));
}

TEST(OverlayTest, PartialOverlapAndNoVertexInside) {
  // A thin horizontal strip and a thin vertical strip crossing: no vertex of
  // either lies in the other's hull... except none: the overlap must still be found
  // through the B vertices located in A or the propagation across A's edges.
  std::vector<Point2> a = testing::UniformPoints(60, 4), b = testing::UniformPoints(60, 5);
  for (Point2& p : b) p = {p.x + 0.5, p.y + 0.3};
  ExpectCellsMatchBruteForce(MakePair(a, b));
}

// Regression (found by fuzz_measure): a hexagram, each triangle's corners
// outside the other, so no vertex location seeds the search; the overlap
// (a hexagon) was reported as empty. Exact truth: A = (0,0) (6,0) (3,6),
// B = (0,4) (6,4) (3,-2) meet in a hexagon of area 12, and d = 1 on it.
TEST(OverlayTest, HexagramWithNoVertexInsideTheOther) {
  const Surface a = MakeSurface({{0, 0, 0}, {6, 0, 0}, {3, 6, 0}});
  const Surface b = MakeSurface({{0, 4, 1}, {6, 4, 1}, {3, -2, 1}});
  for (const bool parallel : {false, true}) {
    MeasureOptions options;
    options.threads = parallel ? 2 : 1;
    for (const bool swap : {false, true}) {
      const MeasureSummary s = swap ? Measure(b, a, options) : Measure(a, b, options);
      EXPECT_NEAR(s.overlap_area, 12.0, 1e-12) << parallel << swap;
      EXPECT_NEAR(s.rho_d, 12.0, 1e-12) << parallel << swap;
    }
  }
}

// Orient2DEdgeSignBits (the overlay's batched side test) gives Orient2D's
// exact signs, also where its filter cannot decide: on grids (exact zeros),
// on a line through far-apart points (tiny determinants), and at random.
TEST(OverlayTest, EdgeSignBitsAreOrient2DSigns) {
  std::mt19937_64 rng(31);
  std::uniform_int_distribution<int> grid(0, 4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int zeros = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Point2 t[3], c;
    const int kind = trial % 3;
    for (Point2* p : {&t[0], &t[1], &t[2], &c}) {
      if (kind == 0) {
        *p = {double(grid(rng)), double(grid(rng))};
      } else if (kind == 1) {  // near the line y = x / 3 far from the origin
        const double s = 1e6 * u(rng);
        *p = {s, s / 3.0 + (grid(rng) - 2) * 1e-10};
      } else {
        *p = {u(rng), u(rng)};
      }
    }
    const unsigned bits = Orient2DEdgeSignBits(t, c);
    for (int i = 0; i < 3; ++i) {
      const double det = Orient2D(t[(i + 1) % 3], t[(i + 2) % 3], c);
      EXPECT_EQ((bits >> i) & 1, det > 0.0 ? 1u : 0u) << trial << " " << i;
      EXPECT_EQ((bits >> (3 + i)) & 1, det < 0.0 ? 1u : 0u) << trial << " " << i;
      zeros += det == 0.0;
    }
  }
  EXPECT_GT(zeros, 1000);  // the degenerate cases were exercised
}

// The clip's labels never change its arithmetic: with and without them,
// the same corners, bit for bit, and the same area.
TEST(OverlayTest, ClipCornersDoNotDependOnLabels) {
  std::mt19937_64 rng(32);
  std::uniform_int_distribution<int> grid(0, 5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int cells = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Point2 a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = trial % 2 ? Point2{double(grid(rng)), double(grid(rng))} : Point2{u(rng), u(rng)};
      b[k] = trial % 2 ? Point2{double(grid(rng)), double(grid(rng))} : Point2{u(rng), u(rng)};
    }
    if (Orient2D(a[0], a[1], a[2]) < 0.0) std::swap(a[1], a[2]);
    if (!(Orient2D(a[0], a[1], a[2]) > 0.0)) continue;
    int8_t side[3][3];
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 3; ++i) {
        const double det = Orient2D(a[(i + 1) % 3], a[(i + 2) % 3], b[k]);
        side[k][i] = static_cast<int8_t>((det > 0.0) - (det < 0.0));
      }
    }
    const int8_t* const s[3] = {side[0], side[1], side[2]};
    double x[8], y[8], lx[8], ly[8], area = 0.0, labelled_area = 0.0;
    uint8_t label[8];
    const int n = overlay_internal::ClipTriangle(a, b, s, x, y, &area, nullptr);
    const int ln = overlay_internal::ClipTriangle(a, b, s, lx, ly, &labelled_area, label);
    ASSERT_EQ(n, ln) << trial;
    if (n == 0) continue;
    ++cells;
    EXPECT_EQ(area, labelled_area) << trial;
    for (int k = 0; k < n; ++k) {
      EXPECT_EQ(x[k], lx[k]) << trial;
      EXPECT_EQ(y[k], ly[k]) << trial;
    }
    const std::array<Point2, 3> pa = {a[0], a[1], a[2]}, pb = {b[0], b[1], b[2]};
    EXPECT_NEAR(0.5 * area, std::fabs(IntersectionArea(pb, pa)), 1e-12) << trial;
  }
  EXPECT_GT(cells, 5000);
}

// Midpoint rule of |F̂_B − F̂_A| on an m x m grid over [x0,x1]x[y0,y1], with
// samples outside either domain (measure/domain.h; the hulls with kHull)
// contributing nothing.
double Quadrature(const std::vector<Point2>& pa, const Triangulation& ma, const std::vector<double>& za,
                  const std::vector<Point2>& pb, const Triangulation& mb, const std::vector<double>& zb,
                  double x0, double x1, double y0, double y1, int m, DomainKind kind) {
  DomainRule rule;
  rule.kind = kind;
  const MeshDomain da = MakeMeshDomain(pa, ma, rule), db = MakeMeshDomain(pb, mb, rule);
  auto value = [](const Triangulation& mesh, const std::vector<double>& z, const Location& l) {
    const int32_t* v = &mesh.triangles[3 * l.triangle];
    return l.barycentric[0] * z[v[0]] + l.barycentric[1] * z[v[1]] + l.barycentric[2] * z[v[2]];
  };
  const double hx = (x1 - x0) / m, hy = (y1 - y0) / m;
  double sum = 0.0;
  int32_t ta = 0, tb = 0;
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      const Point2 q{x0 + (i + 0.5) * hx, y0 + (j + 0.5) * hy};
      const Location la = LocatePoint(pa, ma, q, ta), lb = LocatePoint(pb, mb, q, tb);
      ta = la.triangle;
      tb = lb.triangle;
      if (da.Contains(ma, la) && db.Contains(mb, lb)) {
        sum += std::fabs(value(mb, zb, lb) - value(ma, za, la));
      }
    }
  }
  return sum * hx * hy;
}

Surface ToSurface(const std::vector<Point2>& xy, const std::vector<double>& z) {
  std::vector<std::array<double, 3>> points;
  for (std::size_t i = 0; i < xy.size(); ++i) points.push_back({xy[i].x, xy[i].y, z[i]});
  return MakeSurface(points, {}, "q", 0.0);
}

void ExpectOverlayMatchesQuadrature(const std::vector<Point2>& pa, const std::vector<double>& za,
                                    const std::vector<Point2>& pb, const std::vector<double>& zb,
                                    double x0, double x1, double y0, double y1, int m,
                                    DomainKind kind) {
  const Triangulation ma = Triangulate(pa), mb = Triangulate(pb);
  const double coarse = Quadrature(pa, ma, za, pb, mb, zb, x0, x1, y0, y1, m, kind);
  const double fine = Quadrature(pa, ma, za, pb, mb, zb, x0, x1, y0, y1, 2 * m, kind);
  const double quadrature_error = std::fabs(fine - coarse) / 3.0;  // O(h²) Richardson
  MeasureOptions options;
  options.domain.kind = kind;
  const double rho_d = Measure(ToSurface(pa, za), ToSurface(pb, zb), options).rho_d;
  std::printf("overlay %.12g  quadrature %.12g  (estimated error %.3g)\n", rho_d, fine, quadrature_error);
  // The data domain's outline is a jagged polygon of samples, which the
  // midpoint rule resolves only to O(h): no Richardson estimate for that part.
  const double outline = kind == DomainKind::kData ? 3e-4 : 1e-9;
  EXPECT_LT(std::fabs(rho_d - fine), 3.0 * quadrature_error + outline * rho_d);
  EXPECT_LT(std::fabs(rho_d - fine), 1e-3 * rho_d);
}

TEST(OverlayTest, RhoDMatchesQuadratureOnRandomSmoothPairs) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 3; ++trial) {
    const double k1 = 3 + 2 * u(rng), k2 = 3 + 2 * u(rng), s = 0.3 * u(rng);
    std::vector<Point2> pa = testing::UniformPoints(150, 100 + trial), pb = testing::UniformPoints(110, 200 + trial);
    for (auto* p : {&pa, &pb}) {
      p->insert(p->end(), {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    }
    std::vector<double> za, zb;
    for (const Point2& p : pa) za.push_back(std::sin(k1 * p.x) * std::cos(k2 * p.y));
    for (const Point2& p : pb) zb.push_back(s + 0.4 * std::cos(k2 * p.x + k1 * p.y));
    for (DomainKind kind : {DomainKind::kHull, DomainKind::kData}) {
      ExpectOverlayMatchesQuadrature(pa, za, pb, zb, 0, 1, 0, 1, 300, kind);
    }
  }
}

TEST(OverlayTest, RealDemAgainstAnIrregularResamplingOfItself) {
  // The Maunga Whau volcano grid (87 x 61, 10 m) against 3000 random points
  // with heights bilinearly interpolated from the grid.
  std::ifstream in("configs/data/volcano.xyz");
  ASSERT_TRUE(in.good()) << "run from the repository root";
  std::vector<Point2> pa;
  std::vector<double> za;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double x, y, z;
    fields >> x >> y >> z;
    pa.push_back({x, y});
    za.push_back(z);
  }
  ASSERT_EQ(pa.size(), 87u * 61u);
  auto grid = [&](int r, int c) { return za[static_cast<std::size_t>(r) * 61 + c]; };  // x = 10 r, y = 10 c
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> ux(0.0, 860.0), uy(0.0, 600.0);
  std::vector<Point2> pb;
  std::vector<double> zb;
  for (int k = 0; k < 3000; ++k) {
    const double x = ux(rng), y = uy(rng);
    const int r = std::min(85, static_cast<int>(x / 10)), c = std::min(59, static_cast<int>(y / 10));
    const double fx = x / 10 - r, fy = y / 10 - c;
    pb.push_back({x, y});
    zb.push_back((1 - fx) * (1 - fy) * grid(r, c) + fx * (1 - fy) * grid(r + 1, c) +
                 (1 - fx) * fy * grid(r, c + 1) + fx * fy * grid(r + 1, c + 1));
  }
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;  // B's bounding box holds Ω
  for (const Point2& p : pb) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  ExpectOverlayMatchesQuadrature(pa, za, pb, zb, x0, x1, y0, y1, 1200, DomainKind::kData);
}

}  // namespace
}  // namespace surfreg
