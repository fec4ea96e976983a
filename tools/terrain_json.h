#pragma once
// The terrain results as the CLI's JSON shows them (docs/terrain.md): the
// change beyond the level of detection, the change budget with its
// uncertainty, and the errors against a known motion.
#include "terrain/change_uncertainty.h"
#include "terrain/terrain.h"
#include "tools/json_writer.h"

namespace surfreg {

// Cut/fill beyond the level of detection of `s` (MeasureSummary's detected
// change, exact on the overlay) with their ± L × area, as the keys of a
// `change` object: level_of_detection, fill, cut, net, fill_area, cut_area,
// fill_uncertainty, cut_uncertainty, net_uncertainty.
JsonObject DetectedChangeJson(const MeasureSummary& s);

// The budget as JSON (the member `uncertainty` of a `change` object).
JsonObject ChangeUncertaintyJson(const TerrainRequest& config, const ChangeUncertainty& u);

// {"rotation_error_deg", "translation_error", "translation_error_cells"}.
JsonObject KnownErrorJson(const KnownMotionError& error, double cell_size);

}  // namespace surfreg
