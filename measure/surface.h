#pragma once
// A sampled height field z = F(x, y): points stored relative to a local
// origin so that UTM-sized coordinates (1e6 m and more) keep full precision
// in every later computation (squares in the in-circle test, volumes).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "measure/tasks.h"

namespace surfreg {

struct Point2 {
  double x = 0.0;
  double y = 0.0;
};

// The same position, bit for bit (a walk's or a lattice's exact tie).
inline bool SamePoint(const Point2& a, const Point2& b) { return a.x == b.x && a.y == b.y; }

// Twice the signed area of triangle abc, in floating point (positive
// counter-clockwise): for areas and integrals; decisions of topology take
// the exact sign, Orient2D (predicates.h).
inline double TwiceArea(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// A sample's cell in the raster it was read from (row 0 at the top, as GDAL).
struct RasterCell {
  int32_t column = 0;
  int32_t row = 0;
};

struct Surface {
  // Added to every stored sample to get input coordinates (same units).
  std::array<double, 3> origin = {0.0, 0.0, 0.0};
  std::vector<Point2> xy;       // sample positions relative to origin
  std::vector<double> z;        // heights relative to origin[2]; z.size() == xy.size()
  std::vector<double> weight;   // optional per-sample weight >= 0; empty = uniform
  std::string source;           // where the samples came from (for messages)
  // Raster topology: per sample, its cell in the one raster all samples came
  // from; empty for scattered samples. Set by the raster reader and kept by
  // every change of frame and rigid motion (they move points, not cells).
  // The surface is then the raster's cells with four valid samples, each
  // split by one diagonal rule, not a Delaunay triangulation
  // (measure/grid_mesh.h); its data domain is exactly those triangles.
  std::vector<RasterCell> raster_cell;

  std::size_t size() const { return xy.size(); }
  bool raster_grid() const { return !raster_cell.empty(); }
};

// Builds a Surface from points in input coordinates. The origin is the
// centre of the bounding box rounded to a multiple of `origin_step`, so that
// local coordinates are small and the origin itself is a readable number.
// `weight` may be empty. Throws InputError if the sizes disagree.
Surface MakeSurface(const std::vector<std::array<double, 3>>& points,
                    std::vector<double> weight = {}, std::string source = "",
                    double origin_step = 1.0);

// The origin MakeSurface chooses for points whose finite coordinates span
// [lo[k], hi[k]] on each axis k (0 where an axis has none: lo > hi).
std::array<double, 3> SurfaceOrigin(const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                                    double origin_step);

// Checks what every algorithm downstream assumes and throws InputError
// naming `surface.source` if it does not hold: at least 3 samples, all
// coordinates finite and of magnitude at most kMaxCoordinate, weights
// finite and >= 0, one raster cell per sample
// if any, and the xy positions not all on one line: not exactly (exact
// test), nor within rounding (the points' spread across their main
// direction at least kMinBandWidthRatio of their extent along it).
inline constexpr double kMinBandWidthRatio = 1e-9;
// Beyond this, products in the exact predicates (up to the fourth power of
// a coordinate difference) and in the volumes would overflow.
inline constexpr double kMaxCoordinate = 1e60;
void ValidateSurface(const Surface& surface, const Execution& execution = Execution{1});

}  // namespace surfreg
