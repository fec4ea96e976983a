#pragma once
// Jaw motion over a sequence of 3D frames (Dyshkant 2010, section 3.3;
// docs/faces.md): per frame, the motion of the lower (dynamic) part of the
// face relative to the upper (static) part, the skull.
//
// Frames are height fields (point clouds) seen by one camera, in one frame of
// coordinates, already in the normalized face frame if a boundary is to be
// given there (the CLI normalizes the reference once with NormalizeFace and
// applies the same transform to every frame: same camera). One frame is the
// reference (jaw closed). Its points are split by the boundary into the
// upper part A_U and the lower part A_L (each prepared ONCE: triangulated,
// spanning tree), dropping the points within `margin` of the boundary from
// both (skin near the boundary deforms).
//
// Frame k, processed from the reference outwards (forward, then backward),
// each warm-started from its neighbour k' nearer the reference:
// - split: its points p are classified at U·p, U the warm start of the
//   upper part (the previous frame's head motion, or its constant-velocity
//   extrapolation), i.e. where that puts them in the reference's frame (the
//   head moves between frames; the boundary must follow it);
// - register its upper part onto A_U: U_k = reference_from_frame for the
//   skull, starting at U_k' (or the extrapolation); and its lower part onto
//   A_L: L_k, starting at L_k' (or the extrapolation). The cost is the
//   axial cost (registration/axial_cost.h), each gap weighted by cos of the
//   slope (AxialSettings::normal_distance: ≈ the distance along the normal)
//   and the largest trimmed, minimized by Ceres (Levenberg-Marquardt, all
//   nodes as one residual block) on a PairState that re-walks every point
//   from its previous location per step: warm-started, 3–8 steps. Optionally a few L-BFGS
//   steps of the volume cost (ρd per unit overlap, volume_cost.h) follow:
//   measured 20× slower and no more accurate here (tests/bench/jaw_bench.cc);
// - per part, ρ'd before/after and ρd per unit overlap after are reported;
// - the jaw motion relative to the skull is
//     J_k = U_k · L_k⁻¹,
//   which maps the reference's lower part to where the lower part is in
//   frame k, in the skull's (reference upper part's) coordinates. Check: for
//   frame = G_k(upper ∪ H_k(lower)) (head motion G_k, jaw motion H_k),
//   U_k = G_k⁻¹ and L_k = H_k⁻¹ G_k⁻¹, so J_k = G_k⁻¹ G_k H_k = H_k.
// J of the reference frame is the identity.
//
// From the J_k (docs/faces.md, Jaw motion):
// - σ: each part's covariance of its six parameters at the solution, a
//   sandwich H⁻¹ M H⁻¹ clustered over spatial tiles of the part
//   (registration/sandwich.h; jaw_internal.h PartSandwichCovariance): M the
//   spread of the tiles' shares of Jᵀr over the kept residuals (the
//   sampling's interpolation errors are correlated within a tile), H the
//   curvature of the trimmed cost by central differences (smaller than
//   JᵀJ: nodes cross the trim threshold as θ moves). Propagated to first
//   order to J_k = U_k · L_k⁻¹ (the parts independent): the σ of the
//   reported Euler angles and translation, and of the path point. On fresh
//   samplings of one motion the errors are a median 0.76 σ (0.67 if
//   calibrated; the Gauss-Newton σ²(JᵀJ)⁻¹ gave 2.1); docs/faces.md;
// - the path of a point p0 of the reference (JawOptions::path_point, or the
//   mean of the kPathLowestPoints reference lower-part points of smallest
//   y): p_k = J_k · p0 (helical_axis.h);
// - the finite helical axis between consecutive frames: of J_{k+1} · J_k⁻¹.
// Neither boundary given (JawOptions::find_boundary): the boundary level is
// found first from the sequence (jaw_split.h).
//
// The library never prints; `JawOptions::on_frame` reports each frame.
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "faces/helical_axis.h"
#include "measure/surface.h"
#include "registration/align.h"  // EulerDegrees

namespace surfreg {

// Where the lower part is, in the reference's (normalized) frame.
struct JawBoundary {
  // y level: points with y ≥ y_level are upper (static), below are lower.
  double y_level = 0.0;
  // If not empty: a simple polygon (xy, either orientation, not closed
  // explicitly); points inside (or on it) are lower, outside upper. Then
  // y_level is not used.
  std::vector<std::array<double, 2>> polygon;
  // Points closer than this to the boundary (the y line, or the polygon's
  // edges) are dropped from both parts (data units, ≥ 0).
  double margin = 0.0;
};

enum class JawPart { kUpper, kLower, kDropped };

struct JawFrame;

// The part of a point at (x, y) in the reference's frame.
JawPart ClassifyJawPoint(const JawBoundary& boundary, double x, double y);

// How each part is registered (axial cost = ρ'd as least squares, trimmed).
enum class JawCost {
  kAxial,   // the trimmed axial cost only, Levenberg-Marquardt (default: fast, accurate here)
  kVolume,  // the same, then up to volume_iterations L-BFGS steps of ρd per unit overlap
};

struct JawOptions {
  JawBoundary boundary;
  int reference = 0;  // index of the reference frame (jaw closed; J = identity)
  JawCost cost = JawCost::kAxial;
  // Each evaluation of the cost drops this fraction (0 ≤ f < 0.5) of the
  // largest |residuals|: the steep sides of a face (near-vertical in the height
  // field) give large vertical gaps for tiny sideways offsets between two
  // samplings, and pull the untrimmed least-squares minimum off the true
  // motion (measured on the chewing sequence, max over 8 frames: 0.13°
  // untrimmed, 0.02° at 0.05, 0.012° at 0.1, 0.008° at 0.2).
  double trim_fraction = 0.2;
  // Weight each vertical gap by cos of the surface's slope there (1/|(−∇F, 1)|),
  // i.e. about the gap along the normal (point-to-plane): steep walls then
  // neither dominate the normal equations (tiny steps, slow convergence)
  // nor bias the minimum (measured on the lower face: 0.3° plain, 0.008°
  // with it). false: plain vertical gaps (ρ'd).
  bool normal_distance = true;
  // Solver iterations (accepted or not) per part and frame; reaching it is a
  // failed verdict.
  int max_iterations = 30;
  // Converged after an accepted step shorter than this (2-norm of the six
  // parameters, rotations times the part's RMS radius), data units; also
  // when the cost decreases by less than 1e-6 of itself.
  double step_tolerance = 1e-3;
  // Warm start: the neighbouring frame's motion (false) or, once two frames
  // are known, that motion extrapolated at constant velocity (true): fewer
  // iterations on smooth motion.
  bool predict = true;
  // JawCost::kVolume: at most this many L-BFGS iterations after the axial solve.
  int volume_iterations = 10;
  // Share of a part's area whose triangles may turn over in projection
  // before the part counts as folded (pair_state.h).
  double max_fold_fraction = 0.5;
  int num_threads = 0;  // for the volume measure and refinement; 0: every core
  // A part with fewer points than this after the split is an error.
  int min_part_points = 50;
  // The point whose path is reported, in the reference frame's coordinates
  // (data units); unset: the mean of the kPathLowestPoints reference
  // lower-part points of smallest y (the chin's lowest point, y running
  // chin → forehead).
  std::optional<Eigen::Vector3d> path_point;
  // Find boundary.y_level from the sequence (jaw_split.h; then
  // boundary.y_level and polygon are not used, boundary.margin is). Each
  // frame is then loaded twice: once by the search, once by the tracking.
  bool find_boundary = false;
  // Called once per frame, in processing order (not frame order).
  std::function<void(const JawFrame&)> on_frame;

  bool IsValid(std::string* error) const;
};

// One part's registration in one frame.
struct JawPartResult {
  Eigen::Matrix4d reference_from_frame = Eigen::Matrix4d::Identity();  // U_k or L_k
  Verdict verdict = Verdict::kConvergedImproved;
  std::string verdict_reason;
  int points = 0;      // the frame's points in this part
  int iterations = 0;  // solver iterations (axial + volume)
  // ρ'd (mean |dz| at the nodes inside the overlap, data units) at the
  // warm start and at the result, and ρd per unit overlap area (mean
  // vertical distance, data units) and overlap area at the result.
  double rho_d_axial_before = 0, rho_d_axial_after = 0;
  double mean_abs_dz_after = 0, overlap_area_after = 0;
  // The covariance of the six parameters θ = (ω, s) at the result:
  // reference_from_frame = R(ω)(p − centre) + centre + s (ω radians, s data
  // units); the clustered sandwich of the trimmed axial cost
  // (jaw_internal.h PartSandwichCovariance), over covariance_tiles spatial
  // tiles, its curvature measured by central differences
  // (covariance_measured_curvature; false: JᵀJ of the kept residuals, the
  // fallback where the differences give no positive definite curvature).
  // covariance_ok false (covariance NaN): fewer than 7 kept residuals, JᵀJ
  // singular or fewer than 12 tiles. The reference frame's parts: zeros, ok.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  bool covariance_ok = true;
  int covariance_tiles = 0;
  bool covariance_measured_curvature = true;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the part's centroid, input coordinates
};

struct JawFrame {
  int index = 0;  // frame number
  bool is_reference = false;
  Eigen::Matrix4d jaw = Eigen::Matrix4d::Identity();  // J_k = U_k · L_k⁻¹
  std::array<double, 3> euler_deg{};    // of J_k: R = Rz · Ry · Rx
  std::array<double, 3> translation{};  // of J_k (its last column), data units
  // σ of (rx, ry, rz) in degrees and (tx, ty, tz) in data units, and their
  // covariance, first order from both parts' (independent) covariances.
  // Zeros for the reference; NaN when either part's covariance is not ok.
  std::array<double, 6> stddev{};
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  // The path point in this frame, J_k · p0 (reference frame coordinates), and its σ.
  Eigen::Vector3d path_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d path_point_stddev = Eigen::Vector3d::Zero();
  JawPartResult upper, lower;
  int dropped = 0;  // points within the margin of the boundary
  double seconds = 0;
};

// The default path point: the mean of this many lowest reference lower-part
// points (one sample's position is as random as the sampling).
inline constexpr int kPathLowestPoints = 5;

// How the boundary was found (JawOptions::find_boundary; jaw_split.h).
struct JawBoundarySearch {
  int frame = -1;          // the frame most different from the reference, whose gaps decided
  double noise = 0;        // robust σ of the skull's gaps in that frame (data units)
  double threshold = 0;    // gaps above this label a reference point as moving (jaw)
  double jaw_gap = 0;      // median |gap| of the reference points below the level
  int points = 0;          // reference points labelled
  int moving_points = 0;   // of them, labelled moving
  int misclassified = 0;   // labels on the wrong side of the level
  double seconds = 0;
};

struct JawSummary {
  std::vector<JawFrame> frames;  // in frame order
  int reference = 0;
  int reference_upper_points = 0, reference_lower_points = 0;
  int failed_frames = 0;  // frames where either part's verdict is failed
  JawBoundary boundary;        // as used: given, or with the y level found
  bool boundary_found = false;  // found from the sequence (then `search`)
  JawBoundarySearch search;
  Eigen::Vector3d path_reference = Eigen::Vector3d::Zero();  // p0
  bool path_point_given = false;                              // p0 from JawOptions::path_point
  // Between consecutive frames k → k + 1 (count − 1 of them): of J_{k+1} · J_k⁻¹.
  std::vector<HelicalAxis> helical_axes;
  double seconds = 0;
  // A few lines: counts, the boundary, ranges of the angles and the path,
  // the largest helical angle, time.
  std::string BriefReport() const;
};

// Tracks the jaw over `count` frames; `load(k)` returns frame k (called once
// per frame, in processing order, and once more before that with
// find_boundary; frames need not all be in memory). Throws InputError for
// invalid options, a frame that is not a valid surface, a part with fewer
// than min_part_points points, parts that do not overlap the reference's at
// the warm start, or (find_boundary) a sequence whose parts cannot be found.
JawSummary TrackJaw(int count, const std::function<Surface(int)>& load, const JawOptions& options);
JawSummary TrackJaw(const std::vector<Surface>& frames, const JawOptions& options);

// Rotation-angle (degrees) and translation (data units) differences between
// two rigid 4×4 motions: the angle of Rᵃ·Rᵇᵀ and |tᵃ − tᵇ|.
std::array<double, 2> MotionDifference(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b);

}  // namespace surfreg
