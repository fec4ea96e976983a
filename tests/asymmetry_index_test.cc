// Asymmetry indices by region (faces/asymmetry_index.h) against closed forms:
// a face symmetric about x = 0 with a bump of known shape on one cheek of
// the lower third. The difference face − mirror is the bump on its side and
// minus the bump on the other, so over the lower third ∫d² = 2∫bump²
// = 2πR²h²/5, a polygon around the bump holds ∫d = πR²h/3, the halves hold
// ±that volume, and the other thirds hold nothing.
#include "faces/asymmetry_index.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "faces/asymmetry_cohort.h"
#include "faces/symmetry.h"
#include "measure/input_error.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfWidth = 8, kHalfHeight = 10;  // the face: [−8, 8] × [−10, 10]
constexpr double kBumpX = 4, kBumpY = -7, kBumpRadius = 2, kBumpHeight = 0.5;

double Bump(double x, double y) {
  const double r2 =
      ((x - kBumpX) * (x - kBumpX) + (y - kBumpY) * (y - kBumpY)) / (kBumpRadius * kBumpRadius);
  return r2 < 1 ? kBumpHeight * (1 - r2) * (1 - r2) : 0.0;
}

// A smooth face symmetric in x.
double Base(double x, double y) { return -0.04 * x * x - 0.02 * y * y + 0.002 * y * y * y; }

// A jittered grid (spacing h) over the rectangle, its border unjittered so
// that the hull is the rectangle; heights Base + Bump (+ noise).
Surface Face(double h, uint32_t seed, double noise = 0, uint32_t noise_seed = 0) {
  std::mt19937 rng(seed), noise_rng(noise_seed);
  std::uniform_real_distribution<double> jitter(-0.35 * h, 0.35 * h);
  std::normal_distribution<double> gauss(0.0, noise);
  const int nx = static_cast<int>(std::lround(2 * kHalfWidth / h));
  const int ny = static_cast<int>(std::lround(2 * kHalfHeight / h));
  std::vector<std::array<double, 3>> points;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      double x = -kHalfWidth + i * h, y = -kHalfHeight + j * h;
      if (i > 0 && i < nx && j > 0 && j < ny) x += jitter(rng), y += jitter(rng);
      double z = Base(x, y) + Bump(x, y);
      if (noise > 0) z += gauss(noise_rng);
      points.push_back({x, y, z});
    }
  }
  return MakeSurface(points, {}, "analytic face");
}

const RegionIndex& Get(const AsymmetryIndices& indices, const std::string& name) {
  const RegionIndex* r = indices.Find(name);
  if (r == nullptr) throw std::runtime_error("no region " + name);
  return *r;
}

TEST(AsymmetryIndexTest, BumpInTheLowerThirdMatchesTheClosedForms) {
  const Surface face = Face(0.1, 1);
  AsymmetryIndexOptions options;
  // A square around the bump (clockwise, to check either orientation works).
  options.regions.push_back({"bump", {{1.5, -9.5}, {1.5, -4.5}, {6.5, -4.5}, {6.5, -9.5}}});
  const AsymmetryIndices indices = ComputeAsymmetryIndices(face, SymmetryPlane(), options);

  const double volume = kPi * kBumpRadius * kBumpRadius * kBumpHeight / 3;
  const double third_area = 2 * kHalfWidth * 2 * kHalfHeight / 3;
  const double integral_d2 = 2 * kPi * kBumpRadius * kBumpRadius * kBumpHeight * kBumpHeight / 5;
  const double rms = std::sqrt(integral_d2 / third_area);
  const RegionIndex& lower = Get(indices, "lower_third");
  std::printf("lower third: rms %.6f (analytic %.6f, %+.3f%%), area %.4f (%.4f), sigma %.2g\n",
              lower.rms, rms, 100 * (lower.rms / rms - 1), lower.area, third_area, lower.rms_sigma);
  EXPECT_NEAR(lower.area, third_area, 1e-9 * third_area);
  EXPECT_NEAR(lower.rms, rms, 0.02 * rms);
  EXPECT_NEAR(lower.volume, 0.0, 0.02 * volume);  // +V and −V, each interpolated
  EXPECT_NEAR(lower.max_abs, kBumpHeight, 0.02 * kBumpHeight);
  for (const char* name : {"upper_third", "middle_third"}) {
    const RegionIndex& r = Get(indices, name);
    EXPECT_LT(r.rms, 0.01 * rms) << name;
    EXPECT_NEAR(r.area, third_area, 1e-9 * third_area) << name;
  }
  EXPECT_NEAR(indices.thirds_y[0], -kHalfHeight, 1e-12);
  EXPECT_NEAR(indices.thirds_y[3], kHalfHeight, 1e-12);

  const RegionIndex& bump = Get(indices, "bump");
  EXPECT_NEAR(bump.volume, volume, 0.01 * volume);
  EXPECT_NEAR(bump.area, 25.0, 1e-9);
  EXPECT_NEAR(bump.mean_abs, bump.volume / 25.0, 1e-3 * volume / 25.0);  // d ≥ 0 there
  // The subject's left (x > 0) holds the bump, the right its mirror image.
  const RegionIndex &left = Get(indices, "left"), &right = Get(indices, "right");
  EXPECT_NEAR(left.volume, volume, 0.01 * volume);
  EXPECT_NEAR(right.volume, -volume, 0.01 * volume);
  EXPECT_NEAR(left.area + right.area, indices.whole.area, 1e-9 * indices.whole.area);
  EXPECT_NEAR(left.rms, right.rms, 0.01 * left.rms);
  EXPECT_NEAR(indices.whole.area, 3 * third_area, 1e-9 * third_area);
  EXPECT_NEAR(indices.whole.rms * indices.whole.rms * indices.whole.area, integral_d2,
              0.04 * integral_d2);
  ASSERT_EQ(indices.node_difference.size(), face.size());
  for (std::size_t i = 0; i < face.size(); i += 97) {
    const double x = face.xy[i].x + face.origin[0], y = face.xy[i].y + face.origin[1];
    EXPECT_NEAR(indices.node_difference[i], Bump(x, y) - Bump(-x, y), 0.05 * kBumpHeight);
  }
}

TEST(AsymmetryIndexTest, TheRefinedPlaneGivesTheSameLowerThird) {
  const Surface face = Face(0.1, 2);
  const SymmetryResult symmetry = EstimateSymmetry(face);
  const AsymmetryIndices indices = ComputeAsymmetryIndices(face, symmetry.refined.plane);
  const double rms = std::sqrt(2 * kPi * kBumpRadius * kBumpRadius * kBumpHeight * kBumpHeight / 5 /
                               (2 * kHalfWidth * 2 * kHalfHeight / 3));
  std::printf(
      "refined plane %.3g deg off x = 0, offset %.3g: lower third rms %.6f (analytic %.6f), middle "
      "%.3g; %s\n",
      symmetry.angle_deg, symmetry.refined.plane.offset, Get(indices, "lower_third").rms, rms,
      Get(indices, "middle_third").rms, symmetry.BriefReport().c_str());
  EXPECT_NEAR(Get(indices, "lower_third").rms, rms, 0.02 * rms);
  EXPECT_LT(Get(indices, "upper_third").rms, 0.01 * rms);
  EXPECT_LT(Get(indices, "middle_third").rms, 0.01 * rms);
}

// Noise: σ_n is recovered from the roughness, and each index's σ matches
// its spread over repeated scans of one face (same samples, fresh noise,
// the plane estimated afresh each time).
TEST(AsymmetryIndexTest, NoiseSigmaAndTheIndicesSpread) {
  const double noise = 0.02, h = 0.25;
  const int scans = 24;
  std::vector<std::vector<double>> values(4);
  std::vector<double> sigma(4, 0.0);
  for (int k = 0; k < scans; ++k) {
    const Surface face = Face(h, 3, noise, 100 + k);
    SymmetryOptions options;
    options.coarse_fraction = 1;
    const SymmetryResult symmetry = EstimateSymmetry(face, options);
    const AsymmetryIndices r = ComputeAsymmetryIndices(face, symmetry.refined.plane);
    if (k == 0) {
      std::printf("noise: estimated %.5f, true %.5f; plane sigma %.3g deg, %.3g deg, %.3g\n",
                  r.noise_sigma, noise, r.plane_sigma[0], r.plane_sigma[1], r.plane_sigma[2]);
      EXPECT_NEAR(r.noise_sigma, noise, 0.15 * noise);
    }
    const RegionIndex &lower = Get(r, "lower_third"), &left = Get(r, "left");
    const double v[4] = {lower.rms, lower.mean_abs, left.volume, r.whole.rms};
    const double s[4] = {lower.rms_sigma, lower.mean_abs_sigma, left.volume_sigma,
                         r.whole.rms_sigma};
    for (int j = 0; j < 4; ++j) values[j].push_back(v[j]), sigma[j] += s[j] / scans;
  }
  const char* names[4] = {"lower_third.rms", "lower_third.mean_abs", "left.volume", "face.rms"};
  for (int j = 0; j < 4; ++j) {
    double mean = 0, var = 0;
    for (double x : values[j]) mean += x;
    mean /= scans;
    for (double x : values[j]) var += (x - mean) * (x - mean);
    const double spread = std::sqrt(var / (scans - 1));
    std::printf("%-22s spread %.3g, sigma %.3g (ratio %.2f)\n", names[j], spread, sigma[j],
                sigma[j] / spread);
    // 24 scans: the spread's own sampling error is ~15%.
    EXPECT_GT(sigma[j], 0.5 * spread) << names[j];
    EXPECT_LT(sigma[j], 2.0 * spread) << names[j];
  }
}

// A cohort: faces of one population (a bump of random height and place on
// the lower left cheek, fresh samples); norms from 40 of them, z-scores of
// 40 others: mean 0 and SD 1 to sampling error (SE of the mean 0.22, of the
// SD about 0.11 for 40 faces).
TEST(AsymmetryIndexTest, CohortZScoresHaveMeanZeroAndSdOne) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> height(0.1, 0.6), shift(-0.5, 0.5);
  const auto random_face = [&](uint32_t seed) {
    const double h = height(rng), dx = shift(rng), dy = shift(rng);
    std::mt19937 jitter(seed);
    std::uniform_real_distribution<double> j(-0.1, 0.1);
    std::vector<std::array<double, 3>> points;
    for (int iy = 0; iy <= 50; ++iy) {
      for (int ix = 0; ix <= 40; ++ix) {
        double x = -8 + 0.4 * ix, y = -10 + 0.4 * iy;
        if (ix > 0 && ix < 40 && iy > 0 && iy < 50) x += j(jitter), y += j(jitter);
        const double r2 = ((x - 4 - dx) * (x - 4 - dx) + (y + 7 - dy) * (y + 7 - dy)) / 4;
        points.push_back({x, y, Base(x, y) + (r2 < 1 ? h * (1 - r2) * (1 - r2) : 0.0)});
      }
    }
    return ComputeAsymmetryIndices(MakeSurface(points, {}, "cohort face"), SymmetryPlane());
  };
  std::string table;
  for (uint32_t k = 0; k < 40; ++k) {
    const AsymmetryIndices r = random_face(k);
    if (k == 0) table = IndexTableHeader(r) + "\n";
    table += IndexTableRow("face " + std::to_string(k) + ".xyz", 2091, 0.0, r) + "\n";
  }
  const AsymmetryNorms norms = ParseAsymmetryNorms(table, "cohort.csv");
  ASSERT_EQ(norms.faces, 40);
  std::vector<double> z;
  for (uint32_t k = 100; k < 140; ++k) {
    for (const ZScore& s : ZScores(norms, IndexValues(random_face(k)))) {
      if (s.name == "lower_third_rms") z.push_back(s.z);
    }
  }
  ASSERT_EQ(z.size(), 40u);
  double mean = 0, var = 0;
  for (double v : z) mean += v;
  mean /= z.size();
  for (double v : z) var += (v - mean) * (v - mean);
  const double sd = std::sqrt(var / (z.size() - 1));
  std::printf("z of lower_third_rms over 40 new faces: mean %.3f, sd %.3f\n", mean, sd);
  // Both cohorts' means err: the SE of the difference is sqrt(1/40 + 1/40).
  EXPECT_LT(std::abs(mean), 3 * std::sqrt(2 / 40.0));
  EXPECT_GT(sd, 0.65);
  EXPECT_LT(sd, 1.35);

  // Repeatability: two scans of one face differ by little; the table's
  // errors are one line with file and line.
  const std::vector<IndexValue> diff =
      IndexDifferences(IndexValues(random_face(1)), IndexValues(random_face(1)));
  EXPECT_EQ(diff.size(), IndexValues(random_face(2)).size());
  EXPECT_THROW(ParseAsymmetryNorms("file,face_rms\na.xyz,1\n", "one.csv"), InputError);
  try {
    ParseAsymmetryNorms("file,face_rms\na.xyz,1\nb.xyz,x\n", "bad.csv");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3: column 'face_rms'"), std::string::npos)
        << e.what();
  }
  const AsymmetryNorms other = ParseAsymmetryNorms("file,cheek_rms\na,1\nb,2\n", "other.csv");
  EXPECT_THROW(ZScores(other, diff), InputError);
}

TEST(AsymmetryIndexTest, BadRegionsAreRefused) {
  const Surface face = Face(0.5, 4);
  const auto refuse = [&](FaceRegion region, const std::string& text) {
    AsymmetryIndexOptions options;
    options.regions.push_back(std::move(region));
    try {
      ComputeAsymmetryIndices(face, SymmetryPlane(), options);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  refuse({"two words", {{0, 0}, {1, 0}, {0, 1}}}, "letters, digits");
  refuse({"left", {{0, 0}, {1, 0}, {0, 1}}}, "used twice");
  refuse({"face", {{0, 0}, {1, 0}, {0, 1}}}, "used twice");
  refuse({"line", {{0, 0}, {1, 0}}}, "region 'line'");
  refuse({"bowtie", {{0, 0}, {1, 1}, {1, 0}, {0, 1}}}, "region 'bowtie'");
  // A region off the face: zero area, zeros everywhere.
  AsymmetryIndexOptions options;
  options.regions.push_back({"far", {{100, 100}, {101, 100}, {100, 101}}});
  const AsymmetryIndices r = ComputeAsymmetryIndices(face, SymmetryPlane(), options);
  EXPECT_EQ(Get(r, "far").area, 0.0);
  EXPECT_EQ(Get(r, "far").nodes, 0);
  // A face all on one side of the plane does not overlap its mirror.
  SymmetryPlane far_plane;
  far_plane.offset = 50;
  EXPECT_THROW(ComputeAsymmetryIndices(face, far_plane), InputError);
}

}  // namespace
}  // namespace surfreg
