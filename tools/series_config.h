#pragma once
// The settings of `surfreg series` (docs/series.md): one table of keys, read
// from a YAML mapping and from --KEY=VALUE flags of the same names, with the
// precedence SeriesOptions' defaults < the config file (or the EPOCH
// arguments) < flags. The alignment keys are align's (registration/
// align_keys.h), each defined once there.
//
// Keys (defaults in brackets):
//   surfaces      the epochs' surface files, in time order   [required]
//   reference     the reference epoch: an index (0-based) or one of the files [0]
//   pairs         the pairs to align, as "i-j" items ([0-1, 1-2]); nothing =
//                 every pair overlapping by min_overlap      [nothing]
//   min_overlap   the smaller footprint's share two epochs must share [0.3]
//   dates         each surface's date, YYYY-MM-DD, in the order of surfaces:
//                 the change between consecutive epochs also per year [none]
//   classes, columns   how point files are read, as for align
//   crs           the epochs' CRS where their files do not say   [none]
//   frame         lon/lat epochs: the metric frame, auto, utm or enu [auto]
//   output        the series JSON                            [none]
//   aligned_dir   a folder: each epoch moved into the reference's frame,
//                 named as its file (.ply unless .xyz/.txt/.ply) [none]
//   dod_dir       a folder: the DoD of each consecutive pair (every epoch
//                 but the last a raster) on the earlier epoch's grid, named
//                 EARLIER_to_LATER.tif                         [none]
//   progress      a line per stage on stderr                 [false]
//   cost, levels, stable, threads, ...: the alignment keys of `align` that
//                 apply to each pair (not its inputs, outputs, starts or masks)
//
// Errors: InputError with one line naming where ("s.yaml:3: key 'pairs'",
// "flag '--pairs'", "argument EPOCH 2") and what.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "measure/option_keys.h"
#include "registration/series.h"

namespace surfreg {

struct SeriesConfig {
  std::vector<std::string> surfaces;
  std::string reference = "0";  // index or file, as given
  std::vector<std::pair<int, int>> pairs;
  std::vector<std::string> dates;  // YYYY-MM-DD per surface, or none
  std::vector<double> days;        // FinishSeriesConfig: each date as days since 1970-01-01
  SeriesOptions options;  // options.reference set by FinishSeriesConfig
  std::vector<int> classes;
  std::vector<std::string> columns;
  std::string crs;             // the epochs' CRS where their files carry none ("" = none)
  std::string frame = "auto";  // terrain key `frame` (terrain/terrain_keys.h)
  std::string output, aligned_dir, dod_dir;
  bool progress = false;
  std::string config_file;
  std::map<std::string, std::string> origin;  // key -> where it was last set

  std::string Where(const std::string& key) const;  // origin[key] or "key 'KEY'"
};

// Every key, in the order of the documentation above.
const std::vector<ConfigKey>& SeriesConfigKeys();
// The value of `key` as YAML text; InputError for an unknown key.
std::string SeriesConfigValue(const SeriesConfig& config, const std::string& key);

void ApplySeriesYaml(const std::string& yaml_text, const std::string& file, SeriesConfig* config);
void ApplySeriesConfigFile(const std::string& path, SeriesConfig* config);
// A flag --KEY=VALUE, or a keyword's value (`where` starts the messages).
void ApplySeriesSetting(const std::string& key, const std::string& value, const std::string& where,
                        SeriesConfig* config);
// The positional form: surfreg series E0 E1 ...
void ApplySeriesArguments(const std::vector<std::string>& files, SeriesConfig* config);

// Once every setting is applied: at least two surfaces that exist, the
// reference resolved, the pairs within range, one valid date per surface
// (if any) in increasing order, the outputs writable (the
// folder exists; no output names an input). Throws InputError naming the key.
void FinishSeriesConfig(SeriesConfig* config);

// The file aligned_dir gives epoch `k` ("" without aligned_dir).
std::string AlignedEpochPath(const SeriesConfig& config, int k);

// The DoD file dod_dir gives the consecutive pair k, k + 1 ("" without dod_dir).
std::string DodPath(const SeriesConfig& config, int k);

}  // namespace surfreg
