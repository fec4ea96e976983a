#pragma once
// How far a linear interpolation between a surface's samples may be from
// the surface near each node, and the volume cost's weight from it.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "measure/delaunay.h"
#include "measure/tasks.h"
#include "registration/pair_state.h"

namespace surfreg {

// Per vertex of `mesh` (every `stride`-th; the others −1): |z − the
// least-squares plane through its Delaunay neighbours| at the vertex, what a
// linear interpolation between samples misses there (curvature and noise).
// −1 for a vertex without a closed ring of triangles (on the hull).
std::vector<double> PlaneGaps(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh,
                              std::size_t stride = 1);

// Per vertex of `mesh`: ¼ ℓ² (|λ₁| + |λ₂|), λ the eigenvalues of the
// Hessian of the least-squares quadratic through the vertex and its
// Delaunay neighbours, ℓ² the median over the vertices of their rings' mean
// squared xy distance: the plane gap a ring of the surface's typical
// spacing would have at a bowl of these curvatures. It follows the surface
// only: not how the ring's neighbours lie against the curvature (a survey's
// line heading against a valley's) nor where this sampling is sparse, which
// are what this sampling's own interpolation error follows. −1 for a vertex
// without a closed ring of at least 5 neighbours that determine a quadratic.
std::vector<double> CurvatureGaps(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh,
                                  const Execution& execution = Execution{1});

// Multiplies the reference's μ (1 where it has none) at every node by
// f / (f + g): g the mean, over the triangles around the node, of their
// corners' CurvatureGaps values (nodes without any get the median g), f =
// floor_fraction × the median g over the nodes. The vertical gap at the
// right pose grows with the local curvature, so this weighs each place by
// the inverse of its expected |gap|, as an L1 cost with unequal scales
// should: curved places (a face's flanks, ridges) stop dominating a clean
// pair, and a noisy pair, whose g is noise everywhere, keeps nearly uniform
// weights. From the curvature, not from the reference's plane gaps or
// spacing: those follow the reference's own interpolation error, so weights
// from them favour the places where the reference happens to interpolate
// well, the L1 fit then shifts toward the moving surface's error there, and
// swapping the surfaces no longer gives the inverse (measured:
// docs/registration.md). f bounds the weight of flat places at 1 (g = 0)
// against f / (f + g); f is at least 1e-9 of the data's extent, so
// rounding-level gaps (a plane) weigh 1. 0 = off.
void ApplyGapWeight(double floor_fraction, ReferenceSide* reference, const Execution& execution = Execution{1});

// Multiplies the reference's μ (1 where it has none) at every node by
// a_median / a_v, a_v the node's local area per sample (a third of its data
// triangles' xy area, averaged over the corners of the triangles around it)
// and a_median its median over the nodes, when the sampling's density is
// uneven by design: the 90th percentile of a_v at least `uneven_ratio` times
// the 10th. Then ∫ μ |gap| counts each sample alike, as ICP's sum over
// points does, instead of each unit of area: a mesh's vertices (dense on a
// face's nose, eyes and ears, a hundred times sparser on its cheeks and
// sides) otherwise let the few samples of the sparse parts, whose long
// triangles carry the largest interpolation error and the fewest samples
// of noise to average, set the motion (tests/bench/face_vertex_bench.py:
// halves 0.031° → 0.010°, noisy copies 0.035° → 0.008°). Random
// samplings (that ratio 2.5-2.6), grids and scan lines (1-1.2) are left as
// they are. 0 = off. Returns whether it applied.
bool ApplyDensityWeight(double uneven_ratio, ReferenceSide* reference);

// The spread of a surface's local area per sample over its data domain (as
// ApplyDensityWeight measures it): its 90th percentile over its 10th; 0 for
// fewer than 10 nodes. At `density_weight` or more the sampling is uneven by
// design and the chord correction (chord_bias.h), whose model is one area
// per sample for the whole surface, is not made.
double DensitySpread(const ReferenceSide& reference);

// The q-quantile (0 ≤ q ≤ 1, by selection) of the positive values; 0 for
// fewer than 10 of them.
double PositiveQuantile(const std::vector<double>& values, double q);
double DensitySpread(const MovingSide& moving);

}  // namespace surfreg
