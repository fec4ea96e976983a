#include "terrain/tiled_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "measure/input_error.h"

namespace surfreg {
namespace {

// The samples of several windows as one surface: each raster cell once, in
// row-major order (as GridCellTriangles wants them).
Surface Merge(std::vector<Surface> parts, const TiledRasterSource& raster) {
  Surface out;
  out.origin = raster.origin;
  out.source = raster.source;
  std::vector<std::pair<int64_t, std::pair<int32_t, int32_t>>> order;  // cell key, (part, sample)
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const Surface& s = parts[p];
    for (std::size_t i = 0; i < s.size(); ++i) {
      const RasterCell& cell = s.raster_cell[i];
      order.push_back({static_cast<int64_t>(cell.row) * raster.columns + cell.column,
                       {static_cast<int32_t>(p), static_cast<int32_t>(i)}});
    }
  }
  std::sort(order.begin(), order.end());
  order.erase(std::unique(order.begin(), order.end(),
                          [](const auto& a, const auto& b) { return a.first == b.first; }),
              order.end());
  out.xy.reserve(order.size());
  out.z.reserve(order.size());
  out.raster_cell.reserve(order.size());
  for (const auto& entry : order) {
    const Surface& s = parts[entry.second.first];
    const int32_t i = entry.second.second;
    out.xy.push_back(s.xy[i]);
    out.z.push_back(s.z[i]);
    out.raster_cell.push_back(s.raster_cell[i]);
  }
  return out;
}

SampleWindow Widen(SampleWindow w, int32_t margin, const TiledRasterSource& raster) {
  if (w.empty()) return w;
  const int32_t c0 = std::max(w.column - margin, 0), r0 = std::max(w.row - margin, 0);
  const int32_t c1 = std::min(w.column + w.columns + margin, raster.columns);
  const int32_t r1 = std::min(w.row + w.rows + margin, raster.rows);
  return {c0, r0, c1 - c0, r1 - r0};
}

// The box of a surface's samples in input coordinates.
XyBox BoxOf(const Surface& s) {
  XyBox box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Point2& p : s.xy) {
    box.x_min = std::min(box.x_min, p.x), box.x_max = std::max(box.x_max, p.x);
    box.y_min = std::min(box.y_min, p.y), box.y_max = std::max(box.y_max, p.y);
  }
  box.x_min += s.origin[0], box.x_max += s.origin[0];
  box.y_min += s.origin[1], box.y_max += s.origin[1];
  return box;
}

// The reference's patches: one per stratum of a gx × gy grid, each at a
// seeded place in its stratum (uniform integers from the 64-bit Mersenne
// twister, whose sequence the standard fixes: the same on every platform).
std::vector<SampleWindow> Patches(int32_t columns, int32_t rows, const PatchSampleOptions& o) {
  const int32_t side = std::min({o.patch, columns, rows});
  const int64_t count = std::max<int64_t>(1, o.max_reference_samples / (int64_t{side} * side));
  int64_t gx = std::max<int64_t>(1, std::llround(std::sqrt(count * double(columns) / rows)));
  gx = std::min<int64_t>(gx, std::max(columns / side, 1));
  int64_t gy = std::max<int64_t>(1, count / gx);
  gy = std::min<int64_t>(gy, std::max(rows / side, 1));
  std::mt19937_64 random(o.seed);
  std::vector<SampleWindow> patches;
  for (int64_t j = 0; j < gy; ++j) {
    for (int64_t i = 0; i < gx; ++i) {
      const int64_t c0 = i * columns / gx, c1 = (i + 1) * columns / gx;
      const int64_t r0 = j * rows / gy, r1 = (j + 1) * rows / gy;
      const uint64_t dc =
          random() % static_cast<uint64_t>(std::max<int64_t>(c1 - c0 - side + 1, 1));
      const uint64_t dr =
          random() % static_cast<uint64_t>(std::max<int64_t>(r1 - r0 - side + 1, 1));
      patches.push_back({static_cast<int32_t>(c0 + dc), static_cast<int32_t>(r0 + dr), side, side});
    }
  }
  return patches;
}

}  // namespace

PatchSample SampleRasterPatches(const TiledRasterSource& reference, const TiledRasterSource& moving,
                                const PatchSampleOptions& o) {
  if (o.max_reference_samples <= 0 || o.patch < 8 || o.margin < 0) {
    throw InputError("a raster sample needs max_reference_samples > 0, patch >= 8 and margin >= 0");
  }
  PatchSample sample;
  const int64_t cells = int64_t{reference.columns} * reference.rows;
  if (cells <= o.max_reference_samples) {
    sample.whole = true;
    sample.patches = {{0, 0, reference.columns, reference.rows}};
    sample.reference = reference.read(sample.patches[0]);
    sample.moving = moving.read({0, 0, moving.columns, moving.rows});
    return sample;
  }
  const TiledRasterSource moved =
      MovedRasterSource(moving, o.initial, o.moving_z_min, o.moving_z_max);
  std::vector<Surface> reference_parts, moving_parts;
  for (const SampleWindow& patch : Patches(reference.columns, reference.rows, o)) {
    Surface part = reference.read(patch);
    if (part.size() == 0) continue;  // all nodata
    const SampleWindow window = Widen(moved.cover(BoxOf(part)), o.margin, moving);
    sample.patches.push_back(patch);
    reference_parts.push_back(std::move(part));
    if (!window.empty()) moving_parts.push_back(moving.read(window));
  }
  sample.reference = Merge(std::move(reference_parts), reference);
  sample.moving = Merge(std::move(moving_parts), moving);
  if (sample.reference.size() < 3 || sample.moving.size() < 3) {
    throw InputError(reference.source + ", " + moving.source + ": the sampled patches (" +
                     std::to_string(sample.patches.size()) + ") hold " +
                     std::to_string(sample.reference.size()) + " and " +
                     std::to_string(sample.moving.size()) +
                     " samples: too few to align on (do the rasters overlap?)");
  }
  return sample;
}

SampleExtent ExtentOfSamples(const TiledRasterSource& raster, int32_t band_rows) {
  SampleExtent e;
  const double inf = std::numeric_limits<double>::infinity();
  XyBox box{inf, inf, -inf, -inf};
  double lo = inf, hi = -inf;
  const int32_t step = std::max(band_rows, 1);
  for (int32_t row = 0; row < raster.rows; row += step) {
    const Surface band = raster.read({0, row, raster.columns, std::min(step, raster.rows - row)});
    for (std::size_t i = 0; i < band.size(); ++i) {
      lo = std::min(lo, band.z[i]), hi = std::max(hi, band.z[i]);
      box.x_min = std::min(box.x_min, band.xy[i].x), box.x_max = std::max(box.x_max, band.xy[i].x);
      box.y_min = std::min(box.y_min, band.xy[i].y), box.y_max = std::max(box.y_max, band.xy[i].y);
    }
    e.count += static_cast<int64_t>(band.size());
  }
  if (e.count == 0) return e;
  const std::array<double, 3>& o = raster.origin;
  e.box = {box.x_min + o[0], box.y_min + o[1], box.x_max + o[0], box.y_max + o[1]};
  e.z_min = lo + o[2], e.z_max = hi + o[2];
  return e;
}

TiledRasterSource MovedRasterSource(TiledRasterSource moving, const RowMajorMatrix4& m,
                                    double z_min, double z_max) {
  const double det = m[0] * m[5] - m[1] * m[4];  // of the rotation's xy block
  if (!(det > 1e-6)) {
    throw InputError(moving.source +
                     ": the motion turns the surface on its side or over "
                     "(xy determinant " +
                     std::to_string(det) + "): no height field to measure");
  }
  const std::array<double, 3> o = moving.origin;
  // Local coordinates p → R p + (R o + t − o): the moved point relative to
  // the same origin.
  std::array<double, 3> shift;
  for (int i = 0; i < 3; ++i) {
    shift[i] = m[4 * i] * o[0] + m[4 * i + 1] * o[1] + m[4 * i + 2] * o[2] + m[4 * i + 3] - o[i];
  }
  auto read = std::move(moving.read);
  moving.read = [read, m, shift](const SampleWindow& w) {
    Surface s = read(w);
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double x = s.xy[i].x, y = s.xy[i].y, z = s.z[i];
      s.xy[i] = {m[0] * x + m[1] * y + m[2] * z + shift[0],
                 m[4] * x + m[5] * y + m[6] * z + shift[1]};
      s.z[i] = m[8] * x + m[9] * y + m[10] * z + shift[2];
    }
    return s;
  };
  // A moved point's xy is A p_xy + c p_z + t (A the rotation's xy block):
  // over the box's corners and the two extreme heights, p_xy = A⁻¹(q − t − c p_z)
  // spans the preimage (a linear image of a box × interval).
  auto cover = std::move(moving.cover);
  moving.cover = [cover, m, det, z_min, z_max](const XyBox& box) {
    const double i00 = m[5] / det, i01 = -m[1] / det, i10 = -m[4] / det, i11 = m[0] / det;
    XyBox pre{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
              -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const double x : {box.x_min, box.x_max}) {
      for (const double y : {box.y_min, box.y_max}) {
        for (const double z : {z_min, z_max}) {
          const double u = x - m[3] - m[2] * z, v = y - m[7] - m[6] * z;
          const double px = i00 * u + i01 * v, py = i10 * u + i11 * v;
          pre.x_min = std::min(pre.x_min, px), pre.x_max = std::max(pre.x_max, px);
          pre.y_min = std::min(pre.y_min, py), pre.y_max = std::max(pre.y_max, py);
        }
      }
    }
    return cover(pre);
  };
  return moving;
}

}  // namespace surfreg
