#pragma once
// The chord bias of a linear interpolation, and its correction when two
// surfaces are sampled at different densities.
//
// Between its samples, the linear interpolation of a curved surface is off
// by a chord: on a triangle T, L − f = ½ Σᵢ λᵢ (pᵢ − x)ᵀ H (pᵢ − x) for a
// quadratic f of Hessian H, whose mean over T is tr(H M_T), M_T = (1/24)
// Σ_edges e eᵀ. The volume cost compares two such interpolations; when both
// samplings have one density their chords cancel on average, but a sparser
// one's lie further off, and on a surface curved one way (a face) the fit
// then moves it toward the other by the difference (measured: a 4 : 1 face
// pair, tz off by 6σ; docs/registration.md).
#include <vector>

#include <Eigen/Core>

#include "measure/delaunay.h"
#include "registration/pair_state.h"

namespace surfreg {

// How a surface is sampled, over the triangles of `mesh` with domain[t] != 0
// (all when `domain` is empty).
struct SamplingShape {
  double area_per_point = 0;  // twice the mean triangle area
  // M / area_per_point, M the area-weighted mean of the triangles' M_T: the
  // sampling's chord tensor for unit density (an equilateral lattice: I / 16
  // × 2 / √3).
  Eigen::Matrix2d chord = Eigen::Matrix2d::Zero();
};
SamplingShape MeasureSampling(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh,
                              const std::vector<uint8_t>& domain);

// What CorrectDensityBias did.
struct DensityCorrection {
  double ratio = 1;        // the sparser side's area per point over the denser side's
  double one_sign_share = 0;  // of the sparser side's corrections, the share with their sum's sign
  bool applied = false;
  bool reference = false;  // the side corrected: the reference (else the moving one)
};

// Below this share of one sign the correction is not applied (see
// CorrectDensityBias).
constexpr double kMinOneSignShare = 0.6;

// When one side's area per point exceeds the other's by `min_ratio` or more
// (0 = never): lowers each node of the sparser side by tr(H (M_sparse −
// M_dense)), the difference of the two sides' mean chords at that node's
// curvature, so that its interpolation lies where the denser one's would on
// average. H from the sparser side's ring quadratic, shrunk by its noise
// (ring_fit.h SampleNoise, FitRingQuadratic): curvature that is noise or
// texture gets little correction; nodes on the data domain's edge and rings
// whose correction exceeds 20 × the median (creases, degenerate rings) get
// none. Applied only when at least kMinOneSignShare of the corrections have
// one sign: a surface curved mostly one way (a face), where the two chords'
// difference is a bias the fit follows; where the curvature's sign changes
// from place to place (terrain) they cancel over the overlap and the
// correction would add only its own error. M of both sides from their own densities and
// one shared chord tensor (the mean of the two): two samplings of one density
// get none, whatever their triangles' shapes. Below `min_ratio` (two clouds
// of one density differ by up to 1.07 in area per point here, from the tilt
// and the domain's edge) the estimate's own error would exceed the bias.
DensityCorrection CorrectDensityBias(double min_ratio, ReferenceSide* reference, MovingSide* moving);

}  // namespace surfreg
