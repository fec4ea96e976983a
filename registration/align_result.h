#pragma once
// What Align found (registration/align.h): the motion in input coordinates,
// the measures before and after, how well the data determine each
// parameter, standard deviations, the verdict, the stable terrain and the
// held-out check, and the result in words.
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "measure/measures.h"
#include "registration/align_options.h"
#include "registration/holdout.h"
#include "registration/rigid_motion.h"
#include "registration/stable_terrain.h"

namespace surfreg {

enum class Verdict {
  kConvergedImproved,     // the solver converged and the measure decreased
  // Converged, but the measure did not decrease: the initial motion is
  // kept. Or (holdout_verdict) the held-out check saw no improvement: the
  // fitted motion is reported, for inspection.
  kConvergedNotImproved,
  kIllConditioned,        // a free parameter is not determined by the data (flat or featureless surface)
  kFailed,                // the solver failed, hit its iteration limit, or the moving surface folded
};
const char* VerdictName(Verdict verdict);  // "converged_improved", ...

struct AlignResult {
  RigidMotion motion;           // in the reference's local frame (centre = moving centroid)
  Rigid3d reference_from_moving;  // the answer: moving input coordinates → reference's
  Eigen::Matrix4d matrix;       // the same as a 4 × 4 homogeneous matrix
  std::array<double, 3> rotation_vector{};  // radians (same as motion.rotation_vector)
  std::array<double, 4> quaternion{};       // w, x, y, z
  std::array<double, 3> euler_deg{};        // rx, ry, rz: R = Rz · Ry · Rx
  std::array<double, 3> translation{};      // t: the shift of the moving centroid
  std::array<double, 3> centre{};           // c, input coordinates
  // Standard deviations of rx, ry, rz (radians), tx, ty, tz (data units) from
  // the axial residuals at the solution; 0 for locked parameters, NaN when
  // the covariance is not defined (rank deficient).
  std::array<double, 6> stddev{};
  // The full covariance of (rx, ry, rz, tx, ty, tz) (radians, data units),
  // its diagonal the stddev²; zero rows and columns for locked parameters,
  // NaN when not defined. From the information or from the subsamples, as
  // the stddev.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Constant(std::nan(""));
  // In [0, 1]: how much of each parameter's information is not shared with
  // other directions (1 = fully determined); `constrained` is false for a
  // free parameter the data do not determine.
  std::array<double, 6> observability{};
  std::array<bool, 6> constrained{};
  double condition_number = 0;  // of the information matrix (rotations scaled by the RMS radius)

  MeasureSummary before, after;  // Measure(reference, moving moved by the initial / final motion)
  double overlap_fraction_before = 0, overlap_fraction_after = 0;  // of the smaller data domain
  int iterations = 0;            // solver iterations over all levels and starts
  std::string termination;       // the solver's message (last level)
  Verdict verdict = Verdict::kFailed;
  std::string verdict_reason;
  // Moving triangles (of its own mesh) turned over at the final motion, and
  // their share of its area: the parts steeper than vertical at that pose,
  // where the moving surface is re-triangulated as seen from above.
  int folded_triangles = 0;
  double folded_area_fraction = 0;
  int remeshes = 0;              // re-triangulations of the moving surface after sliver folds
  // The sparser surface's area per sample over the denser one's (finest
  // level), and which one's chords AlignOptions::density_correction
  // corrected: "reference", "moving" or "none".
  double density_ratio = 1;
  std::string chord_correction = "none";
  // The cost the solve minimized: "volume", "axial", or "axial at the
  // sparser surface's nodes" (cost axial_sparser, or auto on terrain of two
  // resolutions).
  std::string solve_cost = "volume";
  // The sum of both surfaces' interpolation gaps (per surface: the mean
  // vertical distance from a sample to the least-squares plane through its
  // Delaunay neighbours, over inner samples of its data domain): what two
  // samplings of one surface differ by. At the right pose the mean gap is a
  // fraction of it (0.13-0.42 on the benchmark's 36 pairs, about 0.6 where
  // noise dominates); more than it (what wide_search auto looks at) means
  // the surfaces do not lie on each other there, or have changed.
  double sampling_gap = 0;
  // wide_search auto (or always) ran its coarse search: the result from the
  // initial motion failed, did not improve a start whose surfaces lay apart,
  // or left them apart.
  bool wide_search_ran = false;
  // With AlignOptions::holdout_fraction > 0: the check on the held-out
  // tiles. `before` / `after` above are then the fitted part's measures.
  HoldoutCheck holdout;
  // With AlignOptions::stable auto: the reference's samples as stable,
  // changed or outside the overlap, and the rounds it took. `before` and
  // `after` are then measured on the stable part.
  StableTerrain stable;
  double seconds = 0;
  std::string stddev_source;  // how `stddev` was estimated (e.g. "sandwich over 64 tiles")
  double covariance_seconds = 0;  // of `seconds`: observability and standard deviations
  std::vector<AlignOptions::Iteration> log;

  // The result for a person (registration/align_report.cc). BriefReport:
  // one line (verdict, rotation angle, centroid shift, mean |dz| before ->
  // after, time). FullReport: what `surfreg align` prints, one item per
  // line: verdict (and why), rotation, Euler angles, translation, standard
  // deviations and 95% intervals, ρ'd, mean |dz|, overlap, the stable
  // terrain (stable auto; and a warning if any), the held-out check (if
  // any), iterations, time; every line ends in a newline. Lengths are in
  // `units` ("m" for a metric frame; the data's units when not known).
  std::string BriefReport() const;
  std::string FullReport(const std::string& units = "units") const;
};

// The measure an alignment with cost `cost` is judged by: the mean gap
// (ρd over the overlap) unless an axial cost was chosen (ρ'd).
double MeasureOfCost(CostKind cost, const MeasureSummary& summary);

// Whether `result` asks wide_search auto to search: the solve failed, did
// not improve the measure of surfaces that lay apart, or left them apart
// (the measure `cost` is judged by above the sampling gap). A real change
// between the surveys also leaves them apart.
bool WideSearchWanted(const AlignResult& result, CostKind cost);

}  // namespace surfreg
