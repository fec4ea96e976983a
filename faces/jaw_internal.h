#pragma once
// Internal to faces/: the pieces of the jaw tracking (jaw.cc) that the
// boundary search (jaw_split.cc) shares, and what is derived from the poses
// (jaw_outputs.cc): a frame split by the boundary, a part registered onto the
// reference's, the covariance of a part and its propagation to the jaw's
// parameters.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "faces/jaw.h"
#include "registration/axial_cost.h"
#include "registration/pair_state.h"

namespace surfreg {
namespace jaw_internal {

using Points = std::vector<std::array<double, 3>>;

struct Split {
  Points upper, lower;  // input coordinates of the frame
  int dropped = 0;
};

// Classifies each point of `frame` where `reference_from_frame` puts it.
Split SplitFrame(const Surface& frame, const Eigen::Matrix4d& reference_from_frame,
                 const JawBoundary& boundary);

// A part's points as a surface; InputError naming `name` below min_points.
Surface PartSurface(const Points& points, const std::string& name, int min_points);

// One part of the reference, prepared once.
struct ReferencePart {
  Surface surface;
  ReferenceSide side;
};

// Registers a part of a frame onto the reference's part from `warm`
// (reference_from_frame). `measure`: also the volume measure after (mean
// |dz|, overlap area) and the covariance (PartSandwichCovariance), most of
// a frame's time; else they stay zero (the boundary search needs neither).
JawPartResult RegisterPart(const ReferencePart& reference, const Surface& part,
                           const Eigen::Matrix4d& warm, const JawOptions& options,
                           bool measure = true);

// The axial settings a part is solved with (normalize_count for `overlap`
// nodes in the overlap at the start).
AxialSettings PartSettings(const JawOptions& options, int64_t overlap);

// σ²(JᵀJ)⁻¹ of the active residuals (σ² = Σr² / (active − 6)), θ order.
// False (covariance NaN) with fewer than 7 active residuals or JᵀJ singular.
bool GaussNewtonCovariance(const AxialResiduals& residuals,
                           Eigen::Matrix<double, 6, 6>* covariance);

// The bread's central differences step, in Gauss-Newton σ of each
// parameter: wide enough that the nodes crossing the trim threshold (each a
// jump of Jᵀr) average out, narrow enough that the cost stays quadratic.
// On the chewing example the curvatures agree within about 10% from 3 to 30
// σ and scatter at 1 σ (down to 0.16 of JᵀJ's on one part); the Monte Carlo
// of tests/jaw_split_test.cc gives a median |error|/σ of 0.76 to 0.80 from
// 3 to 30 σ.
inline constexpr double kBreadStepSigmas = 10.0;

struct PartCovariance {
  bool ok = false;
  Eigen::Matrix<double, 6, 6> covariance;  // θ order; NaN if not ok
  int tiles = 0;                           // the clusters of the meat
  bool measured_curvature = false;         // the bread by differences (else JᵀJ)
};

// The covariance of a part's six parameters at the state's θ (settings: as
// solved; scale: the rotations' length, the part's RMS radius), a sandwich
// clustered over spatial tiles (registration/sandwich.h,
// AxialSandwichCovariance): H⁻¹ M H⁻¹, M the spread of the tiles' shares of
// Jᵀr over the kept residuals (≈ SandwichTileCount tiles, the first-order
// influence of each tile's sampling errors, correlated within it) with
// HC1's factor G/(G − 6), H the curvature of the trimmed cost, central
// differences of Jᵀr over ±kBreadStepSigmas Gauss-Newton σ. H is smaller
// than the kept residuals' JᵀJ (0.55–0.87 of its diagonal on the example,
// what moves the errors from 1.4 to 0.77 σ; docs/faces.md): as θ moves,
// nodes cross the trim threshold, and the Jacobian's interpolated slopes
// carry the sampling's noise. If the differences give no positive definite
// H: JᵀJ (measured_curvature false). Not ok (NaN) as GaussNewtonCovariance,
// or with fewer than 12 tiles. The state ends at its θ.
PartCovariance PartSandwichCovariance(PairState& state, const AxialSettings& settings,
                                      double scale);

// Fills frame->stddev, covariance and path_point(_stddev) from its parts'
// results and covariances (and its jaw, Euler angles, translation) for the
// path point p0.
void PropagateFrameCovariance(const Eigen::Vector3d& p0, JawFrame* frame);

// The default path point: the mean of the kPathLowestPoints points of
// smallest y (all of them if fewer).
Eigen::Vector3d LowestPoint(const Points& lower);

}  // namespace jaw_internal
}  // namespace surfreg
