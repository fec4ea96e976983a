// Change detection: fill and cut beyond a level of detection, the gap at A's
// nodes, and dz statistics, against closed forms.
//
// The analytic pair: A is the plane z = 0 (exactly linear on any mesh); B is
// 0 except for an n-sided pyramid hill (apex height h, corners on a circle of
// radius R) and an n-sided pyramid pit. B's samples are the apexes, the ring
// corners and random points farther than 1.3 R from each apex, so B's
// Delaunay mesh holds each pyramid's fan of n triangles (each fan triangle's
// circumcircle lies within R / cos(π/n) of its apex) and every other
// triangle has z = 0 at all three corners: F̂_B is the pyramids exactly.
// Volumes beyond L: the part of a pyramid where d > L is the pyramid's base
// scaled by (1 − L/h), so fill = A_L (h − L)/3 + L A_L, A_L = A_0 (1 − L/h)².
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "measure/dz_statistics.h"
#include "measure/input_error.h"
#include "measure/measures.h"
#include "measure/surface.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Pyramid {
  double cx, cy, height, radius;  // height < 0: a pit
  int sides;
  double BaseArea() const { return 0.5 * sides * radius * radius * std::sin(2 * kPi / sides); }
  double Volume() const { return BaseArea() * std::fabs(height) / 3.0; }
  // ∫ over {|d| > L} of |d|, and that area.
  double VolumeBeyond(double lod) const {
    const double h = std::fabs(height);
    if (lod >= h) return 0.0;
    return AreaBeyond(lod) * ((h - lod) / 3.0 + lod);
  }
  double AreaBeyond(double lod) const {
    const double h = std::fabs(height);
    return lod >= h ? 0.0 : BaseArea() * (1 - lod / h) * (1 - lod / h);
  }
};

const Pyramid kHill{2.0, 1.0, 3.0, 2.5, 12};
const Pyramid kPit{-3.0, -2.0, -1.5, 2.0, 12};

Surface PyramidSurface(uint64_t seed) {
  std::vector<std::array<double, 3>> points;
  for (const Pyramid& p : {kHill, kPit}) {
    points.push_back({p.cx, p.cy, p.height});
    for (int k = 0; k < p.sides; ++k) {
      const double angle = 2 * kPi * k / p.sides;
      points.push_back({p.cx + p.radius * std::cos(angle), p.cy + p.radius * std::sin(angle), 0.0});
    }
  }
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> coordinate(-8.0, 8.0);
  while (points.size() < 1500) {
    const double x = coordinate(random), y = coordinate(random);
    bool far = true;
    for (const Pyramid& p : {kHill, kPit}) far = far && std::hypot(x - p.cx, y - p.cy) > 1.3 * p.radius;
    if (far) points.push_back({x, y, 0.0});
  }
  for (double x : {-8.0, 8.0}) {  // a square hull, so Ω is known
    for (double y : {-8.0, 8.0}) points.push_back({x, y, 0.0});
  }
  return MakeSurface(points, {}, "pyramids");
}

Surface Plane(uint64_t seed, int n) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> coordinate(-9.0, 9.0);
  std::vector<std::array<double, 3>> points;
  for (double x : {-9.0, 9.0}) {
    for (double y : {-9.0, 9.0}) points.push_back({x, y, 0.0});
  }
  while (static_cast<int>(points.size()) < n) points.push_back({coordinate(random), coordinate(random), 0.0});
  return MakeSurface(points, {}, "plane");
}

void ExpectRelative(double actual, double expected, double tolerance) {
  EXPECT_NEAR(actual, expected, tolerance * std::fabs(expected)) << "expected " << expected;
}

// Over the hull Ω is the square [-8, 8]² (the corners are samples); the data
// domain leaves out the corners' sparse fans, where d = 0: the same volumes.
TEST(ChangeDetection, CutAndFillOfPyramidsMatchClosedForms) {
  const Surface a = Plane(1, 2000), b = PyramidSurface(2);
  MeasureOptions options;
  options.detect_change = true;
  for (double lod : {0.0, 0.4, 1.0, 2.0}) {
    options.level_of_detection = lod;
    options.domain.kind = lod == 1.0 ? DomainKind::kData : DomainKind::kHull;
    const MeasureSummary s = Measure(a, b, options);
    ExpectRelative(s.volume_above, kHill.Volume(), 1e-9);
    ExpectRelative(s.volume_below, kPit.Volume(), 1e-9);
    if (options.domain.kind == DomainKind::kHull) {
      ExpectRelative(s.overlap_area, 16.0 * 16.0, 1e-12);
    } else {
      EXPECT_LT(s.overlap_area, 16.0 * 16.0 - 1.0);
    }
    ExpectRelative(s.fill_detected, kHill.VolumeBeyond(lod), 1e-9);
    ExpectRelative(s.fill_area, kHill.AreaBeyond(lod), 1e-9);
    if (lod < std::fabs(kPit.height)) {
      ExpectRelative(s.cut_detected, kPit.VolumeBeyond(lod), 1e-9);
      ExpectRelative(s.cut_area, kPit.AreaBeyond(lod), 1e-9);
    } else {
      EXPECT_EQ(s.cut_detected, 0.0);
      EXPECT_EQ(s.cut_area, 0.0);
    }
  }
}

TEST(ChangeDetection, SingleThreadAgrees) {
  const Surface a = Plane(3, 1500), b = PyramidSurface(4);
  MeasureOptions options;
  options.detect_change = true;
  options.level_of_detection = 0.7;
  const MeasureSummary two = Measure(a, b, options);
  options.threads = 1;
  const MeasureSummary one = Measure(a, b, options);
  ExpectRelative(one.fill_detected, two.fill_detected, 1e-12);
  ExpectRelative(one.cut_detected, two.cut_detected, 1e-12);
  ExpectRelative(one.fill_detected, kHill.VolumeBeyond(0.7), 1e-9);
}

TEST(ChangeDetection, LevelAboveEveryGapDetectsNothing) {
  MeasureOptions options;
  options.detect_change = true;
  options.level_of_detection = 3.5;  // above the hill's height and the pit's depth
  const MeasureSummary s = Measure(Plane(5, 800), PyramidSurface(6), options);
  EXPECT_EQ(s.fill_detected, 0.0);
  EXPECT_EQ(s.cut_detected, 0.0);
  EXPECT_EQ(s.fill_area, 0.0);
  ExpectRelative(s.volume_above, kHill.Volume(), 1e-9);  // the plain volumes are unchanged
}

// The hill is symmetric about the vertical line x = 2 (12 corners at multiples
// of 30°), so a mask covering x > 2 keeps exactly half of it, and none of the
// pit (at x < −1). Over the hull, whose part in the mask is known.
TEST(ChangeDetection, MaskKeepsTheAnalyticHalf) {
  MeasureOptions options;
  options.domain.kind = DomainKind::kHull;
  options.detect_change = true;
  options.weight = WeightMode::kMask;
  options.mask = {{{2.0, -8.5}, {8.5, -8.5}, {8.5, 8.5}, {2.0, 8.5}}};
  for (double lod : {0.0, 1.2}) {
    options.level_of_detection = lod;
    const MeasureSummary s = Measure(Plane(7, 1500), PyramidSurface(8), options);
    ExpectRelative(s.volume_above, kHill.Volume() / 2, 1e-9);
    EXPECT_NEAR(s.volume_below, 0.0, 1e-12);
    ExpectRelative(s.weight_integral, 6.0 * 16.0, 1e-9);  // mask ∩ Ω: x in [2, 8], y in [−8, 8]
    ExpectRelative(s.fill_detected, kHill.VolumeBeyond(lod) / 2, 1e-9);
    ExpectRelative(s.fill_area, kHill.AreaBeyond(lod) / 2, 1e-9);
    EXPECT_NEAR(s.cut_detected, 0.0, 1e-12);
  }
}

TEST(ChangeDetection, InvalidLevelOrUnionModeIsAnInputError) {
  MeasureOptions options;
  options.detect_change = true;
  options.level_of_detection = -1.0;
  EXPECT_THROW(Measure(Plane(9, 100), PyramidSurface(10), options), InputError);
  options.level_of_detection = std::nan("");
  EXPECT_THROW(Measure(Plane(9, 100), PyramidSurface(10), options), InputError);
  options.level_of_detection = 0.5;
  options.volume = VolumeMode::kUnion;
  EXPECT_THROW(Measure(Plane(9, 100), PyramidSurface(10), options), InputError);
}

// B = A + 0.25 + 0.5 x on the overlap: the gap at A's nodes is that plane
// (B is linear), in A's input order, NaN at A's nodes outside B's hull. Over
// the hull: B's corners are samples, but its data domain leaves out their
// sparse fans (measure_domain_test checks dz_a over the data domain).
TEST(NodeGaps, GapAtEveryNodeOfAInInputOrder) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::array<double, 3>> pa, pb;
  for (int i = 0; i < 400; ++i) pa.push_back({3 * u(random), 3 * u(random), std::sin(u(random))});
  for (double x : {-2.0, 2.0}) {
    for (double y : {-2.0, 2.0}) pb.push_back({x, y, 0.25 + 0.5 * x});
  }
  for (int i = 0; i < 300; ++i) {
    const double x = 2 * u(random), y = 2 * u(random);
    pb.push_back({x, y, 0.25 + 0.5 * x});
  }
  MeasureOptions options;
  options.keep_node_gaps = true;
  options.domain.kind = DomainKind::kHull;
  const MeasureSummary s = Measure(MakeSurface(pa), MakeSurface(pb), options);
  ASSERT_EQ(s.dz_a.size(), pa.size());
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const bool inside = std::fabs(pa[i][0]) < 2 && std::fabs(pa[i][1]) < 2;
    if (inside) {
      EXPECT_NEAR(s.dz_a[i], 0.25 + 0.5 * pa[i][0] - pa[i][2], 1e-12) << i;
    } else {
      EXPECT_TRUE(std::isnan(s.dz_a[i])) << i;
    }
  }
  EXPECT_TRUE(Measure(MakeSurface(pa), MakeSurface(pb)).dz_a.empty());  // only when asked
}

TEST(DzStatistics, HandValues) {
  // Sorted: −2, 0, 1, 1, 10. Median 1; |dz − 1| = 3, 1, 0, 0, 9 → median 1.
  const DzStatistics s = ComputeDzStatistics({1.0, 10.0, -2.0, 0.0, 1.0});
  EXPECT_EQ(s.count, 5);
  EXPECT_DOUBLE_EQ(s.mean, 2.0);
  EXPECT_DOUBLE_EQ(s.median, 1.0);
  EXPECT_DOUBLE_EQ(s.nmad, 1.4826);
  EXPECT_DOUBLE_EQ(s.stddev, std::sqrt((1 + 64 + 16 + 4 + 1) / 4.0));
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt((1 + 100 + 4 + 0 + 1) / 5.0));
  EXPECT_DOUBLE_EQ(s.min, -2.0);
  EXPECT_DOUBLE_EQ(s.max, 10.0);
  // |dz| sorted 0, 1, 1, 2, 10: the 0.9 quantile at position 3.6 → 2 + 0.6 · 8.
  EXPECT_DOUBLE_EQ(s.le90, 6.8);
}

TEST(DzStatistics, SkipsNonFiniteAndMaskedValues) {
  const double nan = std::nan("");
  const DzStatistics s = ComputeDzStatistics({nan, 4.0, INFINITY, 2.0, 100.0}, {true, true, true, true, false});
  EXPECT_EQ(s.count, 2);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  const DzStatistics none = ComputeDzStatistics({nan});
  EXPECT_EQ(none.count, 0);
  EXPECT_TRUE(std::isnan(none.median));
  const DzStatistics one = ComputeDzStatistics({5.0});
  EXPECT_EQ(one.stddev, 0.0);
  EXPECT_EQ(one.nmad, 0.0);
}

TEST(DzStatistics, NmadOfGaussianSamplesIsSigma) {
  std::mt19937_64 random(12);
  std::normal_distribution<double> noise(0.3, 0.05);
  std::vector<double> dz(200000);
  for (double& v : dz) v = noise(random);
  dz[0] = 1e3;  // one blunder: moves the std, not the NMAD
  const DzStatistics s = ComputeDzStatistics(dz);
  EXPECT_NEAR(s.nmad, 0.05, 0.0015);
  EXPECT_NEAR(s.median, 0.3, 0.001);
  EXPECT_GT(s.stddev, 0.1);
}

// The q-quantile of the sorted values, linear between order statistics.
double SortedQuantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double position = q * static_cast<double>(v.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, v.size() - 1);
  return v[below] + (position - static_cast<double>(below)) * (v[above] - v[below]);
}

// Selection (nth_element) against a full sort: the same order statistics,
// for odd and even counts, ties and a mask.
TEST(DzStatistics, QuantilesEqualThoseOfTheSortedValues) {
  std::mt19937_64 random(7);
  std::uniform_int_distribution<int> level(-40, 40);
  for (const int n : {2, 3, 10, 11, 1000, 1001}) {
    std::vector<double> dz(n);
    std::vector<bool> keep(n);
    for (int i = 0; i < n; ++i) dz[i] = 0.25 * level(random), keep[i] = i % 7 != 3;
    std::vector<double> kept;
    for (int i = 0; i < n; ++i) {
      if (keep[i]) kept.push_back(dz[i]);
    }
    const double median = SortedQuantile(kept, 0.5);
    std::vector<double> deviation, magnitude;
    for (const double v : kept) deviation.push_back(std::fabs(v - median)), magnitude.push_back(std::fabs(v));
    const DzStatistics s = ComputeDzStatistics(dz, keep);
    EXPECT_EQ(s.median, median) << n;
    EXPECT_EQ(s.nmad, 1.4826 * SortedQuantile(deviation, 0.5)) << n;
    EXPECT_EQ(s.le90, SortedQuantile(magnitude, 0.9)) << n;
    EXPECT_EQ(s.min, *std::min_element(kept.begin(), kept.end())) << n;
    EXPECT_EQ(s.max, *std::max_element(kept.begin(), kept.end())) << n;
  }
}


// The parallel selection (rounds of binned counts) against a full sort, on
// inputs large enough for several rounds: a heavy tail that puts nearly
// every value into one bin, few distinct levels (ties across bins), values
// near the largest double, and one value
// repeated. The same bits on 1, 2 and 8 threads; the moments merged by
// chunks equal a plain sum to rounding.
TEST(DzStatistics, LargeInputsSelectExactlyOnAnyThreadCount) {
  std::mt19937_64 random(11);
  std::cauchy_distribution<double> cauchy(0.0, 1e-3);
  std::uniform_int_distribution<int> level(-3, 3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int n = 300001;
  std::vector<std::vector<double>> inputs(4, std::vector<double>(n));
  for (int i = 0; i < n; ++i) {
    inputs[0][i] = i % 1000 == 0 ? 1e12 * unit(random) : cauchy(random);
    inputs[1][i] = 0.5 * level(random);
    inputs[2][i] = 8e307 * unit(random);
    inputs[3][i] = 2.5;
  }
  inputs[0][17] = std::nan("");
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    std::vector<double> kept;
    for (const double v : inputs[k]) {
      if (std::isfinite(v)) kept.push_back(v);
    }
    const double median = SortedQuantile(kept, 0.5);
    std::vector<double> deviation, magnitude;
    long double sum = 0;
    for (const double v : kept) {
      deviation.push_back(std::fabs(v - median)), magnitude.push_back(std::fabs(v));
      sum += v;
    }
    const DzStatistics one = ComputeDzStatistics(inputs[k], {}, Execution{1});
    EXPECT_EQ(one.count, static_cast<int64_t>(kept.size())) << k;
    EXPECT_EQ(one.median, median) << k;
    EXPECT_EQ(one.nmad, 1.4826 * SortedQuantile(deviation, 0.5)) << k;
    EXPECT_EQ(one.le90, SortedQuantile(magnitude, 0.9)) << k;
    if (k != 2) {  // the mean of values near the largest double: rounding at that scale
      EXPECT_NEAR(one.mean, static_cast<double>(sum / kept.size()), 1e-12 * (1 + std::fabs(one.mean))) << k;
    }
    for (const int threads : {2, 8}) {
      const DzStatistics many = ComputeDzStatistics(inputs[k], {}, Execution{threads});
      EXPECT_EQ(std::memcmp(&one, &many, sizeof one), 0) << k << " on " << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace surfreg
