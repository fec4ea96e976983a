#pragma once
// The settings of `surfreg align` (docs/align.md): one table of keys, each a
// field of AlignOptions or an input/output setting, read from a YAML mapping
// ("key: value" lines) and from command-line flags of the same names.
//
// Precedence: AlignOptions' own defaults < the config file (or the
// REFERENCE MOVING arguments) < flags given on the command line. Relative
// paths are used as given, i.e. relative to the current directory.
//
// Error policy: every problem throws InputError with one line saying where
// ("t.yaml:3: key 'cost'", "flag '--cost'", "argument MOVING") and what.
// This is the only user of yaml-cpp; its exceptions are converted here.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "measure/surface.h"
#include "registration/align.h"
#include "tools/config_key.h"
#include "tools/io/surface_reader.h"

namespace surfreg {

// Terrain: rasters, geographic frames, change detection (docs/terrain.md).
struct TerrainSettings {
  std::string reference_crs, moving_crs;  // "" = the raster's own, or none
  std::string frame = "auto";             // auto | enu | utm (geographic inputs)
  int band = 1;                           // raster band
  std::array<int, 4> window = {0, 0, 0, 0};  // column, row, columns, rows; 0 = all
  double lod = 0;                         // level of detection for cut/fill (data units)
  std::string dod;                        // DoD GeoTIFF on the reference raster's grid
  std::string dod_png, histogram_png;     // figures
  std::string change_csv;                 // dz at every reference sample before/after
  std::vector<double> known_matrix;       // 16 numbers (moving -> reference) or empty
  std::string mask_raster;                // stable terrain raster (non-zero cells) as μ; "" = none
  // Each DEM's vertical standard error: a number >= 0 (data units) or a σ
  // raster on that DEM's grid; "" = none (measure/change_budget.h).
  std::string sigma_reference, sigma_moving;
  double lod_confidence = 0;              // (0, 1): threshold t(confidence) · σ_DoD; 0 = none
  std::string dod_sigma, dod_thresholded;  // GeoTIFFs on the reference raster's grid
  // Two DEMs too large to hold (tools/align_tiled.h): a memory budget such
  // as "2G" ("" = untiled), and the per-tile dz statistics CSV.
  std::string max_memory;
  std::string tile_stats;
  std::string patch_shifts;  // each sampled patch's own shift (CSV); "" = none
  // Whether any terrain output or setting is asked for (or an input is a
  // raster or LAS): then `align` also reports change and dz statistics.
  bool Active(const std::string& reference, const std::string& moving) const;
};

struct AlignConfig {
  std::string reference;  // fixed surface file (required)
  std::string moving;     // surface file moved onto the reference (required)
  // Solver settings. initial_rotation is in radians here (the key
  // initial_rotation_deg is in degrees); weight and mask are set by
  // FinishAlignConfig from `mask` and `per_point_weights`.
  AlignOptions options;
  std::string mask;         // polygon file (input coordinates) for μ; "" = uniform
  std::string mask_layer;   // a vector mask's layer; "" = the first
  std::string mask_crs_wkt;  // the mask file's CRS ("" = the reference's), set by FinishAlignConfig
  bool per_point_weights = false;  // key weights: per_point (the reference's sample weights)
  std::string output;       // transform JSON; "" = none
  std::string matrix_txt;   // the 4x4 moving -> reference matrix as text; "" = none
  // The start from a transform file (tools/transform_file.h), in the frame
  // Align works in; initial_matrix (16 numbers, row-major) is read from it
  // by FinishAlignConfig and turned into options' initial motion once the
  // moving surface is read (ApplyInitialTransform, tools/align_run.h).
  std::string initial_transform;
  std::vector<double> initial_matrix;  // empty = none
  std::string aligned;      // the moved `moving` surface (.ply, .xyz, .txt); "" = none
  std::string log;          // per-iteration CSV; "" = none
  // The reference's samples as stable, changed or outside the overlap
  // (stable auto): "x y z stable" text, or a GeoTIFF on a raster
  // reference's grid; "" = none.
  std::string stable_map;
  bool progress = false;    // one line per solver iteration on stderr
  // How both inputs are read (ReadOptions, tools/io/surface_reader.h).
  std::vector<int> classes;          // LAS classifications kept; empty = all
  std::vector<std::string> columns;  // text clouds: x, y, z [, weight] columns; empty = 3 or 4
  TerrainSettings terrain;
  std::string config_file;  // "" when the run has no config file
  // Where each key was last set: "t.yaml:3: key 'cost'", "flag '--cost'",
  // "argument MOVING". Keys left at their default are absent.
  std::map<std::string, std::string> origin;

  // origin[key], or "key 'KEY'" for a default: the start of a message.
  std::string Where(const std::string& key) const;
};

using AlignConfigKey = ConfigKey;

// Whether `key` is one of the terrain keys (docs/terrain.md): settings that
// only a single `align` run uses (not sweeps or manifests).
bool IsTerrainKey(const std::string& key);

// Every key, in the order of the documentation.
const std::vector<AlignConfigKey>& AlignConfigKeys();

// The value of `key` in `config` as YAML text ("axial", "100", "[0, 0, 0]");
// "" for a file key that names no file. Throws InputError for an unknown key.
std::string AlignConfigValue(const AlignConfig& config, const std::string& key);

// The known key closest to `name` (edit distance, or one containing the
// other), or "" when none is close.
std::string NearestAlignKey(const std::string& name);

// The same among `keys` (e.g. the keys `measure` takes).
std::string NearestKey(const std::string& name, const std::vector<std::string>& keys);

// Applies the YAML mapping `yaml_text` on top of *config; `file` names it in
// messages. Rejects text that is not a mapping, unknown and repeated keys,
// and values of the wrong type.
void ApplyAlignYaml(const std::string& yaml_text, const std::string& file, AlignConfig* config);

// Reads the file at `path` (errors name "flag '--config'") and applies it.
void ApplyAlignConfigFile(const std::string& path, AlignConfig* config);

// A flag --KEY=VALUE given on the command line (VALUE as gflags holds it:
// booleans "true"/"false"; lists as "1,2,3" or "[1, 2, 3]"; "" for a file
// key means no file).
void ApplyAlignFlag(const std::string& key, const std::string& value, AlignConfig* config);

// The same value text given elsewhere: `where` starts the messages (the
// Python module's "keyword 'cost'"; ApplyAlignFlag's is "flag '--cost'").
void ApplyAlignSetting(const std::string& key, const std::string& value, const std::string& where,
                       AlignConfig* config);

// The positional form: surfreg align REFERENCE MOVING.
void ApplyAlignArguments(const std::string& reference, const std::string& moving,
                         AlignConfig* config);

// Once every setting is applied: checks that reference and moving are given,
// that the output files can be written (their directories exist, `aligned`
// has a known extension, no output names an input or another output), reads
// the mask polygon into options and the initial_transform file into
// initial_matrix (not together with initial_rotation_deg or
// initial_translation), and checks the options as a whole
// (AlignOptions::IsValid, e.g. a mask with the volume cost). Throws
// InputError naming the key.
void FinishAlignConfig(AlignConfig* config);

// The domain keys as `measure` and `triangulate` take them from their flags
// (`--domain`, `--domain_max_edge_spacings`, `--domain_min_thinness`; ""
// = not given): the same values, defaults and messages as align's keys.
DomainRule DomainRuleFromFlags(const std::string& domain, const std::string& max_edge_spacings,
                               const std::string& min_thinness);

// How config.reference or config.moving (`key`) is read: `classes` if it is
// LAS or the other input is not, `columns` if it is a text cloud or the
// other is not (so a key that fits neither input is refused, by the reader).
ReadOptions AlignReadOptions(const AlignConfig& config, const std::string& key);

// Reads config.reference or config.moving (`key` is "reference" or
// "moving") with its classes and columns; a read error is prefixed with
// where the key was set. A non-null `crs` gets the file's CRS text (see
// ReadSurface).
Surface ReadAlignSurface(const AlignConfig& config, const std::string& key,
                         std::string* crs = nullptr);

}  // namespace surfreg
