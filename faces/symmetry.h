#pragma once
// Facial asymmetry (Dyshkant 2010, section 3.2): the face F is compared with
// its mirror image, first about the plane x = 0 of the normalized face frame
// (faces/face_frame.h), then about the symmetry plane that minimizes the
// measure between them.
//
// A plane {p : n·p = offset} (unit normal n, n_x > 0) reflects a point by
//   S(p) = p − 2 (n·p − offset) n.
// The reflected face S(F) is compared with F by Measure(F, S(F)): its gap
// d = F̂_S(F) − F̂_F (mirror minus face) is, at a point on one side, the
// height of the other side's mirror image minus this side's height.
//
// Refinement: two reflections compose to a rigid motion, S∘S0 = R·p + ..,
// R = (I − 2nnᵀ)(I − 2n0n0ᵀ) a rotation about n0 × n by twice the planes'
// angle. So with the mirror B = S0(F) about a base plane S0 as the moving
// surface of registration/pair_state.h, every plane near S0 is a motion
// θ = (ω, t) of B, and the volume cost ρd / |Ω| (registration/volume_cost/volume_cost.h)
// with its exact gradient ∇θ is minimized over the plane's 3 parameters
// (two tilts of the normal and the offset) with ceres::GradientProblem
// (LBFGS), by the chain rule Jᵀ∇θ (J = ∂θ/∂plane from ceres::Jet). B keeps
// its triangulation while it moves, so each pass re-mirrors the face about
// the plane found by the previous one and solves again: at the last pass B's
// mesh is nearly the Delaunay mesh of S(F).
//
// All coordinates (planes, points, grids) are the face's input coordinates
// (Surface::origin + local), in its units.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "measure/measures.h"
#include "measure/surface.h"

namespace surfreg {

struct SymmetryPlane {
  std::array<double, 3> normal = {1.0, 0.0, 0.0};  // unit, n_x > 0 (see CanonicalPlane)
  double offset = 0.0;                             // n·p on the plane, data units
};

// The plane {n·p = offset} with n scaled to unit length and its sign fixed:
// n_x > 0 (if n_x = 0, then n_y > 0, then n_z > 0), offset scaled and
// negated with it. Throws InputError for a zero or non-finite normal or a
// non-finite offset.
SymmetryPlane CanonicalPlane(const std::array<double, 3>& normal, double offset);

// S(p), input coordinates.
std::array<double, 3> ReflectPoint(const SymmetryPlane& plane, const std::array<double, 3>& p);

// The face reflected across `plane`: every sample moved by S (same order,
// same weights); its origin is S(face.origin), so local coordinates keep
// their precision.
Surface ReflectSurface(const Surface& face, const SymmetryPlane& plane);

// Angle between two planes' normals, degrees in [0, 90] (orientation ignored).
double PlaneAngleDegrees(const SymmetryPlane& a, const SymmetryPlane& b);

struct SymmetryOptions {
  // false: report the initial estimate only (the refined one equals it).
  bool refine = true;
  // Full-resolution passes (≥ 1): each re-mirrors the face about the plane
  // where the previous pass (or the coarse one, or x = 0) ended, so that the
  // mirror's mesh is triangulated afresh there, and solves again.
  int passes = 1;
  // A first, coarse pass on this fraction of the points (a fixed
  // pseudo-random subset, the same for the face and its mirror, so a
  // symmetric face stays symmetric) before the passes above; 1 = none.
  // Skipped when it would keep fewer than 2000 points.
  double coarse_fraction = 0.25;
  int max_iterations = 100;           // LBFGS iterations per pass
  double function_tolerance = 1e-12;  // relative cost decrease to stop
  // Stop a pass when two successive steps of the plane are both shorter
  // than this fraction of the face's RMS radius L (a step of ε·L tilts the
  // plane by ≈ ε radians or shifts it by ε·L): far below what sampled
  // surfaces determine, while the line search would otherwise crawl along
  // the cost's sampling noise.
  double step_tolerance = 1e-7;
  // As AlignOptions::max_fold_fraction: the share of the mirror's area whose
  // triangles may turn over in projection (slivers on steep sides) before a
  // step counts as infeasible.
  double max_fold_fraction = 0.5;
  int threads = 0;  // for Measure and the cost; 0: every core
  // Keep the gap at every face sample in both estimates' summaries
  // (MeasureSummary::dz_a: mirror minus face, NaN outside the overlap).
  bool keep_node_gaps = false;

  bool IsValid(std::string* error) const;
};

struct SymmetryEstimate {
  SymmetryPlane plane;
  // Measure(face, ReflectSurface(face, plane)): rho_d (units³, counting each
  // asymmetric volume twice: once on each side), mean_abs_dz = ρd per unit
  // overlap area (units), overlap_area (units²), signed volumes, ...
  MeasureSummary measure;
};

struct SymmetryResult {
  SymmetryEstimate initial;  // the plane x = 0
  SymmetryEstimate refined;  // the optimized plane (or a copy of `initial`, see below)
  // False when the optimized plane did not lower ρd per unit area (or the
  // solver failed, or refinement is off): `refined` is then the initial
  // estimate, and `note` says why.
  bool improved = false;
  std::string note;
  double angle_deg = 0;          // between the two planes' normals
  int iterations = 0;            // LBFGS iterations over all passes
  std::string termination;       // the last pass's solver message
  // The solver's ρd/|Ω| at the start of the first pass (on the coarse
  // subset, if any) and at the end of the last one.
  double cost_initial = 0, cost_final = 0;
  double seconds_refine = 0;     // the optimization (wall clock)
  double seconds = 0;            // everything, both Measures included

  // A few lines for people: both estimates, the planes, the angle, timings.
  std::string BriefReport() const;
};

// Compares `face` (in the normalized face frame: x across the face, centred
// so that x = 0 is roughly its middle) with its mirror image and optimizes
// the symmetry plane. Throws InputError for an invalid surface or options, or
// a face that does not straddle x = 0 (it cannot overlap its mirror image).
SymmetryResult EstimateSymmetry(const Surface& face, const SymmetryOptions& options = {});

// The refinement's objective, exposed for tests and diagnostics: for the
// plane parameters x = (L·a, L·b, e) about a base plane (n0, d0),
//   n ∝ n0 + a u + b v,   offset = d0 + e,
// (u, v an orthonormal basis of n0's complement, L the face's RMS radius in
// xy, so that all three parameters are lengths), the value ρd / |Ω| between
// the face and the mirror S0(F) moved by S∘S0, and its gradient (the exact
// ∇θ of the volume cost, chained through ∂θ/∂x).
class SymmetryObjective {
 public:
  // Copies what it needs from `face` (it may go away afterwards). With
  // keep_fraction < 1, on that fraction of the points (SymmetryOptions::coarse_fraction).
  SymmetryObjective(const Surface& face, const SymmetryPlane& base, const SymmetryOptions& options,
                    double keep_fraction = 1.0);
  ~SymmetryObjective();
  SymmetryObjective(const SymmetryObjective&) = delete;
  SymmetryObjective& operator=(const SymmetryObjective&) = delete;

  static constexpr int kNumParameters = 3;
  double scale() const;  // L, data units
  // The plane at x (canonical sign).
  SymmetryPlane PlaneAt(const double* x) const;
  // False if the mirror folds beyond max_fold_fraction or the overlap is
  // empty at x. `gradient` may be null.
  bool Evaluate(const double* x, double* cost, double* gradient) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The signed left-right difference of the face about `plane` (mirror minus
// face, as in Measure(face, S(face))) on a regular grid over the face's
// bounding box: `columns` × `rows` cells (the longer side gets
// `cells_long_side`), cell (c, r) centred at
//   x = x_min + (c + ½)·dx,  y = y_max − (r + ½)·dy,
// row 0 at the top, values row-major, NaN outside the overlap of the face's
// and its mirror's convex hulls. Also the gap at every face sample (input
// order; NaN outside the mirror's hull).
struct AsymmetryMap {
  int columns = 0, rows = 0;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  std::vector<double> values;
  std::vector<double> node_gap;
};
AsymmetryMap MapAsymmetry(const Surface& face, const SymmetryPlane& plane,
                          int cells_long_side = 300);

}  // namespace surfreg
