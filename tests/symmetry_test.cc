// Facial asymmetry (faces/symmetry.h) against independent truth:
// an exactly symmetric node set (zero asymmetry, the exact plane), a bump of
// closed-form volume on one cheek (ρd = 2V), a symmetric face rotated out of
// its plane by a known motion (the plane recovered), the chained gradient
// against central differences, and the edge cases.
#include "faces/symmetry.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "measure/input_error.h"
#include "io/surface_reader.h"

namespace surfreg {
namespace {

using Points = std::vector<std::array<double, 3>>;

// A face file's points in input coordinates (read by the project's reader).
Points FacePoints(const std::string& path) {
  const Surface surface = ReadSurface(path);
  Points points;
  for (std::size_t i = 0; i < surface.size(); ++i) {
    points.push_back({surface.xy[i].x + surface.origin[0], surface.xy[i].y + surface.origin[1],
                      surface.z[i] + surface.origin[2]});
  }
  return points;
}

// The face with x centred, its x > 0 half kept and mirrored: exactly
// symmetric about x = 0 (negation is exact in floating point).
Points SymmetricFace(const std::string& path) {
  const Points face = FacePoints(path);
  double mean = 0;
  for (const auto& p : face) mean += p[0];
  mean /= static_cast<double>(face.size());
  Points out;
  for (const auto& p : face) {
    const double x = p[0] - mean;
    if (x <= 1e-6) continue;
    out.push_back({x, p[1], p[2]});
    out.push_back({-x, p[1], p[2]});
  }
  return out;
}

constexpr double kPi = 3.14159265358979323846;

// h (1 − r²/R²)² on the disk of radius R about (cx, cy): volume πR²h/3.
double Bump(double x, double y, double cx, double cy, double radius, double height) {
  const double r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (radius * radius);
  return r2 < 1 ? height * (1 - r2) * (1 - r2) : 0.0;
}

const Points& FaceA() {
  static const Points* face = new Points(SymmetricFace("configs/data/face_a.xyz"));
  return *face;
}

TEST(SymmetryTest, SymmetricFaceHasZeroAsymmetryAndTheExactPlane) {
  const Surface face = MakeSurface(FaceA(), {}, "symmetric face");
  ASSERT_GT(face.size(), 10000u);
  const SymmetryResult result = EstimateSymmetry(face);
  std::printf("symmetric face: rho_d initial %.3g, refined %.3g; %s", result.initial.measure.rho_d,
              result.refined.measure.rho_d, result.BriefReport().c_str());
  // Hull area ~450 units², heights span ~20 units: 1e-9 is numerical zero.
  EXPECT_LT(result.initial.measure.rho_d, 1e-9);
  EXPECT_LT(result.refined.measure.rho_d, 1e-9);
  EXPECT_GT(result.initial.measure.overlap_area, 300);
  for (const SymmetryEstimate* e : {&result.initial, &result.refined}) {
    EXPECT_NEAR(e->plane.normal[0], 1.0, 1e-12);
    EXPECT_NEAR(e->plane.normal[1], 0.0, 1e-9);
    EXPECT_NEAR(e->plane.normal[2], 0.0, 1e-9);
    EXPECT_NEAR(e->plane.offset, 0.0, 1e-9);
  }
  EXPECT_LT(result.angle_deg, 1e-7);
}

TEST(SymmetryTest, BumpOnOneCheekCountsTwice) {
  const double cx = 4.0, cy = 2.0, radius = 2.5, height = 0.8;
  Points points = FaceA();
  for (auto& p : points) p[2] += Bump(p[0], p[1], cx, cy, radius, height);
  const Surface face = MakeSurface(points, {}, "face with a bump");
  SymmetryOptions options;
  options.keep_node_gaps = true;
  const SymmetryResult result = EstimateSymmetry(face, options);
  const double volume = kPi * radius * radius * height / 3;
  std::printf("bump: rho_d %.6f vs 2V %.6f (%.3f%%); refined %.6f; %s",
              result.initial.measure.rho_d, 2 * volume,
              100 * (result.initial.measure.rho_d / (2 * volume) - 1),
              result.refined.measure.rho_d, result.BriefReport().c_str());
  EXPECT_NEAR(result.initial.measure.rho_d, 2 * volume, 0.01 * 2 * volume);
  // The bump is above the mirror on its side, below it on the other: no net volume.
  EXPECT_NEAR(result.initial.measure.signed_volume, 0.0, 1e-9);
  // Never worse than the initial plane.
  EXPECT_LE(result.refined.measure.mean_abs_dz, result.initial.measure.mean_abs_dz);

  // Node gaps (mirror minus face): exactly −bump on the bump, +bump at its
  // mirror image (each node's mirror is a node), 0 elsewhere.
  const AsymmetryMap map = MapAsymmetry(face, SymmetryPlane(), 200);
  ASSERT_EQ(map.node_gap.size(), points.size());
  double worst = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double x = points[i][0], y = points[i][1];
    const double expected = Bump(-x, y, cx, cy, radius, height) - Bump(x, y, cx, cy, radius, height);
    worst = std::max(worst, std::abs(map.node_gap[i] - expected));
    // Measure's own node gaps agree.
    EXPECT_NEAR(result.initial.measure.dz_a[i], expected, 1e-9);
  }
  EXPECT_LT(worst, 1e-9);
  // The grid integrates to the same ±V on each side.
  const double cell = (map.x_max - map.x_min) / map.columns;
  EXPECT_NEAR(cell, (map.y_max - map.y_min) / map.rows, 1e-12);
  double positive = 0, negative = 0;
  int nan = 0;
  for (double v : map.values) {
    if (std::isnan(v)) {
      ++nan;
      continue;
    }
    (v > 0 ? positive : negative) += v * cell * cell;
  }
  EXPECT_GT(nan, 0);  // the corners of the bounding box are outside the face
  EXPECT_NEAR(positive, volume, 0.03 * volume);
  EXPECT_NEAR(negative, -volume, 0.03 * volume);
  // A grid cell centre at the bump's top: −h up to interpolation error.
  const int c = static_cast<int>((cx - map.x_min) / cell), r = static_cast<int>((map.y_max - cy) / cell);
  EXPECT_NEAR(map.values[r * map.columns + c], -height, 0.05 * height);
}

// The symmetric face moved by a known rigid motion: its symmetry plane is the
// image of x = 0, n = R e_x, offset = n·t.
TEST(SymmetryTest, RotatedFaceIsRefinedBackToItsPlane) {
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(2.0 * kPi / 180, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(3.0 * kPi / 180, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  const Eigen::Vector3d shift(0.6, -0.4, 0.3);
  Points points;
  for (const auto& p : FaceA()) {
    const Eigen::Vector3d q = rotation * Eigen::Vector3d(p[0], p[1], p[2]) + shift;
    points.push_back({q.x(), q.y(), q.z()});
  }
  const Surface face = MakeSurface(points, {}, "rotated symmetric face");
  const Eigen::Vector3d n = rotation.col(0);
  SymmetryPlane truth;
  truth.normal = {n.x(), n.y(), n.z()};
  truth.offset = n.dot(shift);
  const SymmetryResult result = EstimateSymmetry(face);
  const double error_deg = PlaneAngleDegrees(result.refined.plane, truth);
  std::printf("rotated: plane error %.2e deg, offset error %.2e, initial angle %.4f deg; %s",
              error_deg, result.refined.plane.offset - truth.offset,
              PlaneAngleDegrees(result.initial.plane, truth), result.BriefReport().c_str());
  EXPECT_TRUE(result.improved);
  EXPECT_GT(result.refined.plane.normal[0], 0);
  EXPECT_LT(error_deg, 0.05);
  EXPECT_NEAR(result.refined.plane.offset, truth.offset, 0.005);
  EXPECT_LT(result.refined.measure.mean_abs_dz, 0.01 * result.initial.measure.mean_abs_dz);
}

TEST(SymmetryTest, ChainedGradientMatchesCentralDifferences) {
  Points points = FaceA();
  for (auto& p : points) p[2] += Bump(p[0], p[1], 4.0, 2.0, 2.5, 0.8);
  const Surface face = MakeSurface(points, {}, "face with a bump");
  SymmetryPlane base = CanonicalPlane({1.0, 0.02, -0.01}, 0.1);
  const SymmetryObjective objective(face, base, SymmetryOptions());
  const double zero[3] = {0, 0, 0};
  const SymmetryPlane at_zero = objective.PlaneAt(zero);
  EXPECT_LT(PlaneAngleDegrees(at_zero, base), 1e-12);
  EXPECT_NEAR(at_zero.offset, base.offset, 1e-12);
  double worst = 0;
  for (const auto& x0 : {std::array<double, 3>{0.3, -0.2, 0.05}, std::array<double, 3>{-0.1, 0.15, -0.2}}) {
    double cost = 0, gradient[3];
    ASSERT_TRUE(objective.Evaluate(x0.data(), &cost, gradient));
    const double step = 1e-6;
    for (int i = 0; i < 3; ++i) {
      std::array<double, 3> plus = x0, minus = x0;
      plus[i] += step;
      minus[i] -= step;
      double f_plus = 0, f_minus = 0;
      ASSERT_TRUE(objective.Evaluate(plus.data(), &f_plus, nullptr));
      ASSERT_TRUE(objective.Evaluate(minus.data(), &f_minus, nullptr));
      const double numeric = (f_plus - f_minus) / (2 * step);
      EXPECT_NEAR(gradient[i], numeric, 1e-6 + 1e-5 * std::abs(numeric)) << "parameter " << i;
      worst = std::max(worst, std::abs(gradient[i] - numeric));
    }
  }
  std::printf("chained gradient vs central differences: worst difference %.2e\n", worst);
  // At the base plane the objective is Measure's ρd per area between the face
  // and its mirror image (the mirror is triangulated afresh there), both over
  // their data domains.
  double cost = 0;
  ASSERT_TRUE(objective.Evaluate(zero, &cost, nullptr));
  const MeasureSummary measure = Measure(face, ReflectSurface(face, base));
  EXPECT_NEAR(cost, measure.mean_abs_dz, 1e-9 * measure.mean_abs_dz);
}

TEST(SymmetryTest, FaceThatDoesNotMeetItsMirrorIsAnInputError) {
  Points points;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) points.push_back({5.5 + 0.1 * i, 0.1 * j, 0.01 * i * j});
  }
  const Surface face = MakeSurface(points, {}, "far.xyz");
  try {
    EstimateSymmetry(face);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("far.xyz"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("mirror"), std::string::npos) << error.what();
  }
  // Wholly at x < 0, and touching x = 0 only on its edge: the same.
  for (auto& p : points) p[0] = -p[0];
  EXPECT_THROW(EstimateSymmetry(MakeSurface(points, {}, "left.xyz")), InputError);
  for (auto& p : points) p[0] += 5.5;  // x in [−1.9, 0]
  EXPECT_THROW(EstimateSymmetry(MakeSurface(points, {}, "edge.xyz")), InputError);
  // The map of a face apart from its mirror is all "no data".
  const AsymmetryMap map = MapAsymmetry(face, SymmetryPlane(), 10);
  for (double v : map.values) EXPECT_TRUE(std::isnan(v));
  EXPECT_THROW(MapAsymmetry(face, SymmetryPlane(), 0), InputError);
}

TEST(SymmetryTest, CanonicalPlaneFixesScaleAndSign) {
  SymmetryPlane p = CanonicalPlane({-2, 0, 0}, 3);
  EXPECT_EQ(p.normal, (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(p.offset, -1.5);
  p = CanonicalPlane({0, -3, 4}, 10);
  EXPECT_NEAR(p.normal[1], 0.6, 1e-15);
  EXPECT_NEAR(p.normal[2], -0.8, 1e-15);
  EXPECT_NEAR(p.offset, -2, 1e-15);
  p = CanonicalPlane({0, 0, -1}, 1);
  EXPECT_EQ(p.normal[2], 1);
  EXPECT_THROW(CanonicalPlane({0, 0, 0}, 1), InputError);
  EXPECT_THROW(CanonicalPlane({NAN, 1, 0}, 1), InputError);
  EXPECT_THROW(CanonicalPlane({1, 0, 0}, INFINITY), InputError);
}

TEST(SymmetryTest, ReflectionIsAnInvolutionAndSurfacesFollowPoints) {
  const SymmetryPlane plane = CanonicalPlane({1, 0.1, -0.2}, 0.7);
  const std::array<double, 3> p = {1.5, -2, 3};
  const std::array<double, 3> s = ReflectPoint(plane, p), back = ReflectPoint(plane, s);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], p[k], 1e-14);
  // The midpoint lies on the plane.
  double on = 0;
  for (int k = 0; k < 3; ++k) on += plane.normal[k] * (p[k] + s[k]) / 2;
  EXPECT_NEAR(on, plane.offset, 1e-14);
  const Points points = {{1000.5, 20, 3}, {1001, 21, 4}, {999, 22.5, 5}};
  const Surface surface = MakeSurface(points, {1, 2, 3}, "s");
  const Surface mirror = ReflectSurface(surface, plane);
  ASSERT_EQ(mirror.size(), 3u);
  EXPECT_EQ(mirror.weight, surface.weight);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::array<double, 3> expected = ReflectPoint(plane, points[i]);
    EXPECT_NEAR(mirror.origin[0] + mirror.xy[i].x, expected[0], 1e-10);
    EXPECT_NEAR(mirror.origin[1] + mirror.xy[i].y, expected[1], 1e-10);
    EXPECT_NEAR(mirror.origin[2] + mirror.z[i], expected[2], 1e-10);
  }
}

TEST(SymmetryTest, PlaneAngleAndOptions) {
  SymmetryPlane a, b;
  b.normal = {std::cos(0.01), std::sin(0.01), 0};
  EXPECT_NEAR(PlaneAngleDegrees(a, b), 0.01 * 180 / kPi, 1e-12);
  b.normal = {-1, 0, 0};  // orientation ignored
  EXPECT_NEAR(PlaneAngleDegrees(a, b), 0.0, 1e-12);
  std::string error;
  SymmetryOptions options;
  EXPECT_TRUE(options.IsValid(&error));
  options.passes = 0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("passes"), std::string::npos);
  EXPECT_THROW(EstimateSymmetry(MakeSurface(FaceA(), {}, "f"), options), InputError);
  options = SymmetryOptions();
  options.max_fold_fraction = 2;
  EXPECT_FALSE(options.IsValid(&error));
  options = SymmetryOptions();
  options.refine = false;
  const SymmetryResult result = EstimateSymmetry(MakeSurface(FaceA(), {}, "f"), options);
  EXPECT_FALSE(result.improved);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_FALSE(result.note.empty());
}

// The real (not symmetric) face: the refinement is never worse, and its time
// on a 20k-point face is reported.
TEST(SymmetryTest, RealFaceTwentyThousandPoints) {
  const Points dense = FacePoints("configs/data/mannequin_face_dense.xyz");
  ASSERT_GT(dense.size(), 40000u);
  Points points;
  const std::size_t step = dense.size() / 20000;
  for (std::size_t i = 0; i < dense.size() && points.size() < 20000; i += step) points.push_back(dense[i]);
  double mean = 0;
  for (const auto& p : points) mean += p[0];
  mean /= static_cast<double>(points.size());
  for (auto& p : points) p[0] -= mean;
  const SymmetryResult result = EstimateSymmetry(MakeSurface(points, {}, "mannequin 20k"));
  std::printf("20k-point face: %s", result.BriefReport().c_str());
  EXPECT_LE(result.refined.measure.mean_abs_dz, result.initial.measure.mean_abs_dz);
  EXPECT_GT(result.refined.plane.normal[0], 0);
  // Timing is reported, not asserted: it depends on load and sanitizers.
  RecordProperty("refine_seconds", std::to_string(result.seconds));
}

}  // namespace
}  // namespace surfreg
