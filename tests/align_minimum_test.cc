// Does Align reach its own cost's minimum (issue 20)? From the default start
// (the identity) and from the true motion, with the same settings, the final
// volume cost must be the same: the moving surface is the same function of
// the motion whatever path the solver took (registration/pair_state.h), and
// the solver stops at a minimum of it. One small pair of each family: a grid
// DEM against irregular samples of it, LIDAR-like scan lines against another
// scan, and a face scan against another sampling of it.
// tests/bench/align_peers/own_minimum.py does the same on the benchmark's pairs.
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

TEST(AlignMinimumTest, SameFinalCostFromTheDefaultStartAndFromTheTruth) {
  for (const Family& family : Families()) {
    const Eigen::Vector3d centre = testing::Centroid(family.moving_unmoved);
    const Eigen::Matrix4d truth =
        testing::TrueMotion({1, -2, 0.5}, 2.5, Eigen::Vector3d(3, -2, 0.5) * family.spacing, centre);
    const Surface reference = MakeSurface(family.reference, {}, "reference");
    const Surface moving = MakeSurface(testing::MoveByInverse(family.moving_unmoved, truth), {}, "moving");
    AlignOptions options;
    const AlignResult from_default = Align(reference, moving, options);
    // The truth as Align's start: rotation vector, and the shift of the
    // moving centroid c (T(p) = R(p − c) + c + t).
    const Eigen::Matrix3d r = truth.topLeftCorner<3, 3>();
    const Eigen::AngleAxisd angle_axis(r);
    const Eigen::Vector3d c(from_default.centre[0], from_default.centre[1], from_default.centre[2]);
    const Eigen::Vector3d t = truth.topRightCorner<3, 1>() + r * c - c;
    for (int k = 0; k < 3; ++k) {
      options.initial_rotation[k] = angle_axis.angle() * angle_axis.axis()[k];
      options.initial_translation[k] = t[k];
    }
    const AlignResult from_truth = Align(reference, moving, options);
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

}  // namespace
}  // namespace surfreg
