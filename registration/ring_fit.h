#pragma once
// Least-squares fits through a vertex and its Delaunay ring: the local
// curvature and noise that the gap weight (gap_weight.h) and the chord-bias
// correction (chord_bias.h) read from a sampled surface.
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "measure/delaunay.h"

namespace surfreg {

// The most neighbours a ring may have before it is not looked at (a vertex
// of a degenerate fan).
constexpr int kMaxRing = 64;

// The offsets of v's Delaunay neighbours from v, around its ring of
// triangles; their count, or −1 unless the ring closes (v on the hull).
int RingOffsets(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh, std::size_t v,
                std::array<Eigen::Vector3d, kMaxRing>* offsets);

struct RingQuadratic {
  Eigen::Vector3d hessian;  // (H_xx, H_xy, H_yy) of z over xy
  double spacing2 = 0;      // the ring's mean squared xy distance from v
};

// The least-squares quadratic z = z_v + g·d + ½ dᵀHd through v and its
// ring (at least 5 neighbours on a closed ring). With `noise` > 0 (the
// samples' standard deviation) H is shrunk toward 0 by max(0, 1 − E‖Ĥ −
// H‖² / ‖Ĥ‖²) (Frobenius), E from the fit's covariance under that noise, so
// that a ring whose curvature is mostly noise reports little. False when the
// ring does not close or does not determine a quadratic (its points on a
// conic through v).
bool FitRingQuadratic(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh, std::size_t v,
                      double noise, RingQuadratic* out);

// The standard deviation of the samples' z about a smooth surface through
// them: the median over the vertices with 6 or more neighbours of RSS / dof
// of the least-squares quadratic with a free constant through the vertex and
// its ring, scaled by the median of χ²_dof / dof (Wilson–Hilferty). On a
// clean surface it is what a quadratic misses over one ring (the next order
// of the surface, or its texture); 0 without such a vertex.
double SampleNoise(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh);

}  // namespace surfreg
