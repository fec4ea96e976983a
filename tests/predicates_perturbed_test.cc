// InCirclePerturbed and its documented tie rule against an independent exact
// oracle (tests/testing/exact_rational.h) and brute-force triangulation
// checks. Part of predicates_test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "measure/predicates.h"
#include "tests/testing/delaunay_checks.h"
#include "tests/testing/exact_rational.h"
#include "tests/testing/predicate_oracle.h"

namespace surfreg {
namespace {

using testing::Dyadic;
using testing::ExactInCirclePerturbedSign;
using testing::ExactInCircleSign;
using testing::ExactOrientDet;
using testing::ExactOrientSign;
using testing::LatticeCircle;
using testing::Str;
using testing::Ulps;

// ---------------------------------------------------------------------------
// InCirclePerturbed.

TEST(InCirclePerturbedTest, EqualsInCircleSignWhenNonZero) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0), angle(0.0, 2.0 * M_PI);
  std::uniform_int_distribution<int> k(-2, 2);
  int bad = 0;
  for (int n = 0; n < 20000; ++n) {
    Point2 p[4];
    if (n % 2 == 0) {
      for (Point2& q : p) q = {u(rng), u(rng)};
    } else {  // near-cocircular
      for (Point2& q : p) {
        const double t = angle(rng);
        q = {Ulps(std::cos(t), k(rng)), Ulps(std::sin(t), k(rng))};
      }
    }
    const int exact = ExactInCircleSign(p[0], p[1], p[2], p[3]);
    if (exact == 0) continue;
    const int got = InCirclePerturbed(p[0], p[1], p[2], p[3]);
    if (got != exact && bad++ < 5) {
      ADD_FAILURE() << "InCirclePerturbed(" << Str(p[0], p[1], p[2], p[3]) << ") = " << got
                    << ", exact in-circle sign " << exact;
    }
  }
  EXPECT_EQ(bad, 0);
}

// Exactly cocircular quadruples (lattice circles, also offset), in all 24
// argument orders: never 0; equal to the documented rule evaluated from its
// definition; an alternating function of its four arguments (it is the sign
// of the determinant of the perturbed lifted points, so every transposition
// flips it — in particular swapping a and b, and it is unchanged by the
// rotation (a, b, c) -> (b, c, a)).
TEST(InCirclePerturbedTest, CocircularQuadruplesFollowTheDocumentedRule) {
  std::mt19937_64 rng(32);
  int bad = 0;
  auto report = [&](const std::string& what) {
    if (bad++ < 8) ADD_FAILURE() << what;
  };
  const std::array<int, 4> identity = {0, 1, 2, 3};
  for (int r : {5, 25, 65}) {
    const std::vector<std::pair<int, int>> circle = LatticeCircle(r);
    std::uniform_int_distribution<std::size_t> pick(0, circle.size() - 1);
    for (double offset : {0.0, 1e6}) {
      for (int n = 0; n < 40; ++n) {
        std::size_t i[4];
        for (std::size_t& j : i) j = pick(rng);
        if (std::set<std::size_t>(i, i + 4).size() < 4) continue;
        Point2 p[4];
        for (int j = 0; j < 4; ++j) {
          p[j] = {offset + circle[i[j]].first, -offset + circle[i[j]].second};
        }
        std::array<int, 4> perm = identity;
        const int base = InCirclePerturbed(p[0], p[1], p[2], p[3]);
        do {
          const Point2 &a = p[perm[0]], &b = p[perm[1]], &c = p[perm[2]], &d = p[perm[3]];
          const int got = InCirclePerturbed(a, b, c, d);
          const int expected = ExactInCirclePerturbedSign(a, b, c, d);
          int inversions = 0;
          for (int x = 0; x < 4; ++x) {
            for (int y = x + 1; y < 4; ++y) inversions += perm[x] > perm[y] ? 1 : 0;
          }
          const int parity = inversions % 2 == 0 ? 1 : -1;
          if (got != 1 && got != -1) report("InCirclePerturbed(" + Str(a, b, c, d) + ") = " + std::to_string(got));
          if (got != expected) {
            report("InCirclePerturbed(" + Str(a, b, c, d) + ") = " + std::to_string(got) +
                   ", documented rule gives " + std::to_string(expected));
          }
          if (got != parity * base) {
            report("InCirclePerturbed not alternating: permutation of " + Str(p[0], p[1], p[2], p[3]) +
                   " with parity " + std::to_string(parity) + " gives " + std::to_string(got) +
                   ", identity gives " + std::to_string(base));
          }
          if (InCirclePerturbed(b, a, c, d) != -got) report("swap a,b does not flip: " + Str(a, b, c, d));
          if (InCirclePerturbed(b, c, a, d) != got) report("rotation changes result: " + Str(a, b, c, d));
        } while (std::next_permutation(perm.begin(), perm.end()));
      }
    }
  }
  EXPECT_EQ(bad, 0);
}

// Never 0 for four distinct points with a, b, c not collinear, and equal to
// the documented rule: every ordered quadruple of a 4 x 3 grid (many
// cocircular, many with d on a line through two of a, b, c).
TEST(InCirclePerturbedTest, NeverZeroOnDistinctPoints) {
  std::vector<Point2> grid;
  for (int x = 0; x < 4; ++x) {
    for (int y = 0; y < 3; ++y) grid.push_back({static_cast<double>(x), static_cast<double>(y)});
  }
  int bad = 0, mismatch = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    for (std::size_t j = 0; j < grid.size(); ++j) {
      for (std::size_t k = 0; k < grid.size(); ++k) {
        if (ExactOrientSign(grid[i], grid[j], grid[k]) == 0) continue;
        for (std::size_t l = 0; l < grid.size(); ++l) {
          if (l == i || l == j || l == k) continue;
          const int got = InCirclePerturbed(grid[i], grid[j], grid[k], grid[l]);
          if (got != 1 && got != -1 && bad++ < 5) {
            ADD_FAILURE() << "InCirclePerturbed(" << Str(grid[i], grid[j], grid[k], grid[l]) << ") = " << got;
          }
          const int expected = ExactInCirclePerturbedSign(grid[i], grid[j], grid[k], grid[l]);
          if (got != expected && mismatch++ < 5) {
            ADD_FAILURE() << "InCirclePerturbed(" << Str(grid[i], grid[j], grid[k], grid[l]) << ") = " << got
                          << ", documented rule gives " << expected;
          }
        }
      }
    }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(mismatch, 0);
}

// The four corners p0..p3 (counter-clockwise) of a square: with the
// perturbation they are in convex position and not cocircular, so exactly
// one diagonal has both its triangles locally Delaunay:
//   diagonal p0-p2: triangles (p0,p1,p2) and (p0,p2,p3), opposite p3 and p1;
//   diagonal p1-p3: triangles (p1,p2,p3) and (p1,p3,p0), opposite p0 and p2.
// Which one follows from the rule: the lexicographically largest corner is
// raised the most (dominantly), lifting it above the plane through the other
// three lifted corners, i.e. outside their circle; so the triangle of the
// other three is Delaunay and the chosen diagonal is the one that does not
// touch the largest corner. For an axis-aligned square (x0,y0)+(0|s, 0|s)
// the largest corner is (x0+s, y0+s): the diagonal (x0+s,y0)-(x0,y0+s).
TEST(InCirclePerturbedTest, SquareHasExactlyOneDelaunayDiagonal) {
  struct Square {
    Point2 p[4];
    int diagonal;  // expected: 0 for p0-p2, 1 for p1-p3
  };
  const double s2 = 0.5;
  const std::vector<Square> squares = {
      {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1},                   // largest (1,1) = p2
      {{{1, 0}, {1, 1}, {0, 1}, {0, 0}}, 0},                   // same square, rotated labels
      {{{1e6, 5e6}, {1e6 + s2, 5e6}, {1e6 + s2, 5e6 + s2}, {1e6, 5e6 + s2}}, 1},
      // A diamond: corners (1,0), (2,1), (1,2), (0,1); largest is (2,1) = p1.
      {{{1, 0}, {2, 1}, {1, 2}, {0, 1}}, 0},
      // A rotated square with integer corners (3,0), (4,3), (1,4), (0,1).
      {{{3, 0}, {4, 3}, {1, 4}, {0, 1}}, 0},  // largest (4,3) = p1
      // Not a square, on x² + y² = 25: the largest corner (5,0) = p0 and the
      // smallest (-3,-4) = p3 are adjacent, so this one also tells "largest
      // dominates" from "smallest dominates" (which would give p0-p2).
      {{{5, 0}, {4, 3}, {0, 5}, {-3, -4}}, 1},
  };
  for (const Square& sq : squares) {
    const Point2* p = sq.p;
    ASSERT_EQ(ExactInCircleSign(p[0], p[1], p[2], p[3]), 0);
    const bool d02 = InCirclePerturbed(p[0], p[1], p[2], p[3]) < 0 &&
                     InCirclePerturbed(p[0], p[2], p[3], p[1]) < 0;
    const bool d13 = InCirclePerturbed(p[1], p[2], p[3], p[0]) < 0 &&
                     InCirclePerturbed(p[1], p[3], p[0], p[2]) < 0;
    EXPECT_NE(d02, d13) << "square " << Str(p[0], p[1], p[2], p[3]) << ": diagonal p0-p2 "
                        << (d02 ? "" : "not ") << "Delaunay, p1-p3 " << (d13 ? "" : "not ") << "Delaunay";
    EXPECT_EQ(d13 ? 1 : 0, sq.diagonal) << "square " << Str(p[0], p[1], p[2], p[3]);
  }
}

// k exactly cocircular points (a convex polygon): the perturbed predicate
// must define one triangulation. By brute force, the triangles (i, j, l)
// with every other point outside under InCirclePerturbed must number k - 2,
// use each polygon edge once, and cover the polygon's area exactly.
TEST(InCirclePerturbedTest, CocircularPolygonIsTriangulatedConsistently) {
  for (int r : {5, 25, 65}) {
    std::vector<std::pair<int, int>> circle = LatticeCircle(r);
    std::vector<Point2> p;
    for (const auto& q : circle) p.push_back({static_cast<double>(q.first), static_cast<double>(q.second)});
    std::sort(p.begin(), p.end(), [](const Point2& a, const Point2& b) {
      return std::atan2(a.y, a.x) < std::atan2(b.y, b.x);
    });
    const int k = static_cast<int>(p.size());
    int count = 0;
    Dyadic area;
    std::vector<int> edge_use(static_cast<std::size_t>(k) * k, 0);
    for (int i = 0; i < k; ++i) {
      for (int j = i + 1; j < k; ++j) {
        for (int l = j + 1; l < k; ++l) {  // i < j < l in angle order: counter-clockwise
          bool empty = true;
          for (int m = 0; m < k && empty; ++m) {
            if (m != i && m != j && m != l) empty = InCirclePerturbed(p[i], p[j], p[l], p[m]) < 0;
          }
          if (!empty) continue;
          ++count;
          area = area + ExactOrientDet(p[i], p[j], p[l]);
          ++edge_use[i * k + j];
          ++edge_use[j * k + l];
          ++edge_use[i * k + l];
        }
      }
    }
    std::vector<int32_t> polygon(k);
    for (int i = 0; i < k; ++i) polygon[i] = i;
    EXPECT_EQ(count, k - 2) << "radius " << r << ", " << k << " cocircular points";
    EXPECT_TRUE(area == testing::TwiceArea(p, polygon)) << "radius " << r;
    for (int i = 0; i + 1 < k; ++i) {
      EXPECT_EQ(edge_use[i * k + (i + 1)], 1) << "polygon edge " << i;
    }
    EXPECT_EQ(edge_use[0 * k + (k - 1)], 1) << "polygon edge closing";
  }
}

}  // namespace
}  // namespace surfreg
