// PairState against independent truth: warm-started re-location equals a
// brute-force search, folds are detected (and slivers re-meshed), and
// locked parameters stay exactly where they start.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <ceres/cost_function.h>
#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <ceres/numeric_diff_options.h>
#include <gtest/gtest.h>

#include "measure/locator.h"
#include "measure/measures.h"
#include "registration/align.h"
#include "registration/axial_cost.h"
#include "registration/pair_state.h"
#include "registration/rigid_motion.h"
#include "registration/solvers.h"
#include "registration/volume_cost/volume_cost.h"
#include "testing/registration_sides.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

// ---------------------------------------------------------------- 4. re-location

// Every location of the state vs brute force; returns the number of nodes
// whose triangle differs (allowed only on an edge or vertex, same value).
int CheckLocations(const PairState& state) {
  const ReferenceSide& a = state.reference();
  const auto& bxy = state.moved_xy();
  const Triangulation& mesh_b = state.moving_mesh();
  int differing = 0;
  auto compare = [&](const Location& got, const Location& truth, const Triangulation& mesh,
                     const std::vector<double>& values, std::size_t node) {
    ASSERT_EQ(got.found(), truth.found()) << "node " << node;
    if (!truth.found() || got.triangle == truth.triangle) return;
    ++differing;
    EXPECT_TRUE(truth.where != Where::kInside && got.where != Where::kInside) << "node " << node;
    EXPECT_NEAR(InterpolateAt(mesh, values, got), InterpolateAt(mesh, values, truth), 1e-9) << node;
  };
  for (std::size_t i = 0; i < a.xy.size(); ++i) {
    compare(state.a_in_b()[i], LocatePointBruteForce(bxy, mesh_b, a.xy[i]), mesh_b, state.moved_z(), i);
  }
  for (std::size_t j = 0; j < bxy.size(); ++j) {
    compare(state.b_in_a()[j], LocatePointBruteForce(a.xy, a.mesh, bxy[j]), a.mesh, a.z, j);
  }
  return differing;
}

TEST(PairStateTest, WalkedLocationsEqualBruteForce) {
  const auto sides = TerrainSides(1200, 1000, 10, 90);
  PairState state(sides->reference, sides->moving);
  const Theta steps[] = {{0.002, -0.001, 0.01, 1.0, 0.5, 0.1},     // θ1: from scratch
                         {0.002, -0.001, 0.0101, 1.001, 0.499, 0.1},  // small step
                         {-0.004, 0.003, 0.4, 9.0, -6.0, 1.0},        // large step
                         {0.0, 0.0, -0.2, -12.0, 3.0, 0.0}};
  for (const Theta& theta : steps) {
    UpdateStats stats;
    ASSERT_TRUE(state.Update(theta, &stats));
    ASSERT_FALSE(stats.remeshed);  // else this tests LocateAll, not the walks
    const int differing = CheckLocations(state);
    std::printf("re-location: %lld walk steps, %d nodes in another triangle (on an edge)\n",
                static_cast<long long>(stats.walk_steps), differing);
  }
}

// Subsampled and merged reference nodes keep their own weights: each kept
// node's μ is the weight function at its xy; two samples at one xy (merged)
// get the mean of their weights.
TEST(PairStateTest, ReferenceKeepsWeightsWhenSubsampled) {
  auto points = testing::SampleUniform(testing::SmoothTerrain, 3000, 0, 100, 0, 100, 7);
  std::vector<double> mu;
  for (const auto& p : points) mu.push_back(SmoothWeight(p[0], p[1]));
  points.push_back(points[10]);  // a duplicate of sample 10 with weight 0
  mu.push_back(0.0);
  const Surface a = MakeSurface(points, mu, "a");
  for (double keep : {1.0, 0.3}) {
    const ReferenceSide side = PrepareReference(a, keep);
    ASSERT_EQ(side.weight.size(), side.xy.size());
    int duplicates = 0;
    for (std::size_t i = 0; i < side.xy.size(); ++i) {
      const double x = side.xy[i].x + a.origin[0], y = side.xy[i].y + a.origin[1];
      if (side.xy[i].x != a.xy[10].x || side.xy[i].y != a.xy[10].y) {
        EXPECT_DOUBLE_EQ(side.weight[i], SmoothWeight(x, y)) << i;
        continue;
      }
      ++duplicates;  // at 0.3 either copy may have been dropped
      if (keep == 1.0) {
        EXPECT_DOUBLE_EQ(side.weight[i], 0.5 * SmoothWeight(x, y));
      }
    }
    std::printf("subsample %.1f: %zu reference nodes carry weights\n", keep, side.xy.size());
    EXPECT_LT(side.xy.size(), keep * 3300);
    EXPECT_LE(duplicates, 1);
    if (keep == 1.0) {
      EXPECT_EQ(duplicates, 1);
    }
    EXPECT_TRUE(PrepareReference(MakeSurface(points, {}, "a"), keep).weight.empty());
  }
}

// cos(slope)^p on a plane is the same at every node: (1 + a² + b²)^(−p/2);
// a user's μ is multiplied, and exponent 0 adds no weights.
TEST(PairStateTest, SlopeWeightOnAPlaneIsTheCosinePower) {
  auto points = testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 11);
  std::vector<double> mu;
  for (auto& p : points) {
    p[2] = 0.3 * p[0] - 0.7 * p[1] + 2.0;
    mu.push_back(SmoothWeight(p[0], p[1]));
  }
  const double cosine = 1.0 / std::sqrt(1.0 + 0.3 * 0.3 + 0.7 * 0.7);
  for (double exponent : {1.0, 2.0, 3.5}) {
    ReferenceSide side = PrepareReference(MakeSurface(points, {}, "plane"));
    ApplySlopeWeight(exponent, &side);
    ASSERT_EQ(side.weight.size(), side.xy.size());
    for (double w : side.weight) EXPECT_NEAR(w, std::pow(cosine, exponent), 1e-12);
  }
  const Surface weighted = MakeSurface(points, mu, "plane");
  ReferenceSide side = PrepareReference(weighted);
  const std::vector<double> before = side.weight;
  ApplySlopeWeight(2.0, &side);
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_NEAR(side.weight[i], before[i] * cosine * cosine, 1e-12);
  }
  ReferenceSide plain = PrepareReference(MakeSurface(points, {}, "plane"));
  ApplySlopeWeight(0.0, &plain);
  EXPECT_TRUE(plain.weight.empty());
}

// A roof z = |x − 50|: nodes whose triangles all lie on one flank get
// cos²(45°) = 1/2; the others, on triangles across the ridge (whose slope
// a sliver can make steeper or flatter), lie in (0, 1].
TEST(PairStateTest, SlopeWeightOnARoof) {
  auto points = testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 12);
  for (auto& p : points) p[2] = std::fabs(p[0] - 50.0);
  ReferenceSide side = PrepareReference(MakeSurface(points, {}, "roof"));
  ApplySlopeWeight(2.0, &side);
  std::vector<int> side_of(side.xy.size(), 0);  // bit 1: a triangle left of the ridge, 2: right
  const double ridge = 50.0 - MakeSurface(points, {}, "roof").origin[0];
  const std::vector<int32_t>& t = side.mesh.triangles;
  for (std::size_t k = 0; k < t.size(); k += 3) {
    const double cx = (side.xy[t[k]].x + side.xy[t[k + 1]].x + side.xy[t[k + 2]].x) / 3;
    bool straddles = false;
    for (int j = 0; j < 3; ++j) straddles |= (side.xy[t[k + j]].x - ridge) * (cx - ridge) < 0;
    const int bit = straddles ? 3 : (cx < ridge ? 1 : 2);
    for (int j = 0; j < 3; ++j) side_of[t[k + j]] |= bit;
  }
  int flank = 0;
  for (std::size_t i = 0; i < side.xy.size(); ++i) {
    if (side_of[i] == 1 || side_of[i] == 2) {
      EXPECT_NEAR(side.weight[i], 0.5, 1e-12) << i;
      ++flank;
    } else {
      EXPECT_GT(side.weight[i], 0.0) << i;
      EXPECT_LE(side.weight[i], 1.0) << i;
    }
  }
  EXPECT_GT(flank, 1800);
}

// ---------------------------------------------------------------- 5. folds

std::vector<std::array<double, 3>> TiltedPlaneGrid() {
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) points.push_back({10.0 * i, 10.0 * j, 0.1 * i + 0.05 * j});
  }
  return points;
}

TEST(PairStateTest, TiltPastVerticalFails) {
  const auto sides = MakeSides(TiltedPlaneGrid(), TiltedPlaneGrid());
  PairState state(sides->reference, sides->moving);
  UpdateStats stats;
  ASSERT_TRUE(state.Update({60 * M_PI / 180, 0, 0, 0, 0, 0}, &stats));  // steep, not folded
  EXPECT_EQ(stats.folded, 0);
  const std::vector<Location> before = state.a_in_b();
  stats = UpdateStats();
  EXPECT_FALSE(state.Update({100 * M_PI / 180, 0, 0, 0, 0, 0}, &stats));
  std::printf("100° tilt: %d folded, area fraction %.3f\n", stats.folded, stats.folded_area_fraction);
  EXPECT_EQ(stats.folded, sides->moving.mesh.num_triangles());
  EXPECT_GT(stats.folded_area_fraction, 0.01);
  EXPECT_FALSE(stats.remeshed);
  ASSERT_EQ(state.a_in_b().size(), before.size());  // "locations left untouched"
  for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(state.a_in_b()[i].triangle, before[i].triangle);
  // A failed step leaves the state usable: walks resume from the old locations.
  ASSERT_TRUE(state.Update({30 * M_PI / 180, 0, 0.1, 2, 1, 0}));
  CheckLocations(state);
}

TEST(PairStateTest, SliverFoldsAreRemeshed) {
  const auto sides = TerrainSides(1500, 1500, 0, 100);
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update({0, 0, 0, 0, 0, 0}));
  UpdateStats stats;
  const Theta tilted = {5 * M_PI / 180, 0, 0, 0.5, -0.5, 0};
  ASSERT_TRUE(state.Update(tilted, &stats));
  std::printf("5° tilt: %d slivers folded (area fraction %.2e), remeshed %d\n", stats.folded,
              stats.folded_area_fraction, stats.remeshed);
  EXPECT_GT(stats.folded, 0);
  EXPECT_LE(stats.folded_area_fraction, 0.01);
  EXPECT_TRUE(stats.remeshed);
  EXPECT_EQ(state.remeshes(), 1);
  const Triangulation& mesh = state.moving_mesh();  // the new mesh is unfolded
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& p = state.moved_xy();
    const Point2 &p0 = p[mesh.triangles[3 * t]], &p1 = p[mesh.triangles[3 * t + 1]], &p2 = p[mesh.triangles[3 * t + 2]];
    ASSERT_GT((p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x), 0.0) << t;
  }
  CheckLocations(state);
  // And walking on the new mesh from there.
  stats = UpdateStats();
  ASSERT_TRUE(state.Update({5.01 * M_PI / 180, 0.001, 0.002, 0.6, -0.4, 0.1}, &stats));
  EXPECT_FALSE(stats.remeshed);
  CheckLocations(state);
}

// B's active triangles as sorted vertex triples.
std::vector<std::array<int32_t, 3>> ActiveTriples(const PairState& state) {
  std::vector<std::array<int32_t, 3>> out;
  const Triangulation& mesh = state.moving_mesh();
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (!state.active_b()[t]) continue;
    std::array<int32_t, 3> v = {mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]};
    std::sort(v.begin(), v.end());
    out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void ExpectUnfolded(const PairState& state) {
  const Triangulation& mesh = state.moving_mesh();
  const auto& p = state.moved_xy();
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const Point2 &p0 = p[mesh.triangles[3 * t]], &p1 = p[mesh.triangles[3 * t + 1]], &p2 = p[mesh.triangles[3 * t + 2]];
    ASSERT_GT((p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x), 0.0) << t;
  }
}

// With the data domain, the slivers a 5° tilt turns over are junk: B is
// re-meshed around its surface, which keeps exactly its own domain
// triangles (so no cost changes), unfolded and located as brute force
// locates it.
TEST(PairStateTest, FixedSurfaceKeepsItsTrianglesThroughJunkFolds) {
  const auto sides = TerrainSides(1500, 1500, 0, 100, nullptr, DomainRule());
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update({0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(state.FixSurface(80.0), 0);  // SmoothTerrain has no slope near 80°
  const auto surface = ActiveTriples(state);
  EXPECT_LT(surface.size(), static_cast<std::size_t>(sides->moving.mesh.num_triangles()));
  UpdateStats stats;
  const bool moved = state.Update({5 * M_PI / 180, 0, 0, 0.5, -0.5, 0}, &stats);
  std::printf("5° tilt: %d folded, %d of them active, remeshed %d\n", stats.folded, stats.folded_active,
              stats.remeshed);
  ASSERT_TRUE(moved);
  EXPECT_GT(stats.folded, 0) << "nothing folded: the test lost its point";
  EXPECT_EQ(stats.folded_active, 0);
  EXPECT_TRUE(stats.remeshed);
  EXPECT_EQ(ActiveTriples(state), surface);
  ExpectUnfolded(state);
  CheckLocations(state);
  ASSERT_TRUE(state.Update({5.01 * M_PI / 180, 0.001, 0.002, 0.6, -0.4, 0.1}));
  EXPECT_EQ(ActiveTriples(state), surface);
  CheckLocations(state);
}

// OwnMeshFolds counts what Update on a fresh state would (the same stats),
// without a state; beyond the fold limit it fails as Update does.
TEST(PairStateTest, OwnMeshFoldsCountsAsAFreshUpdate) {
  const auto sides = TerrainSides(1500, 1500, 0, 100, nullptr, DomainRule());
  const Theta tilted = {5 * M_PI / 180, 0, 0, 0.5, -0.5, 0};
  PairState updated(sides->reference, sides->moving);
  UpdateStats only_count, full;
  ASSERT_TRUE(OwnMeshFolds(sides->moving, tilted, 0.01, &only_count));
  ASSERT_TRUE(updated.Update(tilted, &full));
  EXPECT_GT(full.folded, 0) << "nothing folded: the test lost its point";
  EXPECT_EQ(only_count.folded, full.folded);
  EXPECT_EQ(only_count.folded_active, full.folded_active);
  EXPECT_EQ(only_count.folded_area_fraction, full.folded_area_fraction);
  UpdateStats none;
  EXPECT_TRUE(OwnMeshFolds(sides->moving, Theta{}, 0.01, &none));
  EXPECT_EQ(none.folded, 0);
  EXPECT_FALSE(OwnMeshFolds(sides->moving, {100 * M_PI / 180, 0, 0, 0, 0, 0}, 0.01, nullptr));
  PairState steep(sides->reference, sides->moving, 0.01);
  EXPECT_FALSE(steep.Update({100 * M_PI / 180, 0, 0, 0, 0, 0}));
}

// Fixed before its first Update at a pose where a steep band of B's data
// turns over, B re-meshes once, around the same surface that a free
// re-mesh (B's Delaunay there) followed by FixSurface keeps with two, and
// is located there.
TEST(PairStateTest, FixedBeforeTheFirstUpdateRemeshesOnce) {
  const auto cliff = [](double x, double) { return 30.0 * std::tanh((x - 50.0) / 0.4); };  // up to 89.8°
  const auto sides = MakeSides(testing::SampleUniform(cliff, 1500, 0, 100, 0, 100, 11),
                               testing::SampleUniform(cliff, 1500, 0, 100, 0, 100, 23), nullptr, DomainRule());
  const Theta tilted = {0, -5 * M_PI / 180, 0, 0.5, -0.5, 0};
  PairState fixed_first(sides->reference, sides->moving, 0.5), free_first(sides->reference, sides->moving, 0.5);
  UpdateStats stats;
  ASSERT_TRUE(OwnMeshFolds(sides->moving, tilted, 0.5, &stats));
  ASSERT_GT(stats.folded_active, 0) << "no data triangle turns over: the test lost its point";
  fixed_first.MoveTo(tilted);
  fixed_first.FixSurface(80.0);
  ASSERT_TRUE(fixed_first.Update(tilted));
  ASSERT_TRUE(free_first.Update(tilted));
  free_first.FixSurface(80.0);
  EXPECT_EQ(fixed_first.remeshes(), 1);
  EXPECT_EQ(free_first.remeshes(), 2);
  EXPECT_EQ(ActiveTriples(fixed_first), ActiveTriples(free_first));
  EXPECT_EQ(fixed_first.surface_key(), free_first.surface_key());
  ExpectUnfolded(fixed_first);
  CheckLocations(fixed_first);
}

// Located on two threads (large clouds), every location is the one found on
// one thread, from scratch and walking.
TEST(PairStateTest, TwoThreadLocationsEqualOneThreads) {
  const auto sides = TerrainSides(15000, 12000, 0, 100);
  PairState one(sides->reference, sides->moving), two(sides->reference, sides->moving);
  two.set_execution(Execution{2});
  for (const Theta& theta : {Theta{0.002, -0.001, 0.01, 1.0, 0.5, 0.1}, Theta{0.0021, -0.001, 0.0102, 1.01, 0.49, 0.1}}) {
    UpdateStats stats_one, stats_two;
    ASSERT_TRUE(one.Update(theta, &stats_one));
    ASSERT_TRUE(two.Update(theta, &stats_two));
    EXPECT_EQ(stats_one.walk_steps, stats_two.walk_steps);
    for (std::size_t i = 0; i < one.a_in_b().size(); ++i) {
      ASSERT_EQ(one.a_in_b()[i].triangle, two.a_in_b()[i].triangle) << i;
    }
    for (std::size_t j = 0; j < one.b_in_a().size(); ++j) {
      ASSERT_EQ(one.b_in_a()[j].triangle, two.b_in_a()[j].triangle) << j;
    }
  }
}

// A fixed surface is one function of θ: the axial residuals and the volume
// cost at a pose are the same before and after B went through junk folds
// and re-meshes elsewhere (a solver compares values across its steps; a
// whole re-mesh changed them and made Levenberg-Marquardt cycle).
TEST(PairStateTest, FixedSurfaceCostsDoNotDependOnThePath) {
  const auto sides = TerrainSides(1500, 1500, 0, 100, nullptr, DomainRule());
  PairState state(sides->reference, sides->moving);
  const Theta here = {1 * M_PI / 180, 0.002, 0, 0.1, -0.1, 0};
  ASSERT_TRUE(state.Update(here));
  state.FixSurface(80.0);
  AxialResiduals before, after;
  ComputeAxialResiduals(state, AxialSettings(), false, &before);
  const double volume_before = EvaluateVolumeCost(state, false, Execution{1}).PerArea();
  const int remeshes = state.remeshes();
  ASSERT_TRUE(state.Update({5 * M_PI / 180, 0, 0, 0.5, -0.5, 0}));
  ASSERT_TRUE(state.Update({6 * M_PI / 180, 0.01, 0, 0.6, -0.4, 0}));
  ASSERT_TRUE(state.Update(here));
  EXPECT_GT(state.remeshes(), remeshes) << "no junk fold on the way: the test lost its point";
  ComputeAxialResiduals(state, AxialSettings(), false, &after);
  ASSERT_EQ(before.active_count, after.active_count);
  double worst = 0;
  for (std::size_t k = 0; k < before.r.size(); ++k) worst = std::max(worst, std::fabs(before.r[k] - after.r[k]));
  EXPECT_LT(worst, 1e-12);
  EXPECT_NEAR(EvaluateVolumeCost(state, false, Execution{1}).PerArea(), volume_before, 1e-12 * volume_before);
}

// With every triangle part of the surface (hull domain) and the surface
// fixed, the same slivers are active: the step is refused and B's mesh kept.
TEST(PairStateTest, FixedSurfaceRefusesActiveFolds) {
  const auto sides = TerrainSides(1500, 1500, 0, 100);
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update({0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(state.FixSurface(90.0), 0);
  UpdateStats stats;
  EXPECT_FALSE(state.Update({5 * M_PI / 180, 0, 0, 0.5, -0.5, 0}, &stats));
  EXPECT_GT(stats.folded_active, 0);
  EXPECT_TRUE(stats.remesh_refused);
  EXPECT_EQ(state.remeshes(), 0);
  EXPECT_EQ(state.moving_mesh().triangles, sides->moving.mesh.triangles);
  ASSERT_TRUE(state.Update({1 * M_PI / 180, 0, 0, 0.1, -0.1, 0}));  // short of the fold
  CheckLocations(state);
  // Released, the fold re-meshes B freely (the height field seen from above).
  state.ReleaseSurface();
  ASSERT_TRUE(state.Update({5 * M_PI / 180, 0, 0, 0.5, -0.5, 0}, &stats));
  EXPECT_EQ(state.remeshes(), 1);
  ExpectUnfolded(state);
  CheckLocations(state);
}

// A raster is its cells, split by one rule (measure/grid_mesh.h), on both
// sides; after a free re-mesh too. A 5° tilt turns the cliff cells of a
// 20 m step over one 1 m row past vertical: re-meshed, the moving raster is
// its cells again, less the folded row and the rows next to it.
TEST(PairStateTest, RasterSidesAreTheirCellsAlsoAfterAFreeRemesh) {
  std::vector<std::array<double, 3>> points;
  std::vector<RasterCell> cells;
  for (int r = 0; r < 30; ++r) {
    for (int c = 0; c < 30; ++c) {
      points.push_back({1.0 * c, 1.0 * r, r >= 15 ? 20.0 : 0.0});
      cells.push_back({c, r});
    }
  }
  Surface raster = MakeSurface(points, {}, "cliff.tif");
  raster.raster_cell = cells;
  const ReferenceSide reference = PrepareReference(raster);
  const MovingSide moving = PrepareMoving(raster, {0, 0, 0});
  // Each triangle by the rule: its cell's corners (c, r) and (c+1, r+1) on it
  // (at θ = 0 a point's xy is its (column, row)).
  auto by_rule = [](const std::vector<Point2>& at_rest, const int32_t* v) {
    double c = 1e9, r = 1e9;
    for (int i = 0; i < 3; ++i) c = std::min(c, at_rest[v[i]].x), r = std::min(r, at_rest[v[i]].y);
    int on_diagonal = 0;
    for (int i = 0; i < 3; ++i) {
      const Point2& p = at_rest[v[i]];
      on_diagonal += (p.x == c && p.y == r) || (p.x == c + 1 && p.y == r + 1);
    }
    return on_diagonal == 2;
  };
  auto count_by_rule = [&](const std::vector<Point2>& at_rest, const Triangulation& mesh,
                           const std::vector<uint8_t>& in) {
    int n = 0;
    for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
      if (!in[t]) continue;
      EXPECT_TRUE(by_rule(at_rest, &mesh.triangles[3 * t])) << t;
      ++n;
    }
    return n;
  };
  std::vector<Point2> rest(moving.points.size());
  for (std::size_t j = 0; j < rest.size(); ++j) rest[j] = {moving.points[j].x(), moving.points[j].y()};
  EXPECT_EQ(count_by_rule(reference.xy, reference.mesh, reference.domain), 2 * 29 * 29);
  EXPECT_EQ(count_by_rule(rest, moving.mesh, moving.domain), 2 * 29 * 29);
  EXPECT_EQ(moving.grid.size(), 6u * 29 * 29);

  PairState state(reference, moving, /*max_fold_fraction=*/0.9);
  UpdateStats stats;
  ASSERT_TRUE(state.Update({5 * M_PI / 180, 0, 0, 0, 0, 0}, &stats));
  EXPECT_GT(stats.folded_active, 0);
  EXPECT_TRUE(stats.remeshed);
  ExpectUnfolded(state);
  CheckLocations(state);
  // Cell rows 13, 14 (the cliff, folded) and 15 are left out.
  EXPECT_EQ(count_by_rule(rest, state.moving_mesh(), state.active_b()), 2 * 29 * 26);
}

// The volume solver keeps B's surface fixed for the whole solve: the moving
// cloud is a second sampling turned by −15° about x, so B's own mesh folds
// slivers (junk) on the way from 12° to the solution; they are re-meshed
// around the surface, no step is refused, and the motion is recovered.
TEST(SolverRoundsTest, VolumeSolveKeepsTheSurfaceThroughJunkFolds) {
  const Theta truth = {15 * M_PI / 180, 0, 0, 0, 0, 0};
  std::vector<std::array<double, 3>> pb =
      testing::SampleUniform(testing::SmoothTerrain, 1500, 0, 100, 0, 100, 23);
  {  // moving = b turned by −15° about x through its centroid: T_true brings it back
    Eigen::Vector3d c(0, 0, 0);
    for (const auto& p : pb) c += Eigen::Vector3d(p[0], p[1], p[2]);
    c /= static_cast<double>(pb.size());
    const Eigen::Matrix3d r = Eigen::AngleAxisd(truth[0], Eigen::Vector3d::UnitX()).matrix();
    for (auto& p : pb) {
      const Eigen::Vector3d q = r.transpose() * (Eigen::Vector3d(p[0], p[1], p[2]) - c) + c;
      p = {q.x(), q.y(), q.z()};
    }
  }
  const auto sides = MakeSides(testing::SampleUniform(testing::SmoothTerrain, 1500, 0, 100, 0, 100, 11),
                               pb, nullptr, DomainRule());
  AlignOptions options;
  PairState state(sides->reference, sides->moving);
  SolveContext context;
  context.options = &options;
  context.rotation_scale = sides->radius;
  const Theta start = {12 * M_PI / 180, 0, 0, 0, 0, 0};
  ASSERT_TRUE(state.Update(start));
  state.FixSurface(80.0);
  const auto surface = ActiveTriples(state);
  const SolveResult r = SolveVolume(state, context, start);
  std::printf("%d rounds, %d iterations, %d re-meshes, %s\n", r.rounds, r.iterations, state.remeshes(),
              r.message.c_str());
  EXPECT_TRUE(r.usable);
  EXPECT_EQ(r.rounds, 1);
  EXPECT_GT(state.remeshes(), 0) << "no junk fold on the way: the test lost its point";
  EXPECT_EQ(ActiveTriples(state), surface);
  const Eigen::Vector3d w(r.theta[0], r.theta[1], r.theta[2]);
  EXPECT_NEAR(w.norm() * 180 / M_PI, 15.0, 0.05);
  for (int k = 1; k < 6; ++k) EXPECT_NEAR(r.theta[k], truth[k], k < 3 ? 0.05 * M_PI / 180 : 0.05) << k;
}

// ---------------------------------------------------------------- 5b. covariance

// σ² (JᵀJ)⁻¹ of the axial residuals, computed here from the residuals and a
// full-pivot LU: AnalyseInformation must give the same (it inverts JᵀJ by its
// eigen-decomposition), for all six parameters free and with some locked.
TEST(AnalyseInformationTest, CovarianceIsResidualVarianceTimesInverseInformation) {
  const auto sides = MakeSides(testing::SampleUniform(testing::SmoothTerrain, 1200, 0, 100, 0, 100, 5),
                               testing::SampleUniform(testing::SmoothTerrain, 1100, 0, 100, 0, 100, 6));
  for (const std::array<bool, 6> free : {std::array<bool, 6>{true, true, true, true, true, true},
                                         std::array<bool, 6>{false, true, true, true, false, true}}) {
    AlignOptions options;
    options.free = free;
    SolveContext context;
    context.options = &options;
    context.rotation_scale = sides->radius;
    PairState state(sides->reference, sides->moving);
    const Theta theta = {0.001, -0.002, 0.0005, 0.3, -0.2, 0.1};
    ASSERT_TRUE(state.Update(theta));
    const Information info = AnalyseInformation(state, context, true);
    ASSERT_TRUE(info.covariance_ok);

    AxialResiduals r;
    ComputeAxialResiduals(state, context.axial, true, &r);
    std::vector<int> f;
    for (int k = 0; k < 6; ++k) {
      if (free[k]) f.push_back(k);
    }
    const int n = static_cast<int>(f.size());
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
    double squares = 0;
    for (std::size_t k = 0; k < r.r.size(); ++k) {
      if (!r.active[k]) continue;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) h(i, j) += r.jacobian[k][f[i]] * r.jacobian[k][f[j]];
      }
      squares += r.r[k] * r.r[k];
    }
    const Eigen::MatrixXd expected =
        squares / static_cast<double>(r.active_count - n) * h.fullPivLu().inverse();
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        const auto it = [&](int k) { return static_cast<int>(std::find(f.begin(), f.end(), k) - f.begin()); };
        const double want = free[i] && free[j] ? expected(it(i), it(j)) : 0.0;
        const double scale = std::sqrt(std::fabs(expected.diagonal().maxCoeff()));
        EXPECT_NEAR(info.covariance(i, j), want, 1e-9 * std::max(std::fabs(want), scale * scale * 1e-3))
            << i << "," << j;
      }
    }
  }
}

// ---------------------------------------------------------------- 6. locked parameters

TEST(AlignLockedTest, TranslationOnlyKeepsRotationExactly) {
  const auto points = testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 3);
  const Eigen::Vector3d shift(3.2, -2.1, 0.7);
  std::vector<std::array<double, 3>> moving = points;
  for (auto& p : moving) p = {p[0] - shift.x(), p[1] - shift.y(), p[2] - shift.z()};
  const Surface a = MakeSurface(points, {}, "a"), b = MakeSurface(moving, {}, "b");
  for (CostKind cost : {CostKind::kAxial, CostKind::kVolume}) {
    AlignOptions options;
    options.cost = cost;
    options.free = {false, false, false, true, true, true};
    const AlignResult result = Align(a, b, options);
    EXPECT_EQ(result.rotation_vector, (std::array<double, 3>{0, 0, 0}));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(result.translation[k], shift[k], 1e-6) << k;
    EXPECT_EQ(result.stddev[0], 0.0);  // locked
    // A locked non-zero rotation stays bit-identical too.
    options.initial_rotation = {0.002, -0.001, 0.003};
    const AlignResult rotated = Align(a, b, options);
    EXPECT_EQ(rotated.rotation_vector, options.initial_rotation);
    std::printf("locked rotation (%s): t error %.1e, verdict %s\n", cost == CostKind::kAxial ? "axial" : "volume",
                (Eigen::Vector3d(result.translation.data()) - shift).norm(), VerdictName(result.verdict));
  }
}

}  // namespace
}  // namespace surfreg
