#include "faces/symmetry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Core>
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "faces/height_mesh.h"
#include "measure/delaunay.h"
#include "measure/tasks.h"
#include "measure/input_error.h"
#include "measure/locator.h"
#include "measure/spatial_sort.h"
#include "registration/pair_state.h"
#include "registration/volume_cost/volume_cost.h"

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Eigen::Vector3d ToVector(const std::array<double, 3>& a) { return Eigen::Vector3d(a[0], a[1], a[2]); }

// The face's points relative to its origin, as 3D vectors.
Eigen::Vector3d LocalPoint(const Surface& face, std::size_t i) {
  return Eigen::Vector3d(face.xy[i].x, face.xy[i].y, face.z[i]);
}

// The face must straddle x = 0, or its hull cannot meet its mirror's.
void CheckStraddles(const Surface& face) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Point2& p : face.xy) {
    lo = std::min(lo, p.x);
    hi = std::max(hi, p.x);
  }
  lo += face.origin[0];
  hi += face.origin[0];
  if (lo < 0.0 && hi > 0.0) return;
  char range[96];
  std::snprintf(range, sizeof(range), "[%.6g, %.6g]", lo, hi);
  throw InputError(face.source + ": the face lies wholly at x in " + range +
                   ", so it does not overlap its mirror image about x = 0 (is it in the "
                   "normalized face frame, centred in x?)");
}

// An orthonormal basis (u, v) of the plane orthogonal to unit n.
void ComplementBasis(const Eigen::Vector3d& n, Eigen::Vector3d* u, Eigen::Vector3d* v) {
  Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  *u = (helper - helper.dot(n) * n).normalized();
  *v = n.cross(*u);
}

}  // namespace

SymmetryPlane CanonicalPlane(const std::array<double, 3>& normal, double offset) {
  const Eigen::Vector3d n = ToVector(normal);
  const double length = n.norm();
  if (!std::isfinite(length) || !(length > 0) || !std::isfinite(offset)) {
    throw InputError("symmetry plane: the normal must be finite and non-zero, the offset finite");
  }
  double sign = 1.0;
  for (int k = 0; k < 3; ++k) {
    if (n[k] != 0.0) {
      sign = n[k] > 0 ? 1.0 : -1.0;
      break;
    }
  }
  SymmetryPlane plane;
  for (int k = 0; k < 3; ++k) plane.normal[k] = sign * n[k] / length;
  plane.offset = sign * offset / length;
  return plane;
}

std::array<double, 3> ReflectPoint(const SymmetryPlane& plane, const std::array<double, 3>& p) {
  const Eigen::Vector3d n = ToVector(plane.normal), q = ToVector(p);
  const Eigen::Vector3d s = q - 2.0 * (n.dot(q) - plane.offset) * n;
  return {s.x(), s.y(), s.z()};
}

Surface ReflectSurface(const Surface& face, const SymmetryPlane& plane) {
  // S(o + l) = S(o) + H l with H = I − 2nnᵀ: the origin takes the affine
  // part, the small local coordinates only the linear one.
  const Eigen::Vector3d n = ToVector(plane.normal);
  const Eigen::Matrix3d h = Eigen::Matrix3d::Identity() - 2.0 * n * n.transpose();
  Surface out;
  out.origin = ReflectPoint(plane, face.origin);
  out.weight = face.weight;
  out.source = "mirror image of " + face.source;
  out.xy.resize(face.size());
  out.z.resize(face.size());
  for (std::size_t i = 0; i < face.size(); ++i) {
    const Eigen::Vector3d q = h * LocalPoint(face, i);
    out.xy[i] = {q.x(), q.y()};
    out.z[i] = q.z();
  }
  return out;
}

double PlaneAngleDegrees(const SymmetryPlane& a, const SymmetryPlane& b) {
  const Eigen::Vector3d na = ToVector(a.normal).normalized(), nb = ToVector(b.normal).normalized();
  // atan2 of |cross| and |dot| stays accurate for tiny angles (acos does not).
  const double angle = std::atan2(na.cross(nb).norm(), std::abs(na.dot(nb)));
  return angle * 180.0 / M_PI;
}

bool SymmetryOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& text) {
    if (error != nullptr) *error = text;
    return false;
  };
  if (passes < 1) return fail("passes must be >= 1");
  if (!(step_tolerance >= 0) || !std::isfinite(step_tolerance)) {
    return fail("step_tolerance must be finite and >= 0");
  }
  if (!(coarse_fraction > 0 && coarse_fraction <= 1)) return fail("coarse_fraction must be in (0, 1]");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(function_tolerance >= 0) || !std::isfinite(function_tolerance)) {
    return fail("function_tolerance must be finite and >= 0");
  }
  if (!(max_fold_fraction >= 0 && max_fold_fraction <= 1)) {
    return fail("max_fold_fraction must be in [0, 1]");
  }
  return true;
}

// ---------------------------------------------------------------------------
// The objective.

struct SymmetryObjective::State {
  ReferenceSide reference;
  MovingSide moving;
  std::unique_ptr<PairState> pair;
  Eigen::Vector3d n0, u, v;
  double d0 = 0;
  double scale = 1;  // L: the face's RMS radius in xy
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // B's centroid, input coordinates
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the face's origin
  Execution execution;

  // The plane (n, d) at x.
  template <typename T>
  void Plane(const T* x, Eigen::Matrix<T, 3, 1>* n, T* d) const {
    const Eigen::Matrix<T, 3, 1> raw =
        n0.cast<T>() + (x[0] / scale) * u.cast<T>() + (x[1] / scale) * v.cast<T>();
    *n = raw / raw.norm();
    *d = T(d0) + x[2];
  }

  // θ of the motion S∘S0 of the mirror B = S0(F), in the pair's frame
  // (the face's local one). With H = I − 2nnᵀ, H0 likewise, and C the
  // mirror's centroid in input coordinates:
  //   S∘S0(b) = H H0 b + 2 d0 H n0 + 2 d n,
  // and T(b) = R (b − C) + C + t gives R = H H0, t = R C − C + 2 d0 H n0 + 2 d n
  // (the origin shift cancels: T acts on b − origin and returns S∘S0(b) − origin
  // when t is computed with C in input coordinates).
  template <typename T>
  void Theta(const T* x, T* theta) const {
    Eigen::Matrix<T, 3, 1> n;
    T d;
    Plane(x, &n, &d);
    const Eigen::Matrix<T, 3, 3> h = Eigen::Matrix<T, 3, 3>::Identity() - T(2) * n * n.transpose();
    const Eigen::Matrix3d h0 = Eigen::Matrix3d::Identity() - 2.0 * n0 * n0.transpose();
    const Eigen::Matrix<T, 3, 3> r = h * h0.cast<T>();
    ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(r.data()), theta);
    const Eigen::Matrix<T, 3, 1> c = centre.cast<T>();
    const Eigen::Matrix<T, 3, 1> t = r * c - c + T(2 * d0) * (h * n0.cast<T>()) + T(2) * d * n;
    for (int k = 0; k < 3; ++k) theta[3 + k] = t[k];
  }
};

SymmetryObjective::SymmetryObjective(const Surface& face, const SymmetryPlane& base,
                                     const SymmetryOptions& options, double keep_fraction)
    : state_(new State) {
  State& s = *state_;
  s.execution = ExecutionFor(options.threads);
  s.n0 = ToVector(base.normal).normalized();
  s.d0 = base.offset;
  ComplementBasis(s.n0, &s.u, &s.v);
  s.origin = ToVector(face.origin);
  const Surface mirror = ReflectSurface(face, base);
  const std::array<double, 3> shift = {mirror.origin[0] - face.origin[0],
                                       mirror.origin[1] - face.origin[1],
                                       mirror.origin[2] - face.origin[2]};
  s.reference = PrepareReference(face, keep_fraction);
  s.moving = PrepareMoving(mirror, shift, keep_fraction);
  s.centre = s.origin + s.moving.centroid;
  double mx = 0, my = 0, sum2 = 0;
  for (const Point2& p : face.xy) mx += p.x, my += p.y;
  mx /= static_cast<double>(face.size());
  my /= static_cast<double>(face.size());
  for (const Point2& p : face.xy) sum2 += (p.x - mx) * (p.x - mx) + (p.y - my) * (p.y - my);
  s.scale = std::max(std::sqrt(sum2 / static_cast<double>(face.size())), 1e-300);
  s.pair.reset(new PairState(s.reference, s.moving, options.max_fold_fraction));
}

SymmetryObjective::~SymmetryObjective() = default;

double SymmetryObjective::scale() const { return state_->scale; }

SymmetryPlane SymmetryObjective::PlaneAt(const double* x) const {
  Eigen::Vector3d n;
  double d;
  state_->Plane(x, &n, &d);
  return CanonicalPlane({n.x(), n.y(), n.z()}, d);
}

bool SymmetryObjective::Evaluate(const double* x, double* cost, double* gradient) const {
  using Jet = ceres::Jet<double, kNumParameters>;
  Jet xj[kNumParameters];
  for (int i = 0; i < kNumParameters; ++i) xj[i] = Jet(x[i], i);
  Jet theta_jet[6];
  state_->Theta(xj, theta_jet);
  std::array<double, 6> theta;
  for (int k = 0; k < 6; ++k) theta[k] = theta_jet[k].a;
  if (!state_->pair->Update(theta)) return false;
  const VolumeCostValue value =
      EvaluateVolumeCost(*state_->pair, gradient != nullptr, state_->execution);
  if (!(value.area > 0)) return false;
  *cost = value.PerArea();
  if (gradient != nullptr) {
    const Eigen::Matrix<double, 6, 1> g = value.PerAreaGradient();
    for (int i = 0; i < kNumParameters; ++i) {
      gradient[i] = 0;
      for (int k = 0; k < 6; ++k) gradient[i] += g[k] * theta_jet[k].v[i];
    }
  }
  return std::isfinite(*cost);
}

// ---------------------------------------------------------------------------
// The estimate.

namespace {

class ObjectiveFunction : public ceres::FirstOrderFunction {
 public:
  explicit ObjectiveFunction(const SymmetryObjective& objective) : objective_(objective) {}
  bool Evaluate(const double* x, double* cost, double* gradient) const override {
    return objective_.Evaluate(x, cost, gradient);
  }
  int NumParameters() const override { return SymmetryObjective::kNumParameters; }

 private:
  const SymmetryObjective& objective_;  // not owned; outlives the problem
};

// Stops when two successive steps are shorter than `tolerance` (absolute, in
// the parameters' length units).
class StepCallback : public ceres::IterationCallback {
 public:
  explicit StepCallback(double tolerance) : tolerance_(tolerance) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (summary.iteration == 0) return ceres::SOLVER_CONTINUE;
    small_ = summary.step_norm < tolerance_ ? small_ + 1 : 0;
    return small_ >= 2 ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
  }

 private:
  const double tolerance_;
  int small_ = 0;
};

struct PassResult {
  SymmetryPlane plane;
  double initial_cost = 0, final_cost = 0;
  int iterations = 0;
  bool usable = false;
  std::string message;
};

PassResult SolvePass(const Surface& face, const SymmetryPlane& base,
                     const SymmetryOptions& options, double keep_fraction) {
  SymmetryObjective objective(face, base, options, keep_fraction);
  double x[SymmetryObjective::kNumParameters] = {0, 0, 0};
  ceres::GradientProblem problem(new ObjectiveFunction(objective));
  ceres::GradientProblemSolver::Options solver;
  solver.line_search_direction_type = ceres::LBFGS;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.gradient_tolerance = 1e-16;
  solver.parameter_tolerance = 1e-14;
  solver.logging_type = ceres::SILENT;
  StepCallback step(options.step_tolerance * objective.scale());
  solver.callbacks.push_back(&step);
  ceres::GradientProblemSolver::Summary summary;
  ceres::Solve(solver, problem, x, &summary);
  PassResult result;
  result.plane = objective.PlaneAt(x);
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
  result.usable = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
  result.message = summary.message;
  return result;
}

SymmetryEstimate MeasurePlane(const Surface& face, const SymmetryPlane& plane,
                              const SymmetryOptions& options) {
  MeasureOptions measure;
  measure.threads = options.threads;
  measure.keep_node_gaps = options.keep_node_gaps;
  SymmetryEstimate estimate;
  estimate.plane = plane;
  estimate.measure = Measure(face, ReflectSurface(face, plane), measure);
  return estimate;
}

void Refine(const Surface& face, const SymmetryOptions& options, SymmetryResult* result) {
  const Clock::time_point start = Clock::now();
  SymmetryPlane plane = result->initial.plane;
  bool solved = true;
  const bool coarse = options.coarse_fraction < 1.0 &&
                      options.coarse_fraction * static_cast<double>(face.size()) >= 2000;
  for (int pass = coarse ? -1 : 0; pass < options.passes; ++pass) {
    const PassResult solve = SolvePass(face, plane, options, pass < 0 ? options.coarse_fraction : 1.0);
    if (pass == (coarse ? -1 : 0)) result->cost_initial = solve.initial_cost;
    result->iterations += solve.iterations;
    result->termination = solve.message;
    if (!solve.usable) {
      solved = false;
      result->note = "the solver failed (" + solve.message + "): the initial plane is kept";
      break;
    }
    plane = solve.plane;
    result->cost_final = solve.final_cost;
  }
  result->seconds_refine = SecondsSince(start);
  if (!solved) return;
  SymmetryEstimate refined;
  try {
    refined = MeasurePlane(face, plane, options);
  } catch (const InputError& error) {
    result->note = std::string("the optimized plane could not be measured (") + error.what() +
                   "): the initial plane is kept";
    return;
  }
  if (refined.measure.mean_abs_dz < result->initial.measure.mean_abs_dz) {
    result->refined = std::move(refined);
    result->improved = true;
  } else {
    result->note = "the optimized plane did not lower rho_d per unit area: the initial plane is kept";
  }
}

std::string EstimateLine(const char* name, const SymmetryEstimate& e) {
  char line[512];
  std::snprintf(line, sizeof(line),
                "%s rho_d = %.6g units^3, per unit area (mean |dz|) = %.6g units, overlap = %.6g "
                "units^2, plane n = (%.9f, %.9f, %.9f), offset = %.6g units\n",
                name, e.measure.rho_d, e.measure.mean_abs_dz, e.measure.overlap_area,
                e.plane.normal[0], e.plane.normal[1], e.plane.normal[2], e.plane.offset);
  return line;
}

}  // namespace

SymmetryResult EstimateSymmetry(const Surface& face, const SymmetryOptions& options) {
  const Clock::time_point start = Clock::now();
  std::string error;
  if (!options.IsValid(&error)) throw InputError("symmetry options: " + error);
  ValidateSurface(face);
  CheckStraddles(face);
  SymmetryResult result;
  result.initial = MeasurePlane(face, SymmetryPlane(), options);
  result.refined = result.initial;
  if (options.refine) {
    Refine(face, options, &result);
  } else {
    result.note = "refinement off: the refined plane is the initial one";
  }
  result.angle_deg = PlaneAngleDegrees(result.initial.plane, result.refined.plane);
  result.seconds = SecondsSince(start);
  return result;
}

std::string SymmetryResult::BriefReport() const {
  std::string text = EstimateLine("initial (x = 0):", initial);
  text += EstimateLine("refined plane:  ", refined);
  char line[512];
  std::snprintf(line, sizeof(line),
                "angle between the planes: %.4f deg; %d iterations (%s); refinement %.3f s, "
                "total %.3f s\n",
                angle_deg, iterations, termination.empty() ? "none" : termination.c_str(),
                seconds_refine, seconds);
  text += line;
  if (!note.empty()) text += "note: " + note + "\n";
  return text;
}

// ---------------------------------------------------------------------------
// The map.

namespace {

using faces_internal::HeightAt;
using faces_internal::HeightMesh;
using faces_internal::MakeHeightMesh;

}  // namespace

AsymmetryMap MapAsymmetry(const Surface& face, const SymmetryPlane& plane, int cells_long_side) {
  if (cells_long_side < 1) throw InputError("asymmetry map: cells_long_side must be >= 1");
  ValidateSurface(face);
  const Surface mirror = ReflectSurface(face, plane);
  // Both in the face's local frame.
  const double sx = mirror.origin[0] - face.origin[0], sy = mirror.origin[1] - face.origin[1],
               sz = mirror.origin[2] - face.origin[2];
  std::vector<Point2> mirror_xy(mirror.size());
  std::vector<double> mirror_z(mirror.size());
  for (std::size_t i = 0; i < mirror.size(); ++i) {
    mirror_xy[i] = {mirror.xy[i].x + sx, mirror.xy[i].y + sy};
    mirror_z[i] = mirror.z[i] + sz;
  }
  const HeightMesh f = MakeHeightMesh(face.xy, face.z);
  const HeightMesh m = MakeHeightMesh(std::move(mirror_xy), mirror_z);

  AsymmetryMap map;
  map.node_gap.assign(face.size(), std::numeric_limits<double>::quiet_NaN());
  int32_t start = 0;
  for (int32_t i : SpatialOrder(face.xy, /*brio=*/false, 0)) {
    map.node_gap[i] = HeightAt(m, face.xy[i], &start) - f.z[f.mesh.vertex_of_input[i]];
  }

  double lo_x = face.xy[0].x, hi_x = lo_x, lo_y = face.xy[0].y, hi_y = lo_y;
  for (const Point2& p : face.xy) {
    lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x);
    lo_y = std::min(lo_y, p.y), hi_y = std::max(hi_y, p.y);
  }
  // Square cells; the short side is rounded up to whole cells.
  const double cell = std::max(hi_x - lo_x, hi_y - lo_y) / cells_long_side;
  map.columns = std::max(1, static_cast<int>(std::ceil((hi_x - lo_x) / cell - 1e-9)));
  map.rows = std::max(1, static_cast<int>(std::ceil((hi_y - lo_y) / cell - 1e-9)));
  map.x_min = lo_x + face.origin[0];
  map.x_max = map.x_min + map.columns * cell;
  map.y_max = hi_y + face.origin[1];
  map.y_min = map.y_max - map.rows * cell;
  map.values.resize(static_cast<std::size_t>(map.columns) * map.rows);
  int32_t start_f = 0, start_m = 0;
  for (int r = 0; r < map.rows; ++r) {
    for (int c = 0; c < map.columns; ++c) {
      const Point2 p = {lo_x + (c + 0.5) * cell, hi_y - (r + 0.5) * cell};
      const double zf = HeightAt(f, p, &start_f);
      map.values[static_cast<std::size_t>(r) * map.columns + c] =
          std::isnan(zf) ? zf : HeightAt(m, p, &start_m) - zf;
    }
  }
  return map;
}

}  // namespace surfreg
