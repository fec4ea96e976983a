// Joint alignment of a series (registration/series.h): strips of one
// analytic terrain, each moved by its own known motion, recovered jointly;
// the overlap graph, its pieces, and the refusals.
#include "registration/series.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "registration/series_internal.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

using testing::SmoothTerrain;

constexpr double kStripWidth = 40, kStripStep = 12;

// Strip k of the terrain (x in [12k, 12k + 40]) in its own frame: sampled
// in the world, then moved by the inverse of world_from_epoch[k].
struct Series {
  std::vector<Surface> epochs;
  std::vector<Eigen::Matrix4d> world_from_epoch;
};

Series MakeStrips(int n, double x_offset = 0, uint64_t seed = 1) {
  Series series;
  for (int k = 0; k < n; ++k) {
    const double x0 = x_offset + kStripStep * k;
    auto points = testing::SampleUniform(
        [x_offset](double x, double y) { return SmoothTerrain(x - x_offset, y); }, 2500, x0,
        x0 + kStripWidth, 0, 100, seed * 100 + k);
    const Eigen::Matrix4d truth =
        k == 0 ? Eigen::Matrix4d::Identity()
               : testing::TrueMotion({1.0 + k, -1.0, 0.3 * k}, 0.4 + 0.2 * k,
                                     {0.3 * k, -0.2, 0.1 * k}, testing::Centroid(points));
    series.world_from_epoch.push_back(truth);
    series.epochs.push_back(
        MakeSurface(testing::MoveByInverse(points, truth), {}, "strip" + std::to_string(k)));
  }
  return series;
}

Eigen::Vector3d CentroidOf(const Surface& s) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < s.size(); ++k) sum += Eigen::Vector3d(s.xy[k].x, s.xy[k].y, s.z[k]);
  return sum / static_cast<double>(s.size()) +
         Eigen::Vector3d(s.origin[0], s.origin[1], s.origin[2]);
}

TEST(SeriesOverlapsTest, SharedShareOfTheSmallerFootprint) {
  const Series series = MakeStrips(4);
  const Eigen::MatrixXd overlap = SeriesOverlaps(series.epochs);
  ASSERT_EQ(overlap.rows(), 4);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(overlap(k, k), 1);
  // Strips 12 apart share 28 of 40 in x, 24 apart 16 of 40; the grid's cells
  // along the seams blur that by a cell or two.
  for (int k = 0; k + 1 < 4; ++k) EXPECT_NEAR(overlap(k, k + 1), 0.7, 0.08);
  for (int k = 0; k + 2 < 4; ++k) EXPECT_NEAR(overlap(k, k + 2), 0.4, 0.08);
  EXPECT_NEAR(overlap(0, 3), 0.1, 0.08);
  EXPECT_EQ(overlap(1, 2), overlap(2, 1));
}

// The pairs' errors: a pair alone has its own covariance; two pairs at an
// epoch share its half as much as their overlaps share area, with the sign
// of its roles (a chain's links cancel it).
TEST(EdgeCovarianceTest, AnEpochsShareCorrelatesItsPairsByRoleAndSharedArea) {
  using series_internal::Edge;
  series_internal::Footprints footprints;
  // Cells 0-3: epoch 0 on 0-3, epoch 1 on 0-3, epoch 2 on 0-1 and epoch 3 on 2-3.
  footprints.covered = {{1, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 0, 0}, {0, 0, 1, 1}};
  const std::vector<Eigen::Vector3d> centroids(4, Eigen::Vector3d::Zero());
  Eigen::Matrix<double, 6, 6> sigma = Eigen::Matrix<double, 6, 6>::Identity();
  sigma(0, 3) = sigma(3, 0) = 0.3;
  const auto edge = [&](int reference, int moving) {
    Edge e;
    e.reference = reference, e.moving = moving, e.covariance = sigma;
    return e;
  };
  const auto block = [](const Eigen::MatrixXd& c, int p, int q) {
    return Eigen::MatrixXd(c.block(6 * p, 6 * q, 6, 6));
  };
  // 0-1 then 1-2: epoch 1 moving, then reference; 0-1 covers 4 cells, 1-2 two of them.
  Eigen::MatrixXd c =
      series_internal::EdgeCovariance({edge(0, 1), edge(1, 2)}, centroids, footprints, 1.0);
  EXPECT_TRUE(block(c, 0, 0).isApprox(sigma, 1e-12));
  EXPECT_TRUE(block(c, 1, 1).isApprox(sigma, 1e-12));
  EXPECT_TRUE(block(c, 0, 1).isApprox(-0.5 * std::sqrt(2.0 / 4.0) * sigma, 1e-12))
      << block(c, 0, 1);
  // 0-2 and 0-3: epoch 0 the reference of both; their overlaps do not meet.
  c = series_internal::EdgeCovariance({edge(0, 2), edge(0, 3)}, centroids, footprints, 1.0);
  EXPECT_TRUE(block(c, 0, 1).isZero(1e-12));
  // 0-1 and 0-2: the reference of both, shared on 2 of 4 and 2 cells.
  c = series_internal::EdgeCovariance({edge(0, 1), edge(0, 2)}, centroids, footprints, 1.0);
  EXPECT_TRUE(block(c, 0, 1).isApprox(0.5 * (2 / std::sqrt(4.0 * 2.0)) * sigma, 1e-12))
      << block(c, 0, 1);
}

// The joint covariance under another covariance of the pairs' errors (a
// sandwich) against brute force: the spread of the joint motions when the
// pairs' errors are drawn from it. Three epochs in a loop; the model takes
// the pairs as independent, the truth correlates them and is larger.
TEST(SolveJointTest, CovarianceUnderAnAlternativeIsTheSpreadOfTheEstimates) {
  using series_internal::Edge;
  const std::vector<Eigen::Vector3d> centroids = {{0, 0, 0}, {10, 0, 1}, {5, 8, -1}};
  const std::vector<std::pair<int, int>> graph = {{0, 1}, {1, 2}, {0, 2}};
  Eigen::Matrix<double, 6, 6> sigma = Eigen::Matrix<double, 6, 6>::Zero();
  sigma.diagonal() << 1e-6, 1e-6, 2e-6, 1e-4, 1e-4, 4e-4;
  Eigen::MatrixXd model = Eigen::MatrixXd::Zero(18, 18);
  for (int k = 0; k < 3; ++k) model.block(6 * k, 6 * k, 6, 6) = sigma;
  // The truth: each pair's own error doubled, the first two pairs' errors
  // correlated by −0.6 (a chain's links) and the last two by 0.4.
  Eigen::MatrixXd truth = 2 * model;
  truth.block(0, 6, 6, 6) = truth.block(6, 0, 6, 6) = -0.6 * 2 * sigma;
  truth.block(6, 12, 6, 6) = truth.block(12, 6, 6, 6) = 0.4 * 2 * sigma;
  const Eigen::MatrixXd root = truth.llt().matrixL();
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  const std::array<bool, 6> free = {true, true, true, true, true, true};
  const auto solve = [&](const Eigen::VectorXd& error, const std::vector<Eigen::MatrixXd>& alternatives) {
    std::vector<Edge> edges;
    for (int k = 0; k < 3; ++k) {
      Edge& e = edges.emplace_back();
      e.reference = graph[k].first, e.moving = graph[k].second;
      e.centre = centroids[e.moving];
      const Eigen::Vector3d w = error.segment<3>(6 * k);
      e.rotation = w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
                                : Eigen::Matrix3d::Identity();
      e.shift = error.segment<3>(6 * k + 3);
      e.covariance = sigma;
    }
    std::vector<std::array<double, 6>> start(3, std::array<double, 6>{});
    return series_internal::SolveJoint(edges, model, centroids, start, 0, free, 1, alternatives);
  };
  const series_internal::JointSolution reported = solve(Eigen::VectorXd::Zero(18), {truth});
  const series_internal::JointSolution as_modelled = solve(Eigen::VectorXd::Zero(18), {});
  constexpr int kDraws = 600;
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(12, 12);
  for (int draw = 0; draw < kDraws; ++draw) {
    Eigen::VectorXd z(18);
    for (int k = 0; k < 18; ++k) z[k] = normal(random);
    const series_internal::JointSolution s = solve(root * z, {});
    Eigen::VectorXd theta(12);
    for (int k = 0; k < 6; ++k) theta[k] = s.theta[1][k], theta[6 + k] = s.theta[2][k];
    sum += theta * theta.transpose();
  }
  const Eigen::MatrixXd spread = sum / kDraws;
  for (int e = 1; e <= 2; ++e) {
    for (int k = 0; k < 6; ++k) {
      const double measured = spread(6 * (e - 1) + k, 6 * (e - 1) + k);
      // 600 draws: a variance within about ±6% (1σ) of the truth's.
      EXPECT_NEAR(reported.covariance[e](k, k) / measured, 1.0, 0.2) << "epoch " << e << " parameter " << k;
      // The model alone would claim less than the truth gives.
      EXPECT_LT(as_modelled.covariance[e](k, k), 0.8 * measured) << "epoch " << e << " parameter " << k;
    }
  }
  EXPECT_TRUE(reported.covariance[0].isZero());  // the reference
}

TEST(GraphPiecesTest, PiecesInOrderOfTheirFirstEpoch) {
  EXPECT_EQ(GraphPieces(5, {{3, 1}, {0, 4}}), (std::vector<std::vector<int>>{{0, 4}, {1, 3}, {2}}));
  EXPECT_EQ(GraphPieces(3, {{0, 1}, {1, 2}}), (std::vector<std::vector<int>>{{0, 1, 2}}));
  EXPECT_EQ(GraphPieces(2, {}), (std::vector<std::vector<int>>{{0}, {1}}));
}

// Six strips, each with its own motion: every epoch's matrix is the truth
// relative to the reference's, within a few σ and a small absolute margin;
// the reference's is the identity.
TEST(AlignSeriesTest, RecoversEachEpochsMotion) {
  const Series series = MakeStrips(6);
  SeriesOptions options;
  options.reference = 2;
  const SeriesResult result = AlignSeries(series.epochs, options);
  ASSERT_EQ(result.epochs.size(), 6u);
  // Neighbours and next-but-ones: 5 + 4 edges; 12·3 apart is 0.1, left out.
  EXPECT_EQ(result.pairs.size(), 9u);
  EXPECT_TRUE(result.epochs[2].matrix.isIdentity(0));
  for (int k = 0; k < 6; ++k) {
    const SeriesEpoch& epoch = result.epochs[k];
    const Eigen::Matrix4d truth = series.world_from_epoch[2].inverse() * series.world_from_epoch[k];
    const testing::MotionError error =
        testing::CompareMotions(epoch.matrix, truth, CentroidOf(series.epochs[k]));
    EXPECT_LT(error.rotation_deg, 0.01) << "epoch " << k;
    EXPECT_LT(error.translation, 0.01) << "epoch " << k;
    std::printf("epoch %d: error %.5f deg %.5f, sigma %.5f deg %.5f\n", k, error.rotation_deg,
                error.translation, epoch.stddev[0] * 180 / M_PI, epoch.stddev[3]);
    if (k == 2) continue;
    EXPECT_EQ(epoch.verdict, Verdict::kConvergedImproved) << epoch.verdict_reason;
    for (int p = 0; p < 6; ++p)
      EXPECT_GT(epoch.stddev[p], 0) << "epoch " << k << " parameter " << p;
    EXPECT_GE(epoch.pairs, 2);
  }
  for (const SeriesPair& pair : result.pairs) {
    EXPECT_TRUE(pair.used) << pair.reason;
    EXPECT_LT(pair.after.rho_d_axial, pair.before.rho_d_axial);
    std::printf("pair %d-%d: misclosure %.5f deg %.5f chi2 %.3g\n", pair.reference, pair.moving,
                pair.misclosure_deg, pair.misclosure_shift, pair.misclosure_chi2);
    EXPECT_LT(pair.misclosure_deg, 0.05);
  }
}

// An epoch that is another's very samples moved: the joint motion is that
// motion, to the solver's precision.
TEST(AlignSeriesTest, AnEpochEqualToAnotherMovedGetsThatMotion) {
  const Series strips = MakeStrips(2);
  const Eigen::Matrix4d motion =
      testing::TrueMotion({0.2, 1, 0.1}, 1.5, {0.8, -0.4, 0.25}, CentroidOf(strips.epochs[1]));
  std::vector<std::array<double, 3>> points;
  const Surface& source = strips.epochs[1];
  for (std::size_t k = 0; k < source.size(); ++k) {
    points.push_back({source.xy[k].x + source.origin[0], source.xy[k].y + source.origin[1],
                      source.z[k] + source.origin[2]});
  }
  std::vector<Surface> epochs = {strips.epochs[0], strips.epochs[1],
                                 MakeSurface(testing::MoveByInverse(points, motion), {}, "moved")};
  SeriesOptions options;
  options.reference = 1;
  const SeriesResult result = AlignSeries(epochs, options);
  const testing::MotionError error =
      testing::CompareMotions(result.epochs[2].matrix, motion, CentroidOf(epochs[2]));
  EXPECT_LT(error.rotation_deg, 1e-5);
  EXPECT_LT(error.translation, 1e-5);
}

// Only the pairs the user gives are aligned; a chain 0-1-2 then holds.
TEST(AlignSeriesTest, UsesOnlyTheGivenPairs) {
  const Series series = MakeStrips(3);
  SeriesOptions options;
  options.pairs = {{1, 0}, {1, 2}};
  const SeriesResult result = AlignSeries(series.epochs, options);
  ASSERT_EQ(result.pairs.size(), 2u);
  EXPECT_EQ(result.pairs[0].reference, 1);
  EXPECT_EQ(result.pairs[0].moving, 0);
  // Two pairs, six free parameters each: the joint motion is the chain's.
  for (const SeriesPair& pair : result.pairs) EXPECT_LT(pair.misclosure_chi2, 1e-12);
}

bool SameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

// Small pairs align several at a time (on 2 and 8 threads here), each on a
// share of the threads: every number is the one of one pair at a time, and
// each pair's stage is announced once.
TEST(AlignSeriesTest, ResultsAreTheSameWhateverThePairsAtOnce) {
  const Series series = MakeStrips(5);
  std::vector<SeriesResult> results;
  for (const int threads : {1, 2, 8}) {
    SeriesOptions options;
    options.align.num_threads = threads;
    std::mutex mutex;
    std::vector<std::string> stages;
    options.on_stage = [&](const std::string& stage) {
      std::lock_guard<std::mutex> lock(mutex);
      stages.push_back(stage);
    };
    results.push_back(AlignSeries(series.epochs, options));
    const auto pair_stages = std::count_if(stages.begin(), stages.end(), [](const std::string& stage) {
      return stage.rfind("aligning pair ", 0) == 0;
    });
    EXPECT_EQ(pair_stages, static_cast<long>(results.back().pairs.size())) << threads << " threads";
  }
  ASSERT_EQ(results[0].pairs.size(), 7u);
  for (std::size_t r = 1; r < results.size(); ++r) {
    SCOPED_TRACE(r == 1 ? "2 threads" : "8 threads");
    for (std::size_t k = 0; k < results[0].epochs.size(); ++k) {
      EXPECT_TRUE(SameBits(results[r].epochs[k].matrix, results[0].epochs[k].matrix)) << "epoch " << k;
      EXPECT_TRUE(SameBits(results[r].epochs[k].covariance, results[0].epochs[k].covariance)) << "epoch " << k;
    }
    for (std::size_t k = 0; k < results[0].pairs.size(); ++k) {
      const AlignResult& a = results[r].pairs[k].pairwise;
      const AlignResult& b = results[0].pairs[k].pairwise;
      EXPECT_TRUE(SameBits(a.matrix, b.matrix)) << "pair " << k;
      EXPECT_TRUE(SameBits(a.covariance, b.covariance)) << "pair " << k;
      EXPECT_EQ(a.iterations, b.iterations) << "pair " << k;
    }
  }
}

std::string MessageOf(const std::vector<Surface>& epochs, const SeriesOptions& options) {
  try {
    AlignSeries(epochs, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(AlignSeriesTest, RefusesSeriesThatFallApart) {
  const Series near = MakeStrips(2), far = MakeStrips(2, 500);
  const std::vector<Surface> epochs = {near.epochs[0], far.epochs[0], near.epochs[1],
                                       far.epochs[1]};
  EXPECT_EQ(MessageOf(epochs, SeriesOptions()),
            "the series falls apart into {0, 2} and {1, 3}: no pair joins them (give 'pairs', or "
            "lower min_overlap)");
  SeriesOptions given;
  given.pairs = {{0, 2}};
  EXPECT_EQ(MessageOf(epochs, given).rfind("the series falls apart into {0, 2}, {1} and {3}", 0),
            0u)
      << MessageOf(epochs, given);
}

// Given pairs that cannot align: the first pair's error, however many run
// at once and whichever ends first.
TEST(AlignSeriesTest, ReportsTheFirstFailingPairsError) {
  const Series near = MakeStrips(2), far = MakeStrips(1, 500);
  std::vector<Surface> epochs = {near.epochs[0], near.epochs[1], far.epochs[0]};
  epochs[0].source = "a", epochs[1].source = "b", epochs[2].source = "c";
  for (const int threads : {1, 8}) {
    SeriesOptions options;
    options.align.num_threads = threads;
    options.pairs = {{0, 1}, {1, 2}, {0, 2}};
    const std::string message = MessageOf(epochs, options);
    EXPECT_EQ(message.rfind("b and c do not overlap", 0), 0u) << threads << " threads: " << message;
  }
}

TEST(AlignSeriesTest, NamesAnEpochThatOverlapsNoOther) {
  const Series near = MakeStrips(2), far = MakeStrips(1, 500);
  const std::vector<Surface> epochs = {near.epochs[0], near.epochs[1], far.epochs[0]};
  EXPECT_EQ(
      MessageOf(epochs, SeriesOptions()),
      "series: epoch 2 (strip0) overlaps no other by min_overlap 0.3 (at most 0, with epoch 0)");
}

TEST(AlignSeriesTest, RefusesBadArguments) {
  const Series series = MakeStrips(2);
  EXPECT_EQ(MessageOf({series.epochs[0]}, SeriesOptions()),
            "series: at least two epochs are needed, got 1");
  SeriesOptions options;
  options.reference = 2;
  EXPECT_EQ(MessageOf(series.epochs, options), "series: reference 2 is not an epoch (0 to 1)");
  options = SeriesOptions();
  options.pairs = {{0, 0}};
  EXPECT_EQ(MessageOf(series.epochs, options),
            "series: pair 0-0 does not name two different epochs (0 to 1)");
  options = SeriesOptions();
  options.min_overlap = 0;
  EXPECT_EQ(MessageOf(series.epochs, options).rfind("series: min_overlap must be in (0, 1]", 0),
            0u);
  options = SeriesOptions();
  options.align.initial_translation = {1, 0, 0};
  EXPECT_EQ(MessageOf(series.epochs, options),
            "series: an initial motion applies to one pair; the series starts from the inputs");
}

}  // namespace
}  // namespace surfreg
