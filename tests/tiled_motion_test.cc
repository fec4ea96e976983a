// terrain/tiled_motion.h: a moving raster measured moved, tile by tile,
// against Measure on the whole surfaces moved point by point; the extent of
// the valid samples against a brute-force scan; the sample of patches: bounded, every
// sample once, and each reference patch covered by the moving data it needs.
#include "terrain/tiled_motion.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "measure/input_error.h"
#include "measure/measures.h"
#include "tests/testing/raster_grid.h"

namespace surfreg {
namespace {

using testing::Grid;
using testing::kX0;
using testing::kY0;
using testing::MakeGrid;

const std::array<double, 6> kGridA = {kX0, 1.0, 0.0, kY0, 0.0, -1.0};

// A rotation of a few hundredths of a degree about a point near the
// rasters' centre, and a shift of a few cells: input coordinates.
Eigen::Matrix4d Motion(double scale) {
  const Eigen::Vector3d centre(kX0 + 200, kY0 - 150, 100);
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(scale * 0.9 * M_PI / 180, Eigen::Vector3d(0.3, -0.5, 1.0).normalized())
          .toRotationMatrix();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = centre - r * centre + scale * Eigen::Vector3d(2.3, -1.7, 0.4);
  return m;
}

RowMajorMatrix4 RowMajor(const Eigen::Matrix4d& m) {
  RowMajorMatrix4 out;
  for (int k = 0; k < 16; ++k) out[k] = m(k / 4, k % 4);
  return out;
}

// Every sample moved in input coordinates (not through MovedRasterSource).
Surface MovedWhole(Surface s, const Eigen::Matrix4d& m) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d p(s.xy[i].x + s.origin[0], s.xy[i].y + s.origin[1], s.z[i] + s.origin[2]);
    const Eigen::Vector3d q = (m * p.homogeneous()).head<3>();
    s.xy[i] = {q.x() - s.origin[0], q.y() - s.origin[1]};
    s.z[i] = q.z() - s.origin[2];
  }
  return s;
}

MeasureOptions Options() {
  MeasureOptions o;
  o.detect_change = true;
  o.level_of_detection = 0.05;
  return o;
}

void Near(const char* what, double want, double got, double scale) {
  EXPECT_LE(std::fabs(got - want), 1e-9 * std::max(std::fabs(want), scale))
      << what << ": untiled " << want << ", tiled " << got;
}

struct Pair {
  Grid a, b;
};

Pair MakePair() {
  return {
      MakeGrid(400, 300, kGridA, {kX0 + 200, kY0 - 150, 0}, false, {{150, 120, 40}}, 1u, "a.tif"),
      MakeGrid(400, 305, {kX0 + 0.37, 1.01, 0.0, kY0 - 0.23, 0.0, -0.99},
               {kX0 + 210, kY0 - 140, 50}, true, {{260, 200, 18}}, 2u, "b.tif")};
}

TEST(TiledMotionTest, ExtentIsTheValidSamplesBoxAndHeights) {
  const Pair p = MakePair();
  double lo = 1e300, hi = -1e300, x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  int64_t count = 0;
  for (int32_t r = 0; r < p.b.rows; ++r) {
    for (int32_t c = 0; c < p.b.columns; ++c) {
      const double v = p.b.values[static_cast<std::size_t>(r) * p.b.columns + c];
      if (!std::isfinite(v)) continue;
      const auto& g = p.b.gt;
      const double x = g[0] + (c + 0.5) * g[1] + (r + 0.5) * g[2],
                   y = g[3] + (c + 0.5) * g[4] + (r + 0.5) * g[5];
      lo = std::min(lo, v), hi = std::max(hi, v), ++count;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  }
  for (int32_t band : {1, 7, 305, 1000}) {
    const SampleExtent e = ExtentOfSamples(p.b.Source(), band);
    EXPECT_NEAR(e.z_min, lo, 1e-9) << "band " << band;
    EXPECT_NEAR(e.z_max, hi, 1e-9) << "band " << band;
    EXPECT_NEAR(e.box.x_min, x0, 1e-6);
    EXPECT_NEAR(e.box.x_max, x1, 1e-6);
    EXPECT_NEAR(e.box.y_min, y0, 1e-6);
    EXPECT_NEAR(e.box.y_max, y1, 1e-6);
    EXPECT_EQ(e.count, count);
  }
  Grid empty = p.b;
  empty.values.assign(empty.values.size(), std::nan(""));
  const SampleExtent none = ExtentOfSamples(empty.Source(), 50);
  EXPECT_EQ(none.count, 0);
  EXPECT_EQ(none.z_min, 0.0);
  EXPECT_EQ(none.z_max, 0.0);
}

// The moved source tile by tile equals the whole moving raster moved point
// by point and measured at once: its cover finds every moved triangle over
// each tile (else a tile's volume would be short).
TEST(TiledMotionTest, MovedSourceTiledEqualsUntiled) {
  const Pair p = MakePair();
  for (double scale : {1.0, -3.0}) {
    SCOPED_TRACE("motion scale " + std::to_string(scale));
    const Eigen::Matrix4d m = Motion(scale);
    const SampleExtent range = ExtentOfSamples(p.b.Source(), 64);
    const TiledRasterSource moved =
        MovedRasterSource(p.b.Source(), RowMajor(m), range.z_min, range.z_max);
    MeasureOptions options = Options();
    const MeasureSummary untiled = Measure(p.a.Whole(), MovedWhole(p.b.Whole(), m), options);
    ASSERT_GT(untiled.overlap_area, 0.8 * 399 * 299 - 40 * 40 * M_PI - 18 * 18 * M_PI);
    for (int32_t tile : {23, 100}) {
      SCOPED_TRACE("tile " + std::to_string(tile));
      TiledMeasureOptions tiled;
      tiled.measure = options;
      tiled.tile = tile;
      const MeasureSummary t = MeasureTiled(p.a.Source(), moved, tiled);
      const double volume = untiled.rho_d, area = untiled.domain_area_a;
      Near("rho_d", untiled.rho_d, t.rho_d, volume);
      Near("signed_volume", untiled.signed_volume, t.signed_volume, volume);
      Near("volume_above", untiled.volume_above, t.volume_above, volume);
      Near("overlap_area", untiled.overlap_area, t.overlap_area, area);
      Near("domain_area_b", untiled.domain_area_b, t.domain_area_b, area);
      Near("rho_d_axial", untiled.rho_d_axial, t.rho_d_axial, untiled.rho_d_axial);
      Near("fill_detected", untiled.fill_detected, t.fill_detected, volume);
      EXPECT_EQ(untiled.n_overlap_nodes, t.n_overlap_nodes);
      EXPECT_EQ(untiled.n_cells, t.n_cells);
    }
  }
}

TEST(TiledMotionTest, MotionThatTurnsTheSurfaceOverIsRefused) {
  const Pair p = MakePair();
  RowMajorMatrix4 flip = kIdentityMatrix4;
  flip[5] = -1, flip[10] = -1;  // a half turn about x
  EXPECT_THROW(MovedRasterSource(p.b.Source(), flip, 0, 1), InputError);
}

TEST(TiledMotionTest, SmallPairIsSampledWhole) {
  const Pair p = MakePair();
  PatchSampleOptions o;
  o.max_reference_samples = 400 * 300;
  const PatchSample s = SampleRasterPatches(p.a.Source(), p.b.Source(), o);
  EXPECT_TRUE(s.whole);
  EXPECT_EQ(s.reference.size(), p.a.Whole().size());
  EXPECT_EQ(s.moving.size(), p.b.Whole().size());
}

// Patches: within the budget, spread over the strata, each reference
// sample once and in a patch, the moving samples once each and row-major,
// and (B has data there) each patch wholly overlapped by the moving sample
// under the initial motion.
TEST(TiledMotionTest, PatchesAreBoundedAndCovered) {
  const Grid a = MakeGrid(400, 300, kGridA, {kX0 + 200, kY0 - 150, 0}, false, {}, 5u, "a.tif");
  const Grid b = MakeGrid(420, 320, {kX0 - 10.37, 1.01, 0.0, kY0 + 10.23, 0.0, -0.99},
                          {kX0 + 210, kY0 - 140, 50}, true, {}, 6u, "b.tif");
  const Eigen::Matrix4d m = Motion(2.0);
  const SampleExtent range = ExtentOfSamples(b.Source(), 64);
  PatchSampleOptions o;
  o.max_reference_samples = 20000;
  o.patch = 40;
  o.margin = 3;
  o.seed = 7;
  o.initial = RowMajor(m);
  o.moving_z_min = range.z_min, o.moving_z_max = range.z_max;
  const PatchSample s = SampleRasterPatches(a.Source(), b.Source(), o);
  EXPECT_FALSE(s.whole);
  EXPECT_EQ(s.patches.size(), 12u);  // 20000 / 40² = 12 strata of 100 x 75 cells
  EXPECT_LE(static_cast<int64_t>(s.reference.size()), o.max_reference_samples);
  std::set<std::pair<int32_t, int32_t>> strata;
  for (const SampleWindow& w : s.patches) {
    EXPECT_EQ(w.columns, 40);
    strata.insert({w.column / 100, w.row / 75});
  }
  EXPECT_EQ(strata.size(), s.patches.size());
  for (const Surface* side : {&s.reference, &s.moving}) {
    for (std::size_t i = 1; i < side->size(); ++i) {
      const RasterCell &u = side->raster_cell[i - 1], &v = side->raster_cell[i];
      ASSERT_TRUE(u.row < v.row || (u.row == v.row && u.column < v.column))
          << side->source << " " << i;
    }
  }
  for (const RasterCell& cell : s.reference.raster_cell) {
    const bool in = std::any_of(s.patches.begin(), s.patches.end(), [&](const SampleWindow& w) {
      return cell.column >= w.column && cell.column < w.column + w.columns && cell.row >= w.row &&
             cell.row < w.row + w.rows;
    });
    ASSERT_TRUE(in) << cell.column << ", " << cell.row;
  }
  // The moving sample overlaps the patches as the whole moving raster does.
  const MeasureSummary patches = Measure(s.reference, MovedWhole(s.moving, m), Options());
  const MeasureSummary whole = Measure(s.reference, MovedWhole(b.Whole(), m), Options());
  EXPECT_NEAR(patches.overlap_area, whole.overlap_area, 1e-9 * whole.overlap_area);
  EXPECT_NEAR(patches.rho_d, whole.rho_d, 1e-9 * whole.rho_d);
  EXPECT_GT(whole.overlap_area, 0.9 * 12 * 39 * 39);
  // The patches' data domain is their own complete cells: nothing bridges them.
  int64_t complete = 0;
  for (const SampleWindow& w : s.patches) {
    for (int32_t r = w.row; r + 1 < w.row + w.rows; ++r) {
      for (int32_t c = w.column; c + 1 < w.column + w.columns; ++c) {
        auto valid = [&](int32_t cc, int32_t rr) {
          return std::isfinite(a.values[size_t(rr) * a.columns + cc]);
        };
        complete += valid(c, r) && valid(c + 1, r) && valid(c, r + 1) && valid(c + 1, r + 1);
      }
    }
  }
  EXPECT_NEAR(patches.domain_area_a, static_cast<double>(complete), 1e-6);
}

TEST(TiledMotionTest, InvalidSampleOptionsAreRefused) {
  const Pair p = MakePair();
  PatchSampleOptions o;
  o.patch = 4;
  EXPECT_THROW(SampleRasterPatches(p.a.Source(), p.b.Source(), o), InputError);
  o = {};
  o.max_reference_samples = 0;
  EXPECT_THROW(SampleRasterPatches(p.a.Source(), p.b.Source(), o), InputError);
}

}  // namespace
}  // namespace surfreg
