#pragma once
// The terrain part of `surfreg align` (terrain/terrain.h) as the CLI shows it:
// the "terrain" member of the transform JSON.
#include <string>

#include "terrain/terrain.h"
#include "tools/align_config.h"

namespace surfreg {

// "\"terrain\": {...}": frame, the shift on the ground, dz statistics on
// stable terrain before and after, cut/fill beyond the level of detection
// with their uncertainty, and the errors against a known motion.
std::string TerrainJsonMember(const AlignConfig& config, const TerrainInputs& inputs,
                              const TerrainReport& report);

}  // namespace surfreg
