#include "terrain/terrain_measure.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/interrupt.h"
#include "io/raster_io.h"
#include "measure/input_error.h"
#include "measure/mask_region.h"
#include "measure/raster_pair.h"
#include "measure/tasks.h"
#include "terrain/terrain.h"

namespace surfreg {
namespace {

// Each finite value of `cells` replaced by the next of `values` in order,
// every other by NaN (A's samples are its valid cells in row-major order):
// by chunks, each starting at the count of valid cells before it.
void FillValidCells(const std::vector<double>& values, const Execution& execution, UninitializedVector<double>* cells) {
  UninitializedVector<double>& c = *cells;
  const int64_t n = static_cast<int64_t>(c.size());
  const int chunks = ChunksFor(n, kItemChunk * 16);
  std::vector<int64_t> first(chunks + 1, 0);
  ForEachChunk(execution, n, chunks, [&](int k, int64_t begin, int64_t end) {
    int64_t valid = 0;
    for (int64_t i = begin; i < end; ++i) valid += std::isfinite(c[i]) ? 1 : 0;
    first[k + 1] = valid;
  });
  for (int k = 0; k < chunks; ++k) first[k + 1] += first[k];
  if (first[chunks] != static_cast<int64_t>(values.size())) {
    throw std::logic_error("FillValidCells: " + std::to_string(first[chunks]) + " valid cells for " +
                           std::to_string(values.size()) + " values");
  }
  ForEachChunk(execution, n, chunks, [&](int k, int64_t begin, int64_t end) {
    int64_t next = first[k];
    for (int64_t i = begin; i < end; ++i) c[i] = std::isfinite(c[i]) ? values[next++] : std::nan("");
  });
}

}  // namespace

TerrainMeasure MeasureTerrain(const TerrainRequest& request, MeasureOptions options,
                              const std::string& mask_crs_wkt, const std::string& mask_where,
                              const Surface* a, const Surface* b) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  // Two rasters on one grid need only their heights (measure/raster_pair.h).
  const bool compact = options.weight == WeightMode::kUniform && options.volume == VolumeMode::kOverlay &&
                       options.domain.kind == DomainKind::kData && options.grid_shortcut;
  TerrainInputs inputs = ReadTerrainInputs(request, a, b, /*tiled_origin=*/true, options.threads, compact);
  TerrainMeasure m;
  m.frame = inputs.frame;
  m.crs_a = inputs.reference_crs;
  m.crs_b = inputs.moving_crs;
  m.b_reprojected_from = inputs.moving_reprojected_from;
  m.metric = LengthUnit(inputs) == "m";
  if (options.weight == WeightMode::kMask) {
    // The mask is drawn in its file's CRS (or A's): its vertices go where A went.
    MaskToFrame(inputs, mask_crs_wkt, mask_where, &options.mask);
  }
  if (options.detect_change) options.level_of_detection = request.terrain.lod;
  options.keep_node_gaps = true;  // dz at A's nodes: statistics, DoD, budget
  ThrowIfInterrupted();           // between the stages: reading done, measuring next
  m.read_s = std::chrono::duration<double>(Clock::now() - start).count();
  if (inputs.compact) {
    const auto heights = [](const Raster& r) {
      RasterHeights h;
      h.z = r.values.data();
      h.columns = r.columns, h.rows = r.rows;
      h.geotransform = r.geotransform;
      h.source = r.source;
      return h;
    };
    if (MeasureRasterPair(heights(inputs.reference_grid), heights(inputs.moving_grid), inputs.raster_origin,
                          options, &m.summary, /*node_areas=*/false)) {
      m.from_heights = true;
      inputs.moving_grid.values = {};  // the DoD reuses the reference's heights' memory
    } else {
      ExpandCompactRasters(request, &inputs);  // Measure has the answer, or the error
    }
  }
  if (!inputs.compact) m.summary = Measure(inputs.reference, inputs.moving, options);
  if (!request.terrain.dod.empty() && !inputs.reference_is_raster) {
    throw InputError(request.Where("dod") + ": the DoD is written on A's grid, but A is no raster");
  }
  // The DoD is written (GDAL compresses it) beside the dz statistics.
  const Execution execution = ExecutionFor(options.threads);
  RunBoth(
      execution, [&] { m.dz = ComputeDzStatistics(m.summary.dz_a, {}, execution); },
      [&] {
        if (request.terrain.dod.empty()) return;
        // B − A at A's cells, nodata outside Ω; compact: A's samples are its
        // valid cells in row-major order, written over its heights.
        Raster dod;
        if (inputs.compact) {
          dod = std::move(inputs.reference_grid);
          FillValidCells(m.summary.dz_a, execution, &dod.values);
        } else {
          dod = inputs.reference_grid;
          dod.values.assign(static_cast<std::size_t>(dod.columns) * dod.rows, std::nan(""));
          for (std::size_t i = 0; i < inputs.reference_cells.size(); ++i) {
            dod.values[inputs.reference_cells[i]] = m.summary.dz_a[i];
          }
        }
        WriteGeoTiff(request.terrain.dod, dod, request.Where("dod"), execution.threads);
      });
  ReferenceCells cells;
  if (inputs.reference_is_raster) cells.grid = &inputs.reference_grid, cells.cells = &inputs.reference_cells;
  if (options.weight == WeightMode::kMask && !options.mask.empty() && !inputs.compact) {
    // The mask (include: the stable terrain; exclude: the unstable part) is where dz is noise.
    const MaskRegion mask = MakeMaskRegion(options.mask, options.mask_mode,
                                           {inputs.reference.origin[0], inputs.reference.origin[1]},
                                           inputs.reference.xy);
    cells.stable.resize(inputs.reference.size());
    for (std::size_t i = 0; i < inputs.reference.size(); ++i) cells.stable[i] = InsideMask(mask, inputs.reference.xy[i]);
  }
  if (!inputs.compact) cells.counted = ChangeMaskNodes(request, inputs);
  m.uncertainty = AnalyseChangeUncertainty(request, inputs.reference, inputs.moving, inputs.sigma_reference,
                                           inputs.sigma_moving, m.summary, options, cells);
  if (!request.terrain.dod_sigma.empty()) {
    if (!inputs.reference_is_raster || !m.uncertainty.active) {
      throw InputError(request.Where("dod_sigma") + ": σ_DoD is written on A's grid: A must be a raster, "
                       "with a σ or error_model variogram");
    }
    Raster sigma = inputs.reference_grid;
    sigma.values.assign(static_cast<std::size_t>(sigma.columns) * sigma.rows, std::nan(""));
    for (std::size_t i = 0; i < inputs.reference_cells.size(); ++i) {
      sigma.values[inputs.reference_cells[i]] = m.uncertainty.sigma_dod[i];
    }
    WriteGeoTiff(request.terrain.dod_sigma, sigma, request.Where("dod_sigma"), execution.threads);
  }
  // Kept for the budget only (terrain_measure.h).
  m.summary.dz_b = {};
  if (!m.uncertainty.active) m.summary.node_area_a = {};
  return m;
}

}  // namespace surfreg
