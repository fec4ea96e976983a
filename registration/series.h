#pragma once
// Joint alignment of a series of surveys (docs/series.md): N surfaces, one
// rigid motion per epoch into the frame of a reference epoch, solved in one
// problem over every pair that overlaps.
//
// 1. The overlap graph: each epoch's footprint on a common occupancy grid;
//    a pair is an edge when the grid cells both cover are at least
//    `min_overlap` of the smaller footprint (or the pairs the user gives).
//    A graph that falls apart is refused, naming the pieces.
// 2. Each edge aligned as `align` does (Align, the same options): the later
//    epoch onto the earlier one, its motion and covariance.
// 3. One Ceres problem over 6·(N−1) parameters, each epoch's motion about
//    its own centroid (the reference's fixed at the identity): the sum over
//    the edges of each pair's cost, modelled to second order about the
//    pair's own minimum, where δ is the difference between the relative
//    motion the epochs' motions imply and the pair's. The pairs' errors are
//    weighted by their joint covariance: part of each is its epochs' own
//    apparent motion, shared with their other pairs as much as the overlaps
//    share area (series_internal.h EdgeCovariance), the rest the pair's own;
//    the shared share is the one whose residuals fit it. Every overlap
//    counts, so epochs that do not overlap the reference are aligned
//    through the others.
// 4. The joint covariance, its block per epoch: the largest of the joint
//    motions' covariance under each of the shares (a sandwich), since the
//    residuals tell the shares apart poorly; each pair's measures at the
//    joint motion and its misclosure (the joint relative motion against the
//    pair's own).
#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "measure/surface.h"
#include "registration/align_options.h"
#include "registration/align_result.h"

namespace surfreg {

struct SeriesOptions {
  // Each pair's alignment (the moving epoch's motion about its centroid,
  // stable terrain, weights, threads); its initial motion must be unset:
  // every pair starts from the epochs' input coordinates.
  AlignOptions align;
  int reference = 0;  // the epoch whose frame the others are brought into
  // The edges to use, as epoch indices (either order); empty = from the
  // data, every pair whose footprints share at least `min_overlap` of the
  // smaller one's.
  std::vector<std::pair<int, int>> pairs;
  double min_overlap = 0.3;
  // Called as each stage begins ("aligning pair 2-3 (4/9)", "joint solve").
  // Pairs of small epochs align several at a time (one thread each, up to
  // align.num_threads; the results are those of one at a time): their
  // stages are called from the threads that run them, one call at a time.
  std::function<void(const std::string& stage)> on_stage;
};

// One edge of the graph: `moving` aligned onto `reference` (epoch indices,
// reference < moving unless the user gave them the other way).
struct SeriesPair {
  int reference = 0, moving = 0;
  double overlap = 0;    // the footprints' shared share of the smaller one
  AlignResult pairwise;  // the pair's own alignment
  bool used = false;     // in the joint problem (its alignment converged with a covariance)
  std::string reason;    // why not, when not used
  // The pair's measures at the epochs' input coordinates (before) and at the
  // joint motion (after): ρ'd, the mean |dz| at the nodes, and the overlap.
  MeasureSummary before, after;
  // The joint relative motion against the pair's own: the angle between
  // them (degrees) and the distance between where they take the moving
  // epoch's centroid; and δᵀ Σ⁻¹ δ (about χ² with 6 degrees of freedom
  // when the pairs agree to their σ).
  double misclosure_deg = 0, misclosure_shift = 0, misclosure_chi2 = 0;
};

struct SeriesEpoch {
  // Epoch input coordinates → the reference epoch's (the identity for it).
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  std::array<double, 3> centre{};  // the epoch's centroid (input coordinates): the motion's centre
  // Of (rx, ry, rz, tx, ty, tz) about `centre` (radians, data units), the
  // joint covariance's block of this epoch; zeros for the reference and for
  // locked parameters, NaN when the joint problem does not determine them.
  std::array<double, 6> stddev{};
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  std::array<double, 3> euler_deg{};    // rx, ry, rz of the rotation (R = Rz · Ry · Rx)
  std::array<double, 3> translation{};  // the centroid's shift
  Verdict verdict = Verdict::kConvergedImproved;
  std::string verdict_reason;
  int pairs = 0;  // used edges at this epoch
};

struct SeriesResult {
  std::vector<SeriesEpoch> epochs;
  std::vector<SeriesPair> pairs;
  int reference = 0;
  // The share of each pair's error variance taken as its epochs' (shared
  // with their other pairs): the one of 0, 0.5, 0.75, 0.88, 0.94 whose
  // residuals fit it best (docs/series.md).
  double pair_correlation = 0;
  int iterations = 0;                        // of the joint solve
  std::string termination;                   // its message
  double seconds = 0, pairwise_seconds = 0;  // all, and the pairwise alignments within it
  // The coordinates the epochs were solved in (and the matrices map), as
  // their reader describes them (terrain/series_epochs.h: e.g. "UTM zone 33N
  // (WGS 84; EPSG:32633)" for lon/lat epochs); AlignSeries leaves it "".
  std::string frame;
};

// How many of `pairs` pairs of `epochs` align (or are measured) at once on
// `threads` threads: AlignmentsAtOnce (registration/align.h) of the largest
// epoch.
int SeriesPairsAtOnce(const std::vector<Surface>& epochs, int pairs, int threads);

// The overlap of every pair of epochs (symmetric N × N, the diagonal 1):
// the grid cells both footprints cover over the smaller footprint's cells.
// The grid is common to all epochs, its cell a few of the sparsest epoch's
// sample spacings.
Eigen::MatrixXd SeriesOverlaps(const std::vector<Surface>& epochs);

// The connected pieces of the graph of `n` epochs and `edges`, each sorted,
// in the order of their first epoch.
std::vector<std::vector<int>> GraphPieces(int n, const std::vector<std::pair<int, int>>& edges);

// Aligns the epochs jointly. Throws InputError for fewer than two epochs, an
// invalid one (naming its source), a bad reference or pair index, an epoch
// that overlaps no other ("epoch 3 (c.xyz) overlaps no other"), and a graph
// that falls apart, before or after leaving out the pairs that did not
// align ("the series falls apart into {0, 1, 2} and {3, 4}").
SeriesResult AlignSeries(const std::vector<Surface>& epochs,
                         const SeriesOptions& options = SeriesOptions());

}  // namespace surfreg
