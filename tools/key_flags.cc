#include "tools/key_flags.h"

#include <gflags/gflags.h>
#include <glog/logging.h>

#include <cstring>
#include <deque>
#include <map>

#include "measure/measure_keys.h"
#include "measure/option_keys.h"
#include "tools/align_config.h"

namespace surfreg {
namespace {

// gflags keeps pointers to a flag's name, help and values for the life of
// the program: they live here, in containers that never move an element.
struct FlagStorage {
  std::deque<std::string> help;
  std::deque<std::string> strings;  // current, default, current, ...
  std::deque<bool> bools;
  std::map<std::string, const std::string*> by_name;
};

FlagStorage& Storage() {
  static FlagStorage* storage = new FlagStorage;  // never destroyed: gflags outlives main
  return *storage;
}

// CheckCommandFlags (tools/surfreg_main.cc) tells the program's own flags
// by their file under tools/.
constexpr char kFlagFile[] = "tools/key_flags.cc";

}  // namespace

void RegisterKeyFlags() {
  static bool registered = false;
  if (registered) return;
  registered = true;
  FlagStorage& s = Storage();
  const AlignConfig defaults;
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    gflags::CommandLineFlagInfo existing;
    if (gflags::GetCommandLineFlagInfo(key.name, &existing)) continue;
    s.help.push_back(std::string("align: ") + key.help);
    const char* help = s.help.back().c_str();
    if (std::strcmp(key.type, "true or false") == 0) {
      s.bools.push_back(AlignConfigValue(defaults, key.name) == "true");
      bool* current = &s.bools.back();
      s.bools.push_back(*current);
      gflags::FlagRegisterer(key.name, help, kFlagFile, current, &s.bools.back());
    } else {
      s.strings.emplace_back();
      std::string* current = &s.strings.back();
      s.strings.emplace_back();
      gflags::FlagRegisterer(key.name, help, kFlagFile, current, &s.strings.back());
      s.by_name[key.name] = current;
    }
  }
  // measure's keys that align does not have (volume, min_overlap_fraction):
  // string flags, "" = not given; their values are checked by the table.
  for (const MeasureOptionEntry& entry : MeasureOptionKeys()) {
    gflags::CommandLineFlagInfo existing;
    if (gflags::GetCommandLineFlagInfo(entry.key.name, &existing)) continue;
    s.help.push_back(std::string("measure: ") + entry.key.help);
    s.strings.emplace_back();
    std::string* current = &s.strings.back();
    s.strings.emplace_back();
    gflags::FlagRegisterer(entry.key.name, s.help.back().c_str(), kFlagFile, current, &s.strings.back());
    s.by_name[entry.key.name] = current;
  }
}

const std::string& KeyFlag(const char* name) {
  const auto it = Storage().by_name.find(name);
  CHECK(it != Storage().by_name.end()) << "no string flag made for key " << name;
  return *it->second;
}

int ThreadsFlag() {
  const std::string& text = KeyFlag("threads");
  if (text.empty()) return 0;
  config_value::Value value;
  value.where = "flag '--threads'";
  value.expected = config_value::kThreadsType;
  value.text = text;
  return config_value::ThreadCount(value);
}

}  // namespace surfreg
