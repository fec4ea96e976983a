// Two rasters on one grid measured from their heights alone
// (measure/raster_pair.h): every field equals Measure's on the rasters'
// samples, bit for bit against its one-grid path (the same doubles in the
// same chunks) and to rounding against the general path (triangulation,
// walks, overlay); on windows with holes in both directions, mirrored,
// south-up and turned lattices, on lattices offset by a fraction of a
// cell, with a level of detection; a closed form
// for a constant change; every case it must leave to Measure; the same
// bits on 1, 2 and 8 threads.
#include "measure/raster_pair.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "measure/measures.h"
#include "terrain/tiled_measure.h"

namespace surfreg {
namespace {

// A lattice: cell (C, R) centred at base + (C + ½) u + (R + ½) v.
struct Lattice {
  std::array<double, 2> base{500000.0, 4000000.0};
  std::array<double, 2> u{10.0, 0.0}, v{0.0, -10.0};
};

// Cells [c0, c0 + columns) x [r0, r0 + rows) of a lattice as a raster file
// holds them: its own geotransform, NaN where `hole` says.
struct TestRaster {
  int32_t columns = 0, rows = 0;
  std::array<double, 6> gt{};
  std::vector<double> z;
  std::string name;

  RasterHeights Heights() const {
    RasterHeights h;
    h.z = z.data();
    h.columns = columns, h.rows = rows;
    h.geotransform = gt;
    h.source = name;
    return h;
  }
  Surface Samples(const std::array<double, 3>& origin) const {
    return RasterBlockToSurface(gt, {0, 0, columns, rows}, z.data(), z.size(), origin, name);
  }
};

TestRaster Window(const Lattice& g, int c0, int r0, int columns, int rows,
                  const std::function<double(int, int)>& height,
                  const std::function<bool(int, int)>& hole = nullptr) {
  TestRaster t;
  t.columns = columns, t.rows = rows;
  t.gt = {g.base[0] + c0 * g.u[0] + r0 * g.v[0], g.u[0], g.v[0],
          g.base[1] + c0 * g.u[1] + r0 * g.v[1], g.u[1], g.v[1]};
  t.name = "window " + std::to_string(c0) + "," + std::to_string(r0);
  for (int r = r0; r < r0 + rows; ++r) {
    for (int c = c0; c < c0 + columns; ++c)
      t.z.push_back(hole && hole(c, r) ? std::nan("") : height(c, r));
  }
  return t;
}

double Rough(int c, int r) {  // deterministic bumpy heights
  uint64_t x = static_cast<uint64_t>(c + 1000) * 0x9e3779b97f4a7c15ULL ^
               static_cast<uint64_t>(r + 1000) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 31)) * 0x94d049bb133111ebULL;
  return 100.0 + 0.05 * c - 0.03 * r + static_cast<double>((x ^ (x >> 29)) % 1000) / 250.0;
}
double Changed(int c, int r) {
  return Rough(c, r) + 0.7 * std::sin(0.3 * c) * std::cos(0.2 * r) - 0.1;
}
bool HoleA(int c, int r) {
  return (c - 12) * (c - 12) + (r - 9) * (r - 9) < 10 || (c == 30 && r == 4);
}
bool HoleB(int c, int r) {
  return (c - 25) * (c - 25) + (r - 20) * (r - 20) < 6 || (c == 5 && r == 5);
}

std::array<double, 3> OriginOf(const TestRaster& a) {
  return RasterOrigin(a.gt, a.columns, a.rows);
}

void ExpectNear(double general, double compact, const char* what) {
  EXPECT_NEAR(compact, general, 1e-12 * std::max(1.0, std::fabs(general))) << what;
}

// The compact measure against Measure's one-grid path (bits) and its
// general path (rounding).
void ExpectSameAsMeasure(const TestRaster& a, const TestRaster& b, MeasureOptions options,
                         bool offset = false) {
  const std::array<double, 3> origin = OriginOf(a);
  MeasureSummary compact;
  ASSERT_TRUE(MeasureRasterPair(a.Heights(), b.Heights(), origin, options, &compact))
      << "not taken";
  const Surface sa = a.Samples(origin), sb = b.Samples(origin);
  const MeasureSummary grid = Measure(sa, sb, options);
  MeasureOptions general_options = options;
  general_options.grid_shortcut = false;
  const MeasureSummary general = Measure(sa, sb, general_options);
  for (const MeasureSummary* other : {&grid, &general}) {
    const bool bits = other == &grid && !offset;  // offset: the lattice fitted there, given here
    const auto same = [&](double expected, double actual, const char* what) {
      if (bits) {
        EXPECT_EQ(actual, expected) << what << " (one-grid path)";
      } else {
        ExpectNear(expected, actual, what);
      }
    };
    same(other->rho_d, compact.rho_d, "rho_d");
    same(other->rho_d_axial, compact.rho_d_axial, "rho_d_axial");
    same(other->rho_s, compact.rho_s, "rho_s");
    same(other->overlap_area, compact.overlap_area, "overlap_area");
    same(other->domain_area_a, compact.domain_area_a, "domain_area_a");
    same(other->domain_area_b, compact.domain_area_b, "domain_area_b");
    same(other->weight_integral, compact.weight_integral, "weight_integral");
    same(other->mean_abs_dz, compact.mean_abs_dz, "mean_abs_dz");
    same(other->signed_volume, compact.signed_volume, "signed_volume");
    same(other->volume_above, compact.volume_above, "volume_above");
    same(other->volume_below, compact.volume_below, "volume_below");
    same(other->fill_detected, compact.fill_detected, "fill_detected");
    same(other->cut_detected, compact.cut_detected, "cut_detected");
    same(other->fill_area, compact.fill_area, "fill_area");
    same(other->cut_area, compact.cut_area, "cut_area");
    same(other->level_of_detection, compact.level_of_detection, "level_of_detection");
    // The hulls' areas from the lattice's cell area, not fitted to the samples.
    ExpectNear(other->hull_area_a, compact.hull_area_a, "hull_area_a");
    ExpectNear(other->hull_area_b, compact.hull_area_b, "hull_area_b");
    ExpectNear(other->excluded_area_a, compact.excluded_area_a, "excluded_area_a");
    ExpectNear(other->excluded_area_b, compact.excluded_area_b, "excluded_area_b");
    EXPECT_EQ(compact.n_overlap_nodes, other->n_overlap_nodes);
    EXPECT_EQ(compact.n_cells, other->n_cells);
    EXPECT_EQ(compact.n_points_a, other->n_points_a);
    EXPECT_EQ(compact.n_points_b, other->n_points_b);
    EXPECT_EQ(compact.domain_kind, other->domain_kind);
    if (!options.keep_node_gaps) continue;
    ASSERT_EQ(compact.dz_a.size(), other->dz_a.size());
    ASSERT_EQ(compact.node_area_a.size(), other->node_area_a.size());
    for (std::size_t i = 0; i < compact.dz_a.size(); ++i) {
      ASSERT_EQ(std::isnan(compact.dz_a[i]), std::isnan(other->dz_a[i])) << i;
      if (std::isnan(compact.dz_a[i])) continue;
      if (bits) {
        ASSERT_EQ(compact.dz_a[i], other->dz_a[i]) << i;
        ASSERT_EQ(compact.node_area_a[i], other->node_area_a[i]) << i;
      } else {
        ASSERT_NEAR(compact.dz_a[i], other->dz_a[i], 1e-12) << i;
        ASSERT_NEAR(compact.node_area_a[i], other->node_area_a[i], 1e-9) << i;
      }
    }
    if (!offset) {
      EXPECT_TRUE(compact.dz_b.empty());  // every node of B in Ω is one of A's
      continue;
    }
    ASSERT_EQ(compact.dz_b.size(), other->dz_b.size());
    for (std::size_t j = 0; j < compact.dz_b.size(); ++j) {
      ASSERT_EQ(std::isnan(compact.dz_b[j]), std::isnan(other->dz_b[j])) << j;
      if (!std::isnan(compact.dz_b[j])) {
        ASSERT_NEAR(compact.dz_b[j], other->dz_b[j], 1e-12) << j;
      }
    }
  }
  EXPECT_GT(compact.rho_d, 0.0);
}

TEST(RasterPairTest, WindowsWithHolesEqualMeasureInBothDirections) {
  const Lattice g;
  const TestRaster a = Window(g, 0, 0, 40, 30, Rough, HoleA);
  const TestRaster b = Window(g, 3, -2, 45, 28, Changed, HoleB);
  MeasureOptions options;
  ExpectSameAsMeasure(a, b, options);
  ExpectSameAsMeasure(b, a, options);
  options.keep_node_gaps = true;
  ExpectSameAsMeasure(a, b, options);
  ExpectSameAsMeasure(b, a, options);
  options.detect_change = true;
  options.level_of_detection = 0.3;
  ExpectSameAsMeasure(a, b, options);
  options.level_of_detection = 0.0;
  ExpectSameAsMeasure(b, a, options);
}

TEST(RasterPairTest, MirroredSouthUpAndTurnedLatticesEqualMeasure) {
  MeasureOptions options;
  options.keep_node_gaps = true;
  options.detect_change = true;
  options.level_of_detection = 0.2;
  Lattice south_up;
  south_up.v = {0.0, 10.0};  // rows go north: the cells' triangles turn the other way
  Lattice mirrored;
  mirrored.u = {-10.0, 0.0};
  Lattice turned;  // cell vectors (8, 6) and (-6, 8): exact in doubles
  turned.u = {8.0, 6.0}, turned.v = {-6.0, 8.0};
  for (const Lattice& g : {south_up, mirrored, turned}) {
    ExpectSameAsMeasure(Window(g, 0, 0, 30, 25, Rough, HoleA),
                        Window(g, -4, 5, 33, 26, Changed, HoleB), options);
  }
}

Lattice OffsetBy(Lattice g, double columns,
                 double rows) {  // the lattice moved by a fraction of a cell
  g.base = {g.base[0] + columns * g.u[0] + rows * g.v[0],
            g.base[1] + columns * g.u[1] + rows * g.v[1]};
  return g;
}

TEST(RasterPairTest, OffsetLatticesWithHolesEqualMeasureInBothDirections) {
  MeasureOptions options;
  options.keep_node_gaps = true;
  Lattice turned;
  turned.u = {8.0, 6.0}, turned.v = {-6.0, 8.0};
  for (const Lattice& g : {Lattice(), turned}) {
    const TestRaster a = Window(g, 0, 0, 40, 30, Rough, HoleA);
    for (const auto& [fc, fr] :
         {std::pair<double, double>{0.37, -0.61}, {-0.25, 0.5}, {0.8, 0.1}}) {
      const TestRaster b = Window(OffsetBy(g, fc, fr), 3, -2, 45, 28, Changed, HoleB);
      options.detect_change = false;
      ExpectSameAsMeasure(a, b, options, /*offset=*/true);
      ExpectSameAsMeasure(b, a, options, /*offset=*/true);
      options.detect_change = true;
      options.level_of_detection = 0.3;
      ExpectSameAsMeasure(a, b, options, /*offset=*/true);
    }
  }
}

TEST(RasterPairTest, ConstantChangeIsItsHeightTimesTheCommonCells) {
  const Lattice g;
  const TestRaster a = Window(g, 0, 0, 20, 15, Rough);
  const TestRaster b = Window(g, 0, 0, 20, 15, [](int c, int r) { return Rough(c, r) + 0.25; });
  MeasureOptions options;
  options.keep_node_gaps = true;
  MeasureSummary s;
  ASSERT_TRUE(MeasureRasterPair(a.Heights(), b.Heights(), OriginOf(a), options, &s));
  const double area = 19 * 14 * 100.0;
  EXPECT_NEAR(s.overlap_area, area, 1e-9);
  EXPECT_NEAR(s.rho_d, 0.25 * area, 1e-9);
  EXPECT_NEAR(s.signed_volume, 0.25 * area, 1e-9);
  EXPECT_NEAR(s.volume_below, 0.0, 1e-12);
  EXPECT_NEAR(s.rho_d_axial, 0.25, 1e-12);
  EXPECT_EQ(s.n_overlap_nodes, 20 * 15);
  EXPECT_EQ(s.n_cells, 2 * 19 * 14);
  EXPECT_NEAR(s.hull_area_a, area, 1e-9);
  EXPECT_NEAR(s.domain_area_b, area, 1e-9);
  double node_area = 0.0;
  for (const double x : s.node_area_a) node_area += x;
  EXPECT_NEAR(node_area, area, 1e-9);                    // every triangle's corners are all in Ω
  EXPECT_NEAR(s.node_area_a[5 * 20 + 7], 100.0, 1e-12);  // an inner node: one cell's area
  for (const double dz : s.dz_a) EXPECT_NEAR(dz, 0.25, 1e-12);
  // Without node areas: dz only.
  MeasureSummary lean;
  ASSERT_TRUE(MeasureRasterPair(a.Heights(), b.Heights(), OriginOf(a), options, &lean, false));
  EXPECT_TRUE(lean.node_area_a.empty());
  EXPECT_EQ(lean.dz_a, s.dz_a);
  EXPECT_EQ(lean.rho_d, s.rho_d);
}

TEST(RasterPairTest, OtherPairsAreLeftToMeasureWithTheSummaryUntouched) {
  const Lattice g;
  const TestRaster a = Window(g, 0, 0, 20, 15, Rough, HoleA);
  const TestRaster b = Window(g, 2, 1, 20, 15, Changed);
  const auto refused = [&](const TestRaster& x, const TestRaster& y,
                           const MeasureOptions& options) {
    MeasureSummary s;
    s.rho_d = -7.0;  // a sentinel: a refusal leaves it
    const bool taken = MeasureRasterPair(x.Heights(), y.Heights(), OriginOf(x), options, &s);
    return !taken && s.rho_d == -7.0;
  };
  MeasureOptions options;
  ASSERT_FALSE(refused(a, b, options));  // the pair itself is taken
  Lattice finer = g;
  finer.u = {5.0, 0.0};
  EXPECT_TRUE(refused(a, Window(finer, 0, 0, 40, 15, Changed), options));  // another spacing
  TestRaster half = b;
  half.gt[0] += 5.0;  // half a cell
  EXPECT_TRUE(refused(a, half, options));
  // Offsets that put nodes on the other's lattice lines: half a cell along
  // one axis only, and along the cells' diagonal.
  EXPECT_TRUE(refused(a, Window(OffsetBy(g, 0.0, 0.5), 2, 1, 20, 15, Changed), options));
  EXPECT_TRUE(refused(a, Window(OffsetBy(g, 0.3, 0.3), 2, 1, 20, 15, Changed), options));
  ASSERT_FALSE(refused(a, Window(OffsetBy(g, 0.3, 0.4), 2, 1, 20, 15, Changed), options));
  TestRaster hair = b;
  hair.gt[0] += 1e-7;  // on the lattice to 1e-6 of a cell, but no position equal
  EXPECT_TRUE(refused(a, hair, options));
  MeasureOptions other = options;
  other.weight = WeightMode::kMask;
  other.mask = {MaskRing{{500000, 3999800}, {500200, 3999800}, {500200, 4000000}}};
  EXPECT_TRUE(refused(a, b, other));
  other = options;
  other.domain.kind = DomainKind::kHull;
  EXPECT_TRUE(refused(a, b, other));
  other = options;
  other.volume = VolumeMode::kUnion;
  EXPECT_TRUE(refused(a, b, other));
  other = options;
  other.grid_shortcut = false;
  EXPECT_TRUE(refused(a, b, other));
  // No complete cell (a checkerboard), no valid cell, no overlap, a height
  // beyond kMaxCoordinate: Measure's errors.
  EXPECT_TRUE(refused(
      a, Window(g, 0, 0, 10, 10, Changed, [](int c, int r) { return (c + r) % 2 == 0; }), options));
  EXPECT_TRUE(refused(a, Window(g, 0, 0, 10, 10, Changed, [](int, int) { return true; }), options));
  EXPECT_TRUE(refused(a, Window(g, 40, 0, 10, 10, Changed), options));
  TestRaster huge = b;
  huge.z[7] = 1e61;
  EXPECT_TRUE(refused(a, huge, options));
  // A tile's empty overlap is zero, as Measure gives it.
  other = options;
  other.allow_empty_overlap = true;
  MeasureSummary tile;
  ASSERT_TRUE(MeasureRasterPair(a.Heights(), Window(g, 40, 0, 10, 10, Changed).Heights(),
                                OriginOf(a), other, &tile));
  EXPECT_EQ(tile.rho_d, 0.0);
  EXPECT_EQ(tile.n_cells, 0);
}

TEST(RasterPairTest, OneTwoAndEightThreadsGiveTheSameBits) {
  const Lattice g;
  // Enough rows for several chunks.
  const TestRaster a = Window(g, 0, 0, 60, 300, Rough, HoleA);
  const TestRaster b = Window(g, 3, -2, 65, 290, Changed, HoleB);
  const TestRaster offset = Window(OffsetBy(g, 0.37, -0.61), 3, -2, 65, 290, Changed, HoleB);
  MeasureOptions options;
  options.keep_node_gaps = true;
  options.detect_change = true;
  options.level_of_detection = 0.1;
  for (const TestRaster* other : {&b, &offset}) {
    std::vector<MeasureSummary> runs;
    for (const int threads : {1, 2, 8}) {
      options.threads = threads;
      runs.emplace_back();
      ASSERT_TRUE(
          MeasureRasterPair(a.Heights(), other->Heights(), OriginOf(a), options, &runs.back()));
    }
    for (const MeasureSummary& s : runs) {
      ASSERT_EQ(s.dz_b.size(), runs[0].dz_b.size());
      if (!s.dz_b.empty()) {  // on one grid it is empty (every node of B in Ω is A's)
        EXPECT_EQ(0, std::memcmp(s.dz_b.data(), runs[0].dz_b.data(), s.dz_b.size() * sizeof(double)));
      }
      EXPECT_EQ(s.rho_d, runs[0].rho_d);
      EXPECT_EQ(s.rho_d_axial, runs[0].rho_d_axial);
      EXPECT_EQ(s.fill_detected, runs[0].fill_detected);
      EXPECT_EQ(s.domain_area_b, runs[0].domain_area_b);
      ASSERT_EQ(s.dz_a.size(), runs[0].dz_a.size());
      EXPECT_EQ(0, std::memcmp(s.dz_a.data(), runs[0].dz_a.data(), s.dz_a.size() * sizeof(double)));
      EXPECT_EQ(s.node_area_a, runs[0].node_area_a);
    }
  }
}

}  // namespace
}  // namespace surfreg
