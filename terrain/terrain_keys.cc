#include "terrain/terrain_keys.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "io/plot.h"
#include "io/raster_io.h"
#include "terrain/tiled_measure.h"

namespace surfreg {

using namespace config_value;

namespace {

std::array<int, 4> Window(const Value& v) {
  const std::vector<std::string> items = Items(v);
  if (items.size() != 4) Reject(v);
  std::array<int, 4> window;
  for (int k = 0; k < 4; ++k) {
    Value item = v;
    item.kind = Value::kScalar;
    item.text = items[k];
    window[k] = Integer(item, 0);
  }
  return window;
}

std::vector<double> Matrix(const Value& v) {
  const std::vector<std::string> items = Items(v);
  if (items.empty()) return {};
  if (items.size() != 16 && items.size() != 12) Reject(v);
  std::vector<double> m;
  for (const std::string& item : items) m.push_back(NumberOf(v, item));
  if (m.size() == 12) m.insert(m.end(), {0.0, 0.0, 0.0, 1.0});
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1) Reject(v);
  return m;
}

std::string MatrixText(const std::vector<double>& m) {
  std::string out = "[";
  for (std::size_t k = 0; k < m.size(); ++k) out += (k ? ", " : "") + Text(m[k]);
  return out + "]";
}

const char* const kFrames[] = {"auto", "enu", "utm"};

// A vertical standard error: a number >= 0, or the name of a σ raster.
std::string Sigma(const Value& v) {
  const std::string text = Path(v, false);
  double value = 0;
  if (ParseNumber(text, &value) == NumberStatus::kOk) {
    if (!(std::isfinite(value) && value >= 0)) Reject(v);
    return text;
  }
  if (!text.empty() && !IsRasterPath(text)) Reject(v);
  return text;
}

}  // namespace

void CheckTerrainOutput(const std::string& key, const std::string& path, const std::string& where) {
  std::string extension = path.substr(std::min(path.size(), path.find_last_of('.')));
  for (char& ch : extension) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  const bool png = key == "dod_png" || key == "histogram_png" || key == "variogram_png";
  const bool tif = key == "dod" || key == "dod_sigma" || key == "dod_thresholded";
  if (tif && extension != ".tif" && extension != ".tiff") {
    throw InputError(where + ": written as GeoTIFF; expected a name ending in .tif, got '" + path + "'");
  }
  if (png && extension != ".png") {
    throw InputError(where + ": expected a name ending in .png, got '" + path + "'");
  }
  if (png) RequirePngFigures(where);
}

const std::vector<TerrainSettingEntry>& TerrainSettingKeys() {
  static const std::vector<TerrainSettingEntry> keys = {
      {{"reference_crs", "a CRS (EPSG:4326, EPSG:32760, WKT, lonlat), or nothing",
        "the reference's coordinate system when its file does not say (rasters carry their own)"},
       [](const Value& v, TerrainSettings* t) { t->reference_crs = Path(v, false); },
       [](const TerrainSettings& t) { return t.reference_crs; }},
      {{"moving_crs", "a CRS (EPSG:4326, EPSG:32760, WKT, lonlat), or nothing",
        "the moving surface's coordinate system when its file does not say"},
       [](const Value& v, TerrainSettings* t) { t->moving_crs = Path(v, false); },
       [](const TerrainSettings& t) { return t.moving_crs; }},
      {{"frame", "one of auto, enu, utm",
        "metric frame for geographic (lon/lat) inputs: UTM if they share a zone (auto), or local "
        "east-north-up about the centre of their overlap"},
       [](const Value& v, TerrainSettings* t) {
         const std::string text = Scalar(v);
         if (std::find(std::begin(kFrames), std::end(kFrames), text) == std::end(kFrames)) Reject(v);
         t->frame = text;
       },
       [](const TerrainSettings& t) { return t.frame; }},
      {{"band", "an integer >= 1", "raster band read from raster inputs"},
       [](const Value& v, TerrainSettings* t) { t->band = Integer(v, 1); },
       [](const TerrainSettings& t) { return std::to_string(t.band); }},
      {{"window", "a list of 4 integers >= 0 [column, row, columns, rows]",
        "part of each raster input read (columns/rows 0 = to the edge)"},
       [](const Value& v, TerrainSettings* t) { t->window = Window(v); },
       [](const TerrainSettings& t) {
         const auto& w = t.window;
         return "[" + std::to_string(w[0]) + ", " + std::to_string(w[1]) + ", " +
                std::to_string(w[2]) + ", " + std::to_string(w[3]) + "]";
       }},
      {{"lod", "a number >= 0",
        "level of detection (data units): |dz| below it counts as no change in cut/fill"},
       [](const Value& v, TerrainSettings* t) { t->lod = Number(v, 0, HUGE_VAL); },
       [](const TerrainSettings& t) { return Text(t.lod); }},
      {{"sigma_reference", "a number >= 0 or a raster file name (on the reference's grid), or nothing",
        "the reference DEM's vertical standard error (data units): one value, or one per cell"},
       [](const Value& v, TerrainSettings* t) { t->sigma_reference = Sigma(v); },
       [](const TerrainSettings& t) { return t.sigma_reference; }},
      {{"sigma_moving", "a number >= 0 or a raster file name (on the moving DEM's grid), or nothing",
        "the moving DEM's vertical standard error (data units): one value, or one per cell"},
       [](const Value& v, TerrainSettings* t) { t->sigma_moving = Sigma(v); },
       [](const TerrainSettings& t) { return t.sigma_moving; }},
      {{"lod_confidence", "a number in (0, 1), or 0 for none",
        "change only where |dz| > t sigma_DoD, t the two-sided normal quantile (0.95: 1.96); "
        "needs sigma_reference or sigma_moving, or error_model variogram"},
       [](const Value& v, TerrainSettings* t) {
         const double value = Number(v, 0, 1, "[)");
         t->lod_confidence = value;
       },
       [](const TerrainSettings& t) { return Text(t.lod_confidence); }},
      {{"error_model", "one of independent, correlated, variogram",
        "the DoD's errors behind the change budget's +/-: independent cells, fully correlated, or "
        "variogram: sigma by slope and curvature and the spatial correlation, both estimated on the "
        "stable terrain (raster reference)"},
       [](const Value& v, TerrainSettings* t) {
         const std::string text = Scalar(v);
         if (text != "independent" && text != "correlated" && text != "variogram") Reject(v);
         t->error_model = text;
       },
       [](const TerrainSettings& t) { return t.error_model; }},
      {{"variogram_png", "a .png file name, or nothing",
        "with error_model variogram: the empirical variogram of the standardized stable dz and its fit"},
       [](const Value& v, TerrainSettings* t) { t->variogram_png = Path(v, false); },
       [](const TerrainSettings& t) { return t.variogram_png; }},
      {{"change_mask", "a polygon file (text rings or a vector file such as .gpkg), or nothing",
        "the change budget (fill, cut, net and their +/-) over the reference's nodes inside these "
        "polygons only (in the reference's CRS, or the vector file's own); nothing = the whole overlap"},
       [](const Value& v, TerrainSettings* t) { t->change_mask = Path(v, false); },
       [](const TerrainSettings& t) { return t.change_mask; }},
      {{"dod_sigma", "a .tif file name, or nothing",
        "the DoD's propagated standard error on the reference raster's grid"},
       [](const Value& v, TerrainSettings* t) { t->dod_sigma = Path(v, false); },
       [](const TerrainSettings& t) { return t.dod_sigma; }},
      {{"dod_thresholded", "a .tif file name, or nothing",
        "the DoD with |dz| at or below its threshold set to 0 (reference raster's grid)"},
       [](const Value& v, TerrainSettings* t) { t->dod_thresholded = Path(v, false); },
       [](const TerrainSettings& t) { return t.dod_thresholded; }},
      {{"dod", "a .tif file name, or nothing",
        "difference of the aligned surfaces (moving - reference) on the reference raster's grid"},
       [](const Value& v, TerrainSettings* t) { t->dod = Path(v, false); },
       [](const TerrainSettings& t) { return t.dod; }},
      {{"dod_png", "a .png file name, or nothing", "map of the difference after alignment"},
       [](const Value& v, TerrainSettings* t) { t->dod_png = Path(v, false); },
       [](const TerrainSettings& t) { return t.dod_png; }},
      {{"histogram_png", "a .png file name, or nothing",
        "histograms of dz on stable terrain before and after alignment"},
       [](const Value& v, TerrainSettings* t) { t->histogram_png = Path(v, false); },
       [](const TerrainSettings& t) { return t.histogram_png; }},
      {{"change_csv", "a file name, or nothing",
        "x, y, z, dz before, dz after, stable at every reference sample"},
       [](const Value& v, TerrainSettings* t) { t->change_csv = Path(v, false); },
       [](const TerrainSettings& t) { return t.change_csv; }},
      {{"known_matrix", "a list of 16 (or 12) numbers, or []",
        "the true moving -> reference matrix (row-major), when known: the errors are reported"},
       [](const Value& v, TerrainSettings* t) { t->known_matrix = Matrix(v); },
       [](const TerrainSettings& t) { return MatrixText(t.known_matrix); }},
      {{"max_memory", "a memory size such as 512M or 2G, or nothing",
        "two DEMs aligned at bounded memory: the motion solved on full-resolution patches "
        "spread over the reference, the change measured tile by tile; nothing = untiled"},
       [](const Value& v, TerrainSettings* t) {
         const std::string text = v.kind == Value::kNull ? std::string() : Scalar(v);
         if (!text.empty()) ParseMemorySize(text, v.where);
         t->max_memory = text;
       },
       [](const TerrainSettings& t) { return t.max_memory; }},
      {{"tile_stats", "a .csv file name, or nothing",
        "with max_memory: dz after alignment per tile (median, NMAD, RMSE), where the fit is worse"},
       [](const Value& v, TerrainSettings* t) { t->tile_stats = Path(v, false); },
       [](const TerrainSettings& t) { return t.tile_stats; }},
      {{"patch_shifts", "a .csv file name, or nothing",
        "with max_memory: each sampled patch aligned alone (translation from the whole motion): "
        "its shift against the whole motion, a map of spatially varying misregistration"},
       [](const Value& v, TerrainSettings* t) { t->patch_shifts = Path(v, false); },
       [](const TerrainSettings& t) { return t.patch_shifts; }},
      {{"mask_raster", "a raster file name, or nothing",
        "stable terrain as a raster in the reference's CRS: weight 1 at reference samples on "
        "non-zero valid cells, 0 elsewhere (not with 'mask')"},
       [](const Value& v, TerrainSettings* t) { t->mask_raster = Path(v, false); },
       [](const TerrainSettings& t) { return t.mask_raster; }},
  };
  return keys;
}

const TerrainSettingEntry* FindTerrainSetting(const std::string& name) {
  for (const TerrainSettingEntry& entry : TerrainSettingKeys()) {
    if (name == entry.key.name) return &entry;
  }
  return nullptr;
}

}  // namespace surfreg
