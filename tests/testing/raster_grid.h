#pragma once
// Synthetic rasters in memory for the tiled tests (tiled_measure_test,
// tiled_motion_test): a smooth terrain at UTM-sized coordinates, a known
// change, round holes and scattered nodata, read whole or a window at a
// time as a file would be.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "measure/surface.h"
#include "terrain/tiled_measure.h"

namespace surfreg {
namespace testing {

constexpr double kX0 = 500000.0, kY0 = 4200000.0;  // UTM-sized, as real DEMs

inline double Terrain(double x, double y) {
  const double dx = x - kX0, dy = kY0 - y;
  return 100.0 + 8.0 * std::sin(dx / 17.3) * std::cos(dy / 11.1) + 0.02 * dx + 0.01 * dy;
}

// The known change: a bump (fill) and a pit (cut), smooth.
inline double Change(double x, double y) {
  const double dx = x - kX0, dy = kY0 - y;
  auto blob = [&](double cx, double cy, double r) {
    return std::exp(-((dx - cx) * (dx - cx) + (dy - cy) * (dy - cy)) / (r * r));
  };
  return 0.8 * blob(0.3 * 400, 0.4 * 300, 25.0) - 0.5 * blob(0.7 * 400, 0.6 * 300, 30.0);
}

// Scattered nodata, about 1 sample in 200.
inline bool Speckle(int32_t c, int32_t r, uint32_t seed) {
  uint32_t h = static_cast<uint32_t>(c) * 73856093u ^ static_cast<uint32_t>(r) * 19349663u ^ seed;
  h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
  return h % 200u == 0u;
}

struct Hole {
  double cx, cy, radius;  // in cells
};

// A raster in memory, read whole or a window at a time as a file would be.
struct Grid {
  int32_t columns = 0, rows = 0;
  std::array<double, 6> gt{};
  std::array<double, 3> origin{};
  std::vector<double> values;
  std::string name;

  Surface Whole() const {
    return RasterBlockToSurface(gt, {0, 0, columns, rows}, values.data(), values.size(), origin, name);
  }
  TiledRasterSource Source() const {
    TiledRasterSource s;
    s.columns = columns;
    s.rows = rows;
    s.origin = origin;
    s.source = name;
    s.read = [this](const SampleWindow& w) {
      EXPECT_TRUE(w.column >= 0 && w.row >= 0 && w.column + w.columns <= columns &&
                  w.row + w.rows <= rows && !w.empty());
      std::vector<double> block;
      block.reserve(static_cast<std::size_t>(w.columns) * w.rows);
      for (int32_t r = w.row; r < w.row + w.rows; ++r) {
        for (int32_t c = w.column; c < w.column + w.columns; ++c) {
          block.push_back(values[static_cast<std::size_t>(r) * columns + c]);
        }
      }
      return RasterBlockToSurface(gt, w, block.data(), block.size(), origin, name);
    };
    s.cover = AffineGridCover(gt, columns, rows);
    return s;
  }
};

inline Grid MakeGrid(int32_t columns, int32_t rows, std::array<double, 6> gt, std::array<double, 3> origin,
              bool changed, const std::vector<Hole>& holes, uint32_t seed, std::string name) {
  Grid g{columns, rows, gt, origin, {}, std::move(name)};
  g.values.resize(static_cast<std::size_t>(columns) * rows);
  for (int32_t r = 0; r < rows; ++r) {
    for (int32_t c = 0; c < columns; ++c) {
      const double x = gt[0] + (c + 0.5) * gt[1] + (r + 0.5) * gt[2];
      const double y = gt[3] + (c + 0.5) * gt[4] + (r + 0.5) * gt[5];
      double z = Terrain(x, y) + (changed ? Change(x, y) : 0.0);
      for (const Hole& h : holes) {
        if (std::hypot(c - h.cx, r - h.cy) < h.radius) z = std::nan("");
      }
      if (Speckle(c, r, seed)) z = std::nan("");
      g.values[static_cast<std::size_t>(r) * columns + c] = z;
    }
  }
  return g;
}

}  // namespace testing
}  // namespace surfreg
