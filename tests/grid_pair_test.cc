// Two rasters on one grid, on one lattice offset by a fraction of a cell,
// or one moved anywhere, measured by their cells (measure/grid_pair.h): every field of the
// summary equals the general path's (triangulation, walks, overlay) to
// rounding, on windows with holes, after a mirror or a rotation of the
// lattice, with masks and a level of detection; closed forms for a
// constant change; the cases it must leave to the general path; the same
// bits on one and two threads.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "measure/convex_hull.h"
#include "measure/grid_cells.h"
#include "measure/grid_pair.h"
#include "measure/input_error.h"
#include "measure/measures.h"

namespace surfreg {
namespace {

// A lattice: cell (c, r) at origin + c u + r v (input coordinates).
struct Lattice {
  std::array<double, 2> origin{500000.0, 4000000.0};
  std::array<double, 2> u{10.0, 0.0}, v{0.0, -10.0};
};

double Rough(int c, int r) {  // deterministic bumpy heights
  uint64_t x = static_cast<uint64_t>(c + 1000) * 0x9e3779b97f4a7c15ULL ^
               static_cast<uint64_t>(r + 1000) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 31)) * 0x94d049bb133111ebULL;
  return 100.0 + 0.05 * c - 0.03 * r + static_cast<double>((x ^ (x >> 29)) % 1000) / 250.0;
}

// Cells [c0, c0 + columns) x [r0, r0 + rows) of the lattice, heights
// height(c, r), without the cells `hole` says; raster_cell is the window's
// own index (c - c0, r - r0), as a reader of that window gives it.
Surface Window(const Lattice& g, int c0, int r0, int columns, int rows,
               const std::function<double(int, int)>& height,
               const std::function<bool(int, int)>& hole = nullptr) {
  std::vector<std::array<double, 3>> points;
  std::vector<RasterCell> cells;
  for (int r = r0; r < r0 + rows; ++r) {
    for (int c = c0; c < c0 + columns; ++c) {
      if (hole && hole(c, r)) continue;
      points.push_back({g.origin[0] + c * g.u[0] + r * g.v[0], g.origin[1] + c * g.u[1] + r * g.v[1],
                        height(c, r)});
      cells.push_back({c - c0, r - r0});
    }
  }
  Surface s = MakeSurface(points, {}, "window", 1.0);
  s.raster_cell = cells;
  return s;
}

MeasureOptions General(MeasureOptions options) {
  options.grid_shortcut = false;
  return options;
}

void ExpectNear(double general, double grid, const char* what) {
  EXPECT_NEAR(grid, general, 1e-12 * std::max(1.0, std::fabs(general))) << what;
}

enum class Path { kOneGrid, kOffset, kMoved };

// Every field of the two summaries, to rounding.
void ExpectSameMeasure(const Surface& a, const Surface& b, MeasureOptions options, Path path = Path::kOneGrid) {
  GridPairResult direct;
  if (path == Path::kOffset) {
    ASSERT_TRUE(MeasureOnOffsetGrids(a, b, options, &direct)) << "not taken as offset grids";
  } else if (path == Path::kMoved) {
    ASSERT_FALSE(MeasureOnOffsetGrids(a, b, options, &direct));
    ASSERT_TRUE(MeasureOnMovedGrid(a, b, options, &direct)) << "not taken as a moved grid";
  } else {
    ASSERT_TRUE(MeasureOnSameGrid(a, b, options, &direct)) << "not taken as one grid";
  }
  const MeasureSummary grid = Measure(a, b, options);
  const MeasureSummary general = Measure(a, b, General(options));
  ExpectNear(general.rho_d, grid.rho_d, "rho_d");
  ExpectNear(general.rho_d_axial, grid.rho_d_axial, "rho_d_axial");
  ExpectNear(general.overlap_area, grid.overlap_area, "overlap_area");
  ExpectNear(general.hull_area_a, grid.hull_area_a, "hull_area_a");
  ExpectNear(general.hull_area_b, grid.hull_area_b, "hull_area_b");
  ExpectNear(general.domain_area_a, grid.domain_area_a, "domain_area_a");
  ExpectNear(general.domain_area_b, grid.domain_area_b, "domain_area_b");
  ExpectNear(general.excluded_area_a, grid.excluded_area_a, "excluded_area_a");
  ExpectNear(general.excluded_area_b, grid.excluded_area_b, "excluded_area_b");
  ExpectNear(general.weight_integral, grid.weight_integral, "weight_integral");
  ExpectNear(general.signed_volume, grid.signed_volume, "signed_volume");
  ExpectNear(general.volume_above, grid.volume_above, "volume_above");
  ExpectNear(general.volume_below, grid.volume_below, "volume_below");
  ExpectNear(general.fill_detected, grid.fill_detected, "fill_detected");
  ExpectNear(general.cut_detected, grid.cut_detected, "cut_detected");
  ExpectNear(general.fill_area, grid.fill_area, "fill_area");
  ExpectNear(general.cut_area, grid.cut_area, "cut_area");
  EXPECT_EQ(grid.n_overlap_nodes, general.n_overlap_nodes);
  EXPECT_EQ(grid.n_cells, general.n_cells);
  EXPECT_EQ(grid.n_points_a, general.n_points_a);
  EXPECT_EQ(grid.n_duplicates_b, general.n_duplicates_b);
  EXPECT_GT(grid.rho_d, 0.0);
  if (!options.keep_node_gaps) return;
  ASSERT_EQ(grid.dz_a.size(), general.dz_a.size());
  ASSERT_EQ(grid.node_area_a.size(), general.node_area_a.size());
  ASSERT_EQ(grid.dz_b.size(), general.dz_b.size());
  for (std::size_t i = 0; i < grid.dz_a.size(); ++i) {
    ASSERT_EQ(std::isnan(grid.dz_a[i]), std::isnan(general.dz_a[i])) << i;
    if (!std::isnan(grid.dz_a[i])) {
      ASSERT_NEAR(grid.dz_a[i], general.dz_a[i], 1e-12) << i;
    }
    ASSERT_NEAR(grid.node_area_a[i], general.node_area_a[i], 1e-9) << i;
  }
  for (std::size_t j = 0; j < grid.dz_b.size(); ++j) {
    ASSERT_EQ(std::isnan(grid.dz_b[j]), std::isnan(general.dz_b[j])) << j;
  }
}

// A round hole and a one-cell hole in A; another hole in B, whose window is
// offset and of another size.
bool HoleA(int c, int r) { return (c - 12) * (c - 12) + (r - 9) * (r - 9) < 10 || (c == 30 && r == 4); }
bool HoleB(int c, int r) { return (c - 25) * (c - 25) + (r - 20) * (r - 20) < 6; }
double Changed(int c, int r) { return Rough(c, r) + 0.7 * std::sin(0.3 * c) * std::cos(0.2 * r) - 0.1; }
Surface HoledA() { return Window(Lattice(), 0, 0, 40, 30, Rough, HoleA); }
Surface HoledB() { return Window(Lattice(), 3, -2, 45, 28, Changed, HoleB); }

TEST(GridPairTest, WindowsOfOneLatticeWithHolesEqualTheGeneralPath) {
  const Surface a = HoledA(), b = HoledB();
  MeasureOptions options;
  options.keep_node_gaps = true;
  ExpectSameMeasure(a, b, options);
}

TEST(GridPairTest, LevelOfDetectionAndMasksEqualTheGeneralPath) {
  const Surface a = HoledA(), b = HoledB();
  MeasureOptions options;
  options.detect_change = true;
  options.level_of_detection = 0.3;
  options.keep_node_gaps = true;
  ExpectSameMeasure(a, b, options);
  // A triangle across the holes, in input coordinates (corners off the nodes).
  options.weight = WeightMode::kMask;
  options.mask = {{{500033.3, 3999987.1}, {500301.7, 3999903.3}, {500150.2, 3999731.9}}};
  ExpectSameMeasure(a, b, options);
  options.mask_mode = MaskMode::kExclude;
  ExpectSameMeasure(a, b, options);
}

TEST(GridPairTest, MirroredAndTurnedLatticesEqualTheGeneralPath) {
  Lattice mirrored;  // rows going up (clockwise cells)
  mirrored.v = {0.0, 10.0};
  MeasureOptions options;
  options.keep_node_gaps = true;
  ExpectSameMeasure(Window(mirrored, 0, 0, 30, 25, Rough, HoleA), Window(mirrored, 2, 1, 30, 25, Changed),
                    options);
  Lattice turned;  // a lattice at 30 degrees, cells of 2 by 3 m, small coordinates
  turned.origin = {10.0, 20.0};
  turned.u = {2.0 * std::cos(0.5236), 2.0 * std::sin(0.5236)};
  turned.v = {3.0 * std::sin(0.5236), -3.0 * std::cos(0.5236)};
  const Surface a = Window(turned, 0, 0, 30, 25, Rough, HoleA);
  const Surface b = Window(turned, 0, 0, 30, 25, Changed, HoleB);
  ExpectSameMeasure(a, b, options);
}

TEST(GridPairTest, ConstantChangeIsItsHeightTimesTheCommonCells) {
  const Lattice g;  // 10 m cells
  const Surface a = Window(g, 0, 0, 21, 11, Rough);
  const Surface b = Window(g, 5, 0, 21, 11, [](int c, int r) { return Rough(c, r) + 0.25; });
  const MeasureSummary m = Measure(a, b);
  const double area = 15 * 10 * 100.0;  // common cells: columns 5..20, rows 0..10
  EXPECT_NEAR(m.overlap_area, area, 1e-9);
  EXPECT_NEAR(m.rho_d, 0.25 * area, 1e-9);
  EXPECT_NEAR(m.signed_volume, 0.25 * area, 1e-9);
  EXPECT_NEAR(m.volume_below, 0.0, 1e-9);
  EXPECT_NEAR(m.rho_d_axial, 0.25, 1e-12);
  EXPECT_EQ(m.n_overlap_nodes, 16 * 11);
  EXPECT_EQ(m.n_cells, 2 * 15 * 10);
  EXPECT_NEAR(m.hull_area_a, 20 * 10 * 100.0, 1e-9);
  EXPECT_NEAR(m.domain_area_b, 20 * 10 * 100.0, 1e-9);
}

TEST(GridPairTest, OtherGridsAreLeftToTheGeneralPath) {
  const Lattice g;
  const Surface a = Window(g, 0, 0, 20, 15, Rough);
  GridPairResult out;
  Lattice offset = g;  // a fraction of a cell off
  offset.origin = {g.origin[0] + 3.7, g.origin[1] - 6.1};
  EXPECT_FALSE(MeasureOnSameGrid(a, Window(offset, 0, 0, 20, 15, Changed), MeasureOptions(), &out));
  Lattice finer = g;
  finer.u = {5.0, 0.0};
  EXPECT_FALSE(MeasureOnSameGrid(a, Window(finer, 0, 0, 20, 15, Changed), MeasureOptions(), &out));
  // One shared sample an ulp off: not the same node.
  Surface b = Window(g, 0, 0, 20, 15, Changed);
  b.xy[17].x = std::nextafter(b.xy[17].x, 1e9);
  EXPECT_FALSE(MeasureOnSameGrid(a, b, MeasureOptions(), &out));
  // Mirrored index (B's rows counted the other way): other diagonals.
  Surface flipped = Window(g, 0, 0, 20, 15, Changed);
  for (RasterCell& cell : flipped.raster_cell) cell.row = 14 - cell.row;
  EXPECT_FALSE(MeasureOnSameGrid(a, flipped, MeasureOptions(), &out));
  // A far-away sample: a box of cells too sparse for a dense index.
  Surface sparse = Window(g, 0, 0, 20, 15, Changed);
  sparse.raster_cell.push_back({2000000, 0});
  sparse.xy.push_back({sparse.xy[0].x + 2e7, sparse.xy[0].y});
  sparse.z.push_back(sparse.z[0]);
  EXPECT_FALSE(MeasureOnSameGrid(a, sparse, MeasureOptions(), &out));
  Surface scattered = Window(g, 0, 0, 20, 15, Changed);
  scattered.raster_cell.clear();
  EXPECT_FALSE(MeasureOnSameGrid(a, scattered, MeasureOptions(), &out));
  MeasureOptions hull;
  hull.domain.kind = DomainKind::kHull;
  EXPECT_FALSE(MeasureOnSameGrid(a, Window(g, 0, 0, 20, 15, Changed), hull, &out));
  MeasureOptions union_mode;
  union_mode.volume = VolumeMode::kUnion;
  EXPECT_FALSE(MeasureOnSameGrid(a, Window(g, 0, 0, 20, 15, Changed), union_mode, &out));
  // The general path still measures them.
  EXPECT_GT(Measure(a, Window(offset, 0, 0, 20, 15, Changed)).rho_d, 0.0);
}

Lattice OffsetBy(Lattice g, double columns, double rows) {  // the lattice moved by a fraction of a cell
  g.origin = {g.origin[0] + columns * g.u[0] + rows * g.v[0], g.origin[1] + columns * g.u[1] + rows * g.v[1]};
  return g;
}

TEST(GridPairTest, OffsetLatticesWithHolesEqualTheGeneralPath) {
  const Lattice g;
  const Lattice moved = OffsetBy(g, 0.37, -0.61);
  const Surface a = HoledA();
  const Surface b = Window(moved, 3, -2, 45, 28, Changed, HoleB);
  MeasureOptions options;
  options.keep_node_gaps = true;
  ExpectSameMeasure(a, b, options, Path::kOffset);
  options.detect_change = true;
  options.level_of_detection = 0.3;
  ExpectSameMeasure(a, b, options, Path::kOffset);
  ExpectSameMeasure(b, a, options, Path::kOffset);  // and the other way round
  Lattice turned;  // a turned lattice of 2 by 3 m cells, rows going up
  turned.origin = {10.0, 20.0};
  turned.u = {2.0 * std::cos(0.5236), 2.0 * std::sin(0.5236)};
  turned.v = {-3.0 * std::sin(0.5236), 3.0 * std::cos(0.5236)};
  ExpectSameMeasure(Window(turned, 0, 0, 30, 25, Rough, HoleA),
                    Window(OffsetBy(turned, 0.8, 0.25), 0, 0, 30, 25, Changed, HoleB), options, Path::kOffset);
}

TEST(GridPairTest, OffsetsOnALatticeLineAreLeftToTheGeneralPath) {
  const Lattice g;
  const Surface a = HoledA();
  GridPairResult out;
  // Nodes on the other's rows, on its columns, or on its diagonals.
  for (const auto& [dc, dr] : std::vector<std::pair<double, double>>{{0.5, 0.0}, {0.0, 0.3}, {0.4, 0.4}}) {
    const Surface b = Window(OffsetBy(g, dc, dr), 0, 0, 40, 30, Changed);
    EXPECT_FALSE(MeasureOnOffsetGrids(a, b, MeasureOptions(), &out)) << dc << " " << dr;
    EXPECT_GT(Measure(a, b).rho_d, 0.0);
  }
  const Surface b = Window(OffsetBy(g, 0.37, -0.61), 0, 0, 40, 30, Changed);
  MeasureOptions mask;  // masks and per-point weights: the general path
  mask.weight = WeightMode::kMask;
  mask.mask = {{{500033.3, 3999987.1}, {500301.7, 3999903.3}, {500150.2, 3999731.9}}};
  EXPECT_FALSE(MeasureOnOffsetGrids(a, b, mask, &out));
  Lattice finer = g;
  finer.u = {5.0, 0.0};
  EXPECT_FALSE(MeasureOnOffsetGrids(a, Window(finer, 0, 0, 20, 15, Changed), MeasureOptions(), &out));
  EXPECT_FALSE(MeasureOnOffsetGrids(a, Window(g, 2, 1, 20, 15, Changed), MeasureOptions(), &out));  // one grid
  // Turned by 8e-10 rad: cell vectors equal to 1e-9 of a cell, but the far
  // samples 3e-8 cells off A's lattice.
  Lattice turned = OffsetBy(g, 0.37, -0.61);
  const double angle = 8e-10;
  turned.u = {10.0 * std::cos(angle), 10.0 * std::sin(angle)};
  turned.v = {10.0 * std::sin(angle), -10.0 * std::cos(angle)};
  EXPECT_FALSE(MeasureOnOffsetGrids(a, Window(turned, 0, 0, 40, 30, Changed), MeasureOptions(), &out));
}

std::string MessageOf(const Surface& a, const Surface& b, const MeasureOptions& options) {
  try {
    Measure(a, b, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(GridPairTest, NoOverlapAndNoCellsGiveTheGeneralPathsMessages) {
  const Lattice g;
  const Surface a = Window(g, 0, 0, 10, 10, Rough);
  const Surface apart = Window(g, 20, 0, 10, 10, Changed);
  EXPECT_NE(MessageOf(a, apart, MeasureOptions()), "");
  EXPECT_EQ(MessageOf(a, apart, MeasureOptions()), MessageOf(a, apart, General(MeasureOptions())));
  // A checkerboard: no cell has four corners.
  const Surface sparse = Window(g, 0, 0, 10, 10, Changed, [](int c, int r) { return (c + r) % 2 == 0; });
  const std::string message = MessageOf(a, sparse, MeasureOptions());
  EXPECT_NE(message.find("no raster cell has all four corners valid"), std::string::npos) << message;
  EXPECT_EQ(message, MessageOf(a, sparse, General(MeasureOptions())));
  MeasureOptions tile;
  tile.allow_empty_overlap = true;
  EXPECT_EQ(Measure(a, apart, tile).rho_d, 0.0);
}

// `s` moved by a rigid motion about its first sample: turns about z, then
// x and y (radians), a shift; each sample keeps its cell (still meshed on
// its own cells), as a moved raster's tile is (terrain/tiled_motion.h).
Surface Moved(const Surface& s, double yaw, double roll, double pitch, std::array<double, 3> shift) {
  const double cz = std::cos(yaw), sz = std::sin(yaw), cx = std::cos(roll), sx = std::sin(roll),
               cy = std::cos(pitch), sy = std::sin(pitch);
  // R = Ry · Rx · Rz
  const double rz[3][3] = {{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}};
  const double rx[3][3] = {{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}};
  const double ry[3][3] = {{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}};
  double rxz[3][3], r[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rxz[i][j] = rx[i][0] * rz[0][j] + rx[i][1] * rz[1][j] + rx[i][2] * rz[2][j];
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r[i][j] = ry[i][0] * rxz[0][j] + ry[i][1] * rxz[1][j] + ry[i][2] * rxz[2][j];
  }
  std::vector<std::array<double, 3>> points;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double p[3] = {s.xy[i].x - s.xy[0].x, s.xy[i].y - s.xy[0].y, s.z[i] - s.z[0]};
    std::array<double, 3> q;
    for (int k = 0; k < 3; ++k) {
      const double first[3] = {s.origin[0] + s.xy[0].x, s.origin[1] + s.xy[0].y, s.origin[2] + s.z[0]};
      q[k] = first[k] + shift[k] + r[k][0] * p[0] + r[k][1] * p[1] + r[k][2] * p[2];
    }
    points.push_back(q);
  }
  Surface out = MakeSurface(points, {}, "moved", 1.0);
  out.raster_cell = s.raster_cell;
  return out;
}

TEST(GridPairTest, MovedRastersEqualTheGeneralPath) {
  const Surface a = HoledA();
  const Surface b = HoledB();
  MeasureOptions options;
  options.keep_node_gaps = true;
  // Small turns and tilts (a co-registration's), and a large turn.
  const double degree = std::acos(-1.0) / 180.0;
  ExpectSameMeasure(a, Moved(b, 0.7 * degree, 0.3 * degree, -0.2 * degree, {3.1, -4.7, 0.4}), options,
                    Path::kMoved);
  options.detect_change = true;
  options.level_of_detection = 0.3;
  ExpectSameMeasure(a, Moved(b, 0.038 * degree, 0.01 * degree, 0.02 * degree, {23.7, -16.1, 0.35}), options,
                    Path::kMoved);
  ExpectSameMeasure(a, Moved(b, 37.0 * degree, 0.0, 0.0, {50.3, -30.8, 0.0}), options, Path::kMoved);
  // Another spacing, turned, on small coordinates (no motion in z).
  Lattice turned;
  turned.origin = {10.0, 20.0};
  turned.u = {2.0 * std::cos(0.5236), 2.0 * std::sin(0.5236)};
  turned.v = {3.0 * std::sin(0.5236), -3.0 * std::cos(0.5236)};
  Lattice finer = turned;
  finer.u = {1.3 * std::cos(0.61), 1.3 * std::sin(0.61)};
  finer.v = {1.7 * std::sin(0.61), -1.7 * std::cos(0.61)};
  finer.origin = {12.3, 17.9};
  ExpectSameMeasure(Window(turned, 0, 0, 30, 25, Rough, HoleA), Window(finer, 0, 0, 40, 35, Changed, HoleB),
                    options, Path::kMoved);
}

TEST(GridPairTest, MovedRastersLeaveTiesAndOtherWeightsToTheGeneralPath) {
  const Lattice g;
  const Surface a = HoledA();
  GridPairResult out;
  // B's nodes on A's columns: an exact tie; the general path measures it.
  const Surface on_line = Window(OffsetBy(g, 0.5, 0.0), 0, 0, 40, 30, Changed);
  EXPECT_FALSE(MeasureOnMovedGrid(a, on_line, MeasureOptions(), &out));
  EXPECT_GT(Measure(a, on_line).rho_d, 0.0);
  const Surface b = Moved(HoledB(), 0.01, 0.002, 0.001, {1.0, 2.0, 0.0});
  MeasureOptions mask;
  mask.weight = WeightMode::kMask;
  mask.mask = {{{500033.3, 3999987.1}, {500301.7, 3999903.3}, {500150.2, 3999731.9}}};
  EXPECT_FALSE(MeasureOnMovedGrid(a, b, mask, &out));
  MeasureOptions hull;
  hull.domain.kind = DomainKind::kHull;
  EXPECT_FALSE(MeasureOnMovedGrid(a, b, hull, &out));
  // B's rows counted the other way: its cells turn clockwise.
  Surface flipped = b;
  for (RasterCell& cell : flipped.raster_cell) cell.row = 100 - cell.row;
  EXPECT_FALSE(MeasureOnMovedGrid(a, flipped, MeasureOptions(), &out));
  // A not on a lattice.
  EXPECT_FALSE(MeasureOnMovedGrid(b, a, MeasureOptions(), &out));
}

TEST(GridPairTest, AMovedRastersHullFromItsRimEqualsTheHullOfAllSamples) {
  for (const Surface& b : {Moved(HoledB(), 0.3, 0.002, -0.003, {1.0, 2.0, 0.0}),
                           Moved(Window(Lattice(), 0, 0, 40, 30, Changed, HoleA), 1.1, 0.0, 0.004, {0.0, 0.0, 5.0})}) {
    grid_cells::GridIndex index;
    ASSERT_TRUE(grid_cells::BuildIndex(b.raster_cell, &index));
    const std::vector<Point2> rim = grid_cells::HullCandidates(b, index);
    EXPECT_LT(rim.size(), b.size() / 2);
    EXPECT_EQ(PolygonArea(ConvexHull(rim)), PolygonArea(ConvexHull(b.xy)));
  }
  // Samples jittered by up to 0.3 cells: too far off a lattice for the
  // rim to be sure; every sample is a candidate.
  Surface jittered = HoledB();
  for (std::size_t i = 0; i < jittered.size(); ++i) {
    jittered.xy[i].x += 3.0 * std::sin(1.7 * static_cast<double>(i));
    jittered.xy[i].y += 3.0 * std::cos(2.3 * static_cast<double>(i));
  }
  grid_cells::GridIndex index;
  ASSERT_TRUE(grid_cells::BuildIndex(jittered.raster_cell, &index));
  EXPECT_EQ(grid_cells::HullCandidates(jittered, index).size(), jittered.size());
}

TEST(GridPairTest, TheGridIndexHoldsEverySampleInAnyOrderAndRefusesTwoInOneCell) {
  // 300 x 250 cells with every seventh missing: more than one chunk.
  std::vector<RasterCell> cells;
  for (int r = 0; r < 250; ++r) {
    for (int c = 0; c < 300; ++c) {
      if ((r * 300 + c) % 7 != 3) cells.push_back({c + 11, r - 5});
    }
  }
  const auto check = [](const std::vector<RasterCell>& given, int threads) {
    grid_cells::GridIndex index;
    ASSERT_TRUE(grid_cells::BuildIndex(given, &index, Execution{threads}));
    EXPECT_EQ(index.c0, 11);
    EXPECT_EQ(index.r0, -5);
    EXPECT_EQ(index.columns, 300);
    EXPECT_EQ(index.rows, 250);
    int64_t held = 0;
    for (int64_t r = 0; r < index.rows; ++r) {
      for (int64_t c = 0; c < index.columns; ++c) {
        const int32_t i = index.At(c + index.c0, r + index.r0);
        if (i < 0) continue;
        ++held;
        EXPECT_EQ(given[i].column, c + index.c0);
        EXPECT_EQ(given[i].row, r + index.r0);
      }
    }
    EXPECT_EQ(held, static_cast<int64_t>(given.size()));
  };
  for (const int threads : {1, 4}) {
    check(cells, threads);  // row-major: filled by chunks
    std::vector<RasterCell> reversed(cells.rbegin(), cells.rend());
    check(reversed, threads);  // any other order: one after another
    std::vector<RasterCell> twice = cells;
    twice.push_back(cells[1234]);
    grid_cells::GridIndex index;
    EXPECT_FALSE(grid_cells::BuildIndex(twice, &index, Execution{threads}));
    std::vector<RasterCell> repeated = cells;  // in order but for a repeat
    repeated.insert(repeated.begin() + 5000, cells[5000]);
    EXPECT_FALSE(grid_cells::BuildIndex(repeated, &index, Execution{threads}));
  }
  grid_cells::GridIndex index;
  EXPECT_FALSE(grid_cells::BuildIndex({}, &index));
}

TEST(GridPairTest, OneAndTwoThreadsGiveTheSameBits) {
  const Lattice g;
  const Surface a = Window(g, 0, 0, 40, 31, Rough, HoleA);
  MeasureOptions serial;
  serial.threads = 1;
  serial.keep_node_gaps = true;
  MeasureOptions parallel = serial;
  parallel.threads = 2;
  // One grid, a grid offset by a fraction of a cell, a moved grid.
  for (const Surface& b : {Window(g, 3, -2, 45, 28, Changed, HoleB),
                           Window(OffsetBy(g, 0.37, -0.61), 3, -2, 45, 28, Changed, HoleB),
                           Moved(Window(g, 3, -2, 45, 28, Changed, HoleB), 0.01, 0.002, 0.001, {1.0, 2.0, 0.0})}) {
    const MeasureSummary one = Measure(a, b, serial), two = Measure(a, b, parallel);
    EXPECT_EQ(one.rho_d, two.rho_d);
    EXPECT_EQ(one.rho_d_axial, two.rho_d_axial);
    EXPECT_EQ(one.signed_volume, two.signed_volume);
    EXPECT_EQ(one.overlap_area, two.overlap_area);
    ASSERT_EQ(one.dz_a.size(), two.dz_a.size());
    EXPECT_EQ(0, std::memcmp(one.dz_a.data(), two.dz_a.data(), one.dz_a.size() * sizeof(double)));
    ASSERT_EQ(one.dz_b.size(), two.dz_b.size());
    EXPECT_EQ(0, std::memcmp(one.dz_b.data(), two.dz_b.data(), one.dz_b.size() * sizeof(double)));
    EXPECT_EQ(one.node_area_a, two.node_area_a);
  }
}

}  // namespace
}  // namespace surfreg
