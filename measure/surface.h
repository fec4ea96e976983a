#pragma once
// A sampled height field z = F(x, y): points stored relative to a local
// origin so that UTM-sized coordinates (1e6 m and more) keep full precision
// in every later computation (squares in the in-circle test, volumes).
#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace surfreg {

struct Point2 {
  double x = 0.0;
  double y = 0.0;
};

struct Surface {
  // Added to every stored sample to get input coordinates (same units).
  std::array<double, 3> origin = {0.0, 0.0, 0.0};
  std::vector<Point2> xy;       // sample positions relative to origin
  std::vector<double> z;        // heights relative to origin[2]; z.size() == xy.size()
  std::vector<double> weight;   // optional per-sample weight >= 0; empty = uniform
  std::string source;           // where the samples came from (for messages)
  // The samples are the valid cell centres of one raster (a lattice with
  // nodata holes): the data domain is then its complete cells
  // (measure/domain.h, DomainRule::grid). Set by the raster reader.
  bool raster_grid = false;

  std::size_t size() const { return xy.size(); }
};

// Builds a Surface from points in input coordinates. The origin is the
// centre of the bounding box rounded to a multiple of `origin_step`, so that
// local coordinates are small and the origin itself is a readable number.
// `weight` may be empty. Throws InputError if the sizes disagree.
Surface MakeSurface(const std::vector<std::array<double, 3>>& points,
                    std::vector<double> weight = {}, std::string source = "",
                    double origin_step = 1.0);

// Checks what every algorithm downstream assumes and throws InputError
// naming `surface.source` if it does not hold: at least 3 samples, all
// coordinates finite, weights finite and >= 0, and the xy positions not all
// on one line (exact test).
void ValidateSurface(const Surface& surface);

}  // namespace surfreg
