#pragma once
// Two terrain surveys measured against each other, without an alignment
// (`surfreg measure` on DEMs and point clouds, docs/terrain.md): both read
// into one metric frame, the volume between them and the change beyond the
// level of detection, the statistics of dz at the reference's nodes, the DoD
// on the reference raster's grid and the change budget from the DEMs' σ.
#include <string>

#include "measure/dz_statistics.h"
#include "measure/measures.h"
#include "measure/surface.h"
#include "terrain/change_uncertainty.h"
#include "terrain/geo_frame.h"
#include "terrain/terrain_request.h"

namespace surfreg {

struct TerrainMeasure {
  // B against A (request.moving against request.reference), with dz_a;
  // dz_b empty, and node_area_a empty unless a σ was given (the budget's).
  MeasureSummary summary;
  DzStatistics dz;               // dz = B − A at A's nodes inside the overlap
  ChangeUncertainty uncertainty;  // with terrain.sigma_reference / sigma_moving
  GeoFrame frame;                // the frame both were measured in
  Crs crs_a, crs_b;
  std::string b_reprojected_from;  // B's CRS when B was reprojected into A's, else ""
  bool metric = false;  // lengths in metres: a geographic pair's frame, or a projected CRS in m
  double read_s = 0.0;  // reading and the change of frame, seconds
  bool from_heights = false;  // measured from the two rasters' heights alone (measure/raster_pair.h)
};

// Reads request.reference (A) and request.moving (B) as ReadTerrainInputs
// does (rasters on the origin of A's extent, so that a tiled measure gives
// the same doubles), brings a mask of `options` (kMask; its rings in the
// CRS `mask_crs_wkt`, "" = A's; `mask_where` starts its errors) into that
// frame, and measures B against A with `options`; with change detection at
// request.terrain.lod, and dz kept at A's nodes. Two rasters on one grid
// (one CRS or none, uniform weights, no σ) are measured from their heights
// alone (measure/raster_pair.h): the same numbers, without per-sample
// structures. Writes the DoD GeoTIFF when request.terrain.dod names one,
// and σ_DoD when request.terrain.dod_sigma does (A must then be a raster). Non-null `a` or
// `b`: those samples instead of reading the file. Errors are InputError
// naming the key or file.
TerrainMeasure MeasureTerrain(const TerrainRequest& request, MeasureOptions options,
                              const std::string& mask_crs_wkt = "", const std::string& mask_where = "mask",
                              const Surface* a = nullptr, const Surface* b = nullptr);

}  // namespace surfreg
