#include "registration/rigid_consensus.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "measure/tasks.h"

namespace surfreg {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

constexpr int kTilesPerSide = 8;
constexpr int kTilesPerTrial = 4;
constexpr int kTrials = 300;
constexpr int kMinTileSamples = 8;
constexpr double kInlierSigmas = 3.0;
constexpr std::size_t kScoredPerTile = 64;
constexpr double kSamplesPerIndependent = 4.0;

// The upper median; reorders v.
double Median(std::vector<double>& v) {
  if (v.empty()) return 0;
  const std::size_t half = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + half, v.end());
  return v[half];
}

struct Normal {
  Matrix6 ata = Matrix6::Zero();
  Vector6 atb = Vector6::Zero();
  int64_t samples = 0;
  void Add(const Vector6& j, double b, double w) {
    ata.noalias() += w * j * j.transpose();
    atb.noalias() += w * b * j;
    ++samples;
  }
};

// β of the normal equations, with a ridge of 1e-9 of each diagonal so that
// a direction the tiles do not see (a flat place's horizontal shift) stays 0.
Vector6 Solve(const Normal& normal) {
  Matrix6 a = normal.ata;
  for (int k = 0; k < 6; ++k) a(k, k) += 1e-9 * a(k, k) + 1e-300;
  return a.ldlt().solve(normal.atb);
}

}  // namespace

ConsensusFit RigidConsensus(const Surface& reference, const SampleAdjacency& adjacency,
                            const std::vector<double>& dz, const std::vector<uint8_t>& eligible,
                            const Execution& execution) {
  const std::size_t n = dz.size();
  ConsensusFit out;
  out.residual.assign(n, std::nan(""));
  out.flag.assign(n, kOutsideOverlap);
  std::vector<int32_t> usable;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isfinite(dz[i]) && (eligible.empty() || eligible[i] != 0)) usable.push_back(static_cast<int32_t>(i));
  }
  if (usable.size() < 6) {
    for (int32_t i : usable) out.residual[i] = dz[i], out.flag[i] = kStableSample;
    out.inlier_share = 1;
    return out;
  }
  // The noise from neighbour differences: a smooth misfit or a region of
  // change hardly shows in them, unlike in the gaps' own spread.
  std::vector<double> differences;
  const std::size_t edge_stride = std::max<std::size_t>(1, adjacency.neighbour.size() / 400000);
  for (int32_t i : usable) {
    for (int32_t k = adjacency.offset[i]; k < adjacency.offset[i + 1]; k += static_cast<int32_t>(edge_stride)) {
      const int32_t j = adjacency.neighbour[k];
      if (j > i && std::isfinite(dz[j]) && (eligible.empty() || eligible[j] != 0)) {
        differences.push_back(std::abs(dz[i] - dz[j]));
      }
    }
  }
  out.noise = 1.4826 * Median(differences) / std::sqrt(2.0);
  std::vector<double> scale(n, 0.0);
  for (int32_t i : usable) {
    const double g = adjacency.curvature_gap[i];
    scale[i] = std::sqrt(out.noise * out.noise + g * g);
  }

  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double lo_x = HUGE_VAL, hi_x = -HUGE_VAL, lo_y = HUGE_VAL, hi_y = -HUGE_VAL;
  for (int32_t i : usable) {
    centre += Eigen::Vector3d(reference.xy[i].x, reference.xy[i].y, reference.z[i]);
    lo_x = std::min(lo_x, reference.xy[i].x), hi_x = std::max(hi_x, reference.xy[i].x);
    lo_y = std::min(lo_y, reference.xy[i].y), hi_y = std::max(hi_y, reference.xy[i].y);
  }
  centre /= static_cast<double>(usable.size());
  auto jacobian = [&](int32_t i) {
    const Eigen::Vector3d normal(-adjacency.gradient[i][0], -adjacency.gradient[i][1], 1.0);
    const Eigen::Vector3d lever = Eigen::Vector3d(reference.xy[i].x, reference.xy[i].y, reference.z[i]) - centre;
    Vector6 j;
    j << lever.cross(normal), normal;
    return j;
  };
  // Each tile's normal equations once (a trial sums four), its samples (at
  // most kScoredPerTile, evenly) and the scale of its median.
  std::vector<Normal> tiles(kTilesPerSide * kTilesPerSide);
  std::vector<std::vector<int32_t>> members(tiles.size());
  const double wx = std::max(hi_x - lo_x, 1e-300), wy = std::max(hi_y - lo_y, 1e-300);
  for (int32_t i : usable) {
    const int tx = std::min(kTilesPerSide - 1, static_cast<int>((reference.xy[i].x - lo_x) / wx * kTilesPerSide));
    const int ty = std::min(kTilesPerSide - 1, static_cast<int>((reference.xy[i].y - lo_y) / wy * kTilesPerSide));
    members[ty * kTilesPerSide + tx].push_back(i);
  }
  // Each tile's sums in its samples' order, tiles side by side.
  const int64_t num_tiles = static_cast<int64_t>(tiles.size());
  ForEachChunk(execution, num_tiles, static_cast<int>(num_tiles), [&](int t, int64_t, int64_t) {
    for (int32_t i : members[t]) tiles[t].Add(jacobian(i), dz[i], scale[i] > 0 ? 1.0 / (scale[i] * scale[i]) : 1.0);
  });
  std::vector<int> full;
  struct Scored {
    std::vector<int32_t> samples;
    std::vector<Vector6> jacobians;
    double weight = 0;        // the tile's samples, all of them
    double median_scale = 0;  // of its median residual
  };
  for (int t = 0; t < static_cast<int>(tiles.size()); ++t) {
    if (tiles[t].samples >= kMinTileSamples) full.push_back(t);
  }
  std::vector<Scored> scored(full.size());
  ForEachChunk(execution, static_cast<int64_t>(full.size()), static_cast<int>(std::max<std::size_t>(1, full.size())),
               [&](int f, int64_t first, int64_t last) {
    if (first == last) return;
    const int t = full[f];
    Scored& tile = scored[f];
    const std::size_t step = std::max<std::size_t>(1, members[t].size() / kScoredPerTile);
    for (std::size_t k = 0; k < members[t].size(); k += step) {
      tile.samples.push_back(members[t][k]);
      tile.jacobians.push_back(jacobian(members[t][k]));
    }
    tile.weight = static_cast<double>(members[t].size());
    // Neighbouring gaps share curvature and noise patches: a median of n
    // counts as one of n / kSamplesPerIndependent independent samples
    // (1.253 σ / √n for those).
    std::vector<double> tile_differences;
    for (int32_t i : members[t]) {
      for (int32_t k = adjacency.offset[i]; k < adjacency.offset[i + 1]; ++k) {
        const int32_t j = adjacency.neighbour[k];
        if (j > i && std::isfinite(dz[j]) && (eligible.empty() || eligible[j] != 0)) {
          tile_differences.push_back(std::abs(dz[i] - dz[j]));
        }
      }
    }
    const double sigma = 1.4826 * Median(tile_differences) / std::sqrt(2.0);
    tile.median_scale = 1.253 * sigma * std::sqrt(kSamplesPerIndependent / tile.weight);
  });
  // MSAC over tiles: each tile's median residual in its own scale, squares
  // truncated at kInlierSigmas², weighted by the tile's samples. Per tile,
  // not per sample: a hypothesis that fits a flat changed part (a lake)
  // leaves every sample of rough stable terrain within its own large scale,
  // but shifts the tiles' medians there far beyond theirs.
  // `residuals` is the caller's buffer (one per chunk of trials).
  auto tile_z = [&](const Scored& tile, const Vector6& beta, std::vector<double>& residuals) {
    residuals.clear();
    for (std::size_t k = 0; k < tile.samples.size(); ++k) {
      residuals.push_back(dz[tile.samples[k]] - tile.jacobians[k].dot(beta));
    }
    const double m = Median(residuals);
    return tile.median_scale > 0 ? m / tile.median_scale : (m == 0 ? 0.0 : HUGE_VAL);
  };
  auto score = [&](const Vector6& beta, std::vector<double>& residuals) {
    double sum = 0;
    const double cap = kInlierSigmas * kInlierSigmas;
    for (const Scored& tile : scored) {
      const double z = tile_z(tile, beta, residuals);
      sum += tile.weight * std::min(z * z, cap);
    }
    return sum;
  };

  // The trials' draws in turn (one random stream), their scores side by
  // side, the best the first of the lowest: as trials run one by one.
  const int pick = std::min<int>(kTilesPerTrial, static_cast<int>(full.size()));
  const int trials = pick > 0 ? kTrials : 0;
  std::vector<Vector6> hypothesis(trials + 1, Vector6::Zero());  // [0]: no correction
  std::mt19937_64 random(0x57AB1EULL);
  std::vector<int> draw = full;
  for (int trial = 0; trial < trials; ++trial) {
    Normal sum;
    for (int k = 0; k < pick; ++k) {  // a partial Fisher–Yates draw of distinct tiles
      const std::size_t j = k + random() % (draw.size() - k);
      std::swap(draw[k], draw[j]);
      sum.ata += tiles[draw[k]].ata;
      sum.atb += tiles[draw[k]].atb;
    }
    hypothesis[trial + 1] = Solve(sum);
  }
  std::vector<double> trial_score(hypothesis.size());
  ForEachChunk(execution, static_cast<int64_t>(hypothesis.size()), ChunksFor(static_cast<int64_t>(hypothesis.size()), 8),
               [&](int, int64_t first, int64_t last) {
                 std::vector<double> residuals;
                 for (int64_t k = first; k < last; ++k) trial_score[k] = score(hypothesis[k], residuals);
               });
  Vector6 best = hypothesis[0];
  double best_score = trial_score[0];
  for (std::size_t k = 1; k < hypothesis.size(); ++k) {
    if (trial_score[k] < best_score) best_score = trial_score[k], best = hypothesis[k];
  }
  // Refined on the inliers: least squares over the samples of the tiles
  // within kInlierSigmas, each within kInlierSigmas of its own scale.
  std::vector<uint8_t> in_tile(n, 0);
  std::vector<double> residuals;
  auto mark_tiles = [&](const Vector6& beta) {
    std::fill(in_tile.begin(), in_tile.end(), 0);
    for (std::size_t t = 0; t < scored.size(); ++t) {
      if (std::abs(tile_z(scored[t], beta, residuals)) > kInlierSigmas) continue;
      for (int32_t i : members[full[t]]) in_tile[i] = 1;
    }
  };
  for (int pass = 0; pass < 3; ++pass) {
    mark_tiles(best);
    Normal inliers;
    for (int32_t i : usable) {
      if (!in_tile[i]) continue;
      const Vector6 j = jacobian(i);
      const double r = dz[i] - j.dot(best);
      if (std::abs(r) <= kInlierSigmas * scale[i]) {
        inliers.Add(j, dz[i], scale[i] > 0 ? 1.0 / (scale[i] * scale[i]) : 1.0);
      }
    }
    if (inliers.samples < 6) break;
    best = Solve(inliers);
  }
  mark_tiles(best);
  int64_t inlying = 0;
  for (int32_t i : usable) {
    out.residual[i] = dz[i] - jacobian(i).dot(best);
    const bool in = in_tile[i] && std::abs(out.residual[i]) <= kInlierSigmas * scale[i];
    out.flag[i] = in ? kStableSample : kChangedSample;
    inlying += in;
  }
  out.inlier_share = static_cast<double>(inlying) / static_cast<double>(usable.size());
  return out;
}

}  // namespace surfreg
