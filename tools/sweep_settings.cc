#include "tools/sweep_settings.h"

#include <cstdint>
#include <cstdio>

#include "measure/input_error.h"

namespace surfreg {
namespace {

const char kPrefix[] = "# surfreg sweep setting: ";

bool Swept(const SweepConfig& config, const std::string& key) {
  for (const SweptKey& swept : config.swept) {
    if (swept.key == key) return true;
  }
  return false;
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

std::string TruthText(const SweepTruth& truth) {
  switch (truth.kind) {
    case SweepTruth::Kind::kNone:
      return "none";
    case SweepTruth::Kind::kMatrix: {
      std::string text = "matrix";
      for (int i = 0; i < 16; ++i) text += " " + Number(truth.matrix(i / 4, i % 4));
      return text;
    }
    case SweepTruth::Kind::kAboutCentroid: {
      std::string text = "rotation_deg";
      for (double v : truth.rotation_deg) text += " " + Number(v);
      text += " translation";
      for (double v : truth.translation) text += " " + Number(v);
      return text;
    }
  }
  return "";
}

// Values are one line by construction; a newline would end the record.
std::string OneLine(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

}  // namespace

std::map<std::string, std::string> SweepSettings(const SweepConfig& config) {
  std::map<std::string, std::string> settings;
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    const std::string name = key.name;
    // Keys a sweep does not take (tools/sweep_config.cc) stay at their defaults.
    if (IsTerrainKey(name) || Swept(config, name)) continue;
    settings[name] = OneLine(AlignConfigValue(config.base, name));
  }
  for (const SweepPair& pair : config.pairs) {
    settings["pair " + pair.name] =
        OneLine(pair.reference + " " + pair.moving + " truth " + TruthText(pair.truth));
  }
  settings["success.rotation_deg"] = Number(config.success_rotation_deg);
  settings["success.spacings"] = Number(config.success_spacings);
  return settings;
}

std::string SweepFingerprint(const SweepConfig& config) {
  std::string text = SweepSettingsComment(config);
  for (const SweptKey& key : config.swept) {
    text += "swept " + key.key + ":";
    for (const std::string& value : key.values) text += " " + value;
    text += "\n";
  }
  text += "grid:";
  for (double r : config.rotation_deg) text += " " + Number(r);
  text += " /";
  for (double s : config.shift_spacings) text += " " + Number(s);
  text += " / " + std::to_string(config.directions) + " / " + std::to_string(config.seed) + "\n";
  uint64_t hash = 14695981039346656037ull;  // FNV-1a: stable across runs and machines
  for (unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(hash));
  return hex;
}

std::string SweepSettingsComment(const SweepConfig& config) {
  std::string text;
  for (const auto& [name, value] : SweepSettings(config)) text += kPrefix + name + "=" + value + "\n";
  return text;
}

std::string SplitSweepSettings(const std::string& text,
                               std::map<std::string, std::string>* recorded) {
  recorded->clear();
  const std::string prefix = kPrefix;
  std::size_t begin = 0;
  while (text.compare(begin, prefix.size(), prefix) == 0) {
    const std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) break;  // torn: the CSV parser reports it
    const std::string record = text.substr(begin + prefix.size(), end - begin - prefix.size());
    const std::size_t equals = record.find('=');
    if (equals != std::string::npos) (*recorded)[record.substr(0, equals)] = record.substr(equals + 1);
    begin = end + 1;
  }
  return text.substr(begin);
}

void CheckSweepSettings(const std::map<std::string, std::string>& recorded,
                        const SweepConfig& config, const std::string& path) {
  if (recorded.empty()) return;
  const std::map<std::string, std::string> now = SweepSettings(config);
  const auto show = [](const std::map<std::string, std::string>& m, const std::string& name) {
    const auto it = m.find(name);
    return it == m.end() ? std::string("(not set)") : "'" + it->second + "'";
  };
  std::map<std::string, std::string> names = recorded;
  names.insert(now.begin(), now.end());
  for (const auto& entry : names) {
    const std::string& name = entry.first;
    if (show(recorded, name) == show(now, name)) continue;
    throw InputError("flag '--resume': '" + path + "' was written with other settings: " + name +
                     " " + show(recorded, name) + " there, " + show(now, name) +
                     " now (restore the config, or start afresh with another --output)");
  }
}

}  // namespace surfreg
