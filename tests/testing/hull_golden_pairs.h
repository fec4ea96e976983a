#pragma once
// Small fixed comparisons whose every measure was recorded (bit for bit) from
// Measure as it was before the data domain (issue 20): with DomainKind::kHull
// the measures must still be exactly these (tests/measure_domain_test.cc).
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "measure/measures.h"
#include "measure/surface.h"

namespace surfreg::testing {

inline Surface GoldenCloud(std::size_t n, double x0, double x1, double y0, double y1, int shape,
                           uint64_t seed, bool weights) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1), uw(0.5, 2.0);
  std::vector<std::array<double, 3>> points;
  std::vector<double> weight;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = ux(rng), y = uy(rng);
    const double z =
        shape == 0 ? std::sin(x) * std::cos(y) + 0.1 * x : std::cos(0.7 * x) + 0.05 * y * y - 0.3;
    points.push_back({x, y, z});
    if (weights) weight.push_back(uw(rng));
  }
  return MakeSurface(points, weight, shape == 0 ? "golden A" : "golden B");
}

// A lattice with a few samples missing (a raster with nodata cells), and a
// second one offset by a fraction of a cell.
inline Surface GoldenGrid(int columns, int rows, double offset, int shape) {
  std::vector<std::array<double, 3>> points;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      if ((c * 7 + r * 3) % 23 == 0 && c > 0 && r > 0) continue;
      const double x = c + offset, y = r + 0.5 * offset;
      points.push_back({x, y, shape == 0 ? 0.2 * std::sin(0.4 * x) * y : 0.1 * x + 0.02 * y * y});
    }
  }
  return MakeSurface(points, {}, "golden grid");
}

struct GoldenCase {
  Surface a, b;
  MeasureOptions options;
};

inline std::vector<GoldenCase> GoldenCases() {
  std::vector<GoldenCase> cases;
  const Surface a = GoldenCloud(600, 0, 10, 0, 10, 0, 11, false);
  const Surface b = GoldenCloud(450, 1, 11, 0.5, 10.5, 1, 12, false);
  const Surface aw = GoldenCloud(600, 0, 10, 0, 10, 0, 11, true);
  MeasureOptions o;
  o.detect_change = true;
  o.level_of_detection = 0.2;
  o.keep_node_gaps = true;
  o.threads = 1;
  cases.push_back({a, b, o});
  o.threads = 2;
  cases.push_back({a, b, o});
  MeasureOptions u;
  u.volume = VolumeMode::kUnion;
  u.keep_node_gaps = true;
  cases.push_back({a, b, u});
  MeasureOptions w;
  w.weight = WeightMode::kPerPoint;
  w.detect_change = true;
  w.threads = 1;
  cases.push_back({aw, b, w});
  MeasureOptions m;
  m.weight = WeightMode::kMask;
  m.mask = {{{2, 2}, {8, 1.5}, {9, 7}, {5, 4}, {3, 9}}};
  m.threads = 1;
  cases.push_back({a, b, m});
  MeasureOptions g;
  g.detect_change = true;
  g.level_of_detection = 0.05;
  g.keep_node_gaps = true;
  g.threads = 1;
  cases.push_back({GoldenGrid(30, 20, 0.0, 0), GoldenGrid(30, 20, 0.37, 1), g});
  return cases;
}

// Every number a summary holds that does not depend on time; dz_a as the sum
// of its finite values and the count of NaNs.
inline std::vector<double> GoldenFingerprint(const MeasureSummary& s) {
  double dz_sum = 0, dz_nan = 0;
  for (double d : s.dz_a) std::isnan(d) ? ++dz_nan : dz_sum += d;
  return {s.rho_d,
          s.rho_d_axial,
          s.rho_s,
          s.overlap_area,
          s.hull_area_a,
          s.hull_area_b,
          s.weight_integral,
          s.mean_abs_dz,
          s.signed_volume,
          s.volume_above,
          s.volume_below,
          s.fill_detected,
          s.cut_detected,
          s.fill_area,
          s.cut_area,
          static_cast<double>(s.n_overlap_nodes),
          static_cast<double>(s.n_cells),
          static_cast<double>(s.walk_steps),
          dz_sum,
          dz_nan};
}

}  // namespace surfreg::testing
