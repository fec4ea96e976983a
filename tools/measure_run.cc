#include "tools/measure_run.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include "measure/input_error.h"
#include "measure/measure_keys.h"
#include "terrain/terrain_keys.h"
#include "io/atomic_file.h"
#include "tools/config_value.h"
#include "io/interrupt.h"
#include "io/polygon_reader.h"
#include "io/raster_io.h"
#include "io/surface_reader_internal.h"
#include "tools/json_writer.h"
#include "tools/terrain_json.h"
#include "tools/measure_tiled.h"
#include "terrain/terrain.h"
#include "terrain/terrain_measure.h"
#include "terrain/tiled_error.h"

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;

// The align keys that measure takes: how A and B are read and which frame
// they are measured in, and the level of detection.
constexpr const char* kTerrainKeys[] = {"reference_crs", "moving_crs",      "frame",
                                        "band",          "window",          "lod",
                                        "sigma_reference", "sigma_moving", "lod_confidence",
                                        "classes",       "columns",         "dod",
                                        "error_model",   "variogram_png",   "change_mask",
                                        "dod_sigma"};

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// The library's measure keys that the CLI reads as they are (volume,
// min_overlap_fraction, the domain keys): one definition for flags and
// Python (measure/measure_keys.h). `weights` also takes mask:FILE here,
// and `lod` is read with the terrain settings.
bool LibraryKey(const std::string& key) {
  if (key == "weights" || key == "lod") return false;
  for (const MeasureOptionEntry& entry : MeasureOptionKeys()) {
    if (key == entry.key.name) return true;
  }
  return false;
}

// weights = uniform | per_point | mask:POLYGON_FILE
void ParseWeights(const std::string& value, const std::string& where, MeasureReport* report) {
  MeasureOptions& options = report->options;

  const std::string mask = "mask:";
  if (value == "uniform") {
    options.weight = WeightMode::kUniform;
  } else if (value == "per_point") {
    options.weight = WeightMode::kPerPoint;
  } else if (value.compare(0, mask.size(), mask) == 0 && value.size() > mask.size()) {
    options.weight = WeightMode::kMask;
    report->mask_file = value.substr(mask.size());
    MaskFile file = ReadMask(report->mask_file, report->mask_layer);
    options.mask = std::move(file.rings);
    report->mask_crs_wkt = std::move(file.crs_wkt);
  } else {
    throw InputError("bad value " + io_internal::Quote(value) + " for " + where +
                     " (expected uniform, per_point or mask:POLYGON_FILE)");
  }
  std::string error;
  if (!options.IsValid(&error)) {
    throw InputError((options.weight == WeightMode::kMask ? report->mask_file + ": " : "") + error);
  }
}

// The last setting of `key`, or nullptr.
const Setting* Find(const std::vector<Setting>& settings, const std::string& key) {
  const auto found = std::find_if(settings.rbegin(), settings.rend(),
                                  [&key](const Setting& s) { return s.key == key; });
  return found == settings.rend() ? nullptr : &*found;
}

void CheckKeys(const std::vector<Setting>& settings) {
  const std::vector<std::string>& keys = MeasureKeys();
  for (const Setting& s : settings) {
    if (std::find(keys.begin(), keys.end(), s.key) != keys.end()) continue;
    const std::string nearest = NearestKey(s.key, keys);
    std::string known;
    for (const std::string& key : keys) known += (known.empty() ? "" : ", ") + key;
    throw InputError(s.where + ": unknown key " + io_internal::Quote(s.key) + " for measure (" +
                     (nearest.empty() ? "known keys: " + known : "did you mean '" + nearest + "'?") +
                     ")");
  }
}

// A and B as align's reference and moving surfaces (messages say "argument
// A"), with the terrain settings given. Nothing is read yet.
AlignConfig MeasureConfig(const std::string& a, const std::string& b,
                          const std::vector<Setting>& settings) {
  AlignConfig config;
  ApplyAlignArguments(a, b, &config);
  config.origin["reference"] = "argument A";
  config.origin["moving"] = "argument B";
  for (const char* key : kTerrainKeys) {
    if (const Setting* s = Find(settings, key)) ApplyAlignSetting(key, s->value, s->where, &config);
  }
  return config;
}

// The tile side asked for by `tile` (cells of A) or `max_memory` (the side
// that fits), 0 for an untiled measure; *where names the setting.
int32_t TileSetting(const std::vector<Setting>& settings, std::string* where) {
  const Setting* tile = Find(settings, "tile");
  const Setting* memory = Find(settings, "max_memory");
  int32_t side = 0;
  if (tile != nullptr && !tile->value.empty() && tile->value != "0") {
    char* end = nullptr;
    const long value = std::strtol(tile->value.c_str(), &end, 10);
    if (*end != '\0' || value < 16 || value > 32768) {
      throw InputError(tile->where + " expects a tile side in cells of A, 16 to 32768 (0: no tiles), got '" +
                       tile->value + "'");
    }
    side = static_cast<int32_t>(value);
    *where = tile->where;
  }
  if (memory != nullptr && !memory->value.empty()) {
    const double bytes = ParseMemorySize(memory->value, memory->where);
    if (side == 0) {
      side = TileForMemory(bytes);
      *where = memory->where;
    } else if (TileBytes(side) > bytes) {
      throw InputError(tile->where + ": tiles of " + tile->value + " cells need about " +
                       std::to_string(static_cast<int64_t>(TileBytes(side) / (1 << 20))) +
                       " MiB, more than " + memory->where + " allows (" + memory->value + ")");
    }
  }
  return side;
}

// What a tiled measure does not do yet, refused before anything is read.
void CheckTileable(const MeasureOptions& options, const AlignConfig& config,
                   const std::string& where) {
  std::string what;
  if (options.volume != VolumeMode::kOverlay) what = "--volume=union";
  if (options.weight == WeightMode::kPerPoint) what = "per-point weights";
  if (options.domain.kind == DomainKind::kHull) what = "--domain=hull";
  if (!config.terrain.mask_raster.empty()) what = "a mask raster";
  if (!config.terrain.change_mask.empty()) what = "a change_mask";
  if (!config.terrain.dod_sigma.empty()) what = "--dod_sigma";
  if (!what.empty()) throw InputError(where + ": a tiled measure does not take " + what + " yet");
}

// What error_model variogram needs of a tiled run (terrain/tiled_error.h):
// one run (no shards, partials or resume), no mask, a north-up grid in a
// projected CRS or none; the σ given as numbers (`budget`).
TiledErrorInputs TiledErrorSetup(const AlignConfig& config, const MeasureOptions& options, const TiledParts& parts,
                                 const std::string& tile_where, const TiledBudget& budget) {
  const std::string where = config.Where("error_model");
  if (parts.shards > 1 || !parts.partial.empty() || parts.resume) {
    throw InputError(where + ": the variogram error model is fitted on the whole DoD, so it is not computed "
                     "in shards, partials or resumed runs yet: measure in one run");
  }
  if (options.weight == WeightMode::kMask) {
    throw InputError(where + " and a mask: the stable terrain of a tiled variogram is every cell yet; "
                     "measure untiled, or without the mask");
  }
  const RasterShape a = ReadRasterShape(config, "reference");
  const auto& gt = a.geotransform;
  if (a.crs.kind == CrsKind::kGeographic || gt[2] != 0 || gt[4] != 0) {
    throw InputError(where + " and " + tile_where + ": a tiled variogram needs a north-up reference in a "
                     "projected CRS (or none); measure untiled");
  }
  TiledErrorInputs inputs;
  inputs.grid = {a.columns, a.rows, std::fabs(gt[1]), std::fabs(gt[5])};
  const std::string path = config.reference;
  const int band = config.terrain.band;
  inputs.heights = [path, band](int column, int row, int columns, int rows) {
    RasterReadOptions read;
    read.band = band;
    read.window = {column, row, columns, rows};
    const Raster window = ReadRaster(path, read);
    return std::vector<double>(window.values.begin(), window.values.end());
  };
  inputs.sigma_dod = budget.active ? budget.sigma_dod : std::nan("");
  inputs.confidence = config.terrain.lod_confidence;
  inputs.lod = config.terrain.lod;
  inputs.error_model = config.terrain.error_model;
  inputs.where = where;
  return inputs;
}

// What a part of a tiled measure was measured with, equal in every part of
// one measure and in its checkpoint: the inputs (name and size in bytes),
// the tile side and every setting given (but the outputs').
std::string PartSettings(const MeasureReport& report, const std::vector<Setting>& settings) {
  std::string text;
  for (const std::string& file : {report.file_a, report.file_b}) {
    std::error_code error;
    const auto bytes = std::filesystem::file_size(file, error);
    text += file + " (" + (error ? std::string("?") : std::to_string(bytes)) + " bytes); ";
  }
  text += "tile " + std::to_string(report.tile);
  std::vector<std::string> given;
  for (const Setting& s : settings) {
    if (s.key != "dod" && s.key != "tile" && s.key != "max_memory") given.push_back(s.key + "=" + s.value);
  }
  std::sort(given.begin(), given.end());
  for (const std::string& g : given) text += "; " + g;
  return text;
}

}  // namespace

const std::vector<std::string>& MeasureKeys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> out;
    for (const MeasureOptionEntry& entry : MeasureOptionKeys()) {
      if (std::string(entry.key.name) != "lod") out.push_back(entry.key.name);
    }
    for (const char* key : {"mask_mode", "mask_layer", "tile", "max_memory"}) out.push_back(key);
    out.insert(out.end(), std::begin(kTerrainKeys), std::end(kTerrainKeys));
    return out;
  }();
  return keys;
}

MeasureReport MeasureSurfaces(SurfaceInput a, SurfaceInput b, const std::vector<Setting>& settings,
                              const std::function<void(const MeasureProgress&)>& on_progress,
                              const TiledParts* parts) {
  const Clock::time_point start = Clock::now();
  CheckKeys(settings);
  MeasureReport report;
  report.file_a = a.name;
  report.file_b = b.name;
  // Settings first: a bad value is reported before any file is read.
  MeasureOptions& options = report.options;
  options.on_progress = on_progress;
  for (const Setting& s : settings) {  // in order: the last setting of a key wins
    if (!LibraryKey(s.key)) continue;
    config_value::Value value;
    value.text = s.value;
    value.where = s.where;
    SetOption(MeasureOptionKeys(), s.key, std::move(value), &options);
  }
  if (const Setting* s = Find(settings, "mask_layer")) report.mask_layer = s->value;
  if (const Setting* s = Find(settings, "mask_mode")) {
    if (s->value == "exclude") {
      options.mask_mode = MaskMode::kExclude;
    } else if (s->value != "include") {
      throw InputError("bad value " + io_internal::Quote(s->value) + " for " + s->where +
                       " (expected include or exclude)");
    }
  }
  const Setting* weights = Find(settings, "weights");
  const bool masked = weights != nullptr && weights->value.compare(0, 5, "mask:") == 0;
  for (const char* key : {"mask_layer", "mask_mode"}) {  // mask settings without a mask
    const Setting* s = Find(settings, key);
    if (!masked && s != nullptr && !s->value.empty() && s->value != "include") {
      throw InputError(s->where + ": needs a mask (weights mask:FILE)");
    }
  }
  ParseWeights(weights ? weights->value : "uniform", weights ? weights->where : "", &report);
  const AlignConfig config = MeasureConfig(report.file_a, report.file_b, settings);
  // Cut/fill is integrated on the overlay's cells: always there, absent from union.
  options.detect_change = options.volume == VolumeMode::kOverlay;
  options.level_of_detection = config.terrain.lod;
  if (!options.detect_change && config.origin.count("lod") != 0) {
    throw InputError(config.Where("lod") +
                     ": cut/fill beyond a level of detection needs --volume=overlay");
  }
  const bool variogram = config.terrain.error_model == "variogram";
  const bool sigma = !config.terrain.sigma_reference.empty() || !config.terrain.sigma_moving.empty() || variogram;
  if (config.terrain.lod_confidence > 0 && !sigma) {
    throw InputError(config.Where("lod_confidence") +
                     " needs the DEMs' vertical errors: give --sigma_reference and/or --sigma_moving, or "
                     "--error_model=variogram");
  }
  if (!config.terrain.dod_sigma.empty()) {
    const std::string where = config.Where("dod_sigma");
    if (!sigma) {
      throw InputError(where + ": needs the DEMs' vertical errors: give --sigma_reference and/or --sigma_moving, "
                       "or --error_model=variogram");
    }
    if (!a.samples && !IsRasterPath(report.file_a)) {
      throw InputError(where + ": σ_DoD is written on A's grid, but A ('" + report.file_a + "') is no raster");
    }
    CheckTerrainOutput("dod_sigma", config.terrain.dod_sigma, where);
    CheckOutputPath(config.terrain.dod_sigma, where);
  }
  if (!config.terrain.change_mask.empty() && !sigma) {
    throw InputError(config.Where("change_mask") +
                     ": the change budget needs the DEMs' vertical errors: give --sigma_reference and/or "
                     "--sigma_moving, or --error_model=variogram");
  }
  if (sigma && !options.detect_change) {
    const char* key = variogram ? "error_model"
                      : config.terrain.sigma_reference.empty() ? "sigma_moving" : "sigma_reference";
    throw InputError(config.Where(key) + ": the change budget needs --volume=overlay");
  }
  if (!config.terrain.variogram_png.empty()) {
    if (!variogram) {
      throw InputError(config.Where("variogram_png") + ": needs --error_model=variogram");
    }
    CheckTerrainOutput("variogram_png", config.terrain.variogram_png, config.Where("variogram_png"));
    CheckOutputPath(config.terrain.variogram_png, config.Where("variogram_png"));
  }
  // The budget weights dz at A's nodes by their areas; the DoD is dz there.
  options.keep_node_gaps = sigma || !config.terrain.dod.empty();
  if (!config.terrain.dod.empty()) {
    const std::string& path = config.terrain.dod;
    if (!a.samples && !IsRasterPath(report.file_a)) {
      throw InputError(config.Where("dod") + ": the DoD is written on A's grid, but A ('" +
                       report.file_a + "') is no raster");
    }
    CheckTerrainOutput("dod", path, config.Where("dod"));
    CheckOutputPath(path, config.Where("dod"));
    for (const std::string& input : {report.file_a, report.file_b}) {
      std::error_code ignored;
      if (std::filesystem::equivalent(path, input, ignored)) {
        throw InputError(config.Where("dod") + ": '" + path + "' is also an input");
      }
    }
  }
  std::string tile_where;
  report.tile = TileSetting(settings, &tile_where);
  if (report.tile > 0) {
    CheckTileable(options, config, tile_where);
    TiledBudget budget = TiledBudgetOf(config, options.level_of_detection, tile_where);
    TiledParts tiled_parts = parts != nullptr ? *parts : TiledParts();
    tiled_parts.checkpoint = parts != nullptr;  // without parts: no state kept for a resume
    tiled_parts.settings = PartSettings(report, settings);
    // error_model variogram: the tiles' DoD kept on disk for a second pass.
    std::unique_ptr<TileDodStore> store;
    TiledErrorInputs error_inputs;
    if (variogram) {
      error_inputs = TiledErrorSetup(config, options, tiled_parts, tile_where, budget);
      store = std::make_unique<TileDodStore>(error_inputs.grid.columns, error_inputs.grid.rows);
      budget = TiledBudget();  // the second pass adds the budget, σ per cell
    }
    const TiledMeasureRun run = MeasureRasterTiles(
        config, options, report.mask_crs_wkt, report.mask_file, report.tile, tile_where, tiled_parts,
        [&on_progress, start, last = -1.0](const TiledProgress& p) mutable {
          // A line a second at most: there may be thousands of tiles.
          const double seconds = Seconds(Clock::now() - start);
          if (!on_progress || p.total == 0 || (seconds < last + 1.0 && p.done < p.total)) return;
          last = seconds;
          const std::string stage =
              "tiles, " + std::to_string(p.done) + " of " + std::to_string(p.total);
          MeasureProgress progress;
          progress.stage = stage.c_str();
          // The share of this run's work: its ETA then holds after a resume.
          progress.done = static_cast<double>(p.done - p.resumed) / std::max<int64_t>(p.total - p.resumed, 1);
          progress.seconds = seconds;
          on_progress(progress);
        },
        nullptr, store ? [&store](const TileDod& t) { store->Add(t); } : std::function<void(const TileDod&)>(),
        budget);
    report.summary = run.summary;
    report.config = config;
    if (tiled_parts.shards == 1) report.uncertainty = TiledChangeUncertainty(run.part, config);
    if (store) {
      if (on_progress) {
        MeasureProgress progress;
        progress.stage = "the DoD's error model";
        progress.done = 1;
        progress.seconds = Seconds(Clock::now() - start);
        on_progress(progress);
      }
      report.uncertainty = TiledSpatialUncertainty(*store, error_inputs, ExecutionFor(options.threads));
    }
    report.tiles = run.tiles;
    report.crs_a = run.crs_a;
    report.crs_b = run.crs_b;
    report.frame = run.frame;
    report.metric = report.frame.kind != GeoFrame::kAsGiven ||
                    (report.crs_a.kind == CrsKind::kProjected && report.crs_a.metres_per_unit == 1.0);
    report.config = config;
    if (store && !config.terrain.variogram_png.empty()) {
      WriteVariogramPng(config.terrain.variogram_png, report.uncertainty.model, report.metric ? "m" : "units",
                        config.Where("variogram_png"));
    }
    report.total_s = Seconds(Clock::now() - start);
    if (!tiled_parts.partial.empty()) {
      WriteFileAtomically(tiled_parts.partial,
                          PartJson(run.part, tiled_parts.settings, &report, run.dod, tiled_parts.partial),
                          "flag '--partial'");
    }
    std::error_code ignored;  // the outputs are written: the state is not needed
    std::filesystem::remove_all(run.state, ignored);
    return report;
  }
  if (parts != nullptr && (parts->shards > 1 || !parts->partial.empty() || parts->resume)) {
    throw InputError(std::string(parts->shards > 1 ? "flag '--shard'" : !parts->partial.empty()
                                                         ? "flag '--partial'" : "flag '--resume'") +
                     ": for a tiled measure (--tile=N or --max_memory=SIZE)");
  }
  TerrainMeasure measured = MeasureTerrain(config, report.options, report.mask_crs_wkt, report.mask_file,
                                           a.samples ? &*a.samples : nullptr, b.samples ? &*b.samples : nullptr);
  a.samples.reset();  // copied into the measure's inputs
  b.samples.reset();
  report.frame = measured.frame;
  report.crs_a = measured.crs_a;
  report.crs_b = measured.crs_b;
  report.b_reprojected_from = measured.b_reprojected_from;
  report.metric = measured.metric;
  report.summary = std::move(measured.summary);
  report.dz = measured.dz;
  report.has_dz = true;
  report.uncertainty = std::move(measured.uncertainty);
  if (!config.terrain.variogram_png.empty() && report.uncertainty.spatial) {
    WriteVariogramPng(config.terrain.variogram_png, report.uncertainty.model, report.metric ? "m" : "units",
                      config.Where("variogram_png"));
  }
  report.config = config;
  report.read_s = measured.read_s;
  report.total_s = Seconds(Clock::now() - start);
  return report;
}

std::size_t MaskVertices(const MeasureOptions& options) {
  std::size_t n = 0;
  for (const MaskRing& ring : options.mask) n += ring.size();
  return n;
}

std::string MeasureJson(const MeasureReport& r) {
  const MeasureSummary& s = r.summary;
  JsonObject timings;
  // Seconds to the nanosecond (the clock's resolution); the measures above in full.
  timings.Fixed("read", r.read_s, 9)
      .Fixed("triangulate", s.timings.triangulate, 9)
      .Fixed("domain", s.timings.domain, 9)
      .Fixed("spanning_tree", s.timings.spanning_tree, 9)
      .Fixed("locate", s.timings.locate, 9)
      .Fixed("interpolate", s.timings.interpolate, 9)
      .Fixed("volume", s.timings.volume, 9)
      .Fixed("measure", s.timings.total, 9)  // Measure() alone
      .Fixed("total", r.total_s, 9);         // the whole command: read + measure
  JsonObject json;
  json.String("file_a", r.file_a)
      .String("file_b", r.file_b)
      .String("frame", r.frame.Describe())
      .String("crs_a", DescribeCrs(r.crs_a))
      .String("crs_b", DescribeCrs(r.crs_b));
  if (!r.b_reprojected_from.empty()) json.String("b_reprojected_from", r.b_reprojected_from);
  json.String("length_unit", r.metric ? "m" : "units")
      .String("volume_mode", VolumeModeName(s.volume_mode))
      .String("weight_mode", WeightModeName(r.options.weight))
      .String("domain", DomainKindName(s.domain_kind));
  if (r.options.weight == WeightMode::kMask) {
    json.String("mask_file", r.mask_file)
        .String("mask_mode", MaskModeName(r.options.mask_mode))
        .Int("mask_rings", static_cast<int64_t>(r.options.mask.size()))
        .Int("mask_vertices", static_cast<int64_t>(MaskVertices(r.options)));
  }
  if (r.tile > 0) json.Int("tile", r.tile).Int("tiles", r.tiles);
  json.Number("rho_d", s.rho_d)
      .Number("rho_d_axial", s.rho_d_axial)
      .Number("rho_s", s.rho_s)
      .Number("overlap_area", s.overlap_area)
      .Number("domain_area_a", s.domain_area_a)
      .Number("domain_area_b", s.domain_area_b)
      .Number("excluded_area_a", s.excluded_area_a)
      .Number("excluded_area_b", s.excluded_area_b)
      .Number("weight_integral", s.weight_integral)
      .Number("mean_abs_dz", s.mean_abs_dz)
      .Number("signed_volume", s.signed_volume)
      .Number("volume_above", s.volume_above)
      .Number("volume_below", s.volume_below)
      .Int("n_points_a", s.n_points_a)
      .Int("n_points_b", s.n_points_b)
      .Int("n_duplicates_a", s.n_duplicates_a)
      .Int("n_duplicates_b", s.n_duplicates_b)
      .Int("n_overlap_nodes", s.n_overlap_nodes)
      .Int("n_cells", s.n_cells)
      .Int("walk_steps", s.walk_steps);
  if (r.has_dz) json.Object("dz", DzStatisticsJson(r.dz));  // at A's nodes in the overlap
  if (r.options.detect_change) {  // the keys of align's terrain.change
    JsonObject change = DetectedChangeJson(s);
    if (r.uncertainty.active) change.Object("uncertainty", ChangeUncertaintyJson(r.config, r.uncertainty));
    json.Object("change", change);
  }
  json.Object("timings", timings);
  return json.str();
}

}  // namespace surfreg
