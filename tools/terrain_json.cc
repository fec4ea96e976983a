#include "tools/terrain_json.h"

namespace surfreg {

JsonObject DetectedChangeJson(const MeasureSummary& s) {
  const double lod = s.level_of_detection;
  JsonObject change;
  change.Number("level_of_detection", lod)
      .Number("fill", s.fill_detected)
      .Number("cut", s.cut_detected)
      .Number("net", s.fill_detected - s.cut_detected)
      .Number("fill_area", s.fill_area)
      .Number("cut_area", s.cut_area)
      .Number("fill_uncertainty", lod * s.fill_area)
      .Number("cut_uncertainty", lod * s.cut_area)
      .Number("net_uncertainty", lod * (s.fill_area + s.cut_area));
  return change;
}

JsonObject ChangeUncertaintyJson(const TerrainRequest& config, const ChangeUncertainty& u) {
  const ChangeBudget& b = u.budget;
  JsonObject json;
  json.String("sigma_reference", config.terrain.sigma_reference)
      .String("sigma_moving", config.terrain.sigma_moving)
      .Number("lod_confidence", config.terrain.lod_confidence)
      .Number("t", b.t)
      .Number("sigma_dod_median", b.sigma_median)
      .Number("threshold_median", b.threshold_median)
      .Int("nodes", b.nodes)
      .Int("fill_nodes", b.fill_nodes)
      .Int("cut_nodes", b.cut_nodes)
      .Number("fill", b.fill)
      .Number("cut", b.cut)
      .Number("net", b.net)
      .Number("fill_area", b.fill_area)
      .Number("cut_area", b.cut_area)
      .Number("fill_sigma_independent", b.fill_sigma_independent)
      .Number("cut_sigma_independent", b.cut_sigma_independent)
      .Number("net_sigma_independent", b.net_sigma_independent)
      .Number("fill_sigma_correlated", b.fill_sigma_correlated)
      .Number("cut_sigma_correlated", b.cut_sigma_correlated)
      .Number("net_sigma_correlated", b.net_sigma_correlated);
  if (u.registration) {
    json.Number("fill_sigma_registration", u.fill_sigma_registration)
        .Number("cut_sigma_registration", u.cut_sigma_registration)
        .Number("net_sigma_registration", u.net_sigma_registration)
        .Number("fill_sigma_total", u.fill_sigma_total)
        .Number("cut_sigma_total", u.cut_sigma_total)
        .Number("net_sigma_total", u.net_sigma_total);
  }
  return json;
}

JsonObject KnownErrorJson(const KnownMotionError& error, double cell_size) {
  JsonObject known;
  known.Number("rotation_error_deg", error.rotation_deg)
      .Number("translation_error", error.translation)
      .Number("translation_error_cells", error.translation / cell_size);
  return known;
}

}  // namespace surfreg
