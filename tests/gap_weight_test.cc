// The local interpolation gaps (PlaneGaps, CurvatureGaps) and the gap
// weight (ApplyGapWeight) against closed forms on an equilateral lattice
// and on scattered points.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "measure/surface.h"
#include "registration/gap_weight.h"
#include "registration/pair_state.h"
#include "testing/registration_sides.h"

namespace surfreg {
namespace {

// An equilateral lattice of spacing h (i, j in [0, n)): every inner node has
// six neighbours at distance h, so the least-squares plane through them has
// the neighbours' mean height at the node. (Its slanted outline is straight
// only up to rounding, so the nodes near it may see slivers; the tests look
// at the nodes two or more rows inside.)
struct Lattice {
  int n;
  double h;
  std::vector<std::array<double, 3>> points;
  Lattice(int n_in, double h_in, const std::function<double(double, double)>& z) : n(n_in), h(h_in) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = h * (i + 0.5 * j), y = h * j * std::sqrt(3.0) / 2;
        points.push_back({x, y, z(x, y)});
      }
  }
  // The lattice index (i, j) of a node of `side`, prepared from Surface `s`.
  std::array<int, 2> IndexOf(const ReferenceSide& side, const Surface& s, std::size_t v) const {
    const double y = side.xy[v].y + s.origin[1], x = side.xy[v].x + s.origin[0];
    const int j = static_cast<int>(std::lround(y / (h * std::sqrt(3.0) / 2)));
    return {static_cast<int>(std::lround(x / h - 0.5 * j)), j};
  }
  bool Inner(const std::array<int, 2>& ij, int rows) const {
    return std::min(ij[0], ij[1]) >= rows && std::max(ij[0], ij[1]) < n - rows;
  }
};

std::vector<Eigen::Vector3d> PointsOf(const ReferenceSide& side) {
  std::vector<Eigen::Vector3d> p(side.xy.size());
  for (std::size_t v = 0; v < p.size(); ++v) p[v] = {side.xy[v].x, side.xy[v].y, side.z[v]};
  return p;
}

// A flat lattice with one node raised by 3: the gap is 3 there, 3/6 at its
// six neighbours, 0 at the other inner nodes; −1 only on the outline. On
// z = x² it is h²/2 (the mean of h² cos²(60° k)) at every inner node.
TEST(GapWeightTest, PlaneGapsOfABumpAndOfAParabola) {
  const double h = 2.0;
  Lattice flat(12, h, [](double, double) { return 0.0; });
  flat.points[5 * 12 + 4][2] = 3.0;  // (i, j) = (4, 5)
  const Surface bumped = MakeSurface(flat.points, {}, "bump");
  ReferenceSide side = PrepareReference(bumped);
  std::vector<double> gap = PlaneGaps(PointsOf(side), side.mesh);
  int checked = 0, outline = 0;
  for (std::size_t v = 0; v < gap.size(); ++v) {
    const std::array<int, 2> ij = flat.IndexOf(side, bumped, v);
    if (!flat.Inner(ij, 1)) {  // the outline: a ring closed only by slivers, if at all
      outline += gap[v] < 0;
      continue;
    }
    EXPECT_GE(gap[v], 0.0);
    if (!flat.Inner(ij, 2)) continue;
    const int di = ij[0] - 4, dj = ij[1] - 5;
    const bool top = di == 0 && dj == 0;
    const bool ring = std::max({std::abs(di), std::abs(dj), std::abs(di + dj)}) == 1;
    EXPECT_NEAR(gap[v], top ? 3.0 : (ring ? 0.5 : 0.0), 1e-9) << "node " << ij[0] << ", " << ij[1];
    ++checked;
  }
  EXPECT_EQ(checked, 8 * 8);
  EXPECT_GE(outline, 4);  // at least the corners
  Lattice parabola(12, h, [](double x, double) { return x * x; });
  const Surface curved = MakeSurface(parabola.points, {}, "p");
  side = PrepareReference(curved);
  gap = PlaneGaps(PointsOf(side), side.mesh, 7);
  for (std::size_t v = 0; v < gap.size(); ++v) {
    if (v % 7 != 0) {
      EXPECT_EQ(gap[v], -1.0);
    } else if (parabola.Inner(parabola.IndexOf(side, curved, v), 2)) {
      EXPECT_NEAR(gap[v], h * h / 2, 1e-9);
    }
  }
}

// On a quadratic the least-squares quadratic through a ring is the surface
// itself, so at every node with a closed ring the gap is ¼ ℓ² (|λ₁| + |λ₂|)
// of the surface's Hessian, ℓ² the median over those nodes of their ring's
// mean squared distance (here by brute force over the triangles around
// each node): one spacing for the whole surface, so that g follows the
// curvature only, not where this sampling happens to be sparse.
TEST(GapWeightTest, CurvatureGapsOfAQuadraticOnScatteredPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::vector<std::array<double, 3>> points;
  for (int k = 0; k < 400; ++k) {
    const double x = u(rng), y = u(rng);
    points.push_back({x, y, 0.3 * x * x - 0.5 * x * y + 0.2 * y * y + x - 2 * y + 1});
  }
  // Hessian [[0.6, −0.5], [−0.5, 0.4]]: a saddle, λ = 0.5 ± √0.26.
  const double abs_lambda_sum = std::fabs(0.5 + std::sqrt(0.26)) + std::fabs(0.5 - std::sqrt(0.26));
  const ReferenceSide side = PrepareReference(MakeSurface(points, {}, "quadratic"));
  const std::vector<Eigen::Vector3d> p = PointsOf(side);
  const std::vector<double> gap = CurvatureGaps(p, side.mesh);
  std::vector<double> spacing2;
  for (std::size_t v = 0; v < p.size(); ++v) {
    if (gap[v] < 0) continue;
    std::vector<int32_t> ring;
    for (int32_t t = 0; t < side.mesh.num_triangles(); ++t) {
      const int32_t* c = &side.mesh.triangles[3 * t];
      if (c[0] != static_cast<int32_t>(v) && c[1] != static_cast<int32_t>(v) && c[2] != static_cast<int32_t>(v)) continue;
      for (int i = 0; i < 3; ++i)
        if (c[i] != static_cast<int32_t>(v)) ring.push_back(c[i]);
    }
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    double l2 = 0;
    for (int32_t w : ring) l2 += (p[w] - p[v]).head<2>().squaredNorm();
    spacing2.push_back(l2 / static_cast<double>(ring.size()));
  }
  ASSERT_GT(spacing2.size(), 300u);  // all but the hull's nodes and a few next to it
  std::nth_element(spacing2.begin(), spacing2.begin() + spacing2.size() / 2, spacing2.end());
  const double expected = 0.25 * spacing2[spacing2.size() / 2] * abs_lambda_sum;
  for (std::size_t v = 0; v < p.size(); ++v) {
    if (gap[v] >= 0) {
      EXPECT_NEAR(gap[v], expected, 1e-9 * expected) << "node " << v;
    }
  }
}

// A survey of parallel lines (samples 0.5 apart along, lines 1 apart) over
// a valley z = x², once with the lines along the valley's curvature and once
// across it (every point turned by exactly 90°, the surface kept). The
// rings are the same turned, so the curvature gaps are equal node for node;
// the plane gaps follow the lines' heading (about 4 times larger across:
// the lines' spacing squared), and so does the sampling's own
// interpolation error, which the weights must not favour.
TEST(GapWeightTest, CurvatureGapsDoNotDependOnTheLinesHeading) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  std::vector<std::array<double, 3>> along, across;
  for (int line = 0; line < 16; ++line) {
    for (int k = 0; k < 32; ++k) {
      const double x = 0.5 * k + jitter(rng), y = 1.0 * line + jitter(rng);
      along.push_back({x, y, x * x});
      across.push_back({-y, x, y * y});  // turned by 90°: the same z = x², the lines now along y
    }
  }
  const ReferenceSide a = PrepareReference(MakeSurface(along, {}, "along"));
  const ReferenceSide b = PrepareReference(MakeSurface(across, {}, "across"));
  auto known = [](std::vector<double> g) {
    g.erase(std::remove_if(g.begin(), g.end(), [](double x) { return x < 0; }), g.end());
    std::sort(g.begin(), g.end());
    return g;
  };
  const std::vector<double> curvature_a = known(CurvatureGaps(PointsOf(a), a.mesh));
  const std::vector<double> curvature_b = known(CurvatureGaps(PointsOf(b), b.mesh));
  ASSERT_EQ(curvature_a.size(), curvature_b.size());
  ASSERT_GT(curvature_a.size(), 350u);
  for (std::size_t k = 0; k < curvature_a.size(); ++k) {
    EXPECT_NEAR(curvature_a[k], curvature_b[k], 1e-6 * curvature_a[k]);  // rounding of z ≈ 256
  }
  const std::vector<double> plane_a = known(PlaneGaps(PointsOf(a), a.mesh));
  const std::vector<double> plane_b = known(PlaneGaps(PointsOf(b), b.mesh));
  const double median_a = plane_a[plane_a.size() / 2], median_b = plane_b[plane_b.size() / 2];
  EXPECT_GT(median_b, 2.5 * median_a);
}

// A node whose ring does not close (the hull) or has fewer than five
// neighbours gets −1: four points and their centre determine no quadratic.
TEST(GapWeightTest, CurvatureGapsNeedAClosedRingOfFive) {
  const std::vector<std::array<double, 3>> square = {{0, 0, 0}, {2, 0, 1}, {0, 2, 1}, {2, 2, 2}, {1, 1.1, 0.5}};
  const ReferenceSide side = PrepareReference(MakeSurface(square, {}, "square"));
  for (double g : CurvatureGaps(PointsOf(side), side.mesh)) EXPECT_EQ(g, -1.0);
}

// On z = x² the inner nodes' local gaps are all h²/2, so their weights are
// f / (f + g) = 0.3 / 1.3, times a user's μ; on a plane (all gaps 0) and
// with 0 the weights are left alone. On z = max(y − y0, 0)², the flat part's
// inner nodes keep weight 1 and the curved part's have f / (f + h²/2).
TEST(GapWeightTest, GapWeightIsTheInverseLocalGap) {
  const double h = 1.5;
  Lattice parabola(10, h, [](double x, double) { return x * x; });
  std::vector<double> mu;
  for (const auto& p : parabola.points) mu.push_back(SmoothWeight(p[0], p[1]));
  for (bool weighted : {false, true}) {
    const Surface s = MakeSurface(parabola.points, weighted ? mu : std::vector<double>(), "p");
    ReferenceSide side = PrepareReference(s);
    const std::vector<double> before = weighted ? side.weight : std::vector<double>(side.xy.size(), 1.0);
    ApplyGapWeight(0.3, &side);
    ASSERT_EQ(side.weight.size(), side.xy.size());
    for (std::size_t v = 0; v < side.xy.size(); ++v) {
      if (parabola.Inner(parabola.IndexOf(side, s, v), 3)) {
        EXPECT_NEAR(side.weight[v], before[v] * 0.3 / 1.3, 1e-9);
      }
    }
  }
  ReferenceSide off = PrepareReference(MakeSurface(parabola.points, {}, "p"));
  ApplyGapWeight(0.0, &off);
  EXPECT_TRUE(off.weight.empty());
  Lattice tilted(10, h, [](double x, double y) { return x - 2 * y; });
  ReferenceSide plane = PrepareReference(MakeSurface(tilted.points, {}, "q"));
  ApplyGapWeight(0.3, &plane);
  for (double w : plane.weight) EXPECT_NEAR(w, 1.0, 1e-5);  // gaps of rounding only

  const double y0 = 5 * h * std::sqrt(3.0) / 2;  // row 5 of 12
  Lattice half(12, h, [&](double, double y) { return y > y0 ? (y - y0) * (y - y0) : 0.0; });
  const Surface s = MakeSurface(half.points, {}, "half");
  ReferenceSide mixed = PrepareReference(s);
  ApplyGapWeight(0.3, &mixed);
  // f from the median local gap, each node's computed here by brute force:
  // over every triangle having the node as a corner, the corners' gaps.
  const ReferenceSide bare = PrepareReference(s);
  const std::vector<double> own = CurvatureGaps(PointsOf(bare), bare.mesh);
  std::vector<double> local;
  for (std::size_t v = 0; v < bare.xy.size(); ++v) {
    double sum = 0;
    int count = 0;
    for (int32_t t = 0; t < bare.mesh.num_triangles(); ++t) {
      const int32_t* c = &bare.mesh.triangles[3 * t];
      if (c[0] != static_cast<int32_t>(v) && c[1] != static_cast<int32_t>(v) && c[2] != static_cast<int32_t>(v)) continue;
      for (int i = 0; i < 3; ++i)
        if (own[c[i]] >= 0) {
          sum += own[c[i]];
          ++count;
        }
    }
    if (count > 0) local.push_back(sum / count);
  }
  std::nth_element(local.begin(), local.begin() + local.size() / 2, local.end());
  const double f = 0.3 * local[local.size() / 2];
  ASSERT_GT(f, 0.0);
  int flat = 0, curved = 0;
  for (std::size_t v = 0; v < mixed.xy.size(); ++v) {
    const std::array<int, 2> ij = half.IndexOf(mixed, s, v);
    if (!half.Inner(ij, 2)) continue;
    if (ij[1] <= 3) {  // no gap on the ring of any corner around it
      EXPECT_EQ(mixed.weight[v], 1.0);
      ++flat;
    }
    if (ij[1] >= 7) {  // z = (y − y0)² on the ring of every corner around it
      EXPECT_NEAR(mixed.weight[v], f / (f + h * h / 2), 1e-9);
      ++curved;
    }
  }
  EXPECT_EQ(flat, 2 * 8);
  EXPECT_EQ(curved, 3 * 8);
}

}  // namespace
}  // namespace surfreg

namespace surfreg {
namespace {

// A square of side 60 sampled on a grid of spacing 1, with a 10 × 10 patch
// resampled at spacing 0.25 (a mesh's dense nose among sparse cheeks; a
// third of the nodes): the area per sample is 1 away from the patch and
// 1/16 inside it, so the spread (90th over 10th percentile over the nodes)
// is 16 and the density weight makes μ ∝ 1 / area per sample; on the plain
// grid it is about 1 (the outline's nodes own less) and nothing changes.
std::vector<std::array<double, 3>> GridWithDensePatch(bool patch) {
  std::vector<std::array<double, 3>> points;
  for (int j = 0; j <= 60; ++j)
    for (int i = 0; i <= 60; ++i) {
      if (patch && i > 25 && i < 35 && j > 25 && j < 35) continue;
      points.push_back({double(i), double(j), 0.01 * i * j});
    }
  if (patch)
    for (int j = 0; j <= 32; ++j)
      for (int i = 0; i <= 32; ++i) {
        const double x = 26 + i * 0.25, y = 26 + j * 0.25;
        points.push_back({x, y, 0.01 * x * y});
      }
  return points;
}

TEST(DensityWeightTest, UnevenSamplingWeighsEachSampleAlike) {
  ReferenceSide even = PrepareReference(MakeSurface(GridWithDensePatch(false), {}, "grid"));
  EXPECT_LT(DensitySpread(even), 1.2);
  EXPECT_FALSE(ApplyDensityWeight(5.0, &even));
  EXPECT_TRUE(even.weight.empty());

  const Surface uneven_surface = MakeSurface(GridWithDensePatch(true), {}, "patch");
  ReferenceSide uneven = PrepareReference(uneven_surface);
  const double spread = DensitySpread(uneven);
  EXPECT_NEAR(spread, 16.0, 1e-6);
  EXPECT_FALSE(ApplyDensityWeight(0.0, &uneven));  // off
  EXPECT_FALSE(ApplyDensityWeight(spread * 1.01, &uneven));  // below the threshold
  ASSERT_TRUE(ApplyDensityWeight(5.0, &uneven));
  ASSERT_EQ(uneven.weight.size(), uneven.xy.size());
  // Away from the patch's rim: μ of a coarse node over μ of a fine one is
  // the inverse ratio of their areas per sample, 1/16.
  double coarse = 0, fine = 0;
  for (std::size_t v = 0; v < uneven.xy.size(); ++v) {
    const double x = uneven.xy[v].x + uneven_surface.origin[0], y = uneven.xy[v].y + uneven_surface.origin[1];
    if (std::abs(x - 5) < 1e-9 && std::abs(y - 5) < 1e-9) coarse = uneven.weight[v];
    if (std::abs(x - 30) < 1e-9 && std::abs(y - 30) < 1e-9) fine = uneven.weight[v];
  }
  ASSERT_GT(fine, 0);
  EXPECT_NEAR(coarse / fine, 1 / 16.0, 1e-9);

  // Fewer than 10 nodes: no spread.
  ReferenceSide tiny = PrepareReference(MakeSurface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}}, {}, "tiny"));
  EXPECT_EQ(DensitySpread(tiny), 0.0);
  EXPECT_FALSE(ApplyDensityWeight(5.0, &tiny));
}

}  // namespace
}  // namespace surfreg
