#pragma once
// `surfreg series` as a function: reading or taking the epochs, the joint
// alignment (registration/series.h), the change between consecutive epochs
// once aligned, the aligned files and the series JSON. The CLI
// (tools/run_series.cc) and the Python module both call it, so their
// results cannot drift apart.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "measure/dz_statistics.h"
#include "measure/measures.h"
#include "registration/series.h"
#include "terrain/geo_frame.h"
#include "tools/series_config.h"

namespace surfreg {

// Epoch `to` brought onto epoch `from` by the joint relative motion: the
// measures of `to` against `from` (mean |dz|, net volume) and the dz
// statistics at `from`'s samples in the overlap, in `from`'s frame.
struct ConsecutiveChange {
  int from = 0, to = 0;
  MeasureSummary measure;  // without the node gaps
  DzStatistics dz;
  std::string dod;  // the DoD GeoTIFF written (dod_dir), or ""
};

struct SeriesRun {
  SeriesConfig config;
  std::vector<Surface> epochs;  // as read, in `frame`
  GeoFrame frame;               // where the series is solved: input coordinates, or UTM / ENU for lon/lat
  SeriesResult result;
  std::vector<ConsecutiveChange> consecutive;
  std::string json;             // the series JSON, newline-terminated
  std::string units = "units";  // of lengths: "m" or "ft" from the epochs' CRS
};

// Aligns config.surfaces jointly (config through FinishSeriesConfig, or
// `epochs` given instead of reading them: config.surfaces then only names
// them, and dod_dir is refused). Writes the files config names atomically. `on_stage` (may be
// empty) sees each stage's text. Bad input throws InputError.
SeriesRun AlignSeriesFiles(SeriesConfig config, std::optional<std::vector<Surface>> epochs,
                           const std::function<void(const std::string&)>& on_stage);

// The summary for people: one line per epoch and per pair.
std::string SeriesSummary(const SeriesRun& run);

}  // namespace surfreg
