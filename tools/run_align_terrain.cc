#include "tools/run_align_terrain.h"

#include "tools/json_writer.h"
#include "tools/terrain_json.h"

namespace surfreg {

std::string TerrainJsonMember(const AlignConfig& config, const TerrainInputs& in,
                              const TerrainReport& r) {
  const GeographicOffset& o = r.offset;
  JsonObject offset;
  offset.Number("east_m", o.east_m)
      .Number("north_m", o.north_m)
      .Number("up_m", o.up_m)
      .Number("dlat_deg", o.dlat_deg)
      .Number("dlon_deg", o.dlon_deg)
      .Number("dh_m", o.dh_m);
  const MeasureSummary& a = r.after;
  JsonObject change = DetectedChangeJson(a);
  change.String("level_of_detection_source", r.lod_source)
      .Number("overlap_area", a.overlap_area)
      .String("domain", DomainKindName(a.domain_kind))
      .Number("excluded_area_reference", a.excluded_area_a)
      .Number("excluded_area_moving", a.excluded_area_b);
  // Cellwise over the reference's nodes (terrain/change_budget.h).
  if (r.uncertainty.active) change.Object("uncertainty", ChangeUncertaintyJson(config, r.uncertainty));
  JsonObject terrain;
  terrain.String("frame", in.frame.Describe())
      .String("reference_crs", in.reference_crs.name)
      .String("moving_crs", in.moving_crs.name)
      .Number("cell_size", r.spacing)
      .Object("offset", offset)
      .Object("stable_before", DzStatisticsJson(r.stable_before))
      .Object("stable_after", DzStatisticsJson(r.stable_after))
      .Object("change", change);
  if (r.known) terrain.Object("known", KnownErrorJson({r.rotation_error_deg, r.translation_error}, r.spacing));
  return "\"terrain\": " + terrain.str();
}

}  // namespace surfreg
