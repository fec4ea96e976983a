#include "tools/measure_tiled.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <memory>

#include "measure/input_error.h"
#include "tools/interrupt.h"
#include "tools/io/raster_io.h"
#include "tools/terrain.h"

namespace surfreg {
namespace {

// Per reference cell while a tile is measured: the two windows' samples and
// meshes, the overlay and the per-node outputs. Measured with the peak RSS
// of tiles of 100-512 cells (600-650 bytes), with room to spare.
constexpr double kBytesPerCell = 700;

// What tiling needs of one raster: its size and geotransform (read from its
// first row and column, not its values) and its CRS.
struct RasterShape {
  int32_t columns = 0, rows = 0;
  std::array<double, 6> geotransform{};
  Crs crs;
};

RasterShape ReadShape(const AlignConfig& config, const std::string& key) {
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

TiledRasterSource Source(const std::string& path, int band, const RasterShape& shape,
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
    return RasterBlockToSurface(geotransform, w, block.values, origin, path);
  };
  source.cover = AffineGridCover(geotransform, shape.columns, shape.rows);
  return source;
}

}  // namespace

double TileBytes(int32_t tile) { return kBytesPerCell * static_cast<double>(tile) * tile; }

int32_t TileForMemory(double bytes) {
  const double side = std::floor(std::sqrt(std::max(bytes, 0.0) / kBytesPerCell));
  return static_cast<int32_t>(std::clamp(side, 16.0, 32768.0));
}

double ParseMemorySize(const std::string& text, const std::string& where) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double number = std::strtod(begin, &end);
  std::string unit(end);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();                  // "MB", "GiB"
  if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();                      // "Mi", "Gi"
  double scale = 0;
  if (unit.empty()) scale = 1;
  if (unit == "K") scale = 1024.0;
  if (unit == "M") scale = 1024.0 * 1024;
  if (unit == "G") scale = 1024.0 * 1024 * 1024;
  if (end == begin || scale == 0 || !std::isfinite(number) || number <= 0) {
    throw InputError(where + " expects a memory size such as 512M or 2G, got '" + text + "'");
  }
  const double bytes = number * scale;
  if (bytes < TileBytes(16)) {
    throw InputError(where + ": " + text + " is less than the smallest tile needs (16 x 16 cells, " +
                     std::to_string(static_cast<int64_t>(TileBytes(16) / 1024)) + " KiB)");
  }
  return bytes;
}

TiledMeasureRun MeasureRasterTiles(const AlignConfig& config, MeasureOptions options,
                                   const std::string& mask_crs_wkt, const std::string& mask_where,
                                   int32_t tile, const std::string& where,
                                   const std::function<void(const TiledProgress&)>& on_progress) {
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
  const RasterShape a = ReadShape(config, "reference");
  const RasterShape b = ReadShape(config, "moving");
  run.crs_a = a.crs;
  run.crs_b = b.crs;
  if (a.crs.kind == CrsKind::kGeographic || b.crs.kind == CrsKind::kGeographic) {
    throw InputError(where + ": a tiled measure needs both DEMs in one projected CRS (A: " +
                     DescribeCrs(a.crs) + ", B: " + DescribeCrs(b.crs) +
                     "); project them first, e.g. gdalwarp -t_srs EPSG:32633");
  }
  // The frame and the CRS checks of an untiled measure (two projected or
  // CRS-less DEMs: nothing is moved, so no samples are needed for it).
  Surface frame_a, frame_b;
  frame_a.source = config.reference;
  frame_b.source = config.moving;
  run.frame = ToCommonMetricFrame(&frame_a, a.crs, &frame_b, b.crs, FrameChoice::kAuto);
  if (options.weight == WeightMode::kMask) {
    TerrainInputs frame;  // the frame of the rasters as given
    frame.reference_crs = a.crs;
    frame.moving_crs = b.crs;
    MaskToFrame(frame, mask_crs_wkt, mask_where, &options.mask);
  }
  // One origin for both, the centre of A's extent (rounded as MakeSurface
  // rounds): B is then in A's frame with no shift at all.
  const std::array<double, 3> origin = RasterOrigin(a.geotransform, a.columns, a.rows);
  TiledMeasureOptions tiled;
  tiled.measure = options;
  tiled.measure.on_progress = nullptr;
  tiled.tile = tile;
  tiled.on_progress = on_progress;
  std::unique_ptr<GeoTiffStreamWriter> dod;
  if (!config.terrain.dod.empty()) {
    dod = std::make_unique<GeoTiffStreamWriter>(config.terrain.dod, a.columns, a.rows, a.geotransform,
                                                a.crs.wkt, config.Where("dod"));
    tiled.on_tile = [&dod](const TileDod& t) {
      dod->Write(t.window.column, t.window.row, t.window.columns, t.window.rows, t.dz);
    };
  }
  TiledMeasureStats stats;
  run.summary = MeasureTiled(Source(config.reference, config.terrain.band, a, origin),
                             Source(config.moving, config.terrain.band, b, origin), tiled, &stats);
  if (dod) dod->Finish();
  run.tile = tile;
  run.tiles = stats.tiles;
  return run;
}

}  // namespace surfreg
