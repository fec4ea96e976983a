#include "tools/cli_help.h"

#include <gflags/gflags.h>

#include <algorithm>
#include <set>
#include <sstream>
#include <vector>

#include "tools/align_config.h"
#include "tools/jaw_config.h"
#include "tools/series_config.h"
#include "measure/measure_keys.h"
#include "tools/measure_run.h"

namespace surfreg {
namespace {

struct Entry {
  std::string name, values, default_value, help;
};

void Print(const Entry& e, std::ostringstream& out) {
  out << "  " << e.name << ": " << e.values;
  if (!e.default_value.empty()) out << " (default " << e.default_value << ")";
  out << "\n      " << e.help << "\n";
}

Entry AlignEntry(const AlignConfigKey& key) {
  static const AlignConfig defaults;
  return {key.name, key.type, AlignConfigValue(defaults, key.name), key.help};
}

// Flags several commands share, whose descriptions speak for align.
struct Override {
  const char *command, *flag, *help;
};
constexpr Override kOverrides[] = {
    {"sweep", "config", "the sweep's YAML file (keys above; configs/sweep_example.yaml)"},
    {"sweep", "output", "the per-run CSV instead of the config's 'output'; the summary and plots are named after it"},
    {"jaw", "config", "the jaw YAML file (keys above)"},
    {"series", "config", "the series YAML file (keys above; configs/series_volcano.yaml)"},
    {"normalize", "output", "write the face's height field here (.xyz, .ply, .txt)"},
    {"asymmetry", "output", "write the asymmetry JSON here"},
    {"asymmetry", "threads", "threads (all: every core); a folder's faces and two scans run side by side, one thread each"},
    {"transform", "output", "the moved surface (.xyz, .txt, .ply, .las; or .tif, resampled onto a grid)"},
    {"triangulate", "threads", "threads (all: every core) for reading, the triangulation and the domain; the same mesh on any number"},
    {"transform", "band", "the band of a raster INPUT"},
    {"transform", "threads", "threads (all: every core) for reading, the mesh and the resampling; the same output on any number"},
    {"transform", "window", "column,row,columns,rows of a raster INPUT read (0 = to the edge; the default output grid)"},
    {"measure", "shard", "K/N (with --tile or --max_memory and --partial): measure only the K-th of N bands of tile rows"},
    {"measure", "resume", "continue a tiled measure that was interrupted, from its finished tile rows"},
    {"merge", "dod", "join the tiled measure's shards' DoD bands into this GeoTIFF"},
};

// The top-level keys of a sweep's YAML (tools/sweep_config.h); the align
// keys under `settings` and `sweep` are those of `surfreg help align`.
const Entry kSweepKeys[] = {
    {"pairs", "a list of {name, reference, moving, truth}", "", "the surface pairs; truth: {rotation_deg, translation} | {matrix} | {file}"},
    {"settings", "a mapping of align keys", "", "settings shared by every run (see 'surfreg help align')"},
    {"sweep", "a mapping of align keys to lists of values", "", "the settings swept; the first key varies slowest"},
    {"perturbations", "{rotation_deg: [...], shift_spacings: [...], directions: N, seed: S}", "", "initial offsets of each run"},
    {"success", "{rotation_deg: R, spacings: S}", "0.1, 0.5", "a run succeeds when converged_improved and its errors are below these"},
    {"jobs", "an integer >= 1", "the number of cores", "parallel runs"},
    {"output", "a file name ending in .csv", "", "the per-run CSV; the other outputs are named after it"},
};

// The flag's own description less its "measure, align: " list of users.
bool FlagEntry(const std::string& command, const std::string& name, Entry* entry) {
  gflags::CommandLineFlagInfo info;
  if (!gflags::GetCommandLineFlagInfo(name.c_str(), &info)) return false;
  std::string help = info.description;
  for (const Override& o : kOverrides) {
    if (command == o.command && name == o.flag) help = o.help;
  }
  const std::size_t colon = help.find(": ");
  if (colon != std::string::npos && help.find_first_not_of("abcdefghijklmnopqrstuvwxyz, -", 0) >= colon) {
    help = help.substr(colon + 2);
  }
  const bool unset_string = info.type == "string" && info.default_value.empty();
  const std::string type = info.type == "bool"     ? "true or false"
                          : info.type == "double" ? "a number"
                          : info.type == "string" ? "text"
                                                  : "an integer";
  *entry = {"--" + name, type,
            unset_string ? "" : info.default_value, help};
  return true;
}

}  // namespace

std::string CommandKeysHelp(const std::string& command, const std::string& flags) {
  std::ostringstream out;
  std::set<std::string> listed;
  std::vector<Entry> keys;
  if (command == "align") {
    for (const AlignConfigKey& key : AlignConfigKeys()) keys.push_back(AlignEntry(key));
  } else if (command == "series") {
    static const SeriesConfig defaults;
    for (const ConfigKey& key : SeriesConfigKeys()) {
      keys.push_back({key.name, key.type, SeriesConfigValue(defaults, key.name), key.help});
    }
  } else if (command == "jaw") {
    static const JawConfig defaults;
    for (const JawConfigKey& key : JawConfigKeys()) {
      keys.push_back({key.name, key.type, JawConfigValue(defaults, key.name), key.help});
    }
  } else if (command == "measure") {
    static const MeasureOptions measure_defaults;
    for (const std::string& name : MeasureKeys()) {
      // The library's measure keys, as the table defines them (weights: the
      // CLI's flag, which also takes mask:FILE); then the CLI's own flags
      // and align's keys.
      const auto library = std::find_if(MeasureOptionKeys().begin(), MeasureOptionKeys().end(),
                                        [&name](const MeasureOptionEntry& e) { return name == e.key.name; });
      if (library != MeasureOptionKeys().end() && name != "weights") {
        keys.push_back({name, library->key.type, library->get(measure_defaults), library->key.help});
        continue;
      }
      Entry flag;
      gflags::CommandLineFlagInfo info;
      const bool own = gflags::GetCommandLineFlagInfo(name.c_str(), &info) &&
                       info.filename.find("run_measure.cc") != std::string::npos;
      if (own && FlagEntry(command, name, &flag)) {
        keys.push_back({name, flag.values, flag.default_value, flag.help});
        continue;
      }
      for (const AlignConfigKey& key : AlignConfigKeys()) {
        if (name == key.name) keys.push_back(AlignEntry(key));
      }
    }
  }
  if (command == "sweep") {
    out << "\nkeys of the config file:\n";
    for (const Entry& e : kSweepKeys) Print(e, out);
  }
  if (!keys.empty()) {
    out << "\nkeys (" << (command == "measure" ? "" : "in the config file as 'KEY: VALUE', or ")
        << "as flags --KEY=VALUE):\n";
    for (const Entry& e : keys) {
      Print(e, out);
      listed.insert(e.name);
    }
  }
  std::istringstream names(flags);
  std::vector<Entry> rest;
  for (std::string name; names >> name;) {
    Entry entry;
    if (!listed.count(name) && FlagEntry(command, name, &entry)) rest.push_back(entry);
  }
  if (!rest.empty()) {
    out << "\nflags:\n";
    for (const Entry& e : rest) Print(e, out);
  }
  return out.str();
}

}  // namespace surfreg
