// Does Align reach its own cost's minimum (issue 20)? From the default start
// (the identity) and from the true motion, with the same settings, the final
// volume cost must be the same: the moving surface is the same function of
// the motion whatever path the solver took (registration/pair_state.h), and
// the solver stops at a minimum of it. One small pair of each family: a grid
// DEM against irregular samples of it, LIDAR-like scan lines against another
// scan, and a face scan against another sampling of it.
// tests/bench/align_peers/own_minimum.py does the same on the benchmark's pairs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "registration/align.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

using Points = std::vector<std::array<double, 3>>;

// The solver's last volume cost (the log's last "volume" row).
double FinalVolumeCost(const AlignResult& result) {
  double cost = std::nan("");
  for (const auto& entry : result.log) {
    if (std::string(entry.cost_name) == "volume") cost = entry.cost;
  }
  return cost;
}

struct Family {
  const char* name;
  Points reference, moving_unmoved;  // both where the truth puts them
  double spacing;
};

// Scan lines along x, `across` apart, points `along` apart (jittered), with
// heights of SmoothTerrain; `phase` shifts the lines.
Points ScanLines(double along, double across, double phase, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  Points out;
  for (double y = phase; y <= 100; y += across) {
    for (double x = 0; x <= 100; x += along * (1 + jitter(rng))) {
      const double yy = y + 0.01 * x + jitter(rng);
      out.push_back({x, yy, testing::SmoothTerrain(x, yy)});
    }
  }
  return out;
}

Points ReadXyz(const std::string& path, int every, int offset) {
  std::ifstream in(path);
  Points out;
  std::string line;
  int k = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::array<double, 3> p;
    if (!(fields >> p[0] >> p[1] >> p[2])) continue;
    if (k++ % every == offset) out.push_back(p);
  }
  return out;
}

std::vector<Family> Families() {
  std::vector<Family> out;
  {
    const testing::GridDem dem = testing::ReadGridDem("configs/data/volcano.xyz");
    Points grid;
    for (int i = 0; i < dem.nx; ++i) {
      for (int j = 0; j < dem.ny; ++j) {
        const double x = dem.x0 + i * dem.step, y = dem.y0 + j * dem.step;
        grid.push_back({x, y, dem(x, y)});
      }
    }
    out.push_back({"terrain grid", grid,
                   testing::SampleUniform(std::cref(dem), 4000, dem.x0, dem.x1(), dem.y0, dem.y1(), 5),
                   dem.step});
  }
  out.push_back({"LIDAR-like scan lines", ScanLines(0.5, 2.0, 0.0, 1), ScanLines(0.6, 1.7, 0.5, 2), 1.0});
  out.push_back({"face", ReadXyz("configs/data/face_a.xyz", 3, 0), ReadXyz("configs/data/face_a.xyz", 3, 1),
                 0.1});
  return out;
}

// The family's pair with the moving scan moved by the inverse of a fixed
// true motion (2.5° about (1, −2, 0.5), a shift of (3, −2, 0.5) spacings).
struct Moved {
  Eigen::Vector3d centre;
  Eigen::Matrix4d truth;
  Surface reference, moving;
};
Moved MovedPair(const Family& family) {
  Moved out;
  out.centre = testing::Centroid(family.moving_unmoved);
  out.truth = testing::TrueMotion({1, -2, 0.5}, 2.5, Eigen::Vector3d(3, -2, 0.5) * family.spacing, out.centre);
  out.reference = MakeSurface(family.reference, {}, "reference");
  out.moving = MakeSurface(testing::MoveByInverse(family.moving_unmoved, out.truth), {}, "moving");
  return out;
}

// `options` with the truth as Align's start: rotation vector, and the
// shift of the moving centroid c that `result` (an alignment of the same
// pair) reports (T(p) = R(p − c) + c + t).
AlignOptions StartingAtTheTruth(AlignOptions options, const Eigen::Matrix4d& truth, const AlignResult& result) {
  const Eigen::Matrix3d r = truth.topLeftCorner<3, 3>();
  const Eigen::AngleAxisd angle_axis(r);
  const Eigen::Vector3d c(result.centre[0], result.centre[1], result.centre[2]);
  const Eigen::Vector3d t = truth.topRightCorner<3, 1>() + r * c - c;
  for (int k = 0; k < 3; ++k) {
    options.initial_rotation[k] = angle_axis.angle() * angle_axis.axis()[k];
    options.initial_translation[k] = t[k];
  }
  return options;
}

TEST(AlignMinimumTest, SameFinalCostFromTheDefaultStartAndFromTheTruth) {
  for (const Family& family : Families()) {
    const auto [centre, truth, reference, moving] = MovedPair(family);
    AlignOptions options;
    const AlignResult from_default = Align(reference, moving, options);
    const AlignResult from_truth = Align(reference, moving, StartingAtTheTruth(options, truth, from_default));
    const double a = FinalVolumeCost(from_default), b = FinalVolumeCost(from_truth);
    const testing::MotionError error = testing::CompareMotions(from_default.matrix, truth, centre);
    std::printf("%s: final cost %.12g from the default start, %.12g from the truth (relative %.1e); "
                "error %.2g deg, %.2g spacings\n",
                family.name, a, b, (a - b) / b, error.rotation_deg, error.translation / family.spacing);
    EXPECT_EQ(from_default.verdict, Verdict::kConvergedImproved) << family.name;
    EXPECT_LE(std::fabs(a - b), 1e-6 * b) << family.name;
    EXPECT_LT(error.rotation_deg, 0.05) << family.name;
  }
}

// Rows of the log with this cost name.
int LogRows(const AlignResult& result, const char* cost_name) {
  int rows = 0;
  for (const auto& entry : result.log) rows += std::string(entry.cost_name) == cost_name;
  return rows;
}

// On large clouds the prealignment's subsample also gets a volume solve
// (registration/align_steps.cc, kRefineRatio): the finest solve then starts
// near its minimum, and it must still end at the same cost as from the
// truth. On small clouds that step is left out.
TEST(AlignMinimumTest, VolumePrealignmentOnLargeCloudsKeepsTheMinimum) {
  const Points reference = testing::SampleUniform(testing::SmoothTerrain, 30000, 0, 100, 0, 100, 11);
  const Points unmoved = testing::SampleUniform(testing::SmoothTerrain, 30000, 0, 100, 0, 100, 12);
  const Eigen::Vector3d centre = testing::Centroid(unmoved);
  const double spacing = 100.0 / std::sqrt(30000.0);
  const Eigen::Matrix4d truth =
      testing::TrueMotion({1, -2, 0.5}, 2.5, Eigen::Vector3d(3, -2, 0.5) * spacing, centre);
  const Surface a = MakeSurface(reference, {}, "reference");
  const Surface b = MakeSurface(testing::MoveByInverse(unmoved, truth), {}, "moving");
  AlignOptions options;
  const AlignResult from_default = Align(a, b, options);
  EXPECT_GT(LogRows(from_default, "volume_prealign"), 1);
  const AlignResult from_truth = Align(a, b, StartingAtTheTruth(options, truth, from_default));
  const double cost_default = FinalVolumeCost(from_default), cost_truth = FinalVolumeCost(from_truth);
  const testing::MotionError error = testing::CompareMotions(from_default.matrix, truth, centre);
  std::printf("30k points: final cost %.12g from the default start, %.12g from the truth; error %.2g deg, "
              "%.2g spacings\n",
              cost_default, cost_truth, error.rotation_deg, error.translation / spacing);
  EXPECT_EQ(from_default.verdict, Verdict::kConvergedImproved);
  EXPECT_LE(std::fabs(cost_default - cost_truth), 1e-6 * cost_truth);
  EXPECT_LT(error.rotation_deg, 0.01);
  EXPECT_LT(error.translation, 0.01 * spacing);

  // A fifth of the subsample's size more than these: no volume step there.
  const Surface small_a = MakeSurface(
      testing::SampleUniform(testing::SmoothTerrain, 20000, 0, 100, 0, 100, 13), {}, "reference");
  const Surface small_b = MakeSurface(
      testing::MoveByInverse(testing::SampleUniform(testing::SmoothTerrain, 20000, 0, 100, 0, 100, 14), truth),
      {}, "moving");
  const AlignResult small = Align(small_a, small_b, AlignOptions());
  EXPECT_GT(LogRows(small, "axial"), 1);
  EXPECT_EQ(LogRows(small, "volume_prealign"), 0);
  EXPECT_EQ(small.verdict, Verdict::kConvergedImproved);
}

// The axial cost is continuous (registration/axial_cost.h: the taper at Ω's
// edge, the cosine linear on triangles), so Levenberg-Marquardt never
// cycles: no iteration's cost (accepted or trial) equals the cost two
// iterations before unless it also equals the one in between. A cost that
// jumps as nodes cross edges or leave Ω made trial and accepted costs
// alternate for dozens of iterations with steps shrinking to 1e-10.
bool EndsInARevisit(const std::vector<double>& costs) {
  const std::size_t k = costs.size();
  if (k < 3) return false;
  const double scale = std::fabs(costs[k - 1]);
  const double away = std::min(std::fabs(costs[k - 2] - costs[k - 1]), std::fabs(costs[k - 2] - costs[k - 3]));
  return std::fabs(costs[k - 1] - costs[k - 3]) <= 1e-10 * scale && away > 1e-7 * scale;
}

TEST(AlignMinimumTest, AxialSolveNeverRevisitsACost) {
  // The check itself, on costs logged by a solve that cycled (a face with
  // 60% overlap, before the cost was continuous), and on converging ones.
  EXPECT_TRUE(EndsInARevisit({0.97719920066132993, 0.97726507009924646, 0.97719920062954313}));
  EXPECT_FALSE(EndsInARevisit({5.2855557859917104, 5.2855557859510647, 5.2855557859917353}));
  EXPECT_FALSE(EndsInARevisit({1.2286579016909664, 1.2286578964618191, 1.2286578964537114}));
  std::vector<Family> families = Families();
  {  // and the face with partial overlap: the moving scan's left 60%
    Family partial = families.back();
    partial.name = "face, 60% overlap";
    std::vector<double> xs;
    for (const auto& p : partial.moving_unmoved) xs.push_back(p[0]);
    std::sort(xs.begin(), xs.end());
    const double cut = xs[xs.size() * 6 / 10];
    Points kept;
    for (const auto& p : partial.moving_unmoved) {
      if (p[0] < cut) kept.push_back(p);
    }
    partial.moving_unmoved = kept;
    families.push_back(partial);
  }
  for (const Family& family : families) {
    const auto [centre, truth, reference, moving] = MovedPair(family);
    AlignOptions options;
    options.cost = CostKind::kAxial;
    const AlignResult result = Align(reference, moving, options);
    std::vector<double> costs;
    int revisits = 0, rows = 0;
    for (const auto& entry : result.log) {
      if (std::string(entry.cost_name) != "axial") continue;
      ++rows;
      if (entry.iteration == 0) costs.clear();  // a new level or start
      if (!std::isfinite(entry.cost) || entry.cost > 1e300) continue;  // an infeasible trial
      costs.push_back(entry.cost);
      revisits += EndsInARevisit(costs);
    }
    const testing::MotionError error = testing::CompareMotions(result.matrix, truth, centre);
    std::printf("%s (axial): %d log rows, %d revisited costs; error %.2g deg, %.2g spacings\n",
                family.name, rows, revisits, error.rotation_deg, error.translation / family.spacing);
    EXPECT_GT(rows, 3) << family.name;
    EXPECT_EQ(revisits, 0) << family.name;
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << family.name;
    EXPECT_LT(error.rotation_deg, 0.1) << family.name;
  }
}

}  // namespace
}  // namespace surfreg
