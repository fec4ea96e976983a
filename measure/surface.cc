#include "measure/surface.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "measure/input_error.h"
#include "measure/predicates.h"
#include "measure/tasks.h"

namespace surfreg {
namespace {

double RoundedCentre(double lo, double hi, double step) {
  const double centre = 0.5 * lo + 0.5 * hi;
  return step > 0.0 ? std::round(centre / step) * step : centre;
}

std::string Where(const Surface& surface) {
  return surface.source.empty() ? std::string("surface") : surface.source;
}

}  // namespace

Surface MakeSurface(const std::vector<std::array<double, 3>>& points, std::vector<double> weight,
                    std::string source, double origin_step) {
  Surface surface;
  surface.source = std::move(source);
  if (!weight.empty() && weight.size() != points.size()) {
    throw InputError(Where(surface) + ": " + std::to_string(weight.size()) + " weights for " +
                     std::to_string(points.size()) + " points");
  }
  std::array<double, 3> lo, hi;
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -std::numeric_limits<double>::infinity();
  }
  for (const auto& p : points) {
    for (int k = 0; k < 3; ++k) {
      if (std::isfinite(p[k])) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    }
  }
  surface.origin = SurfaceOrigin(lo, hi, origin_step);
  surface.xy.resize(points.size());
  surface.z.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    surface.xy[i] = {points[i][0] - surface.origin[0], points[i][1] - surface.origin[1]};
    surface.z[i] = points[i][2] - surface.origin[2];
  }
  surface.weight = std::move(weight);
  return surface;
}

std::array<double, 3> SurfaceOrigin(const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                                    double origin_step) {
  std::array<double, 3> origin;
  for (int k = 0; k < 3; ++k) origin[k] = lo[k] <= hi[k] ? RoundedCentre(lo[k], hi[k], origin_step) : 0.0;
  return origin;
}

void ValidateSurface(const Surface& surface, const Execution& execution) {
  const std::string where = Where(surface);
  const std::size_t n = surface.xy.size();
  if (surface.z.size() != n) throw InputError(where + ": x/y and z counts differ");
  if (!surface.weight.empty() && surface.weight.size() != n) {
    throw InputError(where + ": weight count differs from point count");
  }
  if (!surface.raster_cell.empty() && surface.raster_cell.size() != n) {
    throw InputError(where + ": raster cell count differs from point count");
  }
  if (n < 3) {
    throw InputError(where + ": " + std::to_string(n) +
                     " points; a surface needs at least 3 not on one line");
  }
  // What is wrong with point i: 0 nothing, 1 not finite, 2 beyond
  // kMaxCoordinate, 3 its weight. The first bad point of each chunk is
  // found; the first of all is reported.
  const auto fault = [&surface](std::size_t i) {
    if (!std::isfinite(surface.xy[i].x) || !std::isfinite(surface.xy[i].y) || !std::isfinite(surface.z[i])) {
      return 1;
    }
    const double x = surface.xy[i].x + surface.origin[0], y = surface.xy[i].y + surface.origin[1];
    if (std::max({std::abs(x), std::abs(y), std::abs(surface.z[i] + surface.origin[2])}) > kMaxCoordinate) {
      return 2;
    }
    return !surface.weight.empty() && !(surface.weight[i] >= 0.0 && std::isfinite(surface.weight[i])) ? 3 : 0;
  };
  const int chunks = ChunksFor(static_cast<int64_t>(n), 1 << 16);
  std::vector<std::size_t> first_bad(chunks, n);
  ForEachChunk(execution, static_cast<int64_t>(n), chunks, [&](int c, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      if (fault(static_cast<std::size_t>(i)) != 0) {
        first_bad[c] = static_cast<std::size_t>(i);
        return;
      }
    }
  });
  const std::size_t i = *std::min_element(first_bad.begin(), first_bad.end());
  if (i < n) {
    const std::string point = std::to_string(i + 1);
    switch (fault(i)) {
      case 1: throw InputError(where + ": point " + point + " is not finite");
      case 2:
        throw InputError(where + ": point " + point +
                         " has a coordinate beyond 1e60 in magnitude (the geometry would overflow)");
      default: throw InputError(where + ": weight of point " + point + " is negative or not finite");
    }
  }
  // All collinear? Find a point distinct from the first, then one off their line.
  const Point2& a = surface.xy[0];
  std::size_t j = 1;
  while (j < n && surface.xy[j].x == a.x && surface.xy[j].y == a.y) ++j;
  if (j == n) throw InputError(where + ": all points have the same x and y");
  const Point2& b = surface.xy[j];
  std::size_t k = j + 1;
  while (k < n && Orient2D(a, b, surface.xy[k]) == 0.0) ++k;
  if (k == n) throw InputError(where + ": all points lie on one line in xy; no surface to triangulate");
  // Exactly not collinear, but perhaps only by rounding (e.g. (0.01 i, 0.02 i)):
  // the exact predicates would see a valid sliver triangulation and the
  // measures would be nonsense (an overlap of 1e-16). The band's width
  // across the points' main direction, against their extent along it.
  double mx = 0, my = 0;
  for (const Point2& p : surface.xy) mx += p.x, my += p.y;
  mx /= static_cast<double>(n), my /= static_cast<double>(n);
  double sxx = 0, sxy = 0, syy = 0;
  for (const Point2& p : surface.xy) {
    const double dx = p.x - mx, dy = p.y - my;
    sxx += dx * dx, sxy += dx * dy, syy += dy * dy;
  }
  // The main axis of [[sxx, sxy], [sxy, syy]] (well determined when the
  // points are nearly on a line: the eigenvalues are then far apart).
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  const double ux = std::cos(angle), uy = std::sin(angle);
  double along_lo = HUGE_VAL, along_hi = -HUGE_VAL, across_lo = HUGE_VAL, across_hi = -HUGE_VAL;
  for (const Point2& p : surface.xy) {
    const double dx = p.x - mx, dy = p.y - my;
    const double along = ux * dx + uy * dy, across = -uy * dx + ux * dy;
    along_lo = std::min(along_lo, along), along_hi = std::max(along_hi, along);
    across_lo = std::min(across_lo, across), across_hi = std::max(across_hi, across);
  }
  if (across_hi - across_lo < kMinBandWidthRatio * (along_hi - along_lo)) {
    char extent[160];
    std::snprintf(extent, sizeof extent, " (%.3g wide across %.3g)", across_hi - across_lo, along_hi - along_lo);
    throw InputError(where + ": all points lie on one line in xy within rounding" + extent +
                     "; no surface to triangulate");
  }
}

}  // namespace surfreg
