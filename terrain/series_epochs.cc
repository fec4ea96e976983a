#include "terrain/series_epochs.h"

#include <cmath>

#include "measure/input_error.h"

namespace surfreg {

SeriesEpochs ReadSeriesEpochs(const std::vector<std::string>& paths, const ReadOptions& read,
                              const std::string& crs, const std::string& crs_where, const std::string& frame) {
  SeriesEpochs epochs;
  epochs.grids.assign(paths.size(), Raster());
  const Crs given = ParseCrs(crs, crs_where);  // for the files without one of their own
  std::vector<std::string> labels;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const std::string& path = paths[k];
    std::string crs_text;
    epochs.surfaces.push_back(ReadSurface(path, read, &crs_text, &epochs.grids[k]));
    const Crs from_file = ParseCrs(crs_text, path);
    epochs.crs.push_back(from_file.kind != CrsKind::kNone ? from_file : given);
    labels.push_back("epoch " + std::to_string(k) + " (" + path + ")");
  }
  std::vector<Surface*> surfaces;
  for (Surface& s : epochs.surfaces) surfaces.push_back(&s);
  epochs.frame = ToSeriesMetricFrame(surfaces, epochs.crs, labels, FrameChoiceOf(frame));
  if (epochs.frame.kind != GeoFrame::kAsGiven) {
    epochs.units = "m";
  } else {
    for (const Crs& c : epochs.crs) {
      if (c.kind != CrsKind::kProjected) continue;
      epochs.units = c.metres_per_unit == 1 ? "m" : std::fabs(c.metres_per_unit - 0.3048) < 1e-6 ? "ft" : "units";
      break;
    }
  }
  return epochs;
}

}  // namespace surfreg
