#pragma once
// The cells of rasters measured on their grids (measure/grid_pair.h):
// dense indices of the samples by cell, the lattice as an affine function,
// completeness of cells and their integrals in closed form. Internal.
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "measure/gap_volume.h"
#include "measure/grid_pair.h"
#include "measure/surface.h"
#include "measure/tasks.h"
#include "measure/uninitialized_vector.h"

namespace surfreg {
namespace grid_cells {

// A surface's samples by cell: a dense row-major index over the bounding
// box of its cells.
struct GridIndex {
  int64_t c0 = 0, r0 = 0, columns = 0, rows = 0;
  UninitializedVector<int32_t> sample;  // -1: no sample (filled by chunks)

  int32_t At(int64_t c, int64_t r) const {
    c -= c0, r -= r0;
    if (c < 0 || r < 0 || c >= columns || r >= rows) return -1;
    return sample[static_cast<std::size_t>(r * columns + c)];
  }
};

// False for a repeated cell or a box too sparse for a dense index.
bool BuildIndex(const std::vector<RasterCell>& cells, GridIndex* index,
                const Execution& execution = Execution{1});

// Positions as an affine function of the cell: origin at cell (c0, r0), u
// per column, v per row.
struct GridAffine {
  Point2 origin, u, v;
  int64_t c0 = 0, r0 = 0;
  Point2 At(int64_t c, int64_t r) const {
    const double dc = static_cast<double>(c - c0), dr = static_cast<double>(r - r0);
    return {origin.x + dc * u.x + dr * v.x, origin.y + dc * u.y + dr * v.y};
  }
};

bool Near(const Point2& p, const Point2& q, double tolerance);

// The affine function through three samples far apart, if every sample is
// on it to `*tolerance` (set here: rounding of the input coordinates, of
// magnitude `magnitude`, plus 1e-9 of a cell).
bool FitAffine(const Surface& s, double magnitude, GridAffine* fit, double* tolerance,
               const Execution& execution = Execution{1});

// The largest input coordinate of a surface's samples (origin included).
double Magnitude(const Surface& s, const Execution& execution = Execution{1});

// The area of the convex hull of a grid's samples, on a lattice of cells of
// area `cell_area`.
double HullArea(const GridIndex& index, double cell_area);
// The same from each row's two ends (column, row) of valid cells, in any
// integer cell coordinates (a row with one sample: one end).
double HullAreaOfRowEnds(std::vector<std::array<int64_t, 2>> ends, double cell_area);

// The samples of a raster surface (indexed by `index`, its own cells) that
// may be corners of its convex hull, for a raster whose samples need not
// lie on a lattice (moved by a rigid motion: each off a lattice L by up to
// E, measured here): when 2E is well inside the inradius of a sample's
// 3 × 3 block of cells, a sample with all eight neighbours lies inside
// their hull, so only the others are returned; otherwise every sample.
std::vector<Point2> HullCandidates(const Surface& s, const GridIndex& index,
                                   const Execution& execution = Execution{1});

// One surface on the grid: its index, positions in A's frame and heights.
struct GridSide {
  const Surface* surface = nullptr;
  GridIndex index;
  Point2 shift;        // added to the surface's xy (B's origin minus A's)
  double z_shift = 0;  // added to its z
  std::vector<uint8_t> complete;  // per index cell: its four corners are samples
  double domain_area = 0;
  double cell_area = 0;  // of the lattice's cells (the hull's area in index units times this)

  Point2 Xy(int32_t i) const {
    const Point2& p = surface->xy[i];
    return shift.x == 0.0 && shift.y == 0.0 ? p : Point2{p.x + shift.x, p.y + shift.y};
  }
  double Z(int32_t i) const { return surface->z[i] + z_shift; }
  // Rows of the index and of the completeness flags (null outside it).
  const int32_t* SampleRow(int64_t r) const {
    return r < 0 || r >= index.rows ? nullptr : &index.sample[static_cast<std::size_t>(r * index.columns)];
  }
  const uint8_t* CompleteRow(int64_t r) const {
    return r < 0 || r >= index.rows ? nullptr : &complete[static_cast<std::size_t>(r * index.columns)];
  }
  // The corners (c, r) (c+1, r) (c+1, r+1) (c, r+1) of cell c of the rows
  // `here` and `below` (index coordinates; c + 1 inside the row).
  static void Corners(const int32_t* here, const int32_t* below, int64_t c, int32_t k[4]) {
    k[0] = here[c], k[1] = here[c + 1], k[2] = below[c + 1], k[3] = below[c];
  }
  // A corner of a complete cell (the cells c − 1 and c of the rows r − 1
  // and r, flags `above` and `here`): a vertex of the data domain.
  bool DomainVertex(const uint8_t* above, const uint8_t* here, int64_t c) const {
    const auto complete_at = [this](const uint8_t* row, int64_t k) {
      return row != nullptr && k >= 0 && k < index.columns && row[k] != 0;
    };
    return complete_at(above, c - 1) || complete_at(above, c) || complete_at(here, c - 1) ||
           complete_at(here, c);
  }
};

// Rows [begin, end) of a side: completeness, orientation and the domain's
// area. False if a complete cell's triangle does not have the sign `sign`
// (a fold or a degenerate cell).
bool MarkComplete(GridSide* side, int64_t begin, int64_t end, double sign, double* area);

// Both sides' MarkComplete over all rows, in chunks of rows (RowChunks) on
// the threads `execution` allows; false if either finds a fold.
bool MarkBoth(GridSide* a, GridSide* b, double sign, const Execution& execution, double* area_a,
              double* area_b);

// The number of row chunks for a grid of `rows` rows: a function of the
// size only, so every sum made per chunk is the same on any thread count.
int RowChunks(int64_t rows);

// A third of each of A's domain triangles whose corners are all in Ω
// (`omega`, per sample of a), per sample: MeasureSummary::node_area_a.
std::vector<double> NodeAreas(const GridSide& side_a, const Surface& a, const std::vector<uint8_t>& omega,
                              const Execution& execution);

// One triangle (counter-clockwise corners p, gaps d) with μ = 1: the overlay
// cell integrator's results (IntegrateConvex, uniform) in closed form.
void IntegrateTriangle(const Point2 p[3], const double d[3], double lod, VolumeResult* result);
// The same for a triangle of area `area` (its corners' gaps d).
void IntegrateTriangleOfArea(double area, const double d[3], double lod, VolumeResult* result);

// One chunk of rows' sums.
// A cache line of its own: each chunk adds to its sums cell by cell.
struct alignas(64) ChunkSums {
  VolumeResult volume;
  double gap_sum = 0, node_weight = 0;
  int64_t nodes = 0;
};

// The chunks' sums added in chunk order.
ChunkSums SumChunks(const std::vector<ChunkSums>& parts);

// Both sides of a pair (B's positions and heights shifted into A's frame),
// indexed; false as BuildIndex.
bool IndexSides(const Surface& a, const Surface& b, const Execution& execution, GridSide* side_a,
                GridSide* side_b);

// The chunks' sums in order (the volume, ρ'd and Ω's nodes), both hulls'
// areas and, with `keep`, A's node areas (NodeAreas) into `result`.
void FinishResult(const std::vector<ChunkSums>& parts, const GridSide& side_a, const GridSide& side_b,
                  const std::vector<uint8_t>& omega_a, bool keep, const Execution& execution,
                  GridPairResult* result);

// The rule's two triangles in a cell's corners (0,0) (1,0) (1,1) (0,1), as
// indices into those four, counter-clockwise in index space.
inline constexpr int kRule[2][3] = {{0, 1, 2}, {0, 2, 3}};
inline constexpr double kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

// Barycentric weights of (x, y) in rule triangle h of the unit cell.
std::array<double, 3> RuleWeights(int h, double x, double y);

// One piece of an A cell: A's triangle `a`, the B cell (dc, dr) from the
// cell's base B cell and its triangle `b`; corners by their weights in both
// triangles, and the fan's areas (index units).
struct Piece {
  int a = 0, b = 0, dc = 0, dr = 0, corners = 0;
  double wa[9][4], wb[9][4];  // per corner of the piece, weights of the cells' four corners
  double fan[7];
};

// The pieces of the unit A cell when B's cell (0, 0) starts at (-fx, -fy)
// (0 < fx, fy < 1): B cells (0..1, 0..1) cover it (the offset sweep's
// pattern: grid_sweep.cc, raster_sweep.cc).
std::vector<Piece> PiecePattern(double fx, double fy);

// One A cell's pieces (PiecePattern) into `volume`: its corners' heights
// `za`, the four B cells' (dr, dc) `zb` where `whole` (complete), each
// piece's gap at its corners from their weights, its fan's triangles of
// `cell_area` per index unit, and one overlay cell per piece.
void IntegratePieces(const std::vector<Piece>& pieces, const double za[4], const double zb[2][2][4],
                     const bool whole[2][2], double cell_area, double lod, VolumeResult* volume);

inline double Fraction(double x) { return x - std::floor(x); }

}  // namespace grid_cells
}  // namespace surfreg
