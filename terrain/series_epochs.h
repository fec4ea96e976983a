#pragma once
// The epochs of a series (registration/series.h) read from their files into
// one metric frame (terrain/geo_frame.h): what `surfreg series` and the
// Python module's series() both use, so a series of lon/lat DEMs is solved in
// metres by either.
#include <string>
#include <vector>

#include "io/raster_io.h"
#include "io/surface_reader.h"
#include "measure/surface.h"
#include "terrain/geo_frame.h"

namespace surfreg {

struct SeriesEpochs {
  std::vector<Surface> surfaces;  // in `frame`'s coordinates
  std::vector<Raster> grids;      // each raster epoch's grid (values empty; 0 columns for clouds)
  std::vector<Crs> crs;           // each epoch's CRS (its file's, else the one given)
  GeoFrame frame;                 // where the series is solved
  std::string units = "units";    // of lengths in `frame`: "m", "ft" or "units" (not known)
};

// Reads paths[k] (`read`: classes, columns, threads) with its CRS: its
// file's own (rasters, LAS), else `crs` (ParseCrs's text; "" = none: the
// coordinates as they are), and brings every epoch into one metric frame
// (ToSeriesMetricFrame; `frame` for lon/lat epochs: "auto", "utm" or "enu").
// `crs_where` names where `crs` was given in its errors. InputError naming
// the file for unreadable input, and the epochs for different CRSs (a file's
// own included).
SeriesEpochs ReadSeriesEpochs(const std::vector<std::string>& paths, const ReadOptions& read,
                              const std::string& crs, const std::string& crs_where, const std::string& frame);

}  // namespace surfreg
