// Registration internals against independent truth: axial Jacobians vs
// numeric differentiation (ceres::GradientChecker) and vs planes computed
// here, the volume cost's gradient vs central differences, its value vs
// Measure(), (re-location, folds and locked parameters: pair_state_test.cc); each
// cost also with per-point weights μ on the reference.
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
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
#include "registration/volume_cost/volume_cost.h"
#include "testing/registration_sides.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

// ---------------------------------------------------------------- 1. axial

// ComputeAxialResiduals as a Ceres cost over (ω·radius, t): all parameters
// lengths, so one relative step size suits all six.
class AxialCost : public ceres::CostFunction {
 public:
  AxialCost(PairState* state, double radius, AxialSettings settings = AxialSettings())
      : state_(state), radius_(radius), settings_(std::move(settings)) {
    set_num_residuals(static_cast<int>(state->reference().xy.size() + state->moving().points.size()));
    mutable_parameter_block_sizes()->push_back(6);
  }
  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const Theta theta = {p[0][0] / radius_, p[0][1] / radius_, p[0][2] / radius_, p[0][3], p[0][4], p[0][5]};
    UpdateStats stats;
    if (!state_->Update(theta, &stats) || stats.remeshed) return false;  // a re-mesh changes F̂_B'
    AxialResiduals out;
    const bool want = jacobians != nullptr && jacobians[0] != nullptr;
    ComputeAxialResiduals(*state_, settings_, want, &out);
    for (std::size_t i = 0; i < out.r.size(); ++i) {
      residuals[i] = out.r[i];
      if (!want) continue;
      for (int k = 0; k < 6; ++k) jacobians[0][6 * i + k] = out.jacobian[i][k] / (k < 3 ? radius_ : 1.0);
    }
    return true;
  }

 private:
  PairState* state_;
  double radius_;
  AxialSettings settings_;
};

void CheckAxialJacobians(const Sides& sides_ref, const AxialSettings& settings, const char* label) {
  const Sides* sides = &sides_ref;
  const Theta thetas[] = {{0.004, -0.003, 0.02, 1.5, -0.8, 0.3},
                          {-0.006, 0.002, -0.05, -2.1, 1.2, -0.4},
                          {0.001, 0.005, 0.3, 6.0, 4.0, 1.0}};
  for (const Theta& theta : thetas) {
    PairState state(sides->reference, sides->moving);
    AxialCost cost(&state, sides->radius, settings);
    ceres::NumericDiffOptions nd;
    // GradientChecker uses Ridders' method, whose first step is 2^5 × this
    // (at least sqrt(ε)): keep it small, the residuals are piecewise smooth
    // in θ (a node crossing an edge changes the piece).
    nd.ridders_relative_initial_step_size = 1e-7;
    const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
    ceres::GradientChecker checker(&cost, no_manifolds, nd);
    double p[6];
    for (int k = 0; k < 6; ++k) p[k] = theta[k] * (k < 3 ? sides->radius : 1.0);
    const double* blocks[] = {p};
    ceres::GradientChecker::ProbeResults results;
    const bool probe_ok = checker.Probe(blocks, 1e-5, &results);
    ASSERT_TRUE(results.return_value) << "Update failed or re-meshed";
    // Per node: relative error of its Jacobian row. A node crossing an edge
    // (or the overlap boundary) within the step legitimately disagrees.
    const ceres::Matrix& ja = results.jacobians[0];
    const ceres::Matrix& jn = results.numeric_jacobians[0];
    int bad = 0, active = 0;
    double worst = 0;
    for (int i = 0; i < ja.rows(); ++i) {
      const double norm = std::max(ja.row(i).norm(), jn.row(i).norm());
      if (norm == 0) continue;
      ++active;
      const double error = (ja.row(i) - jn.row(i)).norm() / norm;
      if (error > 1e-5) ++bad; else worst = std::max(worst, error);
    }
    std::printf("axial jacobians (%s): %d active rows, %d disagree (> 1e-5), worst agreeing %.2e, "
                "probe %s max rel %.2e\n", label, active, bad, worst, probe_ok ? "ok" : "failed",
                results.maximum_relative_error);
    EXPECT_GT(active, 2000);
    EXPECT_LE(bad, active / 1000);
  }
}

// The axial cost's taper, by brute force: per vertex 1 if no triangle around
// it is outside the domain and no hull edge (an edge of one triangle only)
// ends at it; points with that as their height, for HeightAt.
std::vector<Eigen::Vector3d> TaperField(const std::vector<Point2>& xy, const Triangulation& mesh,
                                        const std::vector<uint8_t>& in_domain) {
  std::vector<double> flag(xy.size(), 0.0);
  std::map<std::pair<int32_t, int32_t>, int> edge_count;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    for (int i = 0; i < 3; ++i) {
      const int32_t u = mesh.triangles[3 * t + i], v = mesh.triangles[3 * t + (i + 1) % 3];
      ++edge_count[{std::min(u, v), std::max(u, v)}];
      if (in_domain[t]) flag[u] = 1.0;
    }
  }
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (in_domain[t]) continue;
    for (int i = 0; i < 3; ++i) flag[mesh.triangles[3 * t + i]] = 0.0;
  }
  for (const auto& [edge, count] : edge_count) {
    if (count == 1) flag[edge.first] = flag[edge.second] = 0.0;
  }
  std::vector<Eigen::Vector3d> field(xy.size());
  for (std::size_t v = 0; v < xy.size(); ++v) field[v] = {xy[v].x, xy[v].y, flag[v]};
  return field;
}

TEST(AxialCostTest, JacobiansMatchNumericDifferentiation) {
  CheckAxialJacobians(*TerrainSides(1500, 1200, 0, 100), AxialSettings(), "uniform");
}

// With μ: sqrt(μ) on every residual, B's μ moving with the node, and the
// normalization by Σμ (which moves too) all differentiated exactly.
TEST(AxialCostTest, WeightedJacobiansMatchNumericDifferentiation) {
  const auto smooth = TerrainSides(1500, 1200, 0, 100, SmoothWeight);
  CheckAxialJacobians(*smooth, AxialSettings(), "smooth mu");
  AxialSettings normalized;
  normalized.normalize_count = 2000;
  CheckAxialJacobians(*smooth, normalized, "smooth mu, normalized");
  CheckAxialJacobians(*TerrainSides(1500, 1200, 0, 100, DiscZero), normalized, "0/1 mu, normalized");
}

// normal_distance: the cosine at A's nodes turns with the moved B triangle
// (its derivative is in the Jacobian; the thetas above tilt B), at B's it is
// constant per A triangle; also combined with μ and the normalization.
TEST(AxialCostTest, NormalDistanceJacobiansMatchNumericDifferentiation) {
  AxialSettings normal;
  normal.normal_distance = true;
  CheckAxialJacobians(*TerrainSides(1500, 1200, 0, 100), normal, "normal distance");
  normal.normalize_count = 2000;
  CheckAxialJacobians(*TerrainSides(1500, 1200, 0, 100, SmoothWeight), normal,
                      "normal distance, smooth mu, normalized");
}

// Two parallel planes z = 0.3x − 0.4y (+ d for B; |∇F| = 0.5) with B moved by
// a translation: every vertical gap is g = d + tz − 0.3tx + 0.4ty, and with
// normal_distance every residual is ±g·cos(slope) = ±g / sqrt(1.25) (the
// distance between the planes along their normal). Then B is tilted, which
// changes the cosine at A's nodes: its derivative is checked by central
// differences (exact for planes: no node changes piece).
TEST(AxialCostTest, NormalDistanceOnTiltedPlanes) {
  const double d = 0.7;
  std::vector<std::array<double, 3>> pa, pb;
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      const double x = 5.0 * i + 0.3 * std::sin(j), y = 5.0 * j + 0.3 * std::cos(i);
      pa.push_back({x, y, 0.3 * x - 0.4 * y});
      const double u = 5.0 * i + 2.1, v = 5.0 * j + 1.3;
      pb.push_back({u, v, 0.3 * u - 0.4 * v + d});
    }
  }
  const auto sides = MakeSides(pa, pb);
  const Theta theta = {0, 0, 0, 1.5, -0.8, 0.3};
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update(theta));
  AxialSettings normal;
  normal.normal_distance = true;
  AxialResiduals plain, weighted;
  ComputeAxialResiduals(state, AxialSettings(), true, &plain);
  ComputeAxialResiduals(state, normal, true, &weighted);
  const double gap = d + theta[5] - 0.3 * theta[3] + 0.4 * theta[4];
  const double cosine = 1.0 / std::sqrt(1.25);
  const std::size_t na = sides->reference.xy.size();
  const std::vector<Eigen::Vector3d> taper_a =
      TaperField(sides->reference.xy, sides->reference.mesh, sides->reference.domain);
  const std::vector<Eigen::Vector3d> taper_b =
      TaperField(state.moved_xy(), state.moving_mesh(), state.active_b());
  int checked = 0, full = 0;
  for (std::size_t k = 0; k < weighted.r.size(); ++k) {
    ASSERT_EQ(plain.active[k], weighted.active[k]) << k;
    if (!weighted.active[k]) continue;
    const double sign = k < na ? 1.0 : -1.0;
    const Point2 at = k < na ? sides->reference.xy[k] : state.moved_xy()[k - na];
    double taper = 0;
    ASSERT_TRUE(HeightAt(k < na ? taper_b : taper_a,
                         k < na ? state.moving_mesh() : sides->reference.mesh, at.x, at.y, &taper));
    EXPECT_NEAR(plain.r[k], taper * sign * gap, 1e-12) << k;
    EXPECT_NEAR(weighted.r[k], taper * sign * gap * cosine, 1e-12) << k;
    ++checked;
    if (taper < 1.0) continue;  // τ's own derivative: the numeric Jacobian tests
    // Translation columns: ±n·cos = ±(−0.3, 0.4, 1)/sqrt(1.25) (B moves up: gap grows).
    EXPECT_NEAR(weighted.jacobian[k][3], -sign * 0.3 * cosine, 1e-12) << k;
    EXPECT_NEAR(weighted.jacobian[k][4], sign * 0.4 * cosine, 1e-12) << k;
    EXPECT_NEAR(weighted.jacobian[k][5], sign * cosine, 1e-12) << k;
    ++full;
  }
  EXPECT_GT(full, 400);
  EXPECT_GT(checked, 600);
  // Trimming sees the weighted residuals: a 0.2 trim drops the same count either way.
  normal.trim_fraction = 0.2;
  AxialResiduals trimmed;
  ComputeAxialResiduals(state, normal, false, &trimmed);
  EXPECT_LE(trimmed.active_count, weighted.active_count);
  EXPECT_LE(trimmed.trim_threshold, std::fabs(gap) * cosine + 1e-12);
  // Tilt B about the x axis by α: at A's nodes the cosine is that of B''s
  // slope, which changes with α. Central differences of Σ r (A's nodes)
  // against the analytic Jacobian's column, exact for planes.
  const Theta tilt = {0.05, 0.02, 0.1, 1.5, -0.8, 0.3};
  ASSERT_TRUE(state.Update(tilt));
  normal.trim_fraction = 0;
  ComputeAxialResiduals(state, normal, true, &weighted);
  for (int c = 0; c < 3; ++c) {
    const double h = 1e-6;
    AxialResiduals up, down;
    Theta t = tilt;
    t[c] += h;
    ASSERT_TRUE(state.Update(t));
    ComputeAxialResiduals(state, normal, false, &up);
    t[c] -= 2 * h;
    ASSERT_TRUE(state.Update(t));
    ComputeAxialResiduals(state, normal, false, &down);
    int compared = 0;
    for (std::size_t k = 0; k < na; ++k) {
      if (!weighted.active[k] || !up.active[k] || !down.active[k]) continue;
      const double numeric = (up.r[k] - down.r[k]) / (2 * h);
      EXPECT_NEAR(weighted.jacobian[k][c], numeric, 1e-6 * (1 + std::fabs(numeric))) << "node " << k << " col " << c;
      ++compared;
    }
    EXPECT_GT(compared, 200);
  }
}

// r at a node, from planes through corners moved here (Eigen AngleAxis);
// with μ, times sqrt(μ): μ(x, y) itself at A's nodes, at B's the plane
// through μ at A's corners (brute-force search); times the taper τ, 1 but on
// the outer ring of triangles of each surface, where it falls to 0. Without
// τ, Σμ|gap| / Σμ is Measure's ρ'd when θ moves B in xy only (a tilt changes
// B's Delaunay mesh in Measure, not in the registration, which keeps B's own mesh).
void CheckAxialResiduals(const WeightFunction& weight, const Theta& theta) {
  const auto sides = TerrainSides(1500, 1200, 0, 100, weight);
  const ReferenceSide& a = sides->reference;
  const MovingSide& b = sides->moving;
  PairState state(a, b);
  ASSERT_TRUE(state.Update(theta));
  ASSERT_EQ(state.remeshes(), 0);
  AxialResiduals out;
  ComputeAxialResiduals(state, AxialSettings(), false, &out);
  std::vector<Eigen::Vector3d> moved_b, a3(a.xy.size()), mu3(a.xy.size());
  for (const auto& p : b.points) {
    moved_b.push_back(Moved(b, theta, p));
    EXPECT_LT((moved_b.back() - ApplyMotion(MotionOf(b, theta), p)).norm(), 1e-12);
  }
  const Eigen::Vector3d origin(sides->a.origin[0], sides->a.origin[1], sides->a.origin[2]);
  for (std::size_t i = 0; i < a.xy.size(); ++i) {
    a3[i] = {a.xy[i].x, a.xy[i].y, a.z[i]};
    mu3[i] = {a.xy[i].x, a.xy[i].y, weight ? weight(a.xy[i].x + origin.x(), a.xy[i].y + origin.y()) : 1.0};
  }
  const std::size_t na = a.xy.size();
  const std::vector<Eigen::Vector3d> taper_a = TaperField(a.xy, a.mesh, a.domain);
  const std::vector<Eigen::Vector3d> taper_b =
      TaperField(state.moved_xy(), state.moving_mesh(), state.active_b());
  int checked = 0, outside = 0, tapered = 0;
  double worst = 0, sum_mu = 0, sum_abs_untapered = 0, sum_mu_untapered = 0;
  for (std::size_t k = 0; k < out.r.size(); ++k) {
    const Eigen::Vector3d node = k < na ? a3[k] : moved_b[k - na];
    double z, mu = 1, taper = 0;
    const bool inside = k < na ? HeightAt(moved_b, state.moving_mesh(), node.x(), node.y(), &z)
                               : HeightAt(a3, a.mesh, node.x(), node.y(), &z);
    if (inside && k < na) mu = mu3[k].z();
    if (inside && k >= na) HeightAt(mu3, a.mesh, node.x(), node.y(), &mu);
    if (inside) HeightAt(k < na ? taper_b : taper_a, k < na ? state.moving_mesh() : a.mesh,
                         node.x(), node.y(), &taper);
    if (inside && mu > 0) {
      sum_abs_untapered += mu * std::fabs(z - node.z());
      sum_mu_untapered += mu;
    }
    const bool active = inside && mu > 0 && taper > 1e-12;
    EXPECT_EQ(active, out.active[k] != 0) << "node " << k;
    if (!active) {
      outside += !inside;
      EXPECT_NEAR(out.r[k], 0.0, 1e-12);
      continue;
    }
    tapered += taper < 1.0;
    const double expected = z - node.z();  // F̂_B'(x_i) − z_i, or F̂_A(x'_j) − z'_j
    worst = std::max(worst, std::fabs(out.r[k] - taper * std::sqrt(mu) * expected));
    sum_mu += mu * taper * taper;
    ++checked;
  }
  std::printf("axial residuals (%s): %d nodes checked (%d tapered), %d outside, max |dr| %.2e\n",
              weight ? "weighted" : "uniform", checked, tapered, outside, worst);
  EXPECT_GT(checked, 2000);
  EXPECT_GT(tapered, 50);
  EXPECT_GT(outside, 50);
  EXPECT_LT(worst, 1e-10);
  EXPECT_NEAR(out.active_weight, sum_mu, 1e-9 * sum_mu);
  RigidMotion motion = MotionOf(b, theta);
  for (int k = 0; k < 3; ++k) motion.centre[k] += sides->a.origin[k];  // local → input frame
  MeasureOptions options;
  options.weight = weight ? WeightMode::kPerPoint : WeightMode::kUniform;
  options.domain.kind = DomainKind::kHull;  // the sides' Ω (MakeSides: over the hulls)
  const MeasureSummary m = Measure(sides->a, TransformSurface(sides->b, ReferenceFromMoving(motion)), options);
  if (theta[0] == 0 && theta[1] == 0) {
    const double rho = sum_abs_untapered / sum_mu_untapered;
    EXPECT_NEAR(rho, m.rho_d_axial, 1e-12 * m.rho_d_axial);
  }
}

TEST(AxialCostTest, ResidualsEqualIndependentPlanes) {
  const Theta tilted = {0.004, -0.003, 0.2, 3.5, -2.8, 0.3}, flat = {0, 0, 0.2, 3.5, -2.8, 0.3};
  CheckAxialResiduals(nullptr, tilted);
  CheckAxialResiduals(nullptr, flat);
  CheckAxialResiduals(SmoothWeight, tilted);
  CheckAxialResiduals(SmoothWeight, flat);
  CheckAxialResiduals(DiscZero, flat);
}

// ---------------------------------------------------------------- 2. volume gradient

struct Fd {
  Vector6 abs, area, per_area;
};

// Central differences of abs, area and PerArea (steps 1e-6 rad / 1e-6 units).
Fd CentralDifferences(PairState& state, const Theta& theta) {
  Fd fd;
  const double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    VolumeCostValue v[2];
    for (int s = 0; s < 2; ++s) {
      Theta t = theta;
      t[k] += s == 0 ? h : -h;
      UpdateStats stats;
      EXPECT_TRUE(state.Update(t, &stats));
      EXPECT_FALSE(stats.remeshed);
      v[s] = EvaluateVolumeCost(state, false, Execution{1});
    }
    fd.abs[k] = (v[0].abs - v[1].abs) / (2 * h);
    fd.area[k] = (v[0].area - v[1].area) / (2 * h);
    fd.per_area[k] = (v[0].PerArea() - v[1].PerArea()) / (2 * h);
  }
  return fd;
}

// Rotations scaled to lengths (÷ radius), so that all six count alike.
Vector6 Scaled(const Vector6& g, double radius) {
  Vector6 scale;
  scale << 1 / radius, 1 / radius, 1 / radius, 1, 1, 1;
  return g.cwiseProduct(scale);
}
double RelativeError(const Vector6& got, const Vector6& expected, double radius) {
  return (Scaled(got, radius) - Scaled(expected, radius)).norm() /
         std::max(Scaled(expected, radius).norm(), 1e-300);
}

void CheckVolumeGradient(const Sides& sides, const Theta& theta, bool b_inside_a) {
  PairState state(sides.reference, sides.moving);
  ASSERT_TRUE(state.Update(theta));
  const VolumeCostValue v = EvaluateVolumeCost(state, true, Execution{1});
  const VolumeCostValue vp = EvaluateVolumeCost(state, true, Execution{2});
  const Fd fd = CentralDifferences(state, theta);
  const double r = sides.radius;
  const double e_abs = RelativeError(v.d_abs, fd.abs, r);
  const double e_area = RelativeError(v.d_area, fd.area, r);
  const double e_per = RelativeError(v.PerAreaGradient(), fd.per_area, r);
  // The boundary's share of the PerArea gradient: −PerArea·d_area/area.
  const double boundary = RelativeError(v.PerAreaGradient(), v.d_abs / v.area, r);
  std::printf("volume gradient (%s): rel err d_abs %.2e d_area %.2e per_area %.2e; "
              "|d_area| %.3g, d_area share of per_area gradient %.2e\n",
              b_inside_a ? "B inside A" : "hulls cross", e_abs, e_area, e_per, Scaled(v.d_area, r).norm(), boundary);
  const double tolerance = 1e-5;  // measured: ≤ 1.3e-6 (d_area), ≤ 3e-8 (d_abs)
  EXPECT_LT(e_abs, tolerance);
  EXPECT_LT(e_area, tolerance);
  EXPECT_LT(e_per, tolerance);
  EXPECT_LT(RelativeError(vp.d_abs, v.d_abs, r), 1e-10);  // the two-thread split adds up the same
  EXPECT_NEAR(vp.abs, v.abs, 1e-10 * v.abs);
  // The boundary term matters: without it d_area = 0 and the PerArea
  // gradient would be off by far more than the tolerance.
  EXPECT_GT(boundary, 100 * tolerance);
  EXPECT_GT(Scaled(fd.area, r).norm(), 1.0);  // units² per unit
  if (b_inside_a && sides.reference.weight.empty()) {
    // Ω = B' projected: translations keep its area (ω_z does not: with a
    // tilt, ∂T/∂ω_z is a rotation about a tilted axis). Not ∫μ, with μ.
    for (int k : {3, 4, 5}) EXPECT_NEAR(v.d_area[k], 0.0, 1e-9 * v.d_area.norm()) << k;
  }
}

TEST(VolumeCostTest, GradientMatchesCentralDifferencesHullsCross) {
  const auto sides = TerrainSides(2000, 1500, 0, 100);
  CheckVolumeGradient(*sides, {0.004, -0.003, 0.02, 7.5, -4.8, 0.3}, false);
  CheckVolumeGradient(*sides, {-0.006, 0.005, -0.15, -5.1, 9.2, -0.8}, false);
}

TEST(VolumeCostTest, GradientMatchesCentralDifferencesBInsideA) {
  const auto sides = TerrainSides(2000, 800, 25, 75);
  CheckVolumeGradient(*sides, {0.008, -0.006, 0.05, 1.5, -0.8, 0.3}, true);
  CheckVolumeGradient(*sides, {-0.01, 0.004, -0.3, -3.1, 2.2, -0.5}, true);
}

// With the data domain, ∂Ω also runs along B's edges next to its junk (a
// void's rim): their boundary term is in the gradient too.
TEST(VolumeCostTest, GradientMatchesCentralDifferencesWithVoids) {
  const auto sides = VoidSides(2000, 1800);
  CheckVolumeGradient(*sides, {0.004, -0.003, 0.02, 1.5, -0.8, 0.3}, false);
  CheckVolumeGradient(*sides, {-0.006, 0.005, -0.05, -2.1, 1.2, -0.5}, false);
}

// ∫μ|d| / ∫μ: μ fixed to the reference, linear per cell; the boundary term
// carries μ (0/1 μ: the disc's edge blurs over one triangle, still linear).
TEST(VolumeCostTest, WeightedGradientMatchesCentralDifferences) {
  for (const WeightFunction& weight : {WeightFunction(SmoothWeight), WeightFunction(DiscZero)}) {
    const auto crossing = TerrainSides(2000, 1500, 0, 100, weight);
    CheckVolumeGradient(*crossing, {0.004, -0.003, 0.02, 7.5, -4.8, 0.3}, false);
    CheckVolumeGradient(*crossing, {-0.006, 0.005, -0.15, -5.1, 9.2, -0.8}, false);
    const auto inside = TerrainSides(2000, 800, 25, 75, weight);
    CheckVolumeGradient(*inside, {0.008, -0.006, 0.05, 1.5, -0.8, 0.3}, true);
  }
}

// ---------------------------------------------------------------- 3. volume value

// With μ: abs = ρd = ∫μ|d|, area = ∫μ (weight_integral), PerArea = mean |dz|.
void CheckVolumeValue(const WeightFunction& weight, double tolerance) {
  // Origins differ (B's box is offset) so the frame shift matters.
  const auto sides = MakeSides(testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 5),
                               testing::SampleUniform(testing::SmoothTerrain, 1500, 13, 120, -9, 90, 6),
                               weight);
  const Theta thetas[] = {{0, 0, 0, 0, 0, 0}, {0, 0, 0.3, 4.2, -7.7, 0.6}, {0, 0, -1.1, -12, 3, -2}};
  MeasureOptions options;
  options.weight = weight ? WeightMode::kPerPoint : WeightMode::kUniform;
  options.domain.kind = DomainKind::kHull;  // the sides' Ω (MakeSides: over the hulls)
  for (const Theta& theta : thetas) {
    PairState state(sides->reference, sides->moving);
    ASSERT_TRUE(state.Update(theta));
    const VolumeCostValue v = EvaluateVolumeCost(state, false, Execution{1});
    RigidMotion motion = MotionOf(sides->moving, theta);
    for (int k = 0; k < 3; ++k) motion.centre[k] += sides->a.origin[k];  // local → input frame
    const MeasureSummary m =
        Measure(sides->a, TransformSurface(sides->b, ReferenceFromMoving(motion)), options);
    std::printf("volume value (%s) rz=%.2f: abs %.12g vs rho_d %.12g (rel %.1e), "
                "area %.12g vs %.12g (rel %.1e)\n", weight ? "weighted" : "uniform",
                theta[2], v.abs, m.rho_d, std::fabs(v.abs - m.rho_d) / m.rho_d, v.area,
                m.weight_integral, std::fabs(v.area - m.weight_integral) / m.weight_integral);
    EXPECT_NEAR(v.abs, m.rho_d, tolerance * m.rho_d);
    EXPECT_NEAR(v.area, m.weight_integral, tolerance * m.weight_integral);
    EXPECT_NEAR(v.PerArea(), m.mean_abs_dz, tolerance * m.mean_abs_dz);
    if (weight) {
      EXPECT_LT(v.area, 0.95 * m.overlap_area);  // μ really weights
    }
  }
}

TEST(VolumeCostTest, ValueEqualsMeasureForXyRigidMotion) {
  CheckVolumeValue(nullptr, 1e-9);
  CheckVolumeValue(SmoothWeight, 1e-12);
  CheckVolumeValue(DiscZero, 1e-12);
}

}  // namespace
}  // namespace surfreg
