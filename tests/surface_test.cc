// MakeSurface and ValidateSurface: exact origin handling (checked with exact
// dyadic arithmetic) and the documented input errors.
#include "measure/surface.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "tests/testing/exact_rational.h"

namespace surfreg {
namespace {

using testing::Dyadic;
using Points3 = std::vector<std::array<double, 3>>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Runs ValidateSurface and returns the InputError message ("" if none; a
// different exception type fails the test).
std::string ValidationError(const Surface& surface) {
  try {
    ValidateSurface(surface);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "ValidateSurface threw a non-InputError: " << e.what();
    return e.what();
  }
  return "";
}

void ExpectRejected(const Surface& surface, const std::string& what) {
  const std::string message = ValidationError(surface);
  EXPECT_FALSE(message.empty()) << what << ": ValidateSurface accepted it";
  if (!message.empty() && !surface.source.empty()) {
    EXPECT_NE(message.find(surface.source), std::string::npos)
        << what << ": message \"" << message << "\" does not name the source \"" << surface.source << "\"";
  }
}

void ExpectAccepted(const Surface& surface, const std::string& what) {
  EXPECT_EQ(ValidationError(surface), "") << what;
}

// UTM-sized points with millimetre offsets.
Points3 UtmPoints(std::size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> mm(-400000, 400000);  // ±400 m in mm
  Points3 points(n);
  for (auto& p : points) {
    p = {5e5 + mm(rng) * 1e-3, 4.5e6 + mm(rng) * 1e-3, 250.0 + (mm(rng) % 50000) * 1e-3};
  }
  return points;
}

TEST(MakeSurfaceTest, UtmCoordinatesAreStoredExactly) {
  const Points3 points = UtmPoints(5000, 1);
  const Surface s = MakeSurface(points, {}, "utm");
  ASSERT_EQ(s.size(), points.size());
  ASSERT_EQ(s.z.size(), points.size());
  EXPECT_TRUE(s.weight.empty());
  EXPECT_EQ(s.source, "utm");
  double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  for (const auto& p : points) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  for (int k = 0; k < 3; ++k) {
    // A whole number (multiple of the default step 1.0) within half a step
    // of the bounding box centre.
    EXPECT_EQ(s.origin[k], std::round(s.origin[k])) << k;
    EXPECT_LE(std::fabs(s.origin[k] - 0.5 * (lo[k] + hi[k])), 0.5 + 1e-9) << k;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double local[3] = {s.xy[i].x, s.xy[i].y, s.z[i]};
    for (int k = 0; k < 3; ++k) {
      // The stored value is the exact difference, so origin + local
      // recovers the input bit for bit.
      ASSERT_TRUE(Dyadic::FromDouble(local[k]) ==
                  Dyadic::FromDouble(points[i][k]) - Dyadic::FromDouble(s.origin[k]))
          << "point " << i << " coordinate " << k;
      ASSERT_EQ(s.origin[k] + local[k], points[i][k]) << "point " << i << " coordinate " << k;
      // Small: within the half extent plus the rounding step.
      ASSERT_LE(std::fabs(local[k]), 0.5 * (hi[k] - lo[k]) + 1.0);
    }
  }
  ExpectAccepted(s, "utm points");
}

TEST(MakeSurfaceTest, OriginStep) {
  const Points3 points = UtmPoints(100, 2);
  for (double step : {0.5, 10.0, 1000.0}) {
    const Surface s = MakeSurface(points, {}, "", step);
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(std::fmod(s.origin[k], step), 0.0) << "step " << step;
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
      ASSERT_EQ(s.origin[0] + s.xy[i].x, points[i][0]);
      ASSERT_EQ(s.origin[1] + s.xy[i].y, points[i][1]);
    }
  }
  // Analytic: points (10, 20, 1) and (14, 30, 3): centre (12, 25, 2).
  const Surface s = MakeSurface({{10, 20, 1}, {14, 30, 3}, {12, 21, 2}});
  EXPECT_EQ(s.origin[0], 12.0);
  EXPECT_EQ(s.origin[1], 25.0);
  EXPECT_EQ(s.origin[2], 2.0);
  EXPECT_EQ(s.xy[0].x, -2.0);
  EXPECT_EQ(s.xy[1].y, 5.0);
  EXPECT_EQ(s.z[2], 0.0);
}

TEST(MakeSurfaceTest, Weights) {
  const Points3 points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Surface s = MakeSurface(points, {1.0, 0.0, 2.5}, "w");
  ASSERT_EQ(s.weight.size(), 3u);
  EXPECT_EQ(s.weight[2], 2.5);
  ExpectAccepted(s, "weights with a zero");
  for (const std::vector<double>& w : {std::vector<double>{1.0}, std::vector<double>{1, 1},
                                       std::vector<double>{1, 1, 1, 1}}) {
    try {
      MakeSurface(points, w, "weights.txt");
      ADD_FAILURE() << w.size() << " weights for 3 points accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("weights.txt"), std::string::npos) << e.what();
    }
  }
}

TEST(ValidateSurfaceTest, RejectsNonFiniteCoordinates) {
  const Points3 good = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}};
  for (int coord = 0; coord < 3; ++coord) {
    for (double bad : {kNaN, kInf, -kInf}) {
      for (std::size_t i : {std::size_t{0}, std::size_t{3}}) {
        Points3 points = good;
        points[i][coord] = bad;
        const Surface s = MakeSurface(points, {}, "cloud_17.las");
        ExpectRejected(s, "point " + std::to_string(i) + " coordinate " + std::to_string(coord) +
                              " = " + std::to_string(bad));
      }
    }
  }
}

TEST(ValidateSurfaceTest, RejectsCoordinatesBeyondTheGeometrysRange) {
  const Points3 good = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}};
  for (int coord = 0; coord < 3; ++coord) {
    Points3 points = good;
    points[2][coord] = -2e60;
    const Surface s = MakeSurface(points, {}, "far.xyz");
    ExpectRejected(s, "coordinate " + std::to_string(coord) + " = -2e60");
    EXPECT_NE(ValidationError(s).find("point 3 has a coordinate beyond 1e60"), std::string::npos)
        << ValidationError(s);
  }
  // Far from the origin, but within range: accepted.
  ExpectAccepted(MakeSurface({{1e59, 1e59, 0}, {2e59, 1e59, 0}, {1e59, 2e59, 0}}, {}, "far.xyz"),
                 "coordinates of 1e59-2e59");
}

// Checked in chunks on several threads, the first bad point of all is the
// one named, whichever chunk finishes first.
TEST(ValidateSurfaceTest, NamesTheFirstBadPointOnAnyThreadCount) {
  Points3 points;
  for (int i = 0; i < 300000; ++i) points.push_back({static_cast<double>(i % 1000), static_cast<double>(i / 1000), 0.0});
  points[250000][2] = kNaN;        // a late chunk
  points[140001][0] = -2e60;       // an earlier one, another fault
  points[200000][2] = kInf;
  const Surface s = MakeSurface(points, {}, "big.xyz");
  for (const int threads : {1, 2, 8}) {
    try {
      ValidateSurface(s, Execution{threads});
      ADD_FAILURE() << "accepted on " << threads << " threads";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("point 140002 has a coordinate beyond 1e60"), std::string::npos)
          << threads << ": " << e.what();
    }
  }
}

TEST(ValidateSurfaceTest, RejectsBadWeights) {
  const Points3 points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (double bad : {-1.0, -1e-300, kNaN, kInf, -kInf}) {
    const Surface s = MakeSurface(points, {1.0, bad, 1.0}, "weighted.xyz");
    ExpectRejected(s, "weight " + std::to_string(bad));
  }
  ExpectAccepted(MakeSurface(points, {0.0, 0.0, 1e300}, "weighted.xyz"), "zero and huge weights");
}

TEST(ValidateSurfaceTest, RejectsTooFewIdenticalOrCollinear) {
  const std::string src = "survey_2019.csv";
  ExpectRejected(MakeSurface({}, {}, src), "no points");
  ExpectRejected(MakeSurface({{0, 0, 0}}, {}, src), "one point");
  ExpectRejected(MakeSurface({{0, 0, 0}, {1, 2, 3}}, {}, src), "two points");
  ExpectRejected(MakeSurface({{5, 5, 0}, {5, 5, 1}, {5, 5, 2}, {5, 5, 3}}, {}, src),
                 "identical xy (different z)");
  ExpectRejected(MakeSurface({{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {-7, -7, 4}}, {}, src), "on y = x");
  ExpectRejected(MakeSurface({{3, 0, 0}, {3, 0, 0}, {3, 0, 1}, {3, 9, 0}}, {}, src),
                 "duplicates then a line x = 3");
  // UTM-sized points exactly on a line (5e5 + t/2, 4.5e6 + t): exact test.
  Points3 line;
  for (int t = 0; t < 100; ++t) line.push_back({5e5 + 0.5 * t, 4.5e6 + t, 100.0});
  ExpectRejected(MakeSurface(line, {}, src), "UTM line");
  // One of them a millimetre off: a surface.
  line[50][0] += 0.001;
  ExpectAccepted(MakeSurface(line, {}, src), "UTM line with one point 1 mm off");
}

TEST(ValidateSurfaceTest, CollinearityIsExactAndWithinRounding) {
  // Built directly (no origin shift): the third point is one ulp off y = x,
  // a sliver the exact predicates would triangulate, but no surface.
  Surface s;
  s.source = "ulp";
  s.xy = {{0, 0}, {1, 1}, {2, std::nextafter(2.0, 3.0)}};
  s.z = {0, 0, 0};
  ExpectRejected(s, "one ulp off the line");
  EXPECT_NE(ValidationError(s).find("on one line in xy within rounding"), std::string::npos) << ValidationError(s);
  s.xy[2] = {2, 2};
  ExpectRejected(s, "exactly on the line");
  // A band just wider than kMinBandWidthRatio of its length is a surface
  // (a thin strip), one just narrower is not.
  s.xy = {{0, 0}, {1, 0}, {2, 0}, {1, 3e-9}};  // width 3e-9 across 2: 1.5e-9
  s.z = {0, 0, 0, 0};
  ExpectAccepted(s, "a band 1.5e-9 of its length wide");
  s.xy[3] = {1, 1e-9};  // 0.5e-9
  ExpectRejected(s, "a band 0.5e-9 of its length wide");
  // The case: 100 points (0.01 i, 0.02 i), on y = 2x up to rounding.
  Points3 rounded;
  for (int i = 0; i < 100; ++i) rounded.push_back({0.01 * i, 0.02 * i, 1.0});
  ExpectRejected(MakeSurface(rounded, {}, "rounded_line.xyz"), "(0.01 i, 0.02 i)");
  // Leading duplicates must not hide a non-collinear point.
  s.xy = {{0, 0}, {0, 0}, {0, 0}, {1, 0}, {0, 1}};
  s.z = {0, 0, 0, 0, 0};
  ExpectAccepted(s, "duplicates first");
  s.xy = {{0, 0}, {0, 0}, {0, 0}, {1, 0}, {2, 0}};
  ExpectRejected(s, "duplicates then a line");
}

TEST(ValidateSurfaceTest, RejectsInconsistentSizes) {
  Surface s;
  s.source = "broken";
  s.xy = {{0, 0}, {1, 0}, {0, 1}};
  s.z = {0, 0};
  ExpectRejected(s, "z shorter than xy");
  s.z = {0, 0, 0};
  s.weight = {1, 1};
  ExpectRejected(s, "weight shorter than xy");
  s.weight = {1, 1, 1};
  ExpectAccepted(s, "consistent");
}

}  // namespace
}  // namespace surfreg
