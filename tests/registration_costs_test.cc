// Registration internals against independent truth: axial Jacobians vs
// numeric differentiation (ceres::GradientChecker) and vs planes computed
// here, the volume cost's gradient vs central differences, its value vs
// Measure(), re-location vs brute force, folds, and locked parameters; each
// cost also with per-point weights μ on the reference.
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
#include "registration/volume_cost.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

using Theta = std::array<double, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// Both sides of a pair; heap-held because PairState keeps references.
struct Sides {
  Surface a, b;
  ReferenceSide reference;
  MovingSide moving;
  double radius = 1;  // B's RMS radius: rotations × radius are lengths
};

// μ(x, y) given as a function, sampled at the reference's points.
using WeightFunction = std::function<double(double, double)>;

// A smooth weight in [0.2, 0.8] (no zeros: sqrt(μ) is smooth), and a 0/1
// one (0 on a disc: what a raster mask gives).
double SmoothWeight(double x, double y) { return 0.5 + 0.3 * std::sin(x / 13.0) * std::cos(y / 17.0); }
double DiscZero(double x, double y) { return std::hypot(x - 60, y - 45) < 20 ? 0.0 : 1.0; }

std::unique_ptr<Sides> MakeSides(const std::vector<std::array<double, 3>>& pa,
                                 const std::vector<std::array<double, 3>>& pb,
                                 const WeightFunction& weight = nullptr) {
  auto s = std::make_unique<Sides>();
  std::vector<double> mu;
  for (const auto& p : pa) {
    if (weight) mu.push_back(weight(p[0], p[1]));
  }
  s->a = MakeSurface(pa, mu, "a");
  s->b = MakeSurface(pb, {}, "b");
  s->reference = PrepareReference(s->a);
  s->moving = PrepareMoving(s->b, {s->b.origin[0] - s->a.origin[0], s->b.origin[1] - s->a.origin[1],
                                   s->b.origin[2] - s->a.origin[2]});
  double sum = 0;
  for (const auto& p : s->moving.points) sum += (p - s->moving.centroid).squaredNorm();
  s->radius = std::sqrt(sum / s->moving.points.size());
  return s;
}

// Two different random samplings of SmoothTerrain; B on [b0, b1]².
std::unique_ptr<Sides> TerrainSides(int na, int nb, double b0, double b1,
                                    const WeightFunction& weight = nullptr) {
  return MakeSides(testing::SampleUniform(testing::SmoothTerrain, na, 0, 100, 0, 100, 11),
                   testing::SampleUniform(testing::SmoothTerrain, nb, b0, b1, b0, b1, 23), weight);
}

// The moved point computed with Eigen's AngleAxis (not surfreg's rotation code).
Eigen::Vector3d Moved(const MovingSide& m, const Theta& t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d w(t[0], t[1], t[2]);
  const Eigen::Matrix3d r =
      w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).matrix() : Eigen::Matrix3d::Identity();
  return r * (p - m.centroid) + m.centroid + Eigen::Vector3d(t[3], t[4], t[5]);
}

// Height at (x, y) of the triangle of `corners` that contains it (own
// brute-force search, plain double barycentrics); false if none does.
bool HeightAt(const std::vector<Eigen::Vector3d>& corners, const Triangulation& mesh, double x,
              double y, double* z) {
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d& p0 = corners[mesh.triangles[3 * t]];
    const Eigen::Vector3d& p1 = corners[mesh.triangles[3 * t + 1]];
    const Eigen::Vector3d& p2 = corners[mesh.triangles[3 * t + 2]];
    const double det = (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p1.y() - p0.y()) * (p2.x() - p0.x());
    const double l1 = ((x - p0.x()) * (p2.y() - p0.y()) - (y - p0.y()) * (p2.x() - p0.x())) / det;
    const double l2 = ((p1.x() - p0.x()) * (y - p0.y()) - (p1.y() - p0.y()) * (x - p0.x())) / det;
    if (l1 < -1e-12 || l2 < -1e-12 || l1 + l2 > 1 + 1e-12) continue;
    *z = (1 - l1 - l2) * p0.z() + l1 * p1.z() + l2 * p2.z();
    return true;
  }
  return false;
}

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

// r at a node, from planes through corners moved here (Eigen AngleAxis);
// with μ, times sqrt(μ): μ(x, y) itself at A's nodes, at B's the plane
// through μ at A's corners (brute-force search). Σμ|r| / Σμ is Measure's ρ'd
// when θ moves B in xy only (a tilt changes B's Delaunay mesh in Measure,
// not in the registration, which keeps B's own mesh).
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
  int checked = 0, outside = 0;
  double worst = 0, sum_abs = 0, sum_mu = 0;
  for (std::size_t k = 0; k < out.r.size(); ++k) {
    const Eigen::Vector3d node = k < na ? a3[k] : moved_b[k - na];
    double z, mu = 1;
    const bool inside = k < na ? HeightAt(moved_b, state.moving_mesh(), node.x(), node.y(), &z)
                               : HeightAt(a3, a.mesh, node.x(), node.y(), &z);
    if (inside && k < na) mu = mu3[k].z();
    if (inside && k >= na) HeightAt(mu3, a.mesh, node.x(), node.y(), &mu);
    EXPECT_EQ(inside && mu > 0, out.active[k] != 0) << "node " << k;
    if (!inside || !(mu > 0)) {
      outside += !inside;
      EXPECT_EQ(out.r[k], 0.0);
      continue;
    }
    const double expected = z - node.z();  // F̂_B'(x_i) − z_i, or F̂_A(x'_j) − z'_j
    worst = std::max(worst, std::fabs(out.r[k] - std::sqrt(mu) * expected));
    sum_abs += mu * std::fabs(expected);
    sum_mu += mu;
    ++checked;
  }
  RigidMotion motion = MotionOf(b, theta);
  for (int k = 0; k < 3; ++k) motion.centre[k] += sides->a.origin[k];  // local → input frame
  MeasureOptions options;
  options.weight = weight ? WeightMode::kPerPoint : WeightMode::kUniform;
  const MeasureSummary m = Measure(sides->a, TransformSurface(sides->b, ReferenceFromMoving(motion)), options);
  std::printf("axial residuals (%s): %d nodes checked, %d outside, max |dr| %.2e; "
              "sum mu|r| / sum mu %.12g vs rho'_d %.12g\n", weight ? "weighted" : "uniform", checked,
              outside, worst, sum_abs / sum_mu, m.rho_d_axial);
  EXPECT_GT(checked, 2000);
  EXPECT_GT(outside, 50);
  EXPECT_LT(worst, 1e-10);
  EXPECT_NEAR(out.active_weight, sum_mu, 1e-9 * sum_mu);
  if (theta[0] == 0 && theta[1] == 0) {
    EXPECT_NEAR(sum_abs / sum_mu, m.rho_d_axial, 1e-12 * m.rho_d_axial);
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
      v[s] = EvaluateVolumeCost(state, false, false);
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
  const VolumeCostValue v = EvaluateVolumeCost(state, true, false);
  const VolumeCostValue vp = EvaluateVolumeCost(state, true, true);
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
  for (const Theta& theta : thetas) {
    PairState state(sides->reference, sides->moving);
    ASSERT_TRUE(state.Update(theta));
    const VolumeCostValue v = EvaluateVolumeCost(state, false, false);
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
