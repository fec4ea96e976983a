#include "terrain/terrain.h"

#include <Eigen/Geometry>
#include <glog/logging.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <optional>

#include "measure/input_error.h"
#include "measure/tasks.h"
#include "terrain/tiled_measure.h"
#include "measure/weights.h"
#include "io/atomic_file.h"
#include "io/gdal_module.h"
#include "io/surface_reader.h"
#include "io/surface_reader_internal.h"
#include "io/plot.h"
#include "io/polygon_reader.h"
#include "terrain/terrain_internal.h"

namespace surfreg {
namespace {

using terrain_internal::CellSize;
using terrain_internal::CentroidInput;
using terrain_internal::ReadInputRaster;

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

struct OneInput {
  Surface surface;
  Crs crs;
  bool is_raster = false;
  Raster grid;
  std::vector<int64_t> cells;
};


// An InputError whose message already says where.
struct Named : InputError {
  using InputError::InputError;
};

// `origin` (may be null): a raster's samples are made relative to it, the
// reference's first setting it (RasterOrigin), as a tiled measure does.
// `read_before` (may be null): the input's raster, read already.
OneInput ReadOne(const TerrainRequest& config, const std::string& key, const Surface* given,
                 std::optional<std::array<double, 3>>* origin, Raster* read_before = nullptr) {
  const std::string& path = InputPath(config, key);
  const std::string crs_key = key + "_crs";
  OneInput in;
  Crs file_crs;
  try {
    if (given != nullptr) {
      in.surface = *given;
    } else if (IsRasterPath(path)) {
      in.grid = read_before != nullptr ? std::move(*read_before) : ReadInputRaster(config, key);
      in.is_raster = true;
      if (origin != nullptr && (key == "reference" || origin->has_value())) {
        if (!origin->has_value()) {
          *origin = RasterOrigin(in.grid.geotransform, in.grid.columns, in.grid.rows);
        }
        // RasterToSurface's samples (row-major, nodata skipped) about the
        // shared origin.
        in.surface = RasterBlockToSurface(in.grid.geotransform, {0, 0, in.grid.columns, in.grid.rows},
                                          in.grid.values.data(), in.grid.values.size(), **origin, in.grid.source,
                                          config.options.num_threads);
        if (in.surface.xy.empty()) throw InputError(in.grid.source + ": every cell is nodata");
        ValidateSurface(in.surface, ExecutionFor(config.options.num_threads));
        in.cells.resize(in.surface.size());
        for (std::size_t i = 0; i < in.cells.size(); ++i) {
          const RasterCell& cell = in.surface.raster_cell[i];
          in.cells[i] = static_cast<int64_t>(cell.row) * in.grid.columns + cell.column;
        }
      } else {
        in.surface = RasterToSurface(in.grid, &in.cells, 1.0, config.options.num_threads);
      }
      if (!in.grid.crs_wkt.empty()) file_crs = ParseCrs(in.grid.crs_wkt, path);
      in.grid.values.clear();
      in.grid.values.shrink_to_fit();
    } else {
      std::string crs;  // a LAS file's own; its errors name the key already
      try {
        in.surface = ReadInput(config, key, &crs);
      } catch (const InputError& e) {
        throw Named(e.what());
      }
      if (!crs.empty()) file_crs = ParseCrs(crs, path);
    }
  } catch (const Named& e) {
    throw InputError(e.what());
  } catch (const InputError& e) {
    throw InputError(config.Where(key) + ": " + e.what());
  }
  const std::string& crs_text = key == "reference" ? config.terrain.reference_crs : config.terrain.moving_crs;
  in.crs = ResolveCrs(file_crs, crs_text, config.Where(crs_key), path);
  return in;
}

Eigen::Vector3d Centroid(const Surface& s) {
  const std::array<double, 3> c = CentroidInput(s);
  return {c[0], c[1], c[2]};
}

// "m" when the frame is known to be metric, else the data's own units.
// The unit in figure labels: LengthUnit's, "data units" when not known.
std::string Units(const TerrainInputs& in) {
  const std::string unit = LengthUnit(in);
  return unit == "units" ? "data units" : unit;
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

// Stable terrain from the raster of key mask_raster (any grid and cell
// size, in the reference's CRS): 1 at a reference sample whose cell (the one
// containing it: the nearest cell centre) is valid and non-zero, 0 on
// nodata, zero cells and outside the raster. Samples are in input
// coordinates here, before any change of frame.
std::vector<double> MaskRasterWeights(const TerrainRequest& config, const Surface& reference,
                                      const Crs& reference_crs) {
  const std::string where = config.Where("mask_raster");
  const std::string& path = config.terrain.mask_raster;
  if (!config.mask.empty()) {
    throw InputError(where + ": give either a mask polygon ('mask') or a mask raster, not both");
  }
  Raster mask;
  try {
    mask = ReadRaster(path);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
  if (!mask.crs_wkt.empty() && reference_crs.kind != CrsKind::kNone) {
    const Crs crs = ParseCrs(mask.crs_wkt, where);
    if (crs.kind != reference_crs.kind || crs.name != reference_crs.name) {
      throw InputError(where + ": the CRS of " + path + " ('" + crs.name +
                       "') is not the reference's ('" + reference_crs.name + "')");
    }
  }
  const std::array<double, 6>& g = mask.geotransform;  // north-up (ReadRaster checks)
  std::vector<double> weight(reference.size(), 0.0);
  bool any = false;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const double x = reference.xy[i].x + reference.origin[0];
    const double y = reference.xy[i].y + reference.origin[1];
    const double column = std::floor((x - g[0]) / g[1]), row = std::floor((y - g[3]) / g[5]);
    if (!(column >= 0 && column < mask.columns && row >= 0 && row < mask.rows)) continue;
    const double value = mask.values[static_cast<std::size_t>(row) * mask.columns +
                                     static_cast<std::size_t>(column)];
    weight[i] = std::isnan(value) || value == 0.0 ? 0.0 : 1.0;
    any = any || weight[i] > 0.0;
  }
  if (!any) {
    throw InputError(where + ": no sample of the reference lies on a valid non-zero cell of " +
                     path);
  }
  return weight;
}

}  // namespace

Crs ResolveCrs(const Crs& from_file, const std::string& key_text, const std::string& key_where,
               const std::string& path) {
  if (key_text.empty()) return from_file;
  const Crs from_key = ParseCrs(key_text, key_where);
  if (from_file.kind != CrsKind::kNone &&
      (from_file.kind != from_key.kind || from_file.name != from_key.name)) {
    throw InputError(key_where + ": '" + from_key.name + "' disagrees with the CRS of " + path +
                     " ('" + from_file.name + "')");
  }
  return from_file.kind != CrsKind::kNone ? from_file : from_key;
}

void MaskToFrame(const TerrainInputs& in, const std::string& mask_crs_wkt, const std::string& where,
                 std::vector<MaskRing>* rings) {
  std::vector<std::array<double, 3>> points;
  for (const MaskRing& ring : *rings) {
    for (const auto& p : ring) points.push_back({p[0], p[1], 0.0});
  }
  if (!mask_crs_wkt.empty() && in.reference_crs.kind != CrsKind::kNone) {
    const Crs crs = ParseCrs(mask_crs_wkt, where);
    if (!SameCrs(crs, in.reference_crs)) {
      std::string error;
      if (!Gdal(where).transform_points(crs.wkt, in.reference_crs.wkt, &points, &error)) {
        throw InputError(where + ": cannot reproject the mask from CRS '" + crs.name + "' to '" +
                         in.reference_crs.name + "': " + error);
      }
    }
  }
  PointsToFrame(in.frame, in.reference_crs, &points);  // e.g. lon/lat into UTM or ENU
  std::size_t k = 0;
  for (MaskRing& ring : *rings) {
    for (auto& p : ring) p = {points[k][0], points[k][1]}, ++k;
  }
}

std::vector<bool> ChangeMaskNodes(const TerrainRequest& config, const TerrainInputs& in) {
  const std::string& path = config.terrain.change_mask;
  if (path.empty()) return {};
  const std::string where = config.Where("change_mask");
  MaskFile file;
  try {
    file = ReadMask(path);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
  MaskToFrame(in, file.crs_wkt, where, &file.rings);
  const MaskRegion region = MakeMaskRegion(file.rings, MaskMode::kInclude,
                                           {in.reference.origin[0], in.reference.origin[1]}, in.reference.xy);
  std::vector<bool> inside(in.reference.size());
  int64_t count = 0;
  for (std::size_t i = 0; i < inside.size(); ++i) count += (inside[i] = InsideMask(region, in.reference.xy[i]));
  if (count == 0) throw InputError(where + ": " + path + " holds none of the reference's samples");
  return inside;
}

TerrainInputs ReadTerrainInputs(const TerrainRequest& config, const Surface* given_reference,
                                const Surface* given_moving, bool tiled_origin,
                                std::optional<int> threads, bool compact) {
  const Execution execution = ExecutionFor(threads.value_or(config.options.num_threads));
  // Two raster files read first, side by side: kept whole when the pair
  // allows (compact), else the surfaces below are made from them.
  std::optional<Raster> read_reference, read_moving;
  if (compact && tiled_origin && given_reference == nullptr && given_moving == nullptr &&
      IsRasterPath(InputPath(config, "reference")) && IsRasterPath(InputPath(config, "moving"))) {
    TerrainInputs in;
    if (terrain_internal::ReadCompactRasters(config, execution, &in, &read_reference, &read_moving)) return in;
  }
  std::optional<std::array<double, 3>> origin;
  std::optional<std::array<double, 3>>* shared_origin = tiled_origin ? &origin : nullptr;
  // Side by side: the reference, and the moving surface. Two rasters share
  // the reference's origin (tiled_origin): the moving one's samples wait for
  // it (a promise kept, or broken by the reference's error).
  const bool moving_raster = given_moving == nullptr && IsRasterPath(InputPath(config, "moving"));
  const bool both_rasters = moving_raster && given_reference == nullptr && IsRasterPath(InputPath(config, "reference"));
  const auto read_named = [&](const std::string& key) {
    std::optional<Raster>& read = key == "reference" ? read_reference : read_moving;
    if (read.has_value()) return std::move(*read);
    try {
      return ReadInputRaster(config, key, execution.threads);
    } catch (const InputError& e) {
      throw InputError(config.Where(key) + ": " + e.what());  // as ReadOne names it
    }
  };
  std::promise<std::optional<std::array<double, 3>>> origin_kept;
  std::future<std::optional<std::array<double, 3>>> origin_of_reference = origin_kept.get_future();
  OneInput reference, moving;
  Raster moving_grid;
  RunOnTwoThreads(
      execution.parallel(),
      [&] {
        if (!both_rasters) {
          reference = ReadOne(config, "reference", given_reference, shared_origin);
          return;
        }
        Raster grid;
        try {
          grid = read_named("reference");
          if (shared_origin != nullptr) origin = RasterOrigin(grid.geotransform, grid.columns, grid.rows);
        } catch (...) {
          origin_kept.set_exception(std::current_exception());
          throw;
        }
        origin_kept.set_value(origin);
        reference = ReadOne(config, "reference", nullptr, shared_origin, &grid);
      },
      [&] {
        if (!moving_raster) {
          moving = ReadOne(config, "moving", given_moving, nullptr);  // no raster: no origin
          return;
        }
        moving_grid = read_named("moving");
        if (!both_rasters) return;  // a cloud reference: RasterToSurface's own origin, made after
        std::optional<std::array<double, 3>> moving_origin = origin_of_reference.get();
        moving = ReadOne(config, "moving", nullptr, shared_origin != nullptr ? &moving_origin : nullptr,
                         &moving_grid);
      });
  if (!config.terrain.mask_raster.empty()) {
    reference.surface.weight = MaskRasterWeights(config, reference.surface, reference.crs);
  }
  if (moving_raster && !both_rasters) moving = ReadOne(config, "moving", nullptr, shared_origin, &moving_grid);
  std::vector<double> sigma_reference =
      SigmaPerSample(config, "reference", reference.surface.size(), reference.grid, reference.cells);
  std::vector<double> sigma_moving =
      SigmaPerSample(config, "moving", moving.surface.size(), moving.grid, moving.cells);
  const bool sigma_grids = !config.terrain.dod_sigma.empty() || !config.terrain.dod_thresholded.empty();
  if (sigma_grids && !reference.is_raster) {
    const char* key = config.terrain.dod_sigma.empty() ? "dod_thresholded" : "dod_sigma";
    throw InputError(config.Where(key) + ": written on the reference raster's grid, but the reference (" +
                     config.reference + ") is not a raster");
  }
  const bool wants_grid = !config.terrain.dod.empty() || !config.terrain.dod_png.empty();
  if (wants_grid && !reference.is_raster) {
    throw InputError(config.Where(config.terrain.dod.empty() ? "dod_png" : "dod") +
                     ": the DoD is drawn on the reference raster's grid, but the reference (" +
                     config.reference + ") is not a raster");
  }
  TerrainInputs in;
  // A moving surface in another CRS is brought into the reference's first
  // (GDAL/PROJ): the frame, the motion and every output are the reference's.
  Crs moving_crs_now = moving.crs;
  if (reference.crs.kind != CrsKind::kNone && moving.crs.kind != CrsKind::kNone &&
      !SameCrs(reference.crs, moving.crs)) {
    ReprojectSurface(&moving.surface, moving.crs, reference.crs);
    moving_crs_now = reference.crs;
    in.moving_reprojected_from = moving.crs.name;
  }
  in.moving_centroid_input = CentroidInput(moving.surface);
  const std::string& frame = config.terrain.frame;
  const FrameChoice choice = FrameChoiceOf(frame);
  in.frame = ToCommonMetricFrame(&reference.surface, reference.crs, &moving.surface,
                                 moving_crs_now, choice);
  in.reference = std::move(reference.surface);
  in.moving = std::move(moving.surface);
  in.reference_crs = reference.crs;
  in.moving_crs = moving.crs;
  in.reference_is_raster = reference.is_raster;
  in.reference_grid = std::move(reference.grid);
  in.reference_cells = std::move(reference.cells);
  in.sigma_reference = std::move(sigma_reference);
  in.sigma_moving = std::move(sigma_moving);
  if (in.reference_is_raster) in.cell_size = CellSize(in.reference_grid, in.reference_crs);
  return in;
}

TerrainReport AnalyseTerrain(const TerrainRequest& config, const TerrainInputs& in,
                             const AlignResult& result) {
  MeasureOptions options;
  options.detect_change = true;
  options.keep_node_gaps = true;
  options.threads = config.options.num_threads;
  options.domain = config.options.domain;  // everything over Ω: dz, the DoD, cut/fill
  TerrainReport report;
  report.lod = config.terrain.lod;
  report.lod_source = config.Given("lod") ? "lod" : "none";
  options.level_of_detection = report.lod;
  const Surface moved = TransformSurface(in.moving, result.matrix, options.threads);  // keeps a raster's cells
  report.after = Measure(in.reference, moved, options);

  // Stable terrain: the mask of the registration (frame coordinates, with
  // its mode), or all; and of that, what stable auto found stable.
  report.stable.assign(in.reference.size(), true);
  if (config.options.weight == WeightMode::kMask && !config.options.mask.empty()) {
    const MaskRegion mask =
        MakeMaskRegion(config.options.mask, config.options.mask_mode,
                       {in.reference.origin[0], in.reference.origin[1]}, in.reference.xy);
    for (std::size_t i = 0; i < in.reference.size(); ++i) {
      report.stable[i] = InsideMask(mask, in.reference.xy[i]);
    }
  }
  // Or the mask raster's, as read into the reference's weights (μ is 0/1 at
  // the samples; between them it blurs over one triangle).
  if (!config.terrain.mask_raster.empty() && in.reference.weight.size() == in.reference.size()) {
    for (std::size_t i = 0; i < in.reference.size(); ++i) {
      report.stable[i] = in.reference.weight[i] > 0.5;
    }
  }
  if (result.stable.done && result.stable.flag.size() == in.reference.size()) {
    for (std::size_t i = 0; i < in.reference.size(); ++i) {
      report.stable[i] = report.stable[i] && result.stable.flag[i] != kChangedSample;
    }
  }
  report.stable_after = ComputeDzStatistics(report.after.dz_a, report.stable);
  // No level of detection given: the stable terrain's own noise sets it.
  if (!config.Given("lod") && !(config.terrain.lod_confidence > 0) && report.stable_after.count > 0 &&
      report.stable_after.nmad > 0) {
    report.lod = kAutoLodSigmas * report.stable_after.nmad;
    report.lod_source = "1.96 x NMAD of dz on stable terrain";
    options.level_of_detection = report.lod;
    report.after = Measure(in.reference, moved, options);
  }
  report.before = Measure(in.reference, in.moving, options);
  ReferenceCells cells;
  if (in.reference_is_raster) cells.grid = &in.reference_grid, cells.cells = &in.reference_cells;
  cells.stable = report.stable;
  cells.counted = ChangeMaskNodes(config, in);
  report.uncertainty = AnalyseChangeUncertainty(config, in.reference, moved, in.sigma_reference,
                                                in.sigma_moving, report.after, options, cells);
  AddRegistrationUncertainty(in.reference, in.moving, result.rotation_vector, result.translation, result.centre,
                             result.covariance, report.after, options, &report.uncertainty);
  report.stable_before = ComputeDzStatistics(report.before.dz_a, report.stable);
  report.spacing = in.cell_size > 0
                       ? in.cell_size
                       : std::sqrt(report.before.hull_area_a /
                                   static_cast<double>(std::max<int64_t>(1, report.before.n_points_a)));
  // The moving centroid is in the reference's CRS (a moving surface in
  // another CRS was reprojected into it).
  report.offset = TranslationAsGeographic(in.frame, in.reference_crs, in.moving_centroid_input,
                                          result.translation);

  const std::vector<double>& k = config.terrain.known_matrix;
  if (k.size() == 16) {
    Eigen::Matrix4d known;
    for (int i = 0; i < 16; ++i) known(i / 4, i % 4) = k[i];
    const KnownMotionError error = ErrorAgainstKnown(result.matrix, k, Centroid(in.moving));
    report.rotation_error_deg = error.rotation_deg;
    report.translation_error = error.translation;
    const Eigen::Vector4d c = Centroid(in.moving).homogeneous();
    const Eigen::Vector3d shift = (known * c).head<3>() - c.head<3>();
    report.known_translation = {shift[0], shift[1], shift[2]};
    report.known = true;
  }
  return report;
}

KnownMotionError ErrorAgainstKnown(const Eigen::Matrix4d& matrix, const std::vector<double>& k,
                                   const Eigen::Vector3d& centroid) {
  Eigen::Matrix4d known;
  for (int i = 0; i < 16; ++i) known(i / 4, i % 4) = k[i];
  const Eigen::Matrix3d difference = matrix.topLeftCorner<3, 3>() * known.topLeftCorner<3, 3>().transpose();
  const Eigen::Vector4d c = centroid.homogeneous();
  return {Eigen::AngleAxisd(difference).angle() * kDegrees, (matrix * c - known * c).head<3>().norm()};
}

void WriteTerrainOutputs(const TerrainRequest& config, const TerrainInputs& in,
                         const TerrainReport& report) {
  const TerrainSettings& t = config.terrain;
  Raster dod;
  if (in.reference_is_raster) {
    dod = in.reference_grid;
    dod.values.assign(static_cast<std::size_t>(dod.columns) * dod.rows, std::nan(""));
    for (std::size_t i = 0; i < in.reference_cells.size(); ++i) {
      dod.values[in.reference_cells[i]] = report.after.dz_a[i];
    }
  }
  if (!t.dod.empty()) WriteGeoTiff(t.dod, dod, config.Where("dod"));
  const ChangeUncertainty& u = report.uncertainty;
  if (!t.dod_sigma.empty() || !t.dod_thresholded.empty()) {
    Raster sigma = dod, thresholded = dod;
    for (std::size_t i = 0; i < in.reference_cells.size(); ++i) {
      const double dz = report.after.dz_a[i];
      const double limit = u.active ? u.threshold[i] : report.lod;
      sigma.values[in.reference_cells[i]] = u.active ? u.sigma_dod[i] : std::nan("");
      thresholded.values[in.reference_cells[i]] = std::isfinite(dz) && std::fabs(dz) <= limit ? 0.0 : dz;
    }
    if (!t.dod_sigma.empty()) WriteGeoTiff(t.dod_sigma, sigma, config.Where("dod_sigma"));
    if (!t.dod_thresholded.empty()) {
      WriteGeoTiff(t.dod_thresholded, thresholded, config.Where("dod_thresholded"));
    }
  }
  if (!t.dod_png.empty()) {
    GridField field = MapFieldOn(dod, {dod.values.begin(), dod.values.end()});
    // With a detection threshold, change within it is drawn as none (white).
    const bool thresholded = u.active || report.lod > 0;
    for (std::size_t i = 0; thresholded && i < in.reference_cells.size(); ++i) {
      const double dz = report.after.dz_a[i];
      const double limit = u.active ? u.threshold[i] : report.lod;
      if (std::isfinite(dz) && std::fabs(dz) <= limit) field.values[in.reference_cells[i]] = 0.0;
    }
    const bool degrees = in.reference_crs.kind == CrsKind::kGeographic;
    FigureText text{thresholded ? "Detected change after alignment (moving - reference; white: within the threshold)"
                                : "Difference after alignment (moving - reference)",
                    degrees ? "longitude (deg)" : "easting (" + Units(in) + ")",
                    degrees ? "latitude (deg)" : "northing (" + Units(in) + ")"};
    MapStyle style;
    style.colorbar_label = "dz (" + Units(in) + ")";
    WriteMapPng(t.dod_png, field, text, style, config.Where("dod_png"));
  }
  if (!t.variogram_png.empty() && u.spatial) {
    WriteVariogramPng(t.variogram_png, u.model, Units(in), config.Where("variogram_png"));
  }
  if (!t.histogram_png.empty()) {
    std::vector<Series> series(2);
    series[0].name = "before alignment";
    series[1].name = "after alignment";
    for (std::size_t i = 0; i < report.stable.size(); ++i) {
      if (!report.stable[i]) continue;
      series[0].x.push_back(report.before.dz_a[i]);
      series[1].x.push_back(report.after.dz_a[i]);
    }
    FigureText text{"dz on stable terrain (moving - reference)", "dz (" + Units(in) + ")",
                    "reference samples"};
    ChartStyle style;
    // The detection threshold (its median where it varies), dashed.
    const double limit = u.active ? u.budget.threshold_median : report.lod;
    if (limit > 0) {
      style.x_marks = {-limit, limit};
      text.title += ", change beyond the dashed threshold";
    }
    WriteHistogramPng(t.histogram_png, series, 60, text, style, config.Where("histogram_png"));
  }
  if (!t.change_csv.empty()) {
    std::string csv = "x,y,z,dz_before,dz_after,stable\n";
    char line[192];
    const Surface& r = in.reference;
    for (std::size_t i = 0; i < r.size(); ++i) {
      std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.9g,%.9g,%d\n",
                    r.xy[i].x + r.origin[0], r.xy[i].y + r.origin[1], r.z[i] + r.origin[2],
                    report.before.dz_a[i], report.after.dz_a[i], report.stable[i] ? 1 : 0);
      csv += line;
    }
    WriteFileAtomically(t.change_csv, csv, config.Where("change_csv"));
  }
}

GridField MapFieldOn(const Raster& grid, std::vector<double> values) {
  GridField field;
  field.columns = grid.columns;
  field.rows = grid.rows;
  field.values = std::move(values);
  const auto& g = grid.geotransform;
  field.x_min = std::min(g[0], g[0] + grid.columns * g[1]);
  field.x_max = std::max(g[0], g[0] + grid.columns * g[1]);
  field.y_min = std::min(g[3], g[3] + grid.rows * g[5]);
  field.y_max = std::max(g[3], g[3] + grid.rows * g[5]);
  return field;
}

std::string LengthUnit(const TerrainInputs& inputs) {
  if (inputs.frame.kind != GeoFrame::kAsGiven) return "m";
  if (inputs.reference_crs.kind != CrsKind::kProjected) return "units";
  if (inputs.reference_crs.metres_per_unit == 1.0) return "m";
  if (std::abs(inputs.reference_crs.metres_per_unit - 0.3048) < 1e-6) return "ft";
  return "units";
}

std::string TerrainSummary(const TerrainRequest& config, const TerrainInputs& in,
                           const TerrainReport& r) {
  const MeasureSummary& a = r.after;
  const double lod = r.lod;
  const std::string cube = Units(in) == "m" ? "m^3" : "units^3", square = Units(in) == "m" ? "m^2" : "units^2";
  std::string text = "frame:        " + in.frame.Describe() + "\n";
  if (!in.moving_reprojected_from.empty()) {
    text += "reprojected:  moving from " + in.moving_reprojected_from + " into the reference's " +
            in.reference_crs.name + "\n";
  }
  const GeographicOffset& o = r.offset;
  text += "shift:        east " + Number(o.east_m) + ", north " + Number(o.north_m) + ", up " +
          Number(o.up_m) + " m";
  if (std::isfinite(o.dlat_deg)) {
    text += " (dlat " + Number(o.dlat_deg) + " deg, dlon " + Number(o.dlon_deg) + " deg)";
  }
  text += "\n";
  if (r.known) {
    text += "known motion: centroid shift " + Number(r.known_translation[0]) + ", " +
            Number(r.known_translation[1]) + ", " + Number(r.known_translation[2]) +
            "; error: rotation " + Number(r.rotation_error_deg) + " deg, translation " +
            Number(r.translation_error) + " " + LengthUnit(in) + " (" + Number(r.translation_error / r.spacing) +
            " cells)\n";
  }
  text += "dz stable:    before " + DzStatisticsLine(r.stable_before, "") + "\n";
  text += "              after  " + DzStatisticsLine(r.stable_after, "") + "\n";
  // One cut/fill: with the DEMs' σ, the cellwise budget thresholded by
  // them (its figures with their uncertainty); otherwise the overlay's
  // beyond the level of detection. The JSON holds both (docs/terrain.md).
  if (r.uncertainty.active) {
    text += ChangeUncertaintySummary(config, r.uncertainty, Units(in));
  } else {
    text += "lod:          ";
    if (r.lod_source == "none") {
      text += "none (no stable terrain to measure the noise on): every gap counts as change";
    } else {
      text += Number(lod) + " " + Units(in) +
              (r.lod_source == "lod" ? " (key lod)" : " (" + r.lod_source + "; key lod sets it)");
    }
    text += "\ncut/fill:     fill " + Number(a.fill_detected) + ", cut " + Number(a.cut_detected) +
            ", net " + Number(a.fill_detected - a.cut_detected) + " " + cube;
    if (lod > 0) {
      text += " (|dz| > " + Number(lod) + ": +/- " + Number(lod * a.fill_area) + " / " +
              Number(lod * a.cut_area) + ")";
    }
    text += "\n              over areas of gain " + Number(a.fill_area) + " and loss " +
            Number(a.cut_area) + " " + square + " (overlap " + Number(a.overlap_area) + ")";
  }
  text += std::string("\ndomain:       ") + DomainKindName(a.domain_kind) +
          " (left out of the hulls: reference " + Number(a.excluded_area_a) + ", moving " +
          Number(a.excluded_area_b) + " " + square + ")";
  return text;
}

}  // namespace surfreg
