#include "registration/holdout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace surfreg {

std::vector<uint8_t> HeldOutSamples(const Surface& reference, double fraction, uint64_t seed) {
  const std::size_t n = reference.size();
  std::vector<uint8_t> held(n, 0);
  if (n == 0 || !(fraction > 0 && fraction < 1)) return held;
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (const Point2& p : reference.xy) {
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  const int t = kHoldoutTiles;
  const double wx = std::max(x1 - x0, 1e-300) / t, wy = std::max(y1 - y0, 1e-300) / t;
  auto tile_of = [&](const Point2& p) {
    const int i = std::clamp(static_cast<int>((p.x - x0) / wx), 0, t - 1);
    const int j = std::clamp(static_cast<int>((p.y - y0) / wy), 0, t - 1);
    return j * t + i;
  };
  std::vector<int> count(t * t, 0);
  for (const Point2& p : reference.xy) ++count[tile_of(p)];
  std::vector<int> tiles;
  for (int k = 0; k < t * t; ++k) {
    if (count[k] > 0) tiles.push_back(k);
  }
  if (tiles.size() < 2) return held;  // nothing would be left to fit on
  // A seeded shuffle of its own (std::shuffle's algorithm is not fixed by
  // the standard): the same tiles on every platform.
  std::mt19937_64 random(seed);
  for (std::size_t i = tiles.size() - 1; i > 0; --i) {
    const std::size_t j = static_cast<std::size_t>(random() % (i + 1));
    std::swap(tiles[i], tiles[j]);
  }
  const std::size_t take = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::lround(fraction * static_cast<double>(tiles.size()))), 1,
      tiles.size() - 1);
  std::vector<uint8_t> chosen(t * t, 0);
  for (std::size_t k = 0; k < take; ++k) chosen[tiles[k]] = 1;
  for (std::size_t i = 0; i < n; ++i) held[i] = chosen[tile_of(reference.xy[i])];
  return held;
}

Surface WithoutSamples(const Surface& surface, const std::vector<uint8_t>& drop) {
  Surface out;
  out.origin = surface.origin;
  out.source = surface.source;
  for (std::size_t i = 0; i < surface.size(); ++i) {
    if (drop[i]) continue;
    out.xy.push_back(surface.xy[i]);
    out.z.push_back(surface.z[i]);
    if (!surface.weight.empty()) out.weight.push_back(surface.weight[i]);
    if (!surface.raster_cell.empty()) out.raster_cell.push_back(surface.raster_cell[i]);
  }
  return out;
}

double RobustRmse(const DzStatistics& s) {
  if (s.count == 0) return std::nan("");
  return std::hypot(s.median, s.nmad);
}

}  // namespace surfreg
