#pragma once
// Figures as PNG files, drawn with Cairo (the only Cairo user): a map of a
// gridded field with a colour bar, overlaid histograms, and x-y charts of
// lines and markers. Every figure has a title, labelled axes (the labels
// carry the units) and, where there are several series, a legend.
//
// Files are written atomically (io/atomic_file.h): a failed or
// interrupted write leaves no file. Errors (unwritable path, a figure with
// nothing to draw) throw InputError whose message starts with `label`.
#include <array>
#include <string>
#include <vector>

namespace surfreg {

// Whether this build draws figures: the CMake option SURFREG_PLOTS (Cairo).
// Without it every Write*Png below throws InputError saying so, and
// RequirePngFigures lets a command refuse a .png output before its work.
bool PngFiguresBuilt();
void RequirePngFigures(const std::string& label);  // throws "<label>: ... built without Cairo ..."

struct FigureText {
  std::string title;
  std::string x_label;  // e.g. "easting (m)"
  std::string y_label;  // e.g. "northing (m)"
};

// A field sampled on a regular grid of `columns` × `rows` cells, row 0 at the
// top (as in a raster), `values` row-major; NaN cells are drawn as "no data"
// (light grey). The cell (c, r) spans x in [x_min + c·dx, x_min + (c+1)·dx]
// and y in [y_max − (r+1)·dy, y_max − r·dy], dx = (x_max − x_min)/columns,
// dy = (y_max − y_min)/rows; the map keeps that aspect ratio.
struct GridField {
  int columns = 0, rows = 0;
  std::vector<double> values;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
};

struct MapStyle {
  // Diverging (blue below zero, white at zero, red above; the range is
  // symmetric about 0) or sequential (dark to light over [min, max]).
  bool diverging = true;
  // Colour range: |value| up to `limit` (diverging) or [value_min,
  // value_max] (sequential), in the field's units. 0 (diverging) or equal
  // ends (sequential) = automatic: the 98th percentile of |value| or the
  // 1st..99th percentiles, so a few outliers do not wash out the map (a
  // constant field gets a range around its value). Values beyond the range
  // take the end colours.
  double limit = 0;
  double value_min = 0, value_max = 0;
  std::string colorbar_label;  // e.g. "dz (m)"
  // Lines drawn over the map (dashed, dark grey), in the field's x, y: region
  // outlines, a mid-line. A polyline is closed only if its last point repeats
  // its first.
  std::vector<std::vector<std::array<double, 2>>> outlines;
};

// A map of `field` with a colour bar, one pixel per cell at most (a larger
// grid is averaged down to the plot area). The plot area keeps the data's
// aspect ratio (up to 720×540 px) except that the short side is at least
// 120 px. Throws InputError (starting with `label`) if the field has no
// finite value, its sizes disagree or its extent is empty.
void WriteMapPng(const std::string& path, const GridField& field, const FigureText& text,
                 const MapStyle& style, const std::string& label);

struct Series {
  std::string name;          // legend entry
  std::vector<double> x, y;  // for histograms only `x` (the samples) is used
  bool line = true;          // connect the points with a line
  bool markers = false;      // draw a marker at each point
};

struct ChartStyle {
  bool log_x = false, log_y = false;  // logarithmic axes (non-positive values skipped)
  // Axis ranges; equal ends = automatic (data range, padded to round ticks,
  // or to decades on a log axis). Data outside the range are clipped.
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  int width = 900, height = 600;  // figure size in pixels, 200..8000
  // Histograms: dashed grey vertical lines at these x (e.g. ± a detection
  // threshold); those outside the x range are not drawn.
  std::vector<double> x_marks;
};

// Lines and/or markers, one colour (Okabe-Ito) and marker shape per series,
// legend inside the plot area in the corner with the fewest points. A
// non-finite point (or a non-positive one on a log axis) is skipped and
// breaks the line; a series with a single point is drawn as a marker.
// Throws InputError if `series` is empty, a series' x and y sizes differ,
// or no point at all can be drawn.
void WriteChartPng(const std::string& path, const std::vector<Series>& series,
                   const FigureText& text, const ChartStyle& style, const std::string& label);

// Histograms of each series' `x` samples over common bins (`bins` equal bins
// over [x_min, x_max] of the style, automatic = 1st..99th percentile of all
// samples rounded outward), drawn as outlined steps over a light fill so that
// several series stay readable; y is the count ("count" unless y_label says). Non-finite samples
// (and non-positive ones with log_x, whose bins are then equal in log x) are skipped, as are
// samples outside the bins. All samples equal: bins centred on that value. Throws InputError if
// bins < 1, `series` is empty or no sample is finite.
void WriteHistogramPng(const std::string& path, const std::vector<Series>& series, int bins,
                       const FigureText& text, const ChartStyle& style, const std::string& label);

}  // namespace surfreg
