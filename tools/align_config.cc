#include "tools/align_config.h"

#include <glog/logging.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <utility>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "registration/align_keys.h"
#include "terrain/terrain_keys.h"
#include "tools/align_config_values.h"
#include "tools/config_table.h"
#include "tools/config_value.h"
#include "io/raster_io.h"
#include "io/raster_resample.h"
#include "tools/yaml_value.h"
#include "io/polygon_reader.h"
#include "io/surface_reader.h"
#include "io/surface_reader_internal.h"
#include "io/surface_writer.h"
#include "tools/transform_file.h"

namespace surfreg {
namespace {

using namespace config_value;  // the value parsers shared with the terrain keys

const Names<bool> kWeightModes = {{"uniform", false}, {"per_point", true}};

using C = AlignConfig;

// An option key (registration/align_keys.h) as a key of the config.
KeyEntry Option(const char* name) {
  const AlignOptionEntry* entry = FindAlignOption(name);
  CHECK(entry != nullptr) << "no option key " << name;
  return {entry->key, [entry](const Value& v, C* c) { entry->set(v, &c->options); },
          [entry](const C& c) { return entry->get(c.options); }};
}

const config_table::Table<AlignConfig>& Table() {
  static const std::vector<KeyEntry> table = {
      {{"reference", "a surface file (.xyz .txt .csv .ply .off .obj .las, or a GDAL raster)",
        "the fixed surface"},
       [](const Value& v, C* c) { c->reference = Path(v, true); },
       [](const C& c) { return c.reference; }},
      {{"moving", "a surface file (.xyz .txt .csv .ply .off .obj .las, or a GDAL raster)",
        "the surface moved onto the reference"},
       [](const Value& v, C* c) { c->moving = Path(v, true); },
       [](const C& c) { return c.moving; }},
      Option("cost"),
      Option("prealign"),
      Option("loss"),
      Option("loss_scale"),
      Option("trust_region"),
      Option("line_search"),
      Option("linear_solver"),
      Option("max_iterations"),
      Option("function_tolerance"),
      Option("trim_fraction"),
      Option("normal_distance"),
      Option("slope_weight"),
      Option("gap_weight"),
      Option("density_weight"),
      Option("density_correction"),
      Option("free"),
      Option("levels"),
      Option("level_factor"),
      Option("subsample"),
      Option("multi_start"),
      Option("multi_start_angle_deg"),
      Option("multi_start_shift"),
      Option("stddev"),
      Option("stddev_subsamples"),
      Option("holdout"),
      Option("holdout_seed"),
      Option("holdout_verdict"),
      Option("wide_search"),
      Option("initial_rotation_deg"),
      Option("initial_translation"),
      {{"initial_transform", "a transform file (align JSON or 4 x 4 text), or nothing",
        "the start: the moving -> reference matrix in the file (not with initial_rotation_deg "
        "or initial_translation)"},
       [](const Value& v, C* c) { c->initial_transform = Path(v, false); },
       [](const C& c) { return c.initial_transform; }},
      {{"classes", "a list of LAS classifications (integers 0 to 255), or nothing",
        "LAS inputs: keep only the points of these classes (e.g. [2] for ground); nothing = all"},
       [](const Value& v, C* c) { c->classes = Classes(v); },
       [](const C& c) { return ListText(c.classes); }},
      {{"columns", "a list of 3 or 4 column names or 1-based positions, or nothing",
        "text clouds: the columns of x, y, z and optionally the weight; other columns are "
        "ignored; nothing = 3 columns (x y z) or 4 (x y z weight)"},
       [](const Value& v, C* c) { c->columns = Columns(v); },
       [](const C& c) { return ListText(c.columns); }},
      {{"mask", "a polygon file ('x y' text, or a vector file: .gpkg .shp .geojson ...), or nothing",
        "weight 1 on the mask's polygons (holes and several parts: even-odd), 0 elsewhere"},
       [](const Value& v, C* c) { c->mask = Path(v, false); },
       [](const C& c) { return c.mask; }},
      Option("mask_mode"),
      {{"mask_layer", "a layer name, or nothing",
        "vector masks: the layer to read (nothing = the first)"},
       [](const Value& v, C* c) { c->mask_layer = Scalar(v); },
       [](const C& c) { return c.mask_layer; }},
      {{"weights", "one of uniform, per_point",
        "mu: uniform, or the reference's per-sample weights (4th .xyz column, PLY 'weight')"},
       [](const Value& v, C* c) { c->per_point_weights = Choice(v, kWeightModes); },
       [](const C& c) { return std::string(c.per_point_weights ? "per_point" : "uniform"); }},
      Option("stable"),
      Option("stable_sigmas"),
      Option("stable_grow_sigmas"),
      Option("domain"),
      Option("domain_max_edge_spacings"),
      Option("domain_min_thinness"),
      Option("max_fold_fraction"),
      Option("covariance"),
      Option("threads"),
      Option("cell_kernel"),
      {{"output", "a file name, or nothing", "the transform JSON"},
       [](const Value& v, C* c) { c->output = Path(v, false); },
       [](const C& c) { return c.output; }},
      {{"matrix_txt", "a file name, or nothing",
        "the moving -> reference matrix as text: 4 lines of 4 numbers"},
       [](const Value& v, C* c) { c->matrix_txt = Path(v, false); },
       [](const C& c) { return c.matrix_txt; }},
      {{"aligned", "a file name ending in .ply, .xyz, .txt or .las (or .tif, raster reference), or nothing",
        "the moving surface after the motion (input coordinates; .tif: resampled onto the "
        "reference's grid; .las from a LAS moving file: all its points, attributes kept)"},
       [](const Value& v, C* c) { c->aligned = Path(v, false); },
       [](const C& c) { return c.aligned; }},
      {{"stable_map", "a file name (.xyz, .txt, .csv; .tif or .png on a raster reference's grid), or nothing",
        "stable auto: the reference's samples flagged 1 stable, 0 changed (left out of the fit), 2 outside "
        "the overlap; a GeoTIFF has 1, 0 and nodata; a PNG maps them blue, red and grey"},
       [](const Value& v, C* c) { c->stable_map = Path(v, false); },
       [](const C& c) { return c.stable_map; }},
      {{"log", "a file name, or nothing", "per-iteration CSV"},
       [](const Value& v, C* c) { c->log = Path(v, false); },
       [](const C& c) { return c.log; }},
      {{"progress", "true or false", "a line per solver iteration on stderr"},
       [](const Value& v, C* c) { c->progress = Boolean(v); },
       [](const C& c) { return Text(c.progress); }},
  };
  static const config_table::Table<AlignConfig> all = [] {
    std::vector<KeyEntry> keys = table;
    keys.insert(keys.end(), TerrainKeyTable().begin(), TerrainKeyTable().end());
    return config_table::Table<AlignConfig>(std::move(keys));
  }();
  return all;
}


// The key named first (as a whole word) in `message`, or "": to say where a
// setting that AlignOptions::IsValid rejects came from.
std::string FirstKeyIn(const std::string& message) {
  const auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  std::size_t first = std::string::npos;
  std::string found;
  for (const std::string& key : Table().names()) {
    for (std::size_t at = message.find(key); at != std::string::npos && at < first;
         at = message.find(key, at + 1)) {
      const std::size_t end = at + key.size();
      if ((at == 0 || !word(message[at - 1])) && (end == message.size() || !word(message[end]))) {
        first = at;
        found = key;
      }
    }
  }
  return found;
}


// A surface format, or a GeoTIFF on a raster reference's grid.
void CheckAlignedPath(const std::string& path, const std::string& reference,
                      const std::string& where) {
  if (IsGeoTiffPath(path) && !IsRasterPath(reference)) {
    throw InputError(where + ": a GeoTIFF '" + path +
                     "' is resampled onto the reference's grid, but the reference is no raster");
  }
  if (!IsGeoTiffPath(path) && !IsWritableSurfacePath(path)) {
    throw InputError(where + ": cannot write a surface as '" + path +
                     "' (expected a name ending in .ply, .xyz, .txt or .las, or .tif for a raster reference)");
  }
}

// One start: a transform file or the rotation and shift keys, read here so
// that a bad file stops the run before anything is read or written.
void ReadInitialTransform(AlignConfig* config) {
  config->initial_matrix.clear();
  if (config->initial_transform.empty()) return;
  for (const char* key : {"initial_rotation_deg", "initial_translation"}) {
    if (AlignConfigValue(*config, key) != "[0, 0, 0]") {
      throw InputError(config->Where("initial_transform") + " and " + config->Where(key) +
                       " both set the start: give one of them");
    }
  }
  const Eigen::Matrix4d m =
      ReadTransformFile(config->initial_transform, config->Where("initial_transform"));
  for (int k = 0; k < 16; ++k) config->initial_matrix.push_back(m(k / 4, k % 4));
}

}  // namespace

const std::vector<AlignConfigKey>& AlignConfigKeys() { return Table().keys(); }

std::string AlignConfigValue(const AlignConfig& config, const std::string& key) {
  return Table().Get(config, key);
}

std::string NearestAlignKey(const std::string& name) { return Table().Nearest(name); }

void ApplyAlignYaml(const std::string& yaml_text, const std::string& file, AlignConfig* config) {
  Table().ApplyYaml(yaml_text, file, config);
}

void ApplyAlignConfigFile(const std::string& path, AlignConfig* config) { Table().ApplyFile(path, config); }

void ApplyAlignFlag(const std::string& key, const std::string& value, AlignConfig* config) {
  Table().ApplyFlag(key, value, config);
}

void ApplyAlignSetting(const std::string& key, const std::string& value, const std::string& where,
                       AlignConfig* config) {
  Table().Set(key, value, where, config);
}

void ApplyAlignArguments(const std::string& reference, const std::string& moving,
                         AlignConfig* config) {
  Table().Set("reference", reference, "argument REFERENCE", config);
  Table().Set("moving", moving, "argument MOVING", config);
}

void FinishAlignConfig(AlignConfig* config) {
  const std::string source = config->config_file.empty() ? "" : config->config_file + ": ";
  for (const char* key : {"reference", "moving"}) {
    if (AlignConfigValue(*config, key).empty()) {
      throw InputError(source + "no '" + key + "' surface given (add '" + key +
                       ": FILE' to the config or give --" + key + "=FILE)");
    }
  }
  // Outputs must not overwrite an input or each other.
  std::vector<std::pair<std::string, std::string>> files = {{"reference", config->reference},
                                                            {"moving", config->moving}};
  if (!config->mask.empty()) files.emplace_back("mask", config->mask);
  if (!config->initial_transform.empty()) {
    files.emplace_back("initial_transform", config->initial_transform);
  }
  if (!config->terrain.mask_raster.empty()) {
    files.emplace_back("mask_raster", config->terrain.mask_raster);
  }
  for (const char* key : {"sigma_reference", "sigma_moving"}) {  // σ rasters are inputs too
    const std::string& text = std::string(key) == "sigma_reference" ? config->terrain.sigma_reference
                                                                     : config->terrain.sigma_moving;
    if (IsRasterPath(text)) files.emplace_back(key, text);
  }
  const bool has_sigma = !config->terrain.sigma_reference.empty() || !config->terrain.sigma_moving.empty() ||
                         config->terrain.error_model == "variogram";
  for (const char* key : {"lod_confidence", "dod_sigma", "change_mask"}) {
    if (!has_sigma && config->origin.count(key) != 0 && !AlignConfigValue(*config, key).empty() &&
        AlignConfigValue(*config, key) != "0") {
      throw InputError(config->Where(key) +
                       " needs the DEMs' vertical errors: give sigma_reference and/or sigma_moving, or "
                       "error_model: variogram");
    }
  }
  if (!config->terrain.variogram_png.empty() && config->terrain.error_model != "variogram") {
    throw InputError(config->Where("variogram_png") + ": needs error_model: variogram");
  }
  for (const char* key :
       {"output", "matrix_txt", "aligned", "log", "stable_map", "dod", "dod_png", "histogram_png", "change_csv", "dod_sigma",
        "dod_thresholded", "variogram_png", "tile_stats", "patch_shifts"}) {
    const std::string path = AlignConfigValue(*config, key);
    if (path.empty()) continue;
    const std::string where = config->Where(key);
    if (std::string(key) == "aligned") CheckAlignedPath(path, config->reference, where);
    CheckTerrainOutput(key, path, where);
    CheckOutputPath(path, where);
    for (const auto& [other, other_path] : files) {
      if (SameFile(path, other_path)) {
        throw InputError(where + ": '" + path + "' is also the " + other + " file");
      }
    }
    files.emplace_back(key, path);
  }
  if (config->per_point_weights) {
    // One μ at a time: a mask or a stable-terrain raster is a weight of its own.
    for (const char* other : {"mask", "mask_raster"}) {
      if (!AlignConfigValue(*config, other).empty()) {
        throw InputError(config->Where("weights") + ": per_point cannot be combined with '" +
                         other + "' (" + config->Where(other) + ")");
      }
    }
    config->options.weight = WeightMode::kPerPoint;
  }
  for (const char* key : {"mask_mode", "mask_layer"}) {
    if (config->mask.empty() && config->origin.count(key) != 0 &&
        AlignConfigValue(*config, key) != (std::string(key) == "mask_mode" ? "include" : "")) {
      throw InputError(config->Where(key) + ": needs a mask ('mask')");
    }
  }
  ReadInitialTransform(config);
  if (!config->mask.empty()) {
    try {
      MaskFile file = ReadMask(config->mask, config->mask_layer);
      config->options.mask = std::move(file.rings);
      config->mask_crs_wkt = std::move(file.crs_wkt);
    } catch (const InputError& e) {
      throw InputError(config->Where("mask") + ": " + e.what());
    }
    config->options.weight = WeightMode::kMask;
  }
  // The keys' own checks come first; this catches the combinations (and any
  // rule the table does not know), naming the key the message names.
  std::string error;
  if (!config->options.IsValid(&error)) {
    const std::string key = FirstKeyIn(error);
    throw InputError((key.empty() ? config->config_file.empty() ? "settings" : config->config_file
                                  : config->Where(key)) +
                     ": " + error);
  }
}

DomainRule DomainRuleFromFlags(const std::string& domain, const std::string& max_edge_spacings,
                               const std::string& min_thinness) {
  AlignConfig config;
  const std::pair<const char*, const std::string*> flags[] = {
      {"domain", &domain},
      {"domain_max_edge_spacings", &max_edge_spacings},
      {"domain_min_thinness", &min_thinness}};
  for (const auto& [key, text] : flags) {
    if (!text->empty()) ApplyAlignFlag(key, *text, &config);
  }
  return config.options.domain;
}

}  // namespace surfreg
