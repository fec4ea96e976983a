// Two DEM rasters kept whole for the compact measure (terrain.h,
// TerrainInputs::compact; measure/raster_pair.h), and made into surfaces
// when a measure needs them after all.
#include <cmath>
#include <exception>

#include "io/surface_reader.h"
#include "io/surface_reader_internal.h"
#include "measure/input_error.h"
#include "terrain/terrain_internal.h"
#include "terrain/tiled_measure.h"

namespace surfreg {
namespace terrain_internal {

namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

}  // namespace

Raster ReadInputRaster(const TerrainRequest& config, const std::string& key, int threads) {
  const std::string& path = InputPath(config, key);
  // A raster has no classes or columns to pick.
  io_internal::CheckOptionsFit(InputReadOptions(config, key), io_internal::OptionFit::kOther,
                               "raster", path);
  RasterReadOptions options;
  options.band = config.terrain.band;
  const auto& w = config.terrain.window;
  options.window = {w[0], w[1], w[2], w[3]};
  options.threads = threads;
  return ReadRaster(path, options);
}

std::array<double, 3> CentroidInput(const Surface& s) {
  std::array<double, 3> sum = {0, 0, 0};
  for (std::size_t i = 0; i < s.size(); ++i) {
    sum[0] += s.xy[i].x, sum[1] += s.xy[i].y, sum[2] += s.z[i];
  }
  const double n = static_cast<double>(s.size());
  return {s.origin[0] + sum[0] / n, s.origin[1] + sum[1] / n, s.origin[2] + sum[2] / n};
}

double CellSize(const Raster& grid, const Crs& crs) {
  double dx = std::fabs(grid.geotransform[1]), dy = std::fabs(grid.geotransform[5]);
  if (crs.kind == CrsKind::kGeographic) {
    const double latitude = grid.geotransform[3] + 0.5 * grid.rows * grid.geotransform[5];
    dx *= 111320.0 * std::cos(latitude / kDegrees);
    dy *= 110574.0;
  } else {
    dx *= crs.metres_per_unit, dy *= crs.metres_per_unit;
  }
  return std::sqrt(dx * dy);
}

bool ReadCompactRasters(const TerrainRequest& config, const Execution& execution,
                        TerrainInputs* inputs, std::optional<Raster>* reference,
                        std::optional<Raster>* moving) {
  Raster grids[2];
  std::exception_ptr errors[2];
  const char* const keys[2] = {"reference", "moving"};
  const auto read = [&](int k) {
    try {
      grids[k] = ReadInputRaster(config, keys[k], execution.threads);
    } catch (const InputError& e) {
      errors[k] = std::make_exception_ptr(InputError(config.Where(keys[k]) + ": " + e.what()));
    } catch (...) {
      errors[k] = std::current_exception();
    }
  };
  RunBoth(
      execution, [&] { read(0); }, [&] { read(1); });
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  // The CRSs as ReadOne resolves them: the file's (its errors named by the
  // key), or the key's.
  Crs crs[2];
  for (int k = 0; k < 2; ++k) {
    const std::string& path = InputPath(config, keys[k]);
    Crs file_crs;
    try {
      if (!grids[k].crs_wkt.empty()) file_crs = ParseCrs(grids[k].crs_wkt, path);
    } catch (const InputError& e) {
      throw InputError(config.Where(keys[k]) + ": " + e.what());
    }
    const std::string& text = k == 0 ? config.terrain.reference_crs : config.terrain.moving_crs;
    crs[k] = ResolveCrs(file_crs, text, config.Where(std::string(keys[k]) + "_crs"), path);
  }
  // Coordinates used as they are: no CRS, or one projected CRS (kAsGiven);
  // and nothing per sample but the heights.
  const bool as_given = (crs[0].kind == CrsKind::kNone && crs[1].kind == CrsKind::kNone) ||
                        (crs[0].kind == CrsKind::kProjected && crs[1].kind == CrsKind::kProjected &&
                         SameCrs(crs[0], crs[1]));
  const TerrainSettings& t = config.terrain;
  if (!as_given || !t.sigma_reference.empty() || !t.sigma_moving.empty() || t.error_model == "variogram" || !t.change_mask.empty() ||
      !t.mask_raster.empty() || !t.dod_sigma.empty() || !t.dod_thresholded.empty()) {
    *reference = std::move(grids[0]);
    *moving = std::move(grids[1]);
    return false;
  }
  TerrainInputs& in = *inputs;
  // The frame's checks and description, as for surfaces (only their names
  // are read for kAsGiven).
  Surface named_reference, named_moving;
  named_reference.source = grids[0].source, named_moving.source = grids[1].source;
  const FrameChoice choice = FrameChoiceOf(t.frame);
  in.frame = ToCommonMetricFrame(&named_reference, crs[0], &named_moving, crs[1], choice);
  in.reference_crs = crs[0];
  in.moving_crs = crs[1];
  in.reference_is_raster = true;
  in.raster_origin = RasterOrigin(grids[0].geotransform, grids[0].columns, grids[0].rows);
  in.cell_size = CellSize(grids[0], crs[0]);
  in.reference.source = grids[0].source;
  in.moving.source = grids[1].source;
  in.reference_grid = std::move(grids[0]);
  in.moving_grid = std::move(grids[1]);
  in.compact = true;
  return true;
}

}  // namespace terrain_internal

void ExpandCompactRasters(const TerrainRequest& config, TerrainInputs* inputs) {
  TerrainInputs& in = *inputs;
  if (!in.compact) return;
  const auto make = [&](const char* key, Raster* grid, std::vector<int64_t>* cells) {
    Surface s;
    try {
      s = RasterBlockToSurface(grid->geotransform, {0, 0, grid->columns, grid->rows}, grid->values.data(),
                               grid->values.size(), in.raster_origin, grid->source, config.options.num_threads);
      if (s.xy.empty()) throw InputError(grid->source + ": every cell is nodata");
      ValidateSurface(s, ExecutionFor(config.options.num_threads));
    } catch (const InputError& e) {
      throw InputError(config.Where(key) + ": " + e.what());
    }
    if (cells != nullptr) {
      cells->resize(s.size());
      for (std::size_t i = 0; i < cells->size(); ++i) {
        const RasterCell& cell = s.raster_cell[i];
        (*cells)[i] = static_cast<int64_t>(cell.row) * grid->columns + cell.column;
      }
    }
    grid->values.clear();
    grid->values.shrink_to_fit();
    return s;
  };
  in.reference = make("reference", &in.reference_grid, &in.reference_cells);
  in.moving = make("moving", &in.moving_grid, nullptr);
  in.moving_centroid_input = terrain_internal::CentroidInput(in.moving);
  in.compact = false;
}

}  // namespace surfreg
