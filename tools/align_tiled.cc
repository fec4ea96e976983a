#include "tools/align_tiled.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "measure/dz_statistics.h"
#include "measure/input_error.h"
#include "terrain/tiled_motion.h"
#include "tools/align_run.h"
#include "io/interrupt.h"
#include "tools/json_writer.h"
#include "tools/terrain_json.h"
#include "tools/measure_tiled.h"
#include "io/plot.h"
#include "terrain/terrain.h"
#include "terrain/change_uncertainty.h"
#include "tools/transform_json.h"

namespace surfreg {
namespace {

// Peak memory of the solve per reference sample of a patch sample (the
// moving side has about 1.6 times as many: its windows' margins), and of
// the program around it (GDAL loaded): whole-process peak RSS (GNU time) of
// samples of 6e4 to 2.6e5 was 64 MB + 2.8 to 3.4 KB per sample.
constexpr double kAlignBytesPerSample = 3500, kProgramBytes = 64.0 * 1024 * 1024;
// The least budget worth a tiled alignment: the program and 1e4 samples.
constexpr double kMinAlignBudget = 128.0 * 1024 * 1024;
// The solve's time grows with the sample, and 3e5 samples in patches
// spread over the whole DEM determine a rigid motion to 1e-5 cells on
// clean terrain (tests/bench/run_tiled_align_bench.sh).
constexpr int64_t kMaxSample = 300000, kMinSample = 10000;
constexpr int32_t kPatch = 128, kMargin = 16;
constexpr uint64_t kSeed = 1;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

RowMajorMatrix4 RowMajor(const Eigen::Matrix4d& m) {
  RowMajorMatrix4 out;
  for (int k = 0; k < 16; ++k) out[k] = m(k / 4, k % 4);
  return out;
}

TileDzRow RowOf(const TileDod& t, const std::array<double, 6>& gt) {
  TileDzRow row;
  row.tile = t.tile;
  row.column = t.window.column, row.row = t.window.row;
  row.columns = t.window.columns, row.rows = t.window.rows;
  const double u = t.window.column + 0.5 * t.window.columns, v = t.window.row + 0.5 * t.window.rows;
  row.x = gt[0] + u * gt[1] + v * gt[2];
  row.y = gt[3] + u * gt[4] + v * gt[5];
  const DzStatistics s = ComputeDzStatistics(t.dz);
  row.count = s.count;
  row.median = s.count > 0 ? s.median : kNaN;
  row.nmad = s.count > 0 ? s.nmad : kNaN;
  row.mean = s.count > 0 ? s.mean : kNaN;
  row.rmse = s.count > 0 ? s.rmse : kNaN;
  return row;
}

// The samples of `s` for which keep(i): a surface of its own, the order kept.
template <class Keep>
Surface SubsetOf(const Surface& s, Keep keep) {
  Surface out;
  out.origin = s.origin;
  out.source = s.source;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!keep(i)) continue;
    out.xy.push_back(s.xy[i]);
    out.z.push_back(s.z[i]);
    out.raster_cell.push_back(s.raster_cell[i]);
  }
  return out;
}

Eigen::Vector3d CentroidOf(const Surface& s) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < s.size(); ++i) sum += Eigen::Vector3d(s.xy[i].x, s.xy[i].y, s.z[i]);
  return Eigen::Vector3d(s.origin[0], s.origin[1], s.origin[2]) +
         sum / static_cast<double>(std::max<std::size_t>(s.size(), 1));
}

// Each patch of the sample aligned alone: its reference samples, the moving
// samples the whole motion puts over it (plus `margin` cells), translation
// only from the whole motion (a patch is too small a lever for rotations);
// its shift is where its motion and the whole one take its moving centroid.
std::vector<PatchShift> PatchShifts(const PatchSample& sample, const std::array<double, 6>& gt,
                                    const AlignResult& whole, AlignOptions options, double margin) {
  options.free = {false, false, false, true, true, true};
  // A patch's own shift, all of it: the whole motion already fitted the
  // stable terrain, and a patch's departure from it is what is measured.
  options.stable.mode = StableOptions::Mode::kAll;
  options.initial_reference_from_moving = Rigid3d::FromMatrix(whole.matrix);
  options.initial_rotation = options.initial_translation = {0, 0, 0};
  options.levels = 1;
  options.multi_start = 0;
  options.wide_search = AlignOptions::WideSearch::kNever;
  options.holdout_fraction = 0;
  options.stddev_subsamples = 0;
  options.compute_covariance = true;
  options.on_iteration = nullptr;
  options.on_stage = nullptr;
  const Surface& a = sample.reference;
  const Surface& b = sample.moving;
  std::vector<Point2> moved(b.size());  // B's samples under the whole motion (A's local frame)
  for (std::size_t i = 0; i < b.size(); ++i) {
    const Eigen::Vector4d p(b.xy[i].x + b.origin[0], b.xy[i].y + b.origin[1], b.z[i] + b.origin[2],
                            1.0);
    const Eigen::Vector4d q = whole.matrix * p;
    moved[i] = {q.x() - a.origin[0], q.y() - a.origin[1]};
  }
  std::vector<PatchShift> out;
  for (const SampleWindow& w : sample.patches) {
    ThrowIfInterrupted();
    PatchShift row;
    row.column = w.column, row.row = w.row, row.columns = w.columns, row.rows = w.rows;
    const double u = w.column + 0.5 * w.columns, v = w.row + 0.5 * w.rows;
    row.x = gt[0] + u * gt[1] + v * gt[2];
    row.y = gt[3] + u * gt[4] + v * gt[5];
    const Surface patch_a = SubsetOf(a, [&](std::size_t i) {
      const RasterCell& c = a.raster_cell[i];
      return c.column >= w.column && c.column < w.column + w.columns && c.row >= w.row &&
             c.row < w.row + w.rows;
    });
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const Point2& p : patch_a.xy)
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y),
      y1 = std::max(y1, p.y);
    const Surface patch_b = SubsetOf(b, [&](std::size_t i) {
      const Point2& p = moved[i];
      return p.x >= x0 - margin && p.x <= x1 + margin && p.y >= y0 - margin && p.y <= y1 + margin;
    });
    row.reference_samples = static_cast<int64_t>(patch_a.size());
    row.moving_samples = static_cast<int64_t>(patch_b.size());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    row.dx = row.dy = row.dz = row.sigma_dx = row.sigma_dy = row.sigma_dz = row.mean_abs_dz = nan;
    if (patch_a.size() >= 100 && patch_b.size() >= 100) {
      try {
        const AlignResult r = Align(patch_a, patch_b, options);
        row.verdict = VerdictName(r.verdict);
        const Eigen::Vector4d c = CentroidOf(patch_b).homogeneous();
        const Eigen::Vector4d d = r.matrix * c - whole.matrix * c;
        row.dx = d.x(), row.dy = d.y(), row.dz = d.z();
        row.sigma_dx = r.stddev[3], row.sigma_dy = r.stddev[4], row.sigma_dz = r.stddev[5];
        row.mean_abs_dz = r.after.mean_abs_dz;
      } catch (const InputError&) {
        row.verdict = "";  // no overlap there: no shift
      }
    }
    out.push_back(row);
  }
  return out;
}

void AddToOverview(const TileDod& t, double threshold, DodOverview* o) {
  for (int32_t r = 0; r < t.window.rows; ++r) {
    for (int32_t c = 0; c < t.window.columns; ++c) {
      const double dz = t.dz[static_cast<std::size_t>(r) * t.window.columns + c];
      if (!std::isfinite(dz)) continue;
      const std::size_t k = static_cast<std::size_t>((t.window.row + r) / o->factor) * o->columns +
                            (t.window.column + c) / o->factor;
      o->sum[k] += std::fabs(dz) <= threshold ? 0.0 : dz;
      ++o->count[k];
    }
  }
}

}  // namespace

void WriteDodOverviewPng(const AlignConfig& config, const DodOverview& o) {
  GridField field;
  field.columns = o.columns;
  field.rows = o.rows;
  field.values.resize(o.sum.size());
  for (std::size_t k = 0; k < o.sum.size(); ++k) {
    field.values[k] = o.count[k] > 0 ? o.sum[k] / o.count[k] : std::nan("");
  }
  // The blocks' extent: whole blocks of cells from the raster's corner.
  const auto& g = o.geotransform;
  const double width = static_cast<double>(o.columns) * o.factor * g[1];
  const double height = static_cast<double>(o.rows) * o.factor * g[5];
  field.x_min = std::min(g[0], g[0] + width), field.x_max = std::max(g[0], g[0] + width);
  field.y_min = std::min(g[3], g[3] + height), field.y_max = std::max(g[3], g[3] + height);
  const std::string units = o.metric ? "m" : "units";
  std::string title = o.thresholded
                          ? "Detected change after alignment (moving - reference; white: within the threshold)"
                          : "Difference after alignment (moving - reference)";
  if (o.factor > 1) {
    title += "; means of " + std::to_string(o.factor) + " x " + std::to_string(o.factor) + " cells";
  }
  const FigureText text{title, o.degrees ? "longitude (deg)" : "easting (" + units + ")",
                        o.degrees ? "latitude (deg)" : "northing (" + units + ")"};
  MapStyle style;
  style.colorbar_label = "dz (" + units + ")";
  WriteMapPng(config.terrain.dod_png, field, text, style, config.Where("dod_png"));
}

void CheckTiledAlign(const AlignConfig& config) {
  const std::string where = config.Where("max_memory");
  for (const char* key : {"reference", "moving"}) {
    const std::string path = AlignConfigValue(config, key);
    if (!IsRasterPath(path)) {
      throw InputError(where + ": a tiled alignment is for two rasters, but " + config.Where(key) +
                       " is '" + path + "', a cloud");
    }
  }
  const auto& w = config.terrain.window;
  if (w[0] != 0 || w[1] != 0 || w[2] != 0 || w[3] != 0) {
    throw InputError(where + " and " + config.Where("window") +
                     ": a window and tiles do not go together yet: cut the window out first "
                     "(gdal_translate -srcwin)");
  }
  for (const char* key : {"aligned", "histogram_png", "change_csv", "dod_sigma",
                          "dod_thresholded", "mask_raster", "change_mask"}) {
    if (!AlignConfigValue(config, key).empty()) {
      throw InputError(config.Where(key) + ": not with " + where +
                       " yet (it needs the whole surfaces); a tiled alignment writes output, "
                       "matrix_txt, log, dod, dod_png, tile_stats and patch_shifts");
    }
  }
  if (config.per_point_weights) {
    throw InputError(config.Where("weights") + ": per_point weights are not with " + where +
                     " yet");
  }
  if (config.terrain.error_model == "variogram") {
    throw InputError(config.Where("error_model") + ": the variogram error model is not with " + where +
                     " yet (align untiled, or measure the aligned DEMs with --tile)");
  }
  if (config.options.domain.kind == DomainKind::kHull) {
    throw InputError(config.Where("domain") +
                     ": a tiled alignment measures on the data domain only");
  }

}

TiledAlignRun AlignRasterTiles(
    const AlignConfig& given,
    const std::function<void(const AlignOptions::Iteration&)>& on_iteration) {
  CheckTiledAlign(given);
  AlignConfig config = given;
  const std::string where = config.Where("max_memory");
  const auto stage = [&config](const std::string& what) {
    if (config.options.on_stage) config.options.on_stage(what.c_str(), 0);
  };
  TiledAlignRun run;
  TiledAlignReport& report = run.report;
  report.budget = ParseMemorySize(config.terrain.max_memory, where);
  const TiledBudget change_budget =
      TiledBudgetOf(config, config.terrain.lod, where);  // before the solve
  if (report.budget < kMinAlignBudget) {
    throw InputError(where +
                     ": a tiled alignment needs at least 128M (the program and the solve on "
                     "10000 samples), got " +
                     config.terrain.max_memory);
  }
  const TiledPair pair = OpenTiledPair(config, where);  // the frame: as given, or UTM / ENU of lon/lat DEMs
  const RasterShape &a = pair.a, &b = pair.b;
  const TiledRasterSource& source_a = pair.source_a;
  const TiledRasterSource& source_b = pair.source_b;
  const auto& g = a.geotransform;
  report.cell_size = std::sqrt(std::fabs(g[1] * g[5] - g[2] * g[4]));
  if (a.crs.kind == CrsKind::kGeographic) {  // degrees to metres at the grid's middle latitude
    const double latitude = g[3] + 0.5 * a.rows * g[5];
    report.cell_size *= std::sqrt(111320.0 * std::cos(latitude * M_PI / 180) * 110574.0);
  }

  // The moving DEM's height range (a tilted motion's cover needs it), in
  // bands of rows a quarter of the budget holds (~64 bytes per sample read).
  stage("height range of " + config.moving);
  const double band_rows = report.budget / 4 / (64.0 * std::max(b.columns, 1));
  const SampleExtent extent =
      ExtentOfSamples(source_b, static_cast<int32_t>(std::clamp(band_rows, 1.0, double(b.rows))));
  const std::array<double, 2> range = {extent.z_min, extent.z_max};

  // The sample.
  stage("sampling patches");
  PatchSampleOptions sampling;
  sampling.max_reference_samples = std::clamp(
      static_cast<int64_t>(0.85 * (report.budget - kProgramBytes) / kAlignBytesPerSample),
      kMinSample, kMaxSample);
  sampling.patch = kPatch;
  sampling.margin = kMargin;
  sampling.seed = kSeed;
  if (!config.initial_matrix.empty()) {
    std::copy(config.initial_matrix.begin(), config.initial_matrix.end(), sampling.initial.begin());
  }
  sampling.moving_z_min = range[0], sampling.moving_z_max = range[1];
  PatchSample sample = SampleRasterPatches(source_a, source_b, sampling);
  report.patches = static_cast<int64_t>(sample.patches.size());
  report.patch = sample.whole ? 0 : sampling.patch;
  report.whole = sample.whole;
  report.reference_samples = static_cast<int64_t>(sample.reference.size());
  report.moving_samples = static_cast<int64_t>(sample.moving.size());

  // The solve, on the sample (a mask in its file's CRS brought into A's).
  ApplyInitialTransform(config, &config.options);
  if (config.options.weight == WeightMode::kMask) {
    TerrainInputs frame;
    frame.reference_crs = a.crs;
    frame.moving_crs = b.crs;
    MaskToFrame(frame, config.mask_crs_wkt, config.Where("mask"), &config.options.mask);
  }
  config.options.on_iteration = [&on_iteration](const AlignOptions::Iteration& it) {
    if (on_iteration) on_iteration(it);
    ThrowIfInterrupted();
  };
  run.result = Align(sample.reference, sample.moving, config.options);
  config.options.on_iteration = nullptr;
  double sum_xyz[3] = {0, 0, 0};
  for (std::size_t i = 0; i < sample.moving.size(); ++i) {
    sum_xyz[0] += sample.moving.xy[i].x, sum_xyz[1] += sample.moving.xy[i].y,
        sum_xyz[2] += sample.moving.z[i];
  }
  const double count = static_cast<double>(std::max<std::size_t>(sample.moving.size(), 1));
  const Eigen::Vector3d centroid(sample.moving.origin[0] + sum_xyz[0] / count,
                                 sample.moving.origin[1] + sum_xyz[1] / count,
                                 sample.moving.origin[2] + sum_xyz[2] / count);
  if (!config.terrain.patch_shifts.empty()) {
    stage("aligning each patch alone");
    report.patch_shifts =
        PatchShifts(sample, a.geotransform, run.result, config.options, kMargin * report.cell_size);
  }
  sample = PatchSample();  // its memory is the tiles' now

  // The whole pair after the motion, tile by tile.
  MeasureOptions measure;
  measure.domain = config.options.domain;
  measure.detect_change = true;
  measure.level_of_detection = config.terrain.lod;
  measure.threads = config.options.num_threads;
  // The map's overview: blocks of f × f cells, at most 1024 on a side.
  const double threshold = change_budget.active ? change_budget.threshold : config.terrain.lod;
  if (!config.terrain.dod_png.empty()) {
    DodOverview& o = run.overview;
    o.factor = std::max(1, (std::max(a.columns, a.rows) + 1023) / 1024);
    o.columns = (a.columns + o.factor - 1) / o.factor;
    o.rows = (a.rows + o.factor - 1) / o.factor;
    o.sum.assign(static_cast<std::size_t>(o.columns) * o.rows, 0.0);
    o.count.assign(o.sum.size(), 0);
    o.geotransform = a.geotransform;
    o.thresholded = threshold > 0;
    o.metric = pair.frame.kind != GeoFrame::kAsGiven ||
               (a.crs.kind == CrsKind::kProjected && a.crs.metres_per_unit == 1.0);
    o.degrees = a.crs.kind == CrsKind::kGeographic;
  }
  MovedRaster moved;
  moved.matrix = RowMajor(run.result.matrix);
  moved.z_min = range[0], moved.z_max = range[1];
  TiledParts parts;
  parts.checkpoint = false;
  const auto start = std::chrono::steady_clock::now();
  double last = -1;
  const TiledMeasureRun after = MeasureRasterTiles(
      config, measure, "", config.Where("mask"), TileForMemory(report.budget - kProgramBytes),
      where, parts,
      [&](const TiledProgress& p) {
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (p.total == 0 || (seconds < last + 1.0 && p.done < p.total)) return;
        last = seconds;
        char line[160];
        const double eta = p.done > 0 ? seconds * (p.total - p.done) / p.done : 0.0;
        std::snprintf(line, sizeof line,
                      "measuring after the motion: tiles, %lld of %lld, ETA %.0f s",
                      static_cast<long long>(p.done), static_cast<long long>(p.total), eta);
        stage(line);
      },
      &moved,
      [&](const TileDod& t) {
        report.tile_rows.push_back(RowOf(t, a.geotransform));
        if (!config.terrain.dod_png.empty()) AddToOverview(t, threshold, &run.overview);
      },
      change_budget);
  const ChangeUncertainty uncertainty = TiledChangeUncertainty(after.part, config);
  report.after = after.summary;
  report.tile = after.tile;
  report.tiles = after.tiles;
  double sum = 0, sum_squares = 0;
  for (const TileDzRow& row : report.tile_rows) {
    if (row.count == 0) continue;
    report.dz_count += row.count;
    sum += row.mean * row.count;
    sum_squares += row.rmse * row.rmse * row.count;
  }
  report.dz_mean = report.dz_count > 0 ? sum / report.dz_count : kNaN;
  report.dz_rmse = report.dz_count > 0 ? std::sqrt(sum_squares / report.dz_count) : kNaN;

  if (config.terrain.known_matrix.size() == 16) {
    const KnownMotionError error =
        ErrorAgainstKnown(run.result.matrix, config.terrain.known_matrix, centroid);
    report.rotation_error_deg = error.rotation_deg;
    report.translation_error = error.translation;
    report.known = true;
  }

  const MeasureSummary& s = report.after;
  JsonObject sampled;
  sampled.Int("patches", report.patches)
      .Int("patch", report.patch)
      .Raw("whole", report.whole ? "true" : "false")
      .Int("reference_samples", report.reference_samples)
      .Int("moving_samples", report.moving_samples)
      .Int("seed", static_cast<int64_t>(kSeed))
      .Int("patch_shifts", static_cast<int64_t>(report.patch_shifts.size()));
  JsonObject whole = DetectedChangeJson(s);
  whole.Number("rho_d", s.rho_d)
      .Number("rho_d_axial", s.rho_d_axial)
      .Number("mean_abs_dz", s.mean_abs_dz)
      .Number("overlap_area", s.overlap_area)
      .Number("signed_volume", s.signed_volume)
      .Number("domain_area_reference", s.domain_area_a)
      .Number("domain_area_moving", s.domain_area_b)
      .Int("n_overlap_nodes", s.n_overlap_nodes)
      .Int("dz_count", report.dz_count)
      .Number("dz_mean", report.dz_mean)
      .Number("dz_rmse", report.dz_rmse);
  if (uncertainty.active) whole.Object("uncertainty", ChangeUncertaintyJson(config, uncertainty));
  JsonObject tiled;
  tiled.String("frame", pair.frame.Describe())
      .Number("max_memory_bytes", report.budget)
      .Object("sample", sampled)
      .Int("tile", report.tile)
      .Int("tiles", report.tiles)
      .Number("cell_size", report.cell_size)
      .Object("after", whole);
  if (report.known) {
    tiled.Object("known", KnownErrorJson({report.rotation_error_deg, report.translation_error},
                                         report.cell_size));
  }
  run.json = TransformJson(config, run.result, "\"tiled\": " + tiled.str());
  return run;
}

std::string TileStatsCsv(const std::vector<TileDzRow>& rows) {
  std::string csv = "tile,column,row,columns,rows,x,y,samples,dz_median,dz_nmad,dz_mean,dz_rmse\n";
  char line[320];
  for (const TileDzRow& r : rows) {
    std::snprintf(line, sizeof line, "%lld,%d,%d,%d,%d,%.17g,%.17g,%lld,%.9g,%.9g,%.9g,%.9g\n",
                  static_cast<long long>(r.tile), r.column, r.row, r.columns, r.rows, r.x, r.y,
                  static_cast<long long>(r.count), r.median, r.nmad, r.mean, r.rmse);
    csv += line;
  }
  return csv;
}

std::string PatchShiftsCsv(const std::vector<PatchShift>& rows) {
  std::string csv =
      "patch,column,row,columns,rows,x,y,reference_samples,moving_samples,verdict,dx,dy,dz,sigma_"
      "dx,"
      "sigma_dy,sigma_dz,mean_abs_dz\n";
  char line[512];
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const PatchShift& r = rows[k];
    std::snprintf(line, sizeof line,
                  "%zu,%d,%d,%d,%d,%.17g,%.17g,%lld,%lld,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                  k, r.column, r.row, r.columns, r.rows, r.x, r.y,
                  static_cast<long long>(r.reference_samples),
                  static_cast<long long>(r.moving_samples), r.verdict.c_str(), r.dx, r.dy, r.dz,
                  r.sigma_dx, r.sigma_dy, r.sigma_dz, r.mean_abs_dz);
    csv += line;
  }
  return csv;
}

std::string TiledAlignSummary(const TiledAlignReport& r) {
  char text[1024];
  int n = std::snprintf(
      text, sizeof text,
      "tiled:        %s, %lld reference and %lld moving samples solved on; after the motion, "
      "%lld tiles of %d cells:\n"
      "  whole pair: rho_d %.9g, overlap %.9g, dz over %lld samples: mean %.4g, RMSE %.4g\n",
      r.whole
          ? "the whole pair fitted the budget"
          : ("" + std::to_string(r.patches) + " patches of " + std::to_string(r.patch) + " cells")
                .c_str(),
      static_cast<long long>(r.reference_samples), static_cast<long long>(r.moving_samples),
      static_cast<long long>(r.tiles), r.tile, r.after.rho_d, r.after.overlap_area,
      static_cast<long long>(r.dz_count), r.dz_mean, r.dz_rmse);
  std::string out(text, std::min<std::size_t>(n, sizeof text - 1));
  if (r.known) {
    std::snprintf(
        text, sizeof text,
        "  error against the known motion: rotation %.3g deg, translation %.3g (%.3g cells)\n",
        r.rotation_error_deg, r.translation_error, r.translation_error / r.cell_size);
    out += text;
  }
  return out;
}

}  // namespace surfreg
