#include "tools/align_run.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "measure/input_error.h"
#include "measure/tasks.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "io/las_writer.h"
#include "io/raster_io.h"
#include "io/raster_resample.h"
#include "io/surface_writer.h"
#include "io/plot.h"
#include "tools/run_align_terrain.h"
#include "tools/sweep.h"
#include "tools/transform_file.h"
#include "tools/transform_json.h"

namespace surfreg {
namespace {

bool IsPngPath(const std::string& path) {
  std::string extension = path.substr(std::min(path.size(), path.find_last_of('.')));
  for (char& ch : extension) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return extension == ".png";
}

// AlignConfig::stable_map: the reference's samples with their StableFlag.
void WriteStableMap(const AlignConfig& config, const TerrainInputs& inputs, const AlignResult& result) {
  const Surface& reference = inputs.reference;
  const std::string where = config.Where("stable_map");
  std::vector<uint8_t> flag = result.stable.flag;
  if (flag.size() != reference.size()) flag.assign(reference.size(), kStableSample);  // stable all: everything used
  if (IsPngPath(config.stable_map)) {  // a raster reference: checked before the alignment
    const Raster& grid = inputs.reference_grid;
    GridField field =
        MapFieldOn(grid, std::vector<double>(static_cast<std::size_t>(grid.columns) * grid.rows, std::nan("")));
    // Two classes on a diverging scale: stable −1 (blue), changed +1 (red);
    // outside the overlap no data (grey).
    for (std::size_t i = 0; i < inputs.reference_cells.size(); ++i) {
      if (flag[i] != kOutsideOverlap) field.values[inputs.reference_cells[i]] = flag[i] == kStableSample ? -1.0 : 1.0;
    }
    const bool degrees = inputs.reference_crs.kind == CrsKind::kGeographic;
    const std::string unit = LengthUnit(inputs);
    char title[160];
    std::snprintf(title, sizeof title, "Stable terrain: %.1f%% of the overlap, %d changed region%s left out",
                  100 * result.stable.stable_share, result.stable.regions, result.stable.regions == 1 ? "" : "s");
    FigureText text{title, degrees ? "longitude (deg)" : "easting (" + unit + ")",
                    degrees ? "latitude (deg)" : "northing (" + unit + ")"};
    MapStyle style;
    style.limit = 1;
    style.colorbar_label = "-1 stable (fitted), +1 changed (left out)";
    WriteMapPng(config.stable_map, field, text, style, where);
    return;
  }
  if (IsGeoTiffPath(config.stable_map)) {  // a raster reference: checked before the alignment
    Raster map = inputs.reference_grid;
    map.values.assign(static_cast<std::size_t>(map.columns) * map.rows, std::nan(""));
    for (std::size_t i = 0; i < inputs.reference_cells.size(); ++i) {
      if (flag[i] != kOutsideOverlap) map.values[inputs.reference_cells[i]] = flag[i] == kStableSample ? 1.0 : 0.0;
    }
    WriteGeoTiff(config.stable_map, map, where);
    return;
  }
  std::string text = "# x y z stable (1 stable, 0 changed: left out of the fit, 2 outside the overlap); " +
                     std::to_string(result.stable.changed_samples) + " changed of " +
                     std::to_string(result.stable.changed_samples + result.stable.stable_samples) + "\n";
  char line[160];
  for (std::size_t i = 0; i < reference.size(); ++i) {
    std::snprintf(line, sizeof line, "%.10g %.10g %.10g %d\n", reference.xy[i].x + reference.origin[0],
                  reference.xy[i].y + reference.origin[1], reference.z[i] + reference.origin[2], flag[i]);
    text += line;
  }
  WriteFileAtomically(config.stable_map, text, where);
}

std::string LogCsv(const std::vector<AlignOptions::Iteration>& log) {
  std::string csv = "level,start,cost_kind,iteration,cost,step_norm,gradient_norm,seconds\n";
  char line[256];
  for (const AlignOptions::Iteration& it : log) {
    std::snprintf(line, sizeof(line), "%d,%d,%s,%d,%.17g,%.17g,%.17g,%.6f\n", it.level, it.start,
                  it.cost_name, it.iteration, it.cost, it.step_norm, it.gradient_norm, it.seconds);
    csv += line;
  }
  return csv;
}

// Comment lines of the aligned surface file: where it came from, the frame
// of its coordinates and of the matrix (geographic inputs were moved into a
// metric one, terrain/geo_frame.h), the matrix.
std::vector<std::string> AlignedComments(const AlignConfig& config, const AlignResult& r,
                                         const GeoFrame& frame) {
  const bool input_frame = frame.kind == GeoFrame::kAsGiven;
  const std::string where = input_frame ? "input coordinates" : frame.Describe();
  std::vector<std::string> lines = {
      "aligned: " + config.moving + " moved onto " + config.reference + " by surfreg align",
      "coordinates: " + where,
      std::string("verdict: ") + VerdictName(r.verdict) + "; matrix (moving -> reference, " +
          (input_frame ? "input coordinates" : "in those coordinates") + ", row-major):"};
  for (int i = 0; i < 4; ++i) {
    char row[160];
    std::snprintf(row, sizeof(row), "  %.17g %.17g %.17g %.17g", r.matrix(i, 0), r.matrix(i, 1),
                  r.matrix(i, 2), r.matrix(i, 3));
    lines.push_back(row);
  }
  return lines;
}

// The files an align run writes, for its "writing ..." stage line.
std::string OutputList(const AlignConfig& config) {
  std::string list;
  for (const char* key : {"output", "matrix_txt", "aligned", "log", "dod", "dod_png", "histogram_png",
                          "change_csv", "dod_sigma", "dod_thresholded", "tile_stats", "patch_shifts"}) {
    const std::string path = AlignConfigValue(config, key);
    if (!path.empty()) list += (list.empty() ? "" : ", ") + path;
  }
  return list.empty() ? "nothing (no output key)" : list;
}

// Two DEMs at bounded memory (tools/align_tiled.h).
AlignRun AlignTiled(AlignConfig config,
                    const std::function<void(const AlignOptions::Iteration&)>& on_iteration) {
  AlignRun run;
  run.terrain = true;
  std::vector<AlignOptions::Iteration> seen;  // the log, should the solve be interrupted
  TiledAlignRun tiled;
  try {
    tiled = AlignRasterTiles(config, [&seen, &on_iteration](const AlignOptions::Iteration& it) {
      seen.push_back(it);
      if (on_iteration) on_iteration(it);
    });
  } catch (const Interrupted&) {
    if (!config.log.empty() && !seen.empty()) {
      WriteFileAtomically(config.log, LogCsv(seen), config.Where("log"));
    }
    throw;
  }
  run.result = std::move(tiled.result);
  run.json = std::move(tiled.json);
  if (config.options.on_stage) config.options.on_stage(("writing " + OutputList(config)).c_str(), 0);
  if (!config.output.empty()) WriteFileAtomically(config.output, run.json, config.Where("output"));
  if (!config.matrix_txt.empty()) {
    WriteFileAtomically(config.matrix_txt, MatrixText(run.result.matrix), config.Where("matrix_txt"));
  }
  if (!config.terrain.dod_png.empty()) WriteDodOverviewPng(config, tiled.overview);
  if (!config.terrain.tile_stats.empty()) {
    WriteFileAtomically(config.terrain.tile_stats, TileStatsCsv(tiled.report.tile_rows),
                        config.Where("tile_stats"));
  }
  if (!config.terrain.patch_shifts.empty()) {
    WriteFileAtomically(config.terrain.patch_shifts, PatchShiftsCsv(tiled.report.patch_shifts),
                        config.Where("patch_shifts"));
  }
  if (!config.log.empty()) {
    WriteFileAtomically(config.log, LogCsv(run.result.log.empty() ? seen : run.result.log),
                        config.Where("log"));
  }
  run.tiled = std::move(tiled.report);
  run.config = std::move(config);
  return run;
}

}  // namespace

std::string AlignProgressLine(const AlignOptions::Iteration& it, int levels) {
  char line[320];
  std::snprintf(line, sizeof(line),
                "align: level %d/%d start %d %s iteration %3d  cost %.9g  step %.3g  gradient %.3g  "
                "%.2f s\n",
                it.level + 1, levels, it.start, it.cost_name, it.iteration, it.cost, it.step_norm,
                it.gradient_norm, it.seconds);
  return line;
}

void ApplyInitialTransform(const AlignConfig& config, AlignOptions* options) {
  if (config.initial_matrix.empty()) return;
  Eigen::Matrix4d m;
  for (int k = 0; k < 16; ++k) m(k / 4, k % 4) = config.initial_matrix[k];
  options->initial_reference_from_moving = Rigid3d::FromMatrix(m);
}

AlignRun AlignSurfaces(AlignConfig config, std::optional<Surface> reference,
                       std::optional<Surface> moving,
                       const std::function<void(const AlignOptions::Iteration&)>& on_iteration) {
  AlignRun run;
  if (!config.terrain.max_memory.empty()) return AlignTiled(std::move(config), on_iteration);
  for (const char* key : {"tile_stats", "patch_shifts"}) {
    if (!AlignConfigValue(config, key).empty()) throw InputError(config.Where(key) + ": needs max_memory");
  }
  // Terrain inputs (rasters, CRSs, change outputs) go through terrain/terrain.h.
  run.terrain = config.terrain.Active(config.reference, config.moving);
  TerrainInputs& inputs = run.inputs;
  if (run.terrain) {
    inputs = ReadTerrainInputs(config, reference ? &*reference : nullptr,
                               moving ? &*moving : nullptr);
    // A mask raster became the reference's per-sample weights: μ for Align.
    if (!config.terrain.mask_raster.empty()) config.options.weight = WeightMode::kPerPoint;
    // A mask drawn in its file's CRS (or the reference's) goes where the reference went.
    if (config.options.weight == WeightMode::kMask) {
      MaskToFrame(inputs, config.mask_crs_wkt, config.Where("mask"), &config.options.mask);
    }
  } else {
    // Side by side; of two bad inputs the reference is named, as in order.
    std::exception_ptr error[2];
    const auto read = [&](int k, std::optional<Surface>* given, Surface* out) {
      try {
        *out = *given ? std::move(**given) : ReadInput(config, k == 0 ? "reference" : "moving");
      } catch (...) {
        error[k] = std::current_exception();
      }
    };
    RunBoth(ExecutionFor(config.options.num_threads), [&] { read(0, &reference, &inputs.reference); },
            [&] { read(1, &moving, &inputs.moving); });
    for (const std::exception_ptr& e : error) {
      if (e) std::rethrow_exception(e);
    }
  }
  // An aligned GeoTIFF is on the reference raster's grid, in its CRS.
  // Checked before the long work.
  if (IsGeoTiffPath(config.aligned) && !inputs.reference_is_raster) {
    throw InputError(config.Where("aligned") + ": a GeoTIFF is resampled onto the reference's grid, "
                     "but the reference is no raster; write .ply, .xyz or .las instead");
  }
  if ((IsGeoTiffPath(config.stable_map) || IsPngPath(config.stable_map)) && !inputs.reference_is_raster) {
    throw InputError(config.Where("stable_map") + ": a " + (IsPngPath(config.stable_map) ? "PNG map" : "GeoTIFF") +
                     " is on the reference's grid, but the reference is no raster; write .xyz instead");
  }
  if (IsPngPath(config.stable_map)) RequirePngFigures(config.Where("stable_map"));
  ApplyInitialTransform(config, &config.options);
  std::vector<AlignOptions::Iteration> seen;  // the log, should Align not return one
  config.options.on_iteration = [&seen, &on_iteration](const AlignOptions::Iteration& it) {
    seen.push_back(it);
    if (on_iteration) on_iteration(it);
    ThrowIfInterrupted();  // the solver's iterations are the long loop
  };
  try {
    run.result = Align(inputs.reference, inputs.moving, config.options);
  } catch (const Interrupted&) {
    // The iterations so far are complete rows: worth keeping.
    if (!config.log.empty()) WriteFileAtomically(config.log, LogCsv(seen), config.Where("log"));
    throw;
  }
  config.options.on_iteration = nullptr;  // it refers to this frame's locals
  const AlignResult& result = run.result;

  const auto stage = [&config](const std::string& what) {
    if (config.options.on_stage) config.options.on_stage(what.c_str(), 0);
  };
  if (run.terrain) {
    stage("terrain change");
    run.report = AnalyseTerrain(config, inputs, result);
  }
  stage("writing " + OutputList(config));
  run.json = TransformJson(config, result,
                           run.terrain ? TerrainJsonMember(config, inputs, run.report) : "");
  if (run.terrain) WriteTerrainOutputs(config, inputs, run.report);
  if (!config.output.empty()) WriteFileAtomically(config.output, run.json, config.Where("output"));
  if (!config.matrix_txt.empty()) {
    WriteFileAtomically(config.matrix_txt, MatrixText(result.matrix), config.Where("matrix_txt"));
  }
  if (IsGeoTiffPath(config.aligned)) {
    const Surface aligned = TransformSurface(inputs.moving, result.matrix, config.options.num_threads);
    // A lon/lat grid: its cells' centres (and heights) found in the metric
    // frame align worked in.
    const auto to_frame = [&inputs](std::vector<std::array<double, 3>>* points) {
      PointsToFrame(inputs.frame, inputs.reference_crs, points);
    };
    const Execution execution = ExecutionFor(config.options.num_threads);
    WriteGeoTiff(config.aligned,
                 inputs.frame.kind == GeoFrame::kAsGiven
                     ? ResampleOntoGrid(aligned, inputs.reference_grid, execution)
                     : ResampleOntoGrid(aligned, inputs.reference_grid, to_frame, execution),
                 config.Where("aligned"), execution.threads);
  } else if (IsLasPath(config.aligned) && IsLasPath(config.moving) && inputs.frame.kind == GeoFrame::kAsGiven) {
    // The moving file's own records moved: every class and attribute kept.
    WriteMovedLas(config.moving, RowMajor(result.matrix), config.aligned, config.Where("aligned"));
  } else if (!config.aligned.empty()) {
    WriteSurface(config.aligned, TransformSurface(inputs.moving, result.matrix, config.options.num_threads),
                 config.Where("aligned"), AlignedComments(config, result, inputs.frame));
  }
  if (!config.stable_map.empty()) WriteStableMap(config, inputs, result);
  if (!config.log.empty()) {
    WriteFileAtomically(config.log, LogCsv(result.log.empty() ? seen : result.log),
                        config.Where("log"));
  }
  run.config = std::move(config);
  return run;
}

}  // namespace surfreg
