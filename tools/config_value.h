#pragma once
// The CLI's side of the key values (measure/option_keys.h has the parsers
// every table shares): align's key entries and the terrain keys' table.
// Internal to tools/.
#include <string>
#include <vector>

#include "measure/option_keys.h"
#include "tools/align_config.h"

namespace surfreg {
namespace config_value {

using KeyEntry = Entry<AlignConfig>;  // align's keys (and the terrain keys)

using C = AlignConfig;

// The terrain keys (align_config_terrain.cc), appended to align's own.
const std::vector<KeyEntry>& TerrainKeyTable();

}  // namespace config_value
}  // namespace surfreg
