// The terrain keys of `surfreg align` (docs/terrain.md): how rasters are
// read, which geographic frame both surfaces are brought into, and the change
// outputs, defined in terrain/terrain_keys.h and lifted into align's table.
#include "terrain/terrain_keys.h"
#include "tools/config_value.h"

namespace surfreg {

bool IsTerrainKey(const std::string& key) {
  for (const config_value::KeyEntry& entry : config_value::TerrainKeyTable()) {
    if (key == entry.key.name) return true;
  }
  return false;
}

namespace config_value {

const std::vector<KeyEntry>& TerrainKeyTable() {
  // The terrain library's keys (terrain/terrain_keys.h) as keys of the config.
  static const std::vector<KeyEntry> table = [] {
    std::vector<KeyEntry> keys;
    for (const TerrainSettingEntry& entry : TerrainSettingKeys()) {
      keys.push_back({entry.key, [&entry](const Value& v, C* c) { entry.set(v, &c->terrain); },
                      [&entry](const C& c) { return entry.get(c.terrain); }});
    }
    return keys;
  }();
  return table;
}

}  // namespace config_value
}  // namespace surfreg
