#pragma once
// Internal to faces/: the pieces of the jaw tracking (jaw.cc) that the
// boundary search (jaw_split.cc) shares, and what is derived from the poses
// (jaw_outputs.cc): a frame split by the boundary, a part registered onto the
// reference's, the Gauss-Newton covariance of a part and its propagation to
// the jaw's parameters.
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
// |dz|, overlap area), half of a frame's time; the covariance is always
// computed.
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

// Fills frame->stddev, covariance and path_point(_stddev) from its parts'
// results and covariances (and its jaw, Euler angles, translation) for the
// path point p0.
void PropagateFrameCovariance(const Eigen::Vector3d& p0, JawFrame* frame);

// The default path point: the mean of the kPathLowestPoints points of
// smallest y (all of them if fewer).
Eigen::Vector3d LowestPoint(const Points& lower);

}  // namespace jaw_internal
}  // namespace surfreg
