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
  json.String("error_model", u.error_model).String("change_mask", config.terrain.change_mask);
  if (u.spatial) {
    const Variogram& v = u.model.variogram;
    const EmpiricalVariogram& e = u.model.empirical;
    JsonObject variogram;
    variogram.Number("nugget", v.nugget)
        .Raw("sills", JsonNumbers({v.sill[0], v.sill[1]}))
        .Raw("ranges", JsonNumbers({v.range[0], v.range[1]}))
        .Int("stable_cells", u.model.stable_cells)
        .Number("stable_median", u.model.stable_median)
        .Number("stable_nmad", u.model.stable_nmad)
        .Raw("lags", JsonNumbers(e.lag))
        .Raw("gamma", JsonNumbers(e.gamma));
    JsonObject sigma;
    sigma.Raw("estimated", u.model.sigma_estimated ? "true" : "false");
    if (u.model.sigma_estimated) {
      const SigmaModel& m = u.model.sigma_model;
      sigma.Raw("slope", JsonNumbers(m.slope))
          .Raw("sigma", JsonNumbers(m.sigma))
          .Raw("curvature", JsonNumbers(m.curvature))
          .Raw("factor", JsonNumbers(m.factor));
    }
    json.Number("fill_sigma_spatial", u.fill_sigma_spatial)
        .Number("cut_sigma_spatial", u.cut_sigma_spatial)
        .Number("net_sigma_spatial", u.net_sigma_spatial)
        .Int("spatial_block", u.spatial_block)
        .Object("variogram", variogram)
        .Object("sigma_model", sigma);
  }
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
