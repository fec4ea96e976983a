#pragma once
// `surfreg measure` as a function: its settings, the run and its --json
// document. The CLI (tools/run_measure.cc) and the Python module
// (tools/python) both call it, so their results cannot drift apart.
#include <optional>
#include <functional>
#include <string>
#include <vector>

#include "measure/dz_statistics.h"
#include "measure/measures.h"
#include "measure/surface.h"
#include "tools/align_config.h"
#include "terrain/geo_frame.h"
#include "terrain/change_uncertainty.h"

namespace surfreg {

// One surface of a run: a file to read, or samples already in memory (the
// Python module's arrays; `name` then only names them in messages and the
// output, e.g. "array A").
struct SurfaceInput {
  std::string name;
  std::optional<Surface> samples;  // empty: read the file `name`
};

// One setting as the user gave it: the key, the value as text (a flag's
// text: "true", "1.5", "[1, 2, 3]"; "" for a file key = no file), and where
// it was given, the start of its messages ("flag '--volume'").
struct Setting {
  std::string key;
  std::string value;
  std::string where;
};

// The keys `measure` takes: volume, weights, the domain keys and the align
// keys that say how A and B are read and which frame they are measured in.
const std::vector<std::string>& MeasureKeys();

struct MeasureReport {
  std::string file_a, file_b;
  std::string mask_file;     // for WeightMode::kMask
  std::string mask_layer;    // a vector mask's layer ("" = the first)
  std::string mask_crs_wkt;  // the mask file's CRS ("" = A's)
  MeasureOptions options;
  MeasureSummary summary;
  DzStatistics dz;      // dz = B − A at A's nodes in the overlap (untiled runs)
  bool has_dz = false;
  AlignConfig config;              // the files and the terrain settings
  ChangeUncertainty uncertainty;   // with sigma_reference / sigma_moving
  GeoFrame frame;
  Crs crs_a, crs_b;
  std::string b_reprojected_from;  // B's CRS when B was reprojected into A's, else ""
  bool metric = false;  // lengths in metres: a geographic pair's frame, or a projected CRS in m
  int32_t tile = 0;     // with `tile` or `max_memory`: the tile side (cells of A), else 0
  int64_t tiles = 0;    // and how many tiles A was cut into
  double read_s = 0.0;
  double total_s = 0.0;  // the whole run: settings, read, Measure
};

// Checks the settings (an unknown key or a bad value is an InputError
// starting with its `where`), reads A and B as `align` reads them (or takes
// their samples), brings them into one frame and measures B against A.
// A key given twice: the last one wins. `on_progress` is called at each
// stage of the measure (MeasureOptions::on_progress).
// `parts` (tiled measures only): a shard (its partial written to
// parts->partial) or a resume (tools/measure_tiled.h).
struct TiledParts;
MeasureReport MeasureSurfaces(SurfaceInput a, SurfaceInput b, const std::vector<Setting>& settings,
                              const std::function<void(const MeasureProgress&)>& on_progress = nullptr,
                              const TiledParts* parts = nullptr);

// Vertices of all the mask's rings.
std::size_t MaskVertices(const MeasureOptions& options);

// The --json document of `surfreg measure` (one object, no newline).
std::string MeasureJson(const MeasureReport& report);

}  // namespace surfreg
