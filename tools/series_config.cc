#include "tools/series_config.h"

#include <glog/logging.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "io/atomic_file.h"
#include "io/raster_io.h"
#include "io/surface_writer.h"
#include "measure/input_error.h"
#include "registration/align_keys.h"
#include "terrain/terrain_keys.h"
#include "tools/align_config_values.h"
#include "tools/config_table.h"

namespace surfreg {
namespace {

using config_value::Value;
namespace cv = config_value;
using C = SeriesConfig;
using Entry = cv::Entry<SeriesConfig>;

// An alignment key (registration/align_keys.h) as a key of the series.
Entry Option(const char* name) {
  const AlignOptionEntry* entry = FindAlignOption(name);
  CHECK(entry != nullptr) << "no option key " << name;
  return {entry->key, [entry](const Value& v, C* c) { entry->set(v, &c->options.align); },
          [entry](const C& c) { return entry->get(c.options.align); }};
}

std::string Join(const std::vector<std::string>& items) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

// "i-j" (two epoch indices).
std::pair<int, int> PairOf(const Value& v, const std::string& item) {
  const std::size_t dash = item.find('-');
  const auto index = [&](const std::string& text) {
    if (text.empty() || text.size() > 6 || !std::all_of(text.begin(), text.end(), [](char c) {
          return std::isdigit(static_cast<unsigned char>(c));
        })) {
      throw InputError(v.where + ": expects pairs of epoch indices such as 0-1, got " +
                       Quote(item));
    }
    return std::stoi(text);
  };
  if (dash == std::string::npos) index("");
  return {index(item.substr(0, dash)), index(item.substr(dash + 1))};
}

// A terrain key (terrain/terrain_keys.h) as a key of the series, kept in
// `field`.
Entry Terrain(const char* name, std::string C::*field) {
  const TerrainSettingEntry* entry = FindTerrainSetting(name);
  CHECK(entry != nullptr) << "no terrain key " << name;
  return {entry->key,
          [entry, field](const Value& v, C* c) {
            TerrainSettings settings;
            entry->set(v, &settings);
            c->*field = entry->get(settings);
          },
          [field](const C& c) { return c.*field; }};
}

// Align's option keys that do not apply to a series: each pair starts from
// the inputs, and the held-out check and masks are one pair's.
bool SeriesTakes(const std::string& option) {
  for (const char* other :
       {"initial_rotation_deg", "initial_translation", "holdout", "holdout_seed", "holdout_verdict", "mask_mode"}) {
    if (option == other) return false;
  }
  return true;
}

const config_table::Table<SeriesConfig>& Table() {
  static const std::vector<Entry> own = {
      {{"surfaces", "a list of surface files (.xyz .txt .csv .ply .off .obj .las, or GDAL rasters)",
        "the epochs, in time order"},
       [](const Value& v, C* c) {
         c->surfaces = cv::Items(v);
         if (std::any_of(c->surfaces.begin(), c->surfaces.end(),
                         [](const std::string& s) { return s.empty(); })) {
           cv::Reject(v);
         }
       },
       [](const C& c) { return c.surfaces.empty() ? std::string() : Join(c.surfaces); }},
      {{"reference", "an epoch index >= 0 or one of the surfaces",
        "the epoch the others are brought into"},
       [](const Value& v, C* c) { c->reference = cv::Path(v, true); },
       [](const C& c) { return c.reference; }},
      {{"pairs", "a list of epoch index pairs such as 0-1, or nothing",
        "the pairs to align; nothing = every pair overlapping by min_overlap"},
       [](const Value& v, C* c) {
         c->pairs.clear();
         for (const std::string& item : cv::Items(v)) c->pairs.push_back(PairOf(v, item));
       },
       [](const C& c) {
         std::vector<std::string> items;
         for (const auto& [a, b] : c.pairs)
           items.push_back(std::to_string(a) + "-" + std::to_string(b));
         return items.empty() ? std::string() : Join(items);
       }},
      {{"min_overlap", "a number in (0, 1]",
        "the share of the smaller footprint two epochs must share to be a pair"},
       [](const Value& v, C* c) { c->options.min_overlap = cv::Number(v, 0, 1, "(]"); },
       [](const C& c) { return cv::Text(c.options.min_overlap); }},
      {{"dates", "a list of dates YYYY-MM-DD, one per surface, or nothing",
        "when each epoch was surveyed: the change between consecutive epochs also per year"},
       [](const Value& v, C* c) { c->dates = cv::Items(v); },
       [](const C& c) { return c.dates.empty() ? std::string() : Join(c.dates); }},
      {{"classes", "a list of LAS classifications (integers 0 to 255), or nothing",
        "LAS inputs: keep only the points of these classes (e.g. [2] for ground); nothing = all"},
       [](const Value& v, C* c) { c->classes = cv::Classes(v); },
       [](const C& c) { return cv::ListText(c.classes); }},
      {{"columns", "a list of 3 or 4 column names or 1-based positions, or nothing",
        "text clouds: the columns of x, y, z and optionally the weight"},
       [](const Value& v, C* c) { c->columns = cv::Columns(v); },
       [](const C& c) { return cv::ListText(c.columns); }},
      {{"crs", "a CRS (EPSG:4326, EPSG:32760, WKT, lonlat), or nothing",
        "the epochs' coordinate system where their files do not say (rasters and LAS files carry their "
        "own)"},
       [](const Value& v, C* c) { c->crs = cv::Path(v, false); },
       [](const C& c) { return c.crs; }},
      Terrain("frame", &C::frame),
      {{"output", "a file name, or nothing", "the series JSON"},
       [](const Value& v, C* c) { c->output = cv::Path(v, false); },
       [](const C& c) { return c.output; }},
      {{"aligned_dir", "a folder, or nothing",
        "each epoch moved into the reference's frame, named as its file (.ply unless .xyz, .txt or "
        ".ply)"},
       [](const Value& v, C* c) { c->aligned_dir = cv::Path(v, false); },
       [](const C& c) { return c.aligned_dir; }},
      {{"dod_dir", "a folder, or nothing",
        "the DoD of each consecutive pair of raster epochs on the earlier one's grid "
        "(EARLIER_to_LATER.tif: the later minus the earlier once aligned)"},
       [](const Value& v, C* c) { c->dod_dir = cv::Path(v, false); },
       [](const C& c) { return c.dod_dir; }},
      {{"progress", "true or false", "a line per stage on stderr"},
       [](const Value& v, C* c) { c->progress = cv::Boolean(v); },
       [](const C& c) { return cv::Text(c.progress); }},
  };
  // The inputs' keys, then every alignment key (registration/align_keys.h)
  // a series takes, then the outputs.
  static const config_table::Table<SeriesConfig> table = [] {
    const auto first_output = std::find_if(own.begin(), own.end(), [](const Entry& e) {
      return std::string(e.key.name) == "output";
    });
    std::vector<Entry> keys(own.begin(), first_output);
    for (const AlignOptionEntry& entry : AlignOptionKeys()) {
      if (SeriesTakes(entry.key.name)) keys.push_back(Option(entry.key.name));
    }
    keys.insert(keys.end(), first_output, own.end());
    return config_table::Table<SeriesConfig>(std::move(keys));
  }();
  return table;
}

int ResolveReference(const SeriesConfig& config) {
  const std::string& text = config.reference;
  const int count = static_cast<int>(config.surfaces.size());
  const bool digits = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c));
  });
  if (digits) {
    const long index = text.size() > 9 ? count : std::stol(text);
    if (index >= count) {
      throw InputError(config.Where("reference") + ": epoch " + text + " is beyond the " +
                       std::to_string(count) + " epochs (0-based)");
    }
    return static_cast<int>(index);
  }
  for (int k = 0; k < count; ++k) {
    if (SameFile(text, config.surfaces[k])) return k;
  }
  throw InputError(config.Where("reference") + ": '" + text +
                   "' is neither an epoch index nor one of the " + std::to_string(count) +
                   " surfaces");
}

// "YYYY-MM-DD" as days since 1970-01-01 (timegm, UTC); false for anything
// else or a day the month does not have (timegm would roll it over).
bool ParseDate(const std::string& text, double* days) {
  int y = 0, m = 0, d = 0;
  char tail = 0;
  if (text.size() != 10 || std::sscanf(text.c_str(), "%4d-%2d-%2d%c", &y, &m, &d, &tail) != 3) return false;
  std::tm date{};
  date.tm_year = y - 1900;
  date.tm_mon = m - 1;
  date.tm_mday = d;
  date.tm_hour = 12;  // noon: no leap second or rounding near midnight
  const std::time_t seconds = timegm(&date);
  if (date.tm_year != y - 1900 || date.tm_mon != m - 1 || date.tm_mday != d) return false;
  *days = std::floor(static_cast<double>(seconds) / 86400.0);
  return true;
}

void ResolveDates(SeriesConfig* config) {
  config->days.clear();
  if (config->dates.empty()) return;
  const std::string where = config->Where("dates");
  if (config->dates.size() != config->surfaces.size()) {
    throw InputError(where + ": " + std::to_string(config->dates.size()) + " dates for " +
                     std::to_string(config->surfaces.size()) + " surfaces (one per surface)");
  }
  for (std::size_t k = 0; k < config->dates.size(); ++k) {
    double days = 0;
    if (!ParseDate(config->dates[k], &days)) {
      throw InputError(where + ": expects dates as YYYY-MM-DD, got " + Quote(config->dates[k]));
    }
    if (k > 0 && days <= config->days.back()) {
      throw InputError(where + ": " + config->dates[k] + " is not after " + config->dates[k - 1] +
                       " (the surfaces in time order)");
    }
    config->days.push_back(days);
  }
}

}  // namespace

std::string SeriesConfig::Where(const std::string& key) const {
  const auto found = origin.find(key);
  if (found != origin.end()) return found->second;
  return (config_file.empty() ? "" : config_file + ": ") + "key '" + key + "'";
}

const std::vector<ConfigKey>& SeriesConfigKeys() { return Table().keys(); }

std::string SeriesConfigValue(const SeriesConfig& config, const std::string& key) {
  return Table().Get(config, key);
}

void ApplySeriesYaml(const std::string& yaml_text, const std::string& file, SeriesConfig* config) {
  Table().ApplyYaml(yaml_text, file, config);
}

void ApplySeriesConfigFile(const std::string& path, SeriesConfig* config) {
  Table().ApplyFile(path, config);
}

void ApplySeriesSetting(const std::string& key, const std::string& value, const std::string& where,
                        SeriesConfig* config) {
  Table().Set(key, value, where, config);
}

void ApplySeriesArguments(const std::vector<std::string>& files, SeriesConfig* config) {
  config->surfaces = files;
  config->origin["surfaces"] = "arguments EPOCH";
}

std::string AlignedEpochPath(const SeriesConfig& config, int k) {
  if (config.aligned_dir.empty()) return "";
  namespace fs = std::filesystem;
  fs::path name = fs::path(config.surfaces[k]).filename();
  std::string ext = name.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".xyz" && ext != ".txt" && ext != ".ply") name.replace_extension(".ply");
  return (fs::path(config.aligned_dir) / name).string();
}

std::string DodPath(const SeriesConfig& config, int k) {
  if (config.dod_dir.empty()) return "";
  namespace fs = std::filesystem;
  const std::string name = fs::path(config.surfaces[k]).stem().string() + "_to_" +
                           fs::path(config.surfaces[k + 1]).stem().string() + ".tif";
  return (fs::path(config.dod_dir) / name).string();
}

namespace {

// dod_dir: a folder; every epoch but the last a raster (each DoD is on the
// earlier epoch's grid); no DoD over an input, nor two DoDs on one name.
void CheckDodDir(const SeriesConfig& config) {
  const std::string where = config.Where("dod_dir");
  std::error_code error;
  if (!std::filesystem::is_directory(config.dod_dir, error))
    throw InputError(where + ": no such folder '" + config.dod_dir + "'");
  std::vector<std::string> written;
  for (std::size_t k = 0; k + 1 < config.surfaces.size(); ++k) {
    if (!IsRasterPath(config.surfaces[k])) {
      throw InputError(where + ": epoch " + std::to_string(k) + " (" + config.surfaces[k] +
                       ") is not a raster; the DoD of " + std::to_string(k) + "-" +
                       std::to_string(k + 1) + " is drawn on the earlier epoch's grid");
    }
    const std::string path = DodPath(config, static_cast<int>(k));
    for (const std::string& file : config.surfaces) {
      if (SameFile(path, file))
        throw InputError(where + ": the DoD " + path + " would be written over an epoch");
    }
    if (std::find(written.begin(), written.end(), path) != written.end()) {
      throw InputError(where + ": two consecutive pairs' DoDs would both be " + path +
                       " (epochs of one file name)");
    }
    written.push_back(path);
  }
}

}  // namespace

void FinishSeriesConfig(SeriesConfig* config) {
  const std::string where = config->Where("surfaces");
  if (config->surfaces.size() < 2) {
    throw InputError(where + ": a series needs at least 2 surfaces, got " +
                     std::to_string(config->surfaces.size()));
  }
  std::error_code error;
  for (const std::string& file : config->surfaces) {
    if (!std::filesystem::is_regular_file(file, error))
      throw InputError(where + ": no such file '" + file + "'");
  }
  config->options.reference = ResolveReference(*config);
  const int count = static_cast<int>(config->surfaces.size());
  for (const auto& [a, b] : config->pairs) {
    if (a >= count || b >= count || a == b) {
      throw InputError(config->Where("pairs") + ": " + std::to_string(a) + "-" + std::to_string(b) +
                       " does not name two different epochs of the " + std::to_string(count));
    }
  }
  config->options.pairs = config->pairs;
  ResolveDates(config);
  if (!config->output.empty()) {
    CheckOutputPath(config->output, config->Where("output"));
    for (const std::string& file : config->surfaces) {
      if (SameFile(config->output, file)) {
        throw InputError(config->Where("output") + ": '" + config->output +
                         "' is one of the surfaces");
      }
    }
  }
  if (!config->aligned_dir.empty()) {
    if (!std::filesystem::is_directory(config->aligned_dir, error)) {
      throw InputError(config->Where("aligned_dir") + ": no such folder '" + config->aligned_dir +
                       "'");
    }
    for (int k = 0; k < count; ++k) {
      const std::string path = AlignedEpochPath(*config, k);
      for (const std::string& file : config->surfaces) {
        if (SameFile(path, file)) {
          throw InputError(config->Where("aligned_dir") + ": epoch " + std::to_string(k) +
                           " would be written over '" + file + "'");
        }
      }
    }
  }
  if (!config->dod_dir.empty()) CheckDodDir(*config);
  std::string message;
  if (!config->options.align.IsValid(&message)) throw InputError("series settings: " + message);
}

}  // namespace surfreg
