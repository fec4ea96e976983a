// Masks of several rings (measure/mask_region.h): the even–odd region's
// integrals against analytic answers, the point test against a brute-force
// count of rings, and the ring checks' messages.
#include "measure/mask_region.h"

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "measure/measures.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

using Height = std::function<double(double, double)>;

MaskRing Square(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// Random points in [0, 10]^2 plus the corners, heights f.
Surface Sample(std::size_t n, uint64_t seed, const Height& f) {
  std::vector<Point2> p = testing::UniformPoints(n, seed);
  std::vector<std::array<double, 3>> points;
  for (const Point2& q : p) points.push_back({10 * q.x, 10 * q.y, f(10 * q.x, 10 * q.y)});
  for (const auto& c : {Point2{0, 0}, Point2{10, 0}, Point2{10, 10}, Point2{0, 10}}) {
    points.push_back({c.x, c.y, f(c.x, c.y)});
  }
  return MakeSurface(points, {}, "test");
}

MeasureSummary MeasureMasked(const std::vector<MaskRing>& rings, MaskMode mode, const Height& gap) {
  MeasureOptions options;
  options.domain.kind = DomainKind::kHull;  // Ω = [0, 10]²
  options.weight = WeightMode::kMask;
  options.mask = rings;
  options.mask_mode = mode;
  options.detect_change = true;
  options.level_of_detection = 1.0;
  return Measure(Sample(400, 11, [](double, double) { return 0.0; }), Sample(300, 12, gap), options);
}

const Height kRamp = [](double x, double) { return x - 5.0; };  // d = x − 5
const Height kConstant = [](double, double) { return 0.5; };

double Rel(double value, double truth) { return std::fabs(value - truth) / std::fabs(truth); }

TEST(MaskRegionTest, SquareWithSquareHole) {
  // Outer [1, 9]², hole [3, 6] x [4, 7]: area 64 − 9 = 55.
  const std::vector<MaskRing> rings = {Square(1, 1, 9, 9), Square(3, 4, 6, 7)};
  const MeasureSummary flat = MeasureMasked(rings, MaskMode::kInclude, kConstant);
  EXPECT_LT(Rel(flat.rho_d, 0.5 * 55), 1e-12);
  EXPECT_LT(Rel(flat.weight_integral, 55), 1e-12);
  EXPECT_LT(Rel(flat.signed_volume, 0.5 * 55), 1e-12);
  // d = x − 5: ∫|d| = 8·16 − 3·2.5 = 120.5; ∫d⁺ = 8·8 − 3·0.5 = 62.5.
  const MeasureSummary ramp = MeasureMasked(rings, MaskMode::kInclude, kRamp);
  EXPECT_LT(Rel(ramp.rho_d, 120.5), 1e-12);
  EXPECT_LT(Rel(ramp.volume_above, 62.5), 1e-12);
  EXPECT_LT(Rel(ramp.volume_below, 58.0), 1e-12);
  EXPECT_LT(Rel(ramp.weight_integral, 55), 1e-12);
  // Fill beyond L = 1 (x > 6, where the hole is not): 8·∫_6^9 (x − 5) = 60 on 8·3 = 24.
  EXPECT_LT(Rel(ramp.fill_area, 24.0), 1e-12);
  EXPECT_LT(Rel(ramp.fill_detected, 60.0), 1e-12);
}

TEST(MaskRegionTest, TwoPartsAreTheSumOfEach) {
  const MaskRing left = {{1, 1}, {4, 1.5}, {3.5, 8}, {1.5, 6}};
  const MaskRing right = {{6, 2}, {9, 2}, {9, 9}, {7, 5}, {6, 9}};
  const MeasureSummary both = MeasureMasked({left, right}, MaskMode::kInclude, kRamp);
  const MeasureSummary a = MeasureMasked({left}, MaskMode::kInclude, kRamp);
  const MeasureSummary b = MeasureMasked({right}, MaskMode::kInclude, kRamp);
  EXPECT_LT(Rel(both.rho_d, a.rho_d + b.rho_d), 1e-12);
  EXPECT_LT(Rel(both.weight_integral, a.weight_integral + b.weight_integral), 1e-12);
  EXPECT_LT(Rel(both.signed_volume, a.signed_volume + b.signed_volume), 1e-12);
}

TEST(MaskRegionTest, ExcludeIsFullMinusInclude) {
  const std::vector<MaskRing> rings = {Square(1, 1, 9, 9), Square(3, 4, 6, 7)};
  const MeasureSummary in = MeasureMasked(rings, MaskMode::kInclude, kRamp);
  const MeasureSummary out = MeasureMasked(rings, MaskMode::kExclude, kRamp);
  // Over [0, 10]²: ∫|x − 5| = 10·25 = 250, area 100.
  EXPECT_LT(Rel(out.rho_d, 250 - 120.5), 1e-12);
  EXPECT_LT(Rel(in.rho_d + out.rho_d, 250), 1e-12);
  EXPECT_LT(Rel(out.weight_integral, 100 - 55), 1e-12);
  // A ring reaching past the data: the enclosing ring still covers it.
  const MeasureSummary past = MeasureMasked({Square(-5, -5, 5, 15)}, MaskMode::kExclude, kRamp);
  EXPECT_LT(Rel(past.rho_d, 125), 1e-12);  // x in [5, 10]
}

TEST(MaskRegionTest, IslandInAHole) {
  // [1, 9]² minus [2, 8]² plus [4, 6]²: area 64 − 36 + 4 = 32.
  const std::vector<MaskRing> rings = {Square(4, 4, 6, 6), Square(1, 1, 9, 9), Square(2, 2, 8, 8)};
  const MeasureSummary s = MeasureMasked(rings, MaskMode::kInclude, kConstant);
  EXPECT_LT(Rel(s.weight_integral, 32), 1e-12);
  EXPECT_LT(Rel(s.rho_d, 16), 1e-12);
  const MaskRegion m = MakeMaskRegion(rings, MaskMode::kInclude, {0, 0});
  EXPECT_EQ(m.depth, (std::vector<int>{2, 0, 1}));
  EXPECT_TRUE(InsideMask(m, {5, 5}));    // island
  EXPECT_FALSE(InsideMask(m, {3, 5}));   // hole
  EXPECT_TRUE(InsideMask(m, {1.5, 5}));  // ring between outer and hole
  EXPECT_FALSE(InsideMask(m, {0.5, 5}));
}

TEST(MaskRegionTest, NodesOnAnyBoundaryAreIn) {
  const std::vector<MaskRing> rings = {Square(1, 1, 9, 9), Square(3, 4, 6, 7)};
  for (const MaskMode mode : {MaskMode::kInclude, MaskMode::kExclude}) {
    const MaskRegion m = MakeMaskRegion(rings, mode, {0, 0}, {{0, 0}, {10, 10}});
    const bool include = mode == MaskMode::kInclude;
    for (const Point2& p : {Point2{1, 5}, Point2{9, 9}, Point2{3, 5}, Point2{4.5, 7}, Point2{6, 4}}) {
      EXPECT_TRUE(InsideMask(m, p)) << p.x << " " << p.y;  // boundaries are in, either mode
    }
    EXPECT_EQ(InsideMask(m, {4.5, 5.5}), !include);  // in the hole
    EXPECT_EQ(InsideMask(m, {2, 2}), include);
    EXPECT_EQ(InsideMask(m, {0.5, 0.5}), !include);
  }
}

// The point test against counting the rings that contain p one by one.
TEST(MaskRegionTest, PointTestMatchesBruteForce) {
  std::vector<MaskRing> rings;
  // A 2,000-vertex star, a hole in it, an island in the hole, and a separate part.
  MaskRing star;
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * M_PI * k / 2000, r = k % 2 == 0 ? 4.0 : 3.6;
    star.push_back({5 + r * std::cos(a), 5 + r * std::sin(a)});
  }
  rings.push_back(star);
  rings.push_back(Square(4, 4, 6, 6));
  rings.push_back(Square(4.5, 4.5, 5.5, 5.5));
  rings.push_back({{9.5, 0}, {10, 0.2}, {9.7, 0.6}});
  std::string error;
  ASSERT_TRUE(ValidMaskRings(rings, &error)) << error;
  const MaskRegion m = MakeMaskRegion(rings, MaskMode::kInclude, {0, 0});
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> u(-0.5, 10.5);
  for (int i = 0; i < 5000; ++i) {
    const Point2 p{u(random), u(random)};
    int count = 0;
    for (const auto& ring : m.rings) count += InsidePolygon(ring, p);
    EXPECT_EQ(InsideMask(m, p), count % 2 == 1) << p.x << " " << p.y;
  }
  // And the area: Σ sign × triangle areas = the rings' areas with signs.
  double area = 0;
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    const auto& t = m.triangles[k];
    area += m.sign[k] * 0.5 * ((t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[1].y - t[0].y) * (t[2].x - t[0].x));
  }
  double star_area = 0;
  for (std::size_t k = 0; k < star.size(); ++k) {
    const auto& p = star[k];
    const auto& q = star[(k + 1) % star.size()];
    star_area += 0.5 * (p[0] * q[1] - q[0] * p[1]);
  }
  EXPECT_LT(Rel(area, star_area - 4 + 1 + 0.13), 1e-12);
}

TEST(MaskRegionTest, RingChecksNameTheRings) {
  std::string error;
  EXPECT_FALSE(ValidMaskRings({Square(0, 0, 4, 4), Square(3, 3, 6, 6)}, &error));
  EXPECT_EQ(error, "mask ring 1 and mask ring 2 cross or touch (edges 2 and 1): rings must be "
                   "disjoint or nested");
  EXPECT_FALSE(ValidMaskRings({Square(0, 0, 4, 4), Square(1, 1, 4, 3)}, &error));  // touching
  EXPECT_NE(error.find("mask ring 1 and mask ring 2 cross or touch"), std::string::npos) << error;
  EXPECT_FALSE(ValidMaskRings({Square(0, 0, 4, 4), {{5, 5}, {8, 8}, {8, 5}, {5, 7}}}, &error));
  EXPECT_EQ(error, "mask ring 2 edges 1 and 3 cross: the polygon must be simple");
  EXPECT_FALSE(ValidMaskRings({{{0, 0}, {1, 1}, {2, 2}}}, &error));
  EXPECT_EQ(error, "mask polygon has zero area");
  EXPECT_TRUE(ValidMaskRings({Square(0, 0, 4, 4), Square(1, 1, 3, 3)}, &error));
  MeasureOptions options;
  options.weight = WeightMode::kUniform;
  options.mask_mode = MaskMode::kExclude;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error, "mask_mode exclude needs a mask");
}

// Ear clipping of a many-vertex ring gives compact triangles: each cell of
// the bucket grid holds few of them (the cost per overlay cell stays flat).
TEST(MaskRegionTest, BucketsStaySmallForARoundRing) {
  MaskRing circle;
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * M_PI * k / 2000;
    circle.push_back({5 + 4 * std::cos(a), 5 + 4 * std::sin(a)});
  }
  const MaskRegion m = MakeMaskRegion({circle}, MaskMode::kInclude, {0, 0});
  EXPECT_EQ(m.triangles.size(), 1998u);
  const double per_bucket = static_cast<double>(m.bucket_items.size()) / (m.columns * m.rows);
  EXPECT_LT(per_bucket, 8.0);
}

}  // namespace
}  // namespace surfreg
