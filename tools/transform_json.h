#pragma once
// The transform JSON of `surfreg align` (docs/align.md): matrix (4x4 row-major,
// moving -> reference, input coordinates), rotation_vector, quaternion,
// euler_deg, translation, centre, stddev, before/after measures, iterations,
// termination, seconds, verdict, observability, the cost and free parameters,
// and the two input files. One object and a newline. Used by `align` (one
// pair) and by the batch and sweep commands (one file per pair).
#include <string>

#include "registration/align.h"
#include "tools/align_config.h"

namespace surfreg {

// `extra_members`: more members already in JSON form ("\"terrain\": {...}"),
// appended after the standard keys ("" = none).
std::string TransformJson(const AlignConfig& config, const AlignResult& result,
                          const std::string& extra_members = "");

}  // namespace surfreg
