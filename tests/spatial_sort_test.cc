// HilbertIndex against the defining properties of the Hilbert curve, and
// SpatialOrder as a deterministic, locality-preserving permutation.
#include "measure/spatial_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

struct Cell {
  uint32_t x = 0, y = 0;
  bool set = false;
};

// Inverts HilbertIndex on the 2^order grid by enumeration; fails the test if
// it is not a bijection onto 0 .. 4^order - 1.
std::vector<Cell> CellsInCurveOrder(int order) {
  const uint32_t side = 1u << order;
  std::vector<Cell> cells(static_cast<std::size_t>(side) * side);
  for (uint32_t x = 0; x < side; ++x) {
    for (uint32_t y = 0; y < side; ++y) {
      const uint32_t d = HilbertIndex(x, y, order);
      if (d >= cells.size()) {
        ADD_FAILURE() << "HilbertIndex(" << x << ", " << y << ", " << order << ") = " << d
                      << " out of range";
        continue;
      }
      if (cells[d].set) {
        ADD_FAILURE() << "HilbertIndex(" << x << ", " << y << ", " << order << ") = " << d
                      << " also for (" << cells[d].x << ", " << cells[d].y << ")";
      }
      cells[d] = {x, y, true};
    }
  }
  return cells;
}

bool FourNeighbours(const Cell& a, const Cell& b) {
  const uint32_t dx = a.x > b.x ? a.x - b.x : b.x - a.x;
  const uint32_t dy = a.y > b.y ? a.y - b.y : b.y - a.y;
  return dx + dy == 1;
}

TEST(HilbertIndexTest, BijectionWithUnitStepsOnSmallGrids) {
  for (int order = 1; order <= 6; ++order) {
    const std::vector<Cell> cells = CellsInCurveOrder(order);
    for (std::size_t d = 0; d < cells.size(); ++d) ASSERT_TRUE(cells[d].set) << "order " << order << " index " << d;
    for (std::size_t d = 0; d + 1 < cells.size(); ++d) {
      EXPECT_TRUE(FourNeighbours(cells[d], cells[d + 1]))
          << "order " << order << ": index " << d << " at (" << cells[d].x << ", " << cells[d].y
          << "), index " << d + 1 << " at (" << cells[d + 1].x << ", " << cells[d + 1].y << ")";
    }
    // The curve starts and ends in corners on the same side (an open
    // Hilbert curve runs from one corner to an adjacent one).
    const uint32_t m = (1u << order) - 1;
    auto corner = [&](const Cell& c) { return (c.x == 0 || c.x == m) && (c.y == 0 || c.y == m); };
    EXPECT_TRUE(corner(cells.front())) << order;
    EXPECT_TRUE(corner(cells.back())) << order;
    EXPECT_TRUE(FourNeighbours({cells.front().x / m, cells.front().y / m, true},
                               {cells.back().x / m, cells.back().y / m, true}))
        << "order " << order << ": ends in opposite corners";
  }
}

// Self-similarity: each run of 4^j consecutive indices, aligned to a
// multiple of 4^j, fills one aligned 2^j x 2^j block.
TEST(HilbertIndexTest, AlignedRunsFillAlignedBlocks) {
  for (int order = 1; order <= 6; ++order) {
    const std::vector<Cell> cells = CellsInCurveOrder(order);
    for (int j = 1; j < order; ++j) {
      const std::size_t run = std::size_t{1} << (2 * j);
      for (std::size_t start = 0; start < cells.size(); start += run) {
        const uint32_t bx = cells[start].x >> j, by = cells[start].y >> j;
        for (std::size_t d = start; d < start + run; ++d) {
          ASSERT_EQ(cells[d].x >> j, bx) << "order " << order << " level " << j << " index " << d;
          ASSERT_EQ(cells[d].y >> j, by) << "order " << order << " level " << j << " index " << d;
        }
      }
    }
  }
}

// On the largest grids, sampled: the cell with index d + 1 is a 4-neighbour
// of the cell with index d.
TEST(HilbertIndexTest, SuccessorIsANeighbourOnLargeGrids) {
  std::mt19937_64 rng(3);
  for (int order : {10, 14, 16}) {
    const uint32_t side = 1u << order;
    const uint64_t last = (uint64_t{1} << (2 * order)) - 1;
    std::uniform_int_distribution<uint32_t> c(0, side - 1);
    int bad = 0;
    for (int n = 0; n < 20000; ++n) {
      const uint32_t x = c(rng), y = c(rng);
      const uint32_t d = HilbertIndex(x, y, order);
      ASSERT_LE(d, last);
      if (d == last) continue;
      bool found = false;
      const int64_t nb[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      for (const auto& o : nb) {
        const int64_t nx = int64_t{x} + o[0], ny = int64_t{y} + o[1];
        if (nx < 0 || ny < 0 || nx >= side || ny >= side) continue;
        found = found || HilbertIndex(static_cast<uint32_t>(nx), static_cast<uint32_t>(ny), order) == d + 1;
      }
      if (!found && bad++ < 5) {
        ADD_FAILURE() << "order " << order << ": no 4-neighbour of (" << x << ", " << y
                      << ") has index " << d + 1;
      }
    }
    EXPECT_EQ(bad, 0) << order;
  }
}

// The curve level by level, highest first, as its recursive definition
// reads: a quadrant's digit, then the rest turned into that quadrant's frame
// (HilbertIndex takes four levels a step from a table).
uint32_t HilbertIndexByLevels(uint32_t x, uint32_t y, int order) {
  uint32_t index = 0;
  for (uint32_t s = 1u << (order - 1); s > 0; s >>= 1) {
    const uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    index += s * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = s - 1 - (x & (s - 1));
        y = s - 1 - (y & (s - 1));
      }
      std::swap(x, y);
    }
  }
  return index;
}

TEST(HilbertIndexTest, EqualsTheLevelByLevelDefinitionOnEveryOrder) {
  for (int order = 1; order <= 5; ++order) {
    for (uint32_t x = 0; x < (1u << order); ++x) {
      for (uint32_t y = 0; y < (1u << order); ++y) {
        ASSERT_EQ(HilbertIndex(x, y, order), HilbertIndexByLevels(x, y, order)) << order << " " << x << " " << y;
      }
    }
  }
  std::mt19937_64 rng(11);
  for (int order = 6; order <= 16; ++order) {
    std::uniform_int_distribution<uint32_t> c(0, (1u << order) - 1);
    for (int n = 0; n < 20000; ++n) {
      const uint32_t x = c(rng), y = c(rng);
      ASSERT_EQ(HilbertIndex(x, y, order), HilbertIndexByLevels(x, y, order)) << order << " " << x << " " << y;
    }
  }
}

bool IsPermutation(const std::vector<int32_t>& order, std::size_t n) {
  if (order.size() != n) return false;
  std::vector<char> seen(n, 0);
  for (int32_t i : order) {
    if (i < 0 || static_cast<std::size_t>(i) >= n || seen[i]) return false;
    seen[i] = 1;
  }
  return true;
}

double TourLength(const std::vector<Point2>& points, const std::vector<int32_t>& order) {
  double length = 0.0;
  for (std::size_t k = 1; k < order.size(); ++k) {
    length += std::hypot(points[order[k]].x - points[order[k - 1]].x,
                         points[order[k]].y - points[order[k - 1]].y);
  }
  return length;
}

TEST(SpatialOrderTest, IsAPermutation) {
  std::vector<std::vector<Point2>> inputs = {
      {},
      {{1, 2}},
      {{1, 2}, {1, 2}},
      std::vector<Point2>(100, Point2{3, 3}),  // zero extent
      testing::UniformPoints(10, 1),
      testing::UniformPoints(10000, 2),
      testing::GridPoints(50, 1),  // zero height
      testing::GridPoints(40, 40, 0.5, 1e6, 5e6),
      testing::ClusteredPoints(3000, 3, 1e-6, 4),
  };
  std::vector<Point2> dup = testing::UniformPoints(500, 5);
  dup.insert(dup.end(), dup.begin(), dup.end());
  inputs.push_back(dup);
  for (const auto& points : inputs) {
    for (bool brio : {false, true}) {
      for (uint64_t seed : {0ULL, 7ULL}) {
        EXPECT_TRUE(IsPermutation(SpatialOrder(points, brio, seed), points.size()))
            << points.size() << " points, brio " << brio << ", seed " << seed;
      }
    }
  }
}

TEST(SpatialOrderTest, Deterministic) {
  const std::vector<Point2> points = testing::UniformPoints(5000, 6);
  EXPECT_EQ(SpatialOrder(points, true, 42), SpatialOrder(points, true, 42));
  EXPECT_EQ(SpatialOrder(points, false, 42), SpatialOrder(points, false, 42));
  // Without BRIO the seed plays no part; with it, it draws the rounds.
  EXPECT_EQ(SpatialOrder(points, false, 1), SpatialOrder(points, false, 2));
  EXPECT_NE(SpatialOrder(points, true, 1), SpatialOrder(points, true, 2));
}

// The Hilbert order of n uniform points in the unit square has a tour of
// length O(sqrt(n)) (~0.9 sqrt(n)); input (random) order has ~0.52 n.
TEST(SpatialOrderTest, HilbertOrderIsLocal) {
  const std::size_t n = 10000;
  const std::vector<Point2> points = testing::UniformPoints(n, 7);
  std::vector<int32_t> identity(n);
  std::iota(identity.begin(), identity.end(), 0);
  const double random_tour = TourLength(points, identity);
  const double hilbert_tour = TourLength(points, SpatialOrder(points, false, 0));
  EXPECT_GT(random_tour, 0.4 * n);
  EXPECT_LT(hilbert_tour, 2.0 * std::sqrt(static_cast<double>(n))) << "random order: " << random_tour;
  // BRIO: a few rounds, each along the curve.
  const double brio_tour = TourLength(points, SpatialOrder(points, true, 0));
  EXPECT_LT(brio_tour, 10.0 * std::sqrt(static_cast<double>(n)));
  // Also when the points are far from the origin.
  std::vector<Point2> shifted = points;
  for (Point2& p : shifted) p = {5e5 + 100.0 * p.x, 4.5e6 + 100.0 * p.y};
  EXPECT_LT(TourLength(shifted, SpatialOrder(shifted, false, 0)), 200.0 * std::sqrt(static_cast<double>(n)));
}

// BRIO starts with a small random sample (sorted along the curve, but
// drawn from the whole box): the first 64 points span most of the box, while
// a plain curve order keeps them in one tiny corner region.
struct Spread {
  double width = 0.0, height = 0.0;
  int quadrants = 0;
};
Spread SpreadOfFirst(const std::vector<Point2>& points, const std::vector<int32_t>& order, int k) {
  double min_x = INFINITY, min_y = INFINITY, max_x = -INFINITY, max_y = -INFINITY;
  bool quadrant[4] = {false, false, false, false};
  for (int i = 0; i < k; ++i) {
    const Point2& p = points[order[i]];
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y);
    max_y = std::max(max_y, p.y);
    quadrant[(p.x < 0.5 ? 0 : 1) + (p.y < 0.5 ? 0 : 2)] = true;
  }
  return {max_x - min_x, max_y - min_y, quadrant[0] + quadrant[1] + quadrant[2] + quadrant[3]};
}

TEST(SpatialOrderTest, BrioStartsWithASpreadSample) {
  const std::vector<Point2> points = testing::UniformPoints(10000, 8);
  for (uint64_t seed : {1ULL, 2ULL, 3ULL, 4ULL}) {
    const Spread s = SpreadOfFirst(points, SpatialOrder(points, true, seed), 64);
    EXPECT_GT(s.width, 0.5) << "seed " << seed;
    EXPECT_GT(s.height, 0.5) << "seed " << seed;
    EXPECT_GE(s.quadrants, 3) << "seed " << seed;
  }
  // Control: without BRIO the first 64 of 10000 points are close together.
  const Spread plain = SpreadOfFirst(points, SpatialOrder(points, false, 0), 64);
  EXPECT_LT(plain.width, 0.2);
  EXPECT_LT(plain.height, 0.2);
  EXPECT_EQ(plain.quadrants, 1);
}

// The chunked key computation and radix sort: the order one thread gives
// (checked above against the curve and the rounds) on 2 and 8 threads, for
// an input of several chunks, with and without BRIO rounds.
TEST(SpatialOrderTest, SameOrderOnAnyThreadCount) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Point2> points(300000);
  for (Point2& p : points) p = {1e3 * unit(random), 1e3 * unit(random)};
  for (int i = 0; i < 1000; ++i) points[i * 7] = points[i];  // duplicates: equal keys stay in input order
  for (const bool brio : {false, true}) {
    const std::vector<int32_t> one = SpatialOrder(points, brio, 9, Execution{1});
    ASSERT_TRUE(IsPermutation(one, points.size()));
    for (std::size_t k = 1; k < one.size() && !brio; ++k) {
      if (points[one[k]].x == points[one[k - 1]].x && points[one[k]].y == points[one[k - 1]].y) {
        EXPECT_LT(one[k - 1], one[k]);
      }
    }
    EXPECT_EQ(SpatialOrder(points, brio, 9, Execution{2}), one) << brio;
    EXPECT_EQ(SpatialOrder(points, brio, 9, Execution{8}), one) << brio;
  }
}

}  // namespace
}  // namespace surfreg
