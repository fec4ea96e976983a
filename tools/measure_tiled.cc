#include "tools/measure_tiled.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "tools/sweep.h"  // ParseShard
#include "io/raster_io.h"
#include "terrain/terrain.h"

namespace surfreg {
namespace {


// A lon/lat raster's windows in `frame` (input points moved by
// PointsToFrame, relative to `origin`); a box of the frame found back as the
// lon/lat box of points along its edges at the raster's lowest and highest
// heights (the map is smooth: the cover's extra sample on each side holds
// the edges' bend between them).
TiledRasterSource InFrame(TiledRasterSource lonlat, const GeoFrame& frame, const Crs& crs,
                          const std::array<double, 3>& origin, double z_min, double z_max) {
  TiledRasterSource out = lonlat;
  out.origin = origin;
  out.read = [read = lonlat.read, frame, crs, origin](const SampleWindow& w) {
    Surface s = read(w);
    std::vector<std::array<double, 3>> points(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
      points[i] = {s.xy[i].x + s.origin[0], s.xy[i].y + s.origin[1], s.z[i] + s.origin[2]};
    }
    PointsToFrame(frame, crs, &points);
    s.origin = origin;
    for (std::size_t i = 0; i < s.size(); ++i) {
      s.xy[i] = {points[i][0] - origin[0], points[i][1] - origin[1]};
      s.z[i] = points[i][2] - origin[2];
    }
    return s;
  };
  out.cover = [cover = lonlat.cover, frame, crs, z_min, z_max](const XyBox& box) {
    constexpr int kSteps = 8;  // points per edge
    std::vector<std::array<double, 3>> points;
    for (int k = 0; k <= kSteps; ++k) {
      const double u = static_cast<double>(k) / kSteps;
      const double x = box.x_min + u * (box.x_max - box.x_min), y = box.y_min + u * (box.y_max - box.y_min);
      for (const double z : {z_min, z_max}) {
        points.push_back({x, box.y_min, z}), points.push_back({x, box.y_max, z});
        points.push_back({box.x_min, y, z}), points.push_back({box.x_max, y, z});
      }
    }
    PointsFromFrame(frame, crs, &points);
    XyBox in_crs{points[0][0], points[0][1], points[0][0], points[0][1]};
    for (const auto& p : points) {
      in_crs.x_min = std::min(in_crs.x_min, p[0]), in_crs.x_max = std::max(in_crs.x_max, p[0]);
      in_crs.y_min = std::min(in_crs.y_min, p[1]), in_crs.y_max = std::max(in_crs.y_max, p[1]);
    }
    return cover(in_crs);
  };
  return out;
}

bool Exists(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0;
}

}  // namespace

RasterShape ReadRasterShape(const AlignConfig& config, const std::string& key) {
  const std::string path = AlignConfigValue(config, key);
  RasterReadOptions options;
  options.band = config.terrain.band;
  options.window = {0, 0, 0, 1};  // the first row: the width
  const Raster row = ReadRaster(path, options);
  options.window = {0, 0, 1, 0};  // the first column: the height
  const Raster column = ReadRaster(path, options);
  RasterShape shape;
  shape.columns = row.columns;
  shape.rows = column.rows;
  shape.geotransform = row.geotransform;  // window (0, 0): the raster's own
  const Crs file_crs = row.crs_wkt.empty() ? Crs() : ParseCrs(row.crs_wkt, path);
  const std::string crs_key = key + "_crs";
  shape.crs = ResolveCrs(file_crs, AlignConfigValue(config, crs_key), config.Where(crs_key), path);
  return shape;
}

TiledRasterSource RasterTileSource(const std::string& path, int band, const RasterShape& shape,
                         const std::array<double, 3>& origin) {
  TiledRasterSource source;
  source.columns = shape.columns;
  source.rows = shape.rows;
  source.origin = origin;
  source.source = path;
  const std::array<double, 6> geotransform = shape.geotransform;
  source.read = [path, band, geotransform, origin](const SampleWindow& w) {
    ThrowIfInterrupted();  // between tiles: a signal ends the run here
    RasterReadOptions options;
    options.band = band;
    options.window = {w.column, w.row, w.columns, w.rows};
    const Raster block = ReadRaster(path, options);
    // The whole raster's geotransform, not the window's: every tile then has
    // the coordinates of an untiled read, to the last bit.
    return RasterBlockToSurface(geotransform, w, block.values.data(), block.values.size(), origin, path);
  };
  source.cover = AffineGridCover(geotransform, shape.columns, shape.rows);
  return source;
}

TiledPair OpenTiledPair(const AlignConfig& config, const std::string& where) {
  TiledPair pair;
  pair.a = ReadRasterShape(config, "reference");
  pair.b = ReadRasterShape(config, "moving");
  const RasterShape &a = pair.a, &b = pair.b;
  const bool geographic = a.crs.kind == CrsKind::kGeographic && b.crs.kind == CrsKind::kGeographic;
  if (!geographic) {
    // The frame and the CRS checks of an untiled run (two projected or
    // CRS-less DEMs: nothing is moved, so no samples are needed for it).
    Surface frame_a, frame_b;
    frame_a.source = config.reference;
    frame_b.source = config.moving;
    pair.frame = ToCommonMetricFrame(&frame_a, a.crs, &frame_b, b.crs, FrameChoice::kAuto);
    // One origin for both, the centre of A's extent (rounded as MakeSurface
    // rounds): B is then in A's frame with no shift at all.
    pair.origin = RasterOrigin(a.geotransform, a.columns, a.rows);
    pair.source_a = RasterTileSource(config.reference, config.terrain.band, a, pair.origin);
    pair.source_b = RasterTileSource(config.moving, config.terrain.band, b, pair.origin);
    return pair;
  }
  // Two lon/lat DEMs: the frame from their valid samples' boxes, as an
  // untiled run takes it from its samples (a pass over each, bands of about
  // 1e6 samples).
  const TiledRasterSource lonlat_a =
      RasterTileSource(config.reference, config.terrain.band, a, RasterOrigin(a.geotransform, a.columns, a.rows));
  const TiledRasterSource lonlat_b =
      RasterTileSource(config.moving, config.terrain.band, b, RasterOrigin(b.geotransform, b.columns, b.rows));
  const auto rows_of = [](int32_t columns) { return std::max<int32_t>(1, 1000000 / std::max(columns, 1)); };
  const SampleExtent extent_a = ExtentOfSamples(lonlat_a, rows_of(a.columns));
  const SampleExtent extent_b = ExtentOfSamples(lonlat_b, rows_of(b.columns));
  for (const auto& [extent, name] : {std::pair{&extent_a, &config.reference}, std::pair{&extent_b, &config.moving}}) {
    if (extent->count == 0) throw InputError(*name + ": every cell is nodata");
  }
  const auto corners = [](const SampleExtent& e, const std::string& name) {
    const XyBox& x = e.box;
    return MakeSurface({{x.x_min, x.y_min, e.z_min}, {x.x_max, x.y_min, e.z_min}, {x.x_max, x.y_max, e.z_max},
                        {x.x_min, x.y_max, e.z_max}},
                       {}, name);
  };
  Surface frame_a = corners(extent_a, config.reference), frame_b = corners(extent_b, config.moving);
  const std::string& choice = config.terrain.frame;
  pair.frame = ToCommonMetricFrame(&frame_a, a.crs, &frame_b, b.crs,
                                   choice == "enu"   ? FrameChoice::kEnu
                                   : choice == "utm" ? FrameChoice::kUtm
                                                     : FrameChoice::kAuto);
  pair.origin = {frame_a.origin[0], frame_a.origin[1], 0.0};
  const double z_min = std::min(extent_a.z_min, extent_b.z_min), z_max = std::max(extent_a.z_max, extent_b.z_max);
  pair.source_a = InFrame(lonlat_a, pair.frame, a.crs, pair.origin, z_min, z_max);
  pair.source_b = InFrame(lonlat_b, pair.frame, b.crs, pair.origin, z_min, z_max);
  return pair;
}

TiledMeasureRun MeasureRasterTiles(const AlignConfig& config, MeasureOptions options,
                                   const std::string& mask_crs_wkt, const std::string& mask_where,
                                   int32_t tile, const std::string& where, const TiledParts& parts,
                                   const std::function<void(const TiledProgress&)>& on_progress,
                                   const MovedRaster* moved, const std::function<void(const TileDod&)>& on_tile,
                                   const TiledBudget& budget) {
  for (const char* key : {"reference", "moving"}) {
    const std::string path = AlignConfigValue(config, key);
    if (!IsRasterPath(path)) {
      throw InputError(where + ": tiles are for two rasters, but " + config.Where(key) + " is '" +
                       path + "', a cloud");
    }
  }
  const auto& w = config.terrain.window;
  if (w[0] != 0 || w[1] != 0 || w[2] != 0 || w[3] != 0) {
    throw InputError(where + " and " + config.Where("window") +
                     ": a window and tiles do not go together yet: cut the window out first "
                     "(gdal_translate -srcwin)");
  }
  TiledMeasureRun run;
  const TiledPair pair = OpenTiledPair(config, where);
  const RasterShape &a = pair.a, &b = pair.b;
  run.crs_a = a.crs;
  run.crs_b = b.crs;
  run.frame = pair.frame;
  if (options.weight == WeightMode::kMask) {
    TerrainInputs frame;  // the frame the rasters are measured in
    frame.reference_crs = a.crs;
    frame.moving_crs = b.crs;
    frame.frame = pair.frame;
    MaskToFrame(frame, mask_crs_wkt, mask_where, &options.mask);
  }
  TiledMeasureOptions tiled;
  tiled.measure = options;
  tiled.measure.on_progress = nullptr;
  tiled.tile = tile;
  tiled.on_progress = on_progress;
  tiled.budget = budget.active;
  tiled.budget_sigma_dod = budget.sigma_dod;
  tiled.budget_threshold = budget.threshold;
  const int64_t nx = (std::max(a.columns - 1, 0) + tile - 1) / tile;
  const int64_t ny = (std::max(a.rows - 1, 0) + tile - 1) / tile;

  // The state of an interrupted run of this part, if any.
  run.state = StateDirectory(config.terrain.dod, parts);
  if (!parts.checkpoint) run.state += ".tmp-" + std::to_string(::getpid());
  const std::string state_file = run.state + "/state.json";
  std::unique_ptr<PartFile> resumed;
  if (parts.checkpoint && Exists(state_file)) {
    if (!parts.resume) {
      throw InputError("'" + run.state + "' holds an interrupted tiled measure: add --resume "
                       "(Python: resume=True) to continue it, or delete it");
    }
    resumed = std::make_unique<PartFile>(ReadPart(state_file));
    if (resumed->settings != parts.settings || resumed->part.shard != parts.shard ||
        resumed->part.shards != parts.shards) {
      throw InputError("flag '--resume': '" + state_file + "' is of another measure (other inputs, "
                       "settings or shard); delete '" + run.state + "' to start afresh");
    }
    std::fprintf(stderr, "measure: resuming: %lld of %lld tile rows already done (%s)\n",
                 static_cast<long long>(resumed->part.end_row - resumed->part.first_row),
                 static_cast<long long>(resumed->part.band_end_row - resumed->part.first_row),
                 state_file.c_str());
  }
  std::error_code error;
  std::filesystem::create_directories(run.state, error);
  if (error) throw InputError("'" + run.state + "': cannot create it (" + error.message() + ")");
  struct Scratch {  // without checkpoints the directory goes, whatever happens
    const std::string* path;
    ~Scratch() {
      std::error_code ignored;
      if (path != nullptr) std::filesystem::remove_all(*path, ignored);
    }
  } scratch{parts.checkpoint ? nullptr : &run.state};

  // The DoD one tile row at a time, each row a GeoTIFF in the state
  // directory, finished before the state that counts it is written.
  const bool with_dod = !config.terrain.dod.empty();
  auto row_band = [&](int64_t ty) {
    DodBand band;
    band.path = run.state + "/dod_row_" + std::to_string(ty) + ".tif";
    band.first_row = static_cast<int32_t>(ty * tile);
    band.rows = static_cast<int32_t>((ty + 1 == ny ? a.rows : (ty + 1) * tile) - ty * tile);
    band.columns = a.columns;
    band.raster_rows = a.rows;
    band.geotransform = a.geotransform;
    band.crs_wkt = a.crs.wkt;
    return band;
  };
  std::unique_ptr<GeoTiffStreamWriter> row;
  if (with_dod || on_tile) {
    tiled.on_tile = [&](const TileDod& t) {
      if (on_tile) on_tile(t);
      if (!with_dod) return;
      if (!row) {
        const DodBand band = row_band(t.tile / nx);
        std::array<double, 6> gt = a.geotransform;
        gt[0] += band.first_row * gt[2];
        gt[3] += band.first_row * gt[5];
        row = std::make_unique<GeoTiffStreamWriter>(band.path, a.columns, band.rows, gt, a.crs.wkt,
                                                    config.Where("dod"));
      }
      row->Write(t.window.column, t.window.row - static_cast<int32_t>(t.tile / nx * tile),
                 t.window.columns, t.window.rows, t.dz.data(), t.dz.size());
    };
  }
  tiled.on_row = [&](const TiledPartial& part) {
    if (row) row->Finish();
    row.reset();
    if (!parts.checkpoint) return;
    WriteFileAtomically(state_file, PartJson(part, parts.settings, nullptr, {}, state_file),
                        "the state of the tiled measure");
  };
  const TiledRasterSource& source_a = pair.source_a;
  TiledRasterSource source_b = pair.source_b;
  if (moved != nullptr) source_b = MovedRasterSource(std::move(source_b), moved->matrix, moved->z_min, moved->z_max);
  run.part = MeasureTiledPart(source_a, source_b, tiled, parts.shard, parts.shards,
                              resumed ? &resumed->part : nullptr);
  if (parts.shards == 1) {
    run.summary = FinishTiled(run.part.sums, tiled.measure, source_a.source, source_b.source);
  }
  if (with_dod && run.part.band_end_row > run.part.first_row) {
    std::vector<DodBand> rows;
    for (int64_t ty = run.part.first_row; ty < run.part.band_end_row; ++ty) rows.push_back(row_band(ty));
    JoinDodBands(rows, {}, config.terrain.dod, config.Where("dod"));
    run.dod = rows.front();
    run.dod.path = config.terrain.dod;
    run.dod.rows = rows.back().first_row + rows.back().rows - rows.front().first_row;
  } else if (with_dod) {  // an empty band: no rows, no file
    run.dod = row_band(0);
    run.dod.path = config.terrain.dod;
    run.dod.rows = 0;
  }
  run.tile = tile;
  run.tiles = run.part.stats.tiles;
  return run;
}

TiledBudget TiledBudgetOf(const AlignConfig& config, double level_of_detection, const std::string& where) {
  TiledBudget budget;
  double sigma[2] = {0, 0};
  const char* keys[2] = {"sigma_reference", "sigma_moving"};
  for (int k = 0; k < 2; ++k) {
    const std::string text = AlignConfigValue(config, keys[k]);
    if (text.empty()) continue;
    budget.active = true;
    char* end = nullptr;
    sigma[k] = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0') {
      throw InputError(config.Where(keys[k]) + ": a σ raster does not go with " + where +
                       " yet: give the DEM's σ as a number, or measure untiled");
    }
  }
  if (!budget.active) return budget;
  budget.sigma_dod = std::hypot(sigma[0], sigma[1]);
  const double confidence = config.terrain.lod_confidence;
  budget.t = confidence > 0 ? TwoSidedNormalQuantile(confidence) : 0.0;
  budget.threshold = std::max(level_of_detection, budget.t * budget.sigma_dod);
  return budget;
}

ChangeUncertainty TiledChangeUncertainty(const TiledPartial& whole, const AlignConfig& config) {
  ChangeUncertainty u;
  if (!whole.budget) return u;
  u.active = true;
  const double confidence = config.terrain.lod_confidence;
  const double t = confidence > 0 ? TwoSidedNormalQuantile(confidence) : 0.0;
  const bool any = whole.sums.budget.nodes > 0;
  u.budget = FinishChangeBudget(whole.sums.budget, t, any ? whole.budget_sigma_dod : std::nan(""),
                                any ? whole.budget_threshold : std::nan(""));
  return u;
}

TiledParts TiledPartsOf(const std::string& shard_text, const std::string& partial, bool resume,
                        const std::function<std::string(const std::string&)>& where,
                        const std::string& partial_hint) {
  const Shard shard = ParseShard(shard_text, where("shard"));
  TiledParts parts;
  parts.shard = shard.index;
  parts.shards = shard.count;
  parts.partial = partial;
  parts.resume = resume;
  if (!partial.empty()) {
    if (partial.size() < 6 || partial.compare(partial.size() - 5, 5, ".json") != 0) {
      throw InputError(where("partial") + " expects a file name ending in .json, got '" + partial + "'");
    }
    CheckOutputPath(partial, where("partial"));
  } else if (parts.shards > 1) {
    throw InputError(where("shard") + ": a shard's result is partial: give " + partial_hint +
                     ", then join the shards with 'surfreg merge OUT.json P1.json ...'");
  }
  return parts;
}

std::string StateDirectory(const std::string& dod, const TiledParts& parts) {
  if (!parts.partial.empty()) return parts.partial + ".resume";
  if (!dod.empty()) return dod + ".resume";
  uint64_t hash = 1469598103934665603ull;  // FNV-1a: a name per measure
  for (const unsigned char c : parts.settings) hash = (hash ^ c) * 1099511628211ull;
  char name[64];
  std::snprintf(name, sizeof name, "surfreg-measure-%016llx.resume",
                static_cast<unsigned long long>(hash));
  return name;
}

}  // namespace surfreg
