#pragma once
// The keys of TerrainSettings (docs/terrain.md, the terrain keys): each key's
// documentation row, the field it sets and how it reads back, defined once
// for the CLI's configs and flags (tools/align_config_terrain.cc lifts them
// into align's table) and the Python module's keywords; values parsed and
// checked by measure/option_keys.h.
#include <string>
#include <vector>

#include "measure/option_keys.h"
#include "terrain/terrain_request.h"

namespace surfreg {

using TerrainSettingEntry = config_value::Entry<TerrainSettings>;

// Every terrain key, in the order of the documentation.
const std::vector<TerrainSettingEntry>& TerrainSettingKeys();

// The entry of `name`, or nullptr.
const TerrainSettingEntry* FindTerrainSetting(const std::string& name);

// Throws InputError (starting with `where`) if the terrain output `key` has
// the wrong extension (dod, dod_sigma, dod_thresholded: .tif/.tiff; dod_png,
// histogram_png: .png, and a build with PNG figures); other keys pass.
void CheckTerrainOutput(const std::string& key, const std::string& path, const std::string& where);

}  // namespace surfreg
