// Stable terrain found from the data (registration/stable_terrain.h,
// rigid_consensus.h, AlignOptions::stable): the classification against
// known changed regions, and Align with stable auto against the truth.
#include "registration/stable_terrain.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "measure/delaunay.h"
#include "registration/align.h"
#include "registration/rigid_consensus.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

constexpr double kSide = 100;

bool InBlock(double x, double y) { return x > 60 && x < 90 && y > 20 && y < 70; }  // 15% of the square

std::vector<std::array<double, 3>> WithNoise(std::vector<std::array<double, 3>> points, double sigma,
                                             uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  for (auto& p : points) p[2] += noise(rng);
  return points;
}

// Share of `surface`'s samples with `flag` among those where `where` holds.
template <typename Where>
double ShareFlagged(const Surface& surface, const StableTerrain& stable, uint8_t flag, Where where) {
  int64_t in = 0, flagged = 0;
  for (std::size_t i = 0; i < surface.size(); ++i) {
    const double x = surface.xy[i].x + surface.origin[0], y = surface.xy[i].y + surface.origin[1];
    if (!where(x, y)) continue;
    ++in;
    flagged += stable.flag[i] == flag;
  }
  return in > 0 ? static_cast<double>(flagged) / static_cast<double>(in) : 0.0;
}

// The neighbours by the definition (every directed Delaunay edge and each
// merged duplicate's link, sorted, repeats dropped) and the curvature and
// gradients: the same on 1, 2 and 8 threads (chunks of 8192 samples).
TEST(SampleAdjacency, IsTheSortedEdgesOnAnyNumberOfThreads) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, kSide);
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 30000; ++i) {
    const double x = u(rng), y = u(rng);
    points.push_back({x, y, std::sin(x / 9.0) * std::cos(y / 7.0)});
  }
  points.push_back(points[5]);  // a duplicate, merged into its vertex
  const Surface reference = MakeSurface(points);
  const SampleAdjacency one = MakeSampleAdjacency(reference, Execution{1});
  const Triangulation mesh = Triangulate(reference.xy);
  std::vector<std::pair<int32_t, int32_t>> edges;
  for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      edges.emplace_back(mesh.triangles[t + k], mesh.triangles[t + (k + 1) % 3]);
      edges.emplace_back(mesh.triangles[t + (k + 1) % 3], mesh.triangles[t + k]);
    }
  }
  for (int32_t i = 0; i < static_cast<int32_t>(reference.size()); ++i) {
    const int32_t v = mesh.vertex_of_input[i];
    if (v == i) continue;
    edges.emplace_back(i, v);
    edges.emplace_back(v, i);
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  ASSERT_EQ(one.neighbour.size(), edges.size());
  for (std::size_t k = 0; k < edges.size(); ++k) {
    ASSERT_EQ(one.neighbour[k], edges[k].second) << k;
    ASSERT_GE(k, static_cast<std::size_t>(one.offset[edges[k].first])) << k;
    ASSERT_LT(k, static_cast<std::size_t>(one.offset[edges[k].first + 1])) << k;
  }
  for (const int threads : {2, 8}) {
    const SampleAdjacency many = MakeSampleAdjacency(reference, Execution{threads});
    EXPECT_EQ(many.offset, one.offset);
    EXPECT_EQ(many.neighbour, one.neighbour);
    EXPECT_EQ(many.curvature_gap, one.curvature_gap);
    EXPECT_EQ(many.gradient, one.gradient);
  }
}

TEST(ClassifyStable, MarksAKnownBlockAndNothingElse) {
  const Surface reference =
      MakeSurface(testing::SampleUniform(testing::SmoothTerrain, 8000, 0, kSide, 0, kSide, 11), {}, "reference");
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0, 0.1);
  std::vector<double> dz(reference.size());
  for (std::size_t i = 0; i < dz.size(); ++i) {
    const double x = reference.xy[i].x + reference.origin[0], y = reference.xy[i].y + reference.origin[1];
    dz[i] = noise(rng) + (InBlock(x, y) ? -2.0 : 0.0);
  }
  StableOptions options;
  options.margin_rings = 0;
  const StableTerrain first = ClassifyStable(reference, dz, {}, {}, {}, options);
  EXPECT_EQ(first.regions, 1);
  // The second round measures the centre and scale on the stable part only.
  const StableTerrain stable = ClassifyStable(reference, dz, {}, first.flag, {}, options);
  EXPECT_EQ(stable.regions, 1);
  EXPECT_GT(ShareFlagged(reference, stable, kChangedSample, InBlock), 0.999);
  EXPECT_LT(ShareFlagged(reference, stable, kChangedSample, [](double x, double y) { return !InBlock(x, y); }),
            0.001);
  EXPECT_NEAR(stable.stable_share, 0.85, 0.02);
  EXPECT_NEAR(stable.noise_sigma, 0.1, 0.02);
  EXPECT_NEAR(stable.centre, 0.0, 0.01);
}

TEST(ClassifyStable, IsolatedOutliersAreNoiseNotChange) {
  const Surface reference =
      MakeSurface(testing::SampleUniform(testing::SmoothTerrain, 4000, 0, kSide, 0, kSide, 12), {}, "reference");
  std::vector<double> dz(reference.size(), 0.0);
  std::mt19937_64 rng(6);
  std::normal_distribution<double> noise(0, 0.1);
  for (double& d : dz) d = noise(rng);
  for (std::size_t i = 0; i < dz.size(); i += 97) dz[i] += 5;  // spikes, one sample each
  const StableTerrain stable = ClassifyStable(reference, dz, {}, {}, {}, StableOptions());
  EXPECT_EQ(stable.regions, 0);
  EXPECT_EQ(stable.changed_samples, 0);
  EXPECT_DOUBLE_EQ(stable.stable_share, 1.0);
}

// A sampling whose density varies by design, as a mesh's vertices do (a
// face's nose and eyes against its cheeks): a third of the samples on 2% of
// a plane, a third on 16%, a third on the rest (area per sample 0.05, 0.4 and
// 2 × 2.05), noisy heights, and gaps that are noise only. The scale's
// interpolation gap follows the local spacing, so the sparse part's gaps are
// not taken for change (with the median spacing everywhere, the dense part's
// noisy curvature gave it large scales, the robust σ shrank and much of the
// sparse part came out changed).
TEST(ClassifyStable, UnevenSamplingWithoutChangeIsAllStable) {
  const auto plane = [](double x, double y) { return 0.02 * x + 0.01 * y; };
  std::vector<std::array<double, 3>> points;
  const double edges[] = {0, 2, 18, kSide};
  for (int part = 0; part < 3; ++part) {
    const std::vector<std::array<double, 3>> some =
        testing::SampleUniform(plane, 2000, edges[part], edges[part + 1], 0, kSide, 21 + part);
    points.insert(points.end(), some.begin(), some.end());
  }
  const Surface reference = MakeSurface(WithNoise(points, 0.05, 25));
  std::mt19937_64 rng(26);
  std::normal_distribution<double> noise(0, 0.05 * std::sqrt(2.0));
  std::vector<double> dz(reference.size());
  for (double& d : dz) d = noise(rng);
  const StableTerrain first = ClassifyStable(reference, dz, {}, {}, {}, StableOptions());
  const StableTerrain stable = ClassifyStable(reference, dz, {}, first.flag, {}, StableOptions());
  for (const StableTerrain* round : {&first, &stable}) {
    EXPECT_LE(round->regions, 1);
    EXPECT_GT(round->stable_share, 0.98);
    EXPECT_GT(ShareFlagged(reference, *round, kStableSample, [](double x, double) { return x > 18; }), 0.98);
  }
}

TEST(ClassifyStable, IneligibleAndUnmeasuredSamplesAreNeverStable) {
  const Surface reference =
      MakeSurface(testing::SampleUniform(testing::SmoothTerrain, 3000, 0, kSide, 0, kSide, 13), {}, "reference");
  std::vector<double> dz(reference.size(), 0.0);
  std::vector<uint8_t> eligible(reference.size(), 1);
  for (std::size_t i = 0; i < dz.size(); i += 3) eligible[i] = 0;
  for (std::size_t i = 1; i < dz.size(); i += 5) dz[i] = std::nan("");
  const StableTerrain stable = ClassifyStable(reference, dz, eligible, {}, {}, StableOptions());
  for (std::size_t i = 0; i < dz.size(); ++i) {
    if (!eligible[i] || !std::isfinite(dz[i])) {
      EXPECT_EQ(stable.flag[i], kOutsideOverlap) << i;
    }
  }
}

// Change on curved ground is seen lower from the moving side; a region of
// twice min_region_samples or more is change down to a ratio of 0.3, a
// smaller one only from 0.75 (small disagreeing spots are not change).
TEST(ClassifyStable, MovingSideConfirmationDependsOnTheRegionsSize) {
  const Surface reference =
      MakeSurface(testing::SampleUniform(testing::SmoothTerrain, 8000, 0, kSide, 0, kSide, 14), {}, "reference");
  struct Disc {
    double x, y, r, partner_ratio;
  };
  const Disc large_low{25, 25, 5.0, 0.5}, small_low{75, 25, 2.6, 0.5}, small_agreeing{50, 75, 2.6, 0.9};
  const Disc* discs[] = {&large_low, &small_low, &small_agreeing};
  auto disc_of = [&](double x, double y) -> const Disc* {
    for (const Disc* d : discs) {
      if (std::hypot(x - d->x, y - d->y) < d->r) return d;
    }
    return nullptr;
  };
  std::mt19937_64 rng(8);
  std::normal_distribution<double> noise(0, 0.1);
  GapField gaps;
  gaps.dz.resize(reference.size());
  gaps.partner_sum.resize(reference.size());
  gaps.partner_count.assign(reference.size(), 1);
  int small_low_samples = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const double x = reference.xy[i].x + reference.origin[0], y = reference.xy[i].y + reference.origin[1];
    const Disc* d = disc_of(x, y);
    gaps.dz[i] = noise(rng) + (d ? 3.0 : 0.0);
    gaps.partner_sum[i] = noise(rng) + (d ? 3.0 * d->partner_ratio : 0.0);
    small_low_samples += d == &small_low;
  }
  StableOptions options;
  options.margin_rings = 0;
  // The small discs must sit between min_region_samples and twice it.
  ASSERT_GE(small_low_samples, options.min_region_samples);
  ASSERT_LT(small_low_samples, 2 * options.min_region_samples);
  const StableTerrain stable = ClassifyStable(MakeSampleAdjacency(reference), gaps, {}, {}, options);
  auto in = [&](const Disc& d) { return [&](double x, double y) { return disc_of(x, y) == &d; }; };
  EXPECT_EQ(stable.regions, 2);
  EXPECT_GT(ShareFlagged(reference, stable, kChangedSample, in(large_low)), 0.99);
  EXPECT_EQ(ShareFlagged(reference, stable, kChangedSample, in(small_low)), 0.0);
  EXPECT_GT(ShareFlagged(reference, stable, kChangedSample, in(small_agreeing)), 0.99);
}

// The gaps a small rigid misfit leaves, plus a block of change: the
// consensus removes the misfit exactly and leaves the block.
TEST(RigidConsensus, RemovesARigidMisfitThroughAChangedBlock) {
  const Surface reference =
      MakeSurface(testing::SampleUniform(testing::SmoothTerrain, 6000, 0, kSide, 0, kSide, 14), {}, "reference");
  const SampleAdjacency adjacency = MakeSampleAdjacency(reference);
  std::vector<double> dz(reference.size());
  for (std::size_t i = 0; i < dz.size(); ++i) {
    const double x = reference.xy[i].x, y = reference.xy[i].y;
    const double gx = adjacency.gradient[i][0], gy = adjacency.gradient[i][1];
    // A tilt, a vertical and a horizontal shift, as a linear gap field.
    dz[i] = 0.01 * x - 0.02 * y + 0.5 - 0.3 * gx + 0.2 * gy;
    if (InBlock(x + reference.origin[0], y + reference.origin[1])) dz[i] += 4.0;
  }
  const ConsensusFit fit = RigidConsensus(reference, adjacency, dz, {});
  double worst = 0;
  for (std::size_t i = 0; i < dz.size(); ++i) {
    const double x = reference.xy[i].x + reference.origin[0], y = reference.xy[i].y + reference.origin[1];
    if (InBlock(x, y)) {
      EXPECT_NEAR(fit.residual[i], 4.0, 0.05);
      EXPECT_EQ(fit.flag[i], kChangedSample);
    } else {
      worst = std::max(worst, std::abs(fit.residual[i]));
    }
  }
  EXPECT_LT(worst, 0.05);
  // Tiles across the block's edge are out whole: the inliers are the
  // block's complement less those.
  EXPECT_GT(fit.inlier_share, 0.7);
  EXPECT_LE(fit.inlier_share, 0.85);
}

struct Pair {
  Surface reference, moving;
  Eigen::Matrix4d truth;
  Eigen::Vector3d moving_centroid;
};

// Two noisy samplings of `f` (reference) and `g` (moving, before the
// motion), the moving one moved by a known 2° and (1.5, -1, 0.4).
Pair MakePair(const testing::HeightFunction& f, const testing::HeightFunction& g, double sigma) {
  Pair pair;
  const auto a = WithNoise(testing::SampleUniform(f, 6000, 0, kSide, 0, kSide, 21), sigma, 31);
  const auto b = WithNoise(testing::SampleUniform(g, 6000, 0, kSide, 0, kSide, 22), sigma, 32);
  pair.truth = testing::TrueMotion({1, -2, 0.5}, 2.0, {1.5, -1.0, 0.4}, testing::Centroid(b));
  const auto moved = testing::MoveByInverse(b, pair.truth);
  pair.moving_centroid = testing::Centroid(moved);
  pair.reference = MakeSurface(a, {}, "reference");
  pair.moving = MakeSurface(moved, {}, "moving");
  return pair;
}

testing::MotionError Error(const Pair& pair, const AlignResult& result) {
  return testing::CompareMotions(result.matrix, pair.truth, pair.moving_centroid);
}

AlignOptions WithStable(StableOptions::Mode mode) {
  AlignOptions options;
  options.stable.mode = mode;
  return options;
}

// Everything raised where it changed (buildings, growth): one-sided change
// pulls an L1 fit; the stable part found from the data does not.
TEST(AlignStable, OneSidedChangedBlockIsFoundAndLeftOut) {
  const Pair pair = MakePair(testing::SmoothTerrain, [](double x, double y) {
    return testing::SmoothTerrain(x, y) + (InBlock(x, y) ? 3.0 + 0.05 * (x - 60) : 0.0);
  }, 0.05);
  const AlignResult all = Align(pair.reference, pair.moving, WithStable(StableOptions::Mode::kAll));
  const AlignResult found = Align(pair.reference, pair.moving, WithStable(StableOptions::Mode::kAuto));
  ASSERT_EQ(found.verdict, Verdict::kConvergedImproved) << found.verdict_reason;
  ASSERT_TRUE(found.stable.done);
  EXPECT_EQ(found.stable.regions, 1);
  EXPECT_GT(ShareFlagged(pair.reference, found.stable, kChangedSample, InBlock), 0.99);
  // The block is 15% of the square; the rim where the moving surface's
  // triangles span its edge, and two rings beyond, add several percent.
  EXPECT_GT(1 - found.stable.stable_share, 0.15);
  EXPECT_LT(1 - found.stable.stable_share, 0.27);
  EXPECT_LT(ShareFlagged(pair.reference, found.stable, kChangedSample,
                         [](double x, double y) { return !(x > 52 && x < 98 && y > 12 && y < 78); }),
            0.001);
  EXPECT_TRUE(found.stable.warning.empty()) << found.stable.warning;
  const testing::MotionError e_all = Error(pair, all), e_found = Error(pair, found);
  EXPECT_LT(e_found.rotation_deg, 0.03);
  EXPECT_LT(e_found.translation, 0.03);
  EXPECT_LT(e_found.rotation_deg, 0.2 * e_all.rotation_deg);
  // The σ describe the fit on the stable part: the error within 4σ.
  const double sigma_rotation_deg =
      std::sqrt(found.covariance.topLeftCorner<3, 3>().trace()) * 180 / M_PI;
  EXPECT_LT(e_found.rotation_deg, 4 * sigma_rotation_deg);
}

// Real change leaves the surfaces apart after a fit on all of the overlap,
// as a wrong minimum does: wide_search auto searches there (1-3 s, for the
// same minimum). With the stable terrain found first, the fit on it lies
// close and nothing is searched: the same motion as never searching.
TEST(AlignStable, ChangeThatLeavesTheSurfacesApartRunsNoWideSearch) {
  const Pair pair = MakePair(testing::SmoothTerrain, [](double x, double y) {
    return testing::SmoothTerrain(x, y) + (InBlock(x, y) ? 3.0 + 0.05 * (x - 60) : 0.0);
  }, 0.05);
  const AlignResult all = Align(pair.reference, pair.moving, WithStable(StableOptions::Mode::kAll));
  ASSERT_TRUE(all.wide_search_ran) << "the fit on all left the surfaces close: the test lost its point";
  AlignOptions options = WithStable(StableOptions::Mode::kAuto);
  std::vector<std::string> stages;
  options.on_stage = [&stages](const char* stage, double) { stages.emplace_back(stage); };
  const AlignResult found = Align(pair.reference, pair.moving, options);
  ASSERT_EQ(found.verdict, Verdict::kConvergedImproved) << found.verdict_reason;
  EXPECT_FALSE(found.wide_search_ran);
  for (const std::string& stage : stages) EXPECT_EQ(stage.find("wide search"), std::string::npos) << stage;
  options.wide_search = AlignOptions::WideSearch::kNever;
  EXPECT_EQ(Align(pair.reference, pair.moving, options).matrix, found.matrix);
  EXPECT_LT(Error(pair, found).rotation_deg, 0.03);
}

// Nothing changed: nothing is left out, and the result is the fit on all.
TEST(AlignStable, UnchangedPairKeepsEverythingAndTheSameResult) {
  const Pair pair = MakePair(testing::SmoothTerrain, testing::SmoothTerrain, 0.05);
  const AlignResult all = Align(pair.reference, pair.moving, WithStable(StableOptions::Mode::kAll));
  const AlignResult found = Align(pair.reference, pair.moving, WithStable(StableOptions::Mode::kAuto));
  ASSERT_TRUE(found.stable.done);
  EXPECT_EQ(found.stable.regions, 0);
  EXPECT_EQ(found.stable.changed_samples, 0);
  EXPECT_DOUBLE_EQ(found.stable.stable_share, 1.0);
  EXPECT_EQ(found.matrix, all.matrix);
  EXPECT_FALSE(all.stable.done);
}

// A face-like dome whose lower third turned 4° about a hinge behind it (the
// jaw opened): the alignment holds to the upper two thirds.
TEST(AlignStable, FaceWhoseLowerPartMovedAlignsOnTheRest) {
  const auto dome = [](double x, double y) {
    return 30 * std::exp(-((x - 50) * (x - 50) / 1800.0 + (y - 50) * (y - 50) / 2600.0)) +
           3 * std::exp(-((x - 50) * (x - 50) + (y - 55) * (y - 55)) / 40.0);
  };
  const double hinge_y = 50, hinge_z = -20, angle = 4 * M_PI / 180;
  const auto jaw = [&](double x, double y) {
    const double z = dome(x, y);
    if (y >= 33) return z;
    // The lower part turned about the x-parallel hinge: a height field of it
    // (the turn is small, so the heights at (x, y) follow by one fixed-point step).
    const double c = std::cos(angle), s = std::sin(angle);
    const double y0 = hinge_y + c * (y - hinge_y) + s * (dome(x, y) - hinge_z);
    return hinge_z - s * (y0 - hinge_y) + c * (dome(x, y0) - hinge_z);
  };
  const Pair pair = MakePair(dome, jaw, 0.02);
  const AlignResult all = Align(pair.reference, pair.moving, WithStable(StableOptions::Mode::kAll));
  const AlignResult found = Align(pair.reference, pair.moving, WithStable(StableOptions::Mode::kAuto));
  ASSERT_EQ(found.verdict, Verdict::kConvergedImproved) << found.verdict_reason;
  const testing::MotionError e_all = Error(pair, all), e_found = Error(pair, found);
  EXPECT_LT(e_found.rotation_deg, 0.02);
  EXPECT_LT(e_found.rotation_deg, 0.2 * e_all.rotation_deg);
  EXPECT_GT(ShareFlagged(pair.reference, found.stable, kStableSample, [](double, double y) { return y > 40; }),
            0.97);
  EXPECT_GT(ShareFlagged(pair.reference, found.stable, kChangedSample, [](double, double y) { return y < 25; }),
            0.9);
}

TEST(AlignStable, ASmallStablePartWarns) {
  const Pair pair = MakePair(testing::SmoothTerrain, [](double x, double y) {
    return testing::SmoothTerrain(x, y) - (InBlock(x, y) ? 4.0 : 0.0);
  }, 0.05);
  AlignOptions options = WithStable(StableOptions::Mode::kAuto);
  options.stable.warn_share = 0.9;  // the block leaves 85%
  std::vector<std::string> stages;
  options.on_stage = [&stages](const char* stage, double) { stages.emplace_back(stage); };
  const AlignResult found = Align(pair.reference, pair.moving, options);
  EXPECT_NE(found.stable.warning.find("of the overlap is stable terrain"), std::string::npos)
      << found.stable.warning;
  // The first fit on all leaves the surfaces apart (the change), so the
  // warning asks for the wide search the first fit would have run: it runs
  // alone, finds the same minimum, and the result is the fit without it.
  EXPECT_TRUE(found.wide_search_ran);
  EXPECT_EQ(std::count(stages.begin(), stages.end(),
                       "the stable terrain is small or did not settle: the wide search from the start"),
            1);
  options.on_stage = nullptr;
  options.wide_search = AlignOptions::WideSearch::kNever;
  EXPECT_EQ(Align(pair.reference, pair.moving, options).matrix, found.matrix);
  options.wide_search = AlignOptions::WideSearch::kAuto;
  options.stable.warn_share = 0.4;
  EXPECT_TRUE(Align(pair.reference, pair.moving, options).stable.warning.empty());
}

// The user's mask and the stable terrain: the fit uses their intersection.
TEST(AlignStable, UserMaskIsIntersectedNotReplaced) {
  const Pair pair = MakePair(testing::SmoothTerrain, [](double x, double y) {
    return testing::SmoothTerrain(x, y) + (InBlock(x, y) ? 3.0 : 0.0);
  }, 0.05);
  AlignOptions options = WithStable(StableOptions::Mode::kAuto);
  options.weight = WeightMode::kMask;
  options.mask = {{{0, 0}, {kSide, 0}, {kSide, 80}, {0, 80}}};  // leaves out y > 80
  const AlignResult found = Align(pair.reference, pair.moving, options);
  ASSERT_EQ(found.verdict, Verdict::kConvergedImproved) << found.verdict_reason;
  EXPECT_EQ(ShareFlagged(pair.reference, found.stable, kStableSample, [](double, double y) { return y > 80.5; }),
            0.0);
  EXPECT_GT(ShareFlagged(pair.reference, found.stable, kChangedSample, InBlock), 0.99);
  // Away from the block: at most a spot at the domain's edge (x > 98).
  EXPECT_LT(ShareFlagged(pair.reference, found.stable, kChangedSample,
                         [](double x, double y) { return y < 77 && !(x > 52 && x < 98 && y > 12 && y < 78); }),
            0.005);
  options.stable.mode = StableOptions::Mode::kAll;
  const AlignResult masked_all = Align(pair.reference, pair.moving, options);
  EXPECT_LT(Error(pair, found).rotation_deg, 0.05);
  EXPECT_LT(Error(pair, found).rotation_deg, 0.25 * Error(pair, masked_all).rotation_deg);
}

}  // namespace
}  // namespace surfreg
