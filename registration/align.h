#pragma once
// Rigid registration of a moving surface B onto a reference surface A
// (docs/method.md, How a registration runs): find θ = (ω, t) minimizing ρ'd (axial cost, least squares
// with an optional robust loss) or ρd per unit overlap area (volume cost),
// where B moves by T(p) = R(ω)(p − c) + c + t about its centroid c.
//
// B keeps its own triangulation while it moves; a motion that folds B's xy
// projection (a triangle turning over) is detected: the solver treats it as
// an infeasible step, and a final fold is a failed verdict.
//
// The result is reported in input coordinates (the 4×4 matrix maps moving
// input points onto the reference) together with the measures before and
// after, the overlap fraction, how well each parameter is determined by the
// data, standard deviations, and a verdict that is never "improved" when
// the measure got worse.
#include <array>
#include <cstddef>

#include <Eigen/Core>

#include "measure/surface.h"
#include "registration/align_options.h"
#include "registration/align_result.h"

namespace surfreg {

// Aligns `moving` onto `reference`. Throws InputError for invalid surfaces or
// options (also per-point weights without weights on the reference, or all
// of them 0), surfaces that do not overlap at the initial motion, or an initial
// motion that folds the moving surface.
AlignResult Align(const Surface& reference, const Surface& moving,
                  const AlignOptions& options = AlignOptions());

// How many independent alignments (a series' pairs, a batch's rows) to run
// side by side on `threads` threads, one thread each: min(threads, pairs, 8)
// when the largest of their surfaces has at most 1e5 samples, else 1 (a
// large pair spreads over the threads itself). Small pairs gain more from a
// thread each than from all threads on one: their parallel stages are
// short. An alignment's numbers do not depend on its threads.
int AlignmentsAtOnce(std::size_t largest_samples, int pairs, int threads);

// `surface` with every sample moved by `matrix` (input coordinates), e.g. the
// aligned moving surface. By chunks on `threads`: the same on any number.
Surface TransformSurface(const Surface& surface, const Eigen::Matrix4d& matrix, int threads = 1);

// Euler angles (degrees) rx, ry, rz of a rotation R = Rz · Ry · Rx.
std::array<double, 3> EulerDegrees(const Eigen::Matrix3d& rotation);

}  // namespace surfreg
