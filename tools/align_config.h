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
#include "terrain/terrain_request.h"
#include "measure/option_keys.h"
#include "io/surface_reader.h"

namespace surfreg {

// The settings of one `align` run: what a terrain run is asked
// (terrain/terrain_request.h: the inputs, the alignment's options, the
// terrain keys, where each key was set) and the command's own outputs.
struct AlignConfig : TerrainRequest {
  std::string output;       // transform JSON; "" = none
  std::string matrix_txt;   // the 4x4 moving -> reference matrix as text; "" = none
  // The start from a transform file (tools/transform_file.h), in the frame
  // Align works in; initial_matrix (16 numbers, row-major) is read from it
  // by FinishAlignConfig and turned into options' initial motion once the
  // moving surface is read (ApplyInitialTransform, tools/align_run.h).
  std::string initial_transform;
  std::string aligned;      // the moved `moving` surface (.ply, .xyz, .txt); "" = none
  std::string log;          // per-iteration CSV; "" = none
  // The reference's samples as stable, changed or outside the overlap
  // (stable auto): "x y z stable" text, or a GeoTIFF on a raster
  // reference's grid; "" = none.
  std::string stable_map;
  bool progress = false;    // one line per solver iteration on stderr
  std::string config_file;  // "" when the run has no config file
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

}  // namespace surfreg
