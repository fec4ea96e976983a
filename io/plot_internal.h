#pragma once
// Internals of io/plot.cc and io/plot_axes.cc, declared here so that
// tests/plot_test.cc can check them directly. Not a public API: only the
// plot files and their test include it (it pulls in cairo.h).
#include <cairo.h>

#include <memory>
#include <string>
#include <vector>

#include "io/plot.h"

namespace surfreg {

// ---- Colours ----
struct Rgb {
  double r = 0, g = 0, b = 0;  // each in [0, 1]
};
// t in [-1, 1] (clamped): dark blue (−1) .. near-white #f7f7f7 (0) .. dark
// red (+1), ColorBrewer RdBu interpolated linearly between its 11 classes.
Rgb DivergingColor(double t);
// t in [0, 1] (clamped): viridis-like, dark purple (0) .. yellow (1).
Rgb SequentialColor(double t);
// Okabe-Ito colour-blind-safe palette, cycling; yellow (poor on white) last.
Rgb SeriesColor(int index);
// Cells without a value: a neutral grey that neither colour map contains.
inline constexpr Rgb kNoDataColor{190 / 255.0, 190 / 255.0, 190 / 255.0};

// ---- Numbers ----
// The smallest step 1, 2 or 5 × 10^k with span / step <= max_intervals.
double NiceStep(double span, int max_intervals);
// The multiples of the finest 1-2-5 step that has at most max_ticks (>= 2)
// of them inside [lo, hi] (ends included up to rounding), as exact decimals:
// the first less than one step above lo, the last less than one step below
// hi. lo == hi gives {lo}.
std::vector<double> NiceTicks(double lo, double hi, int max_ticks);
// Ticks for a log axis over [lo, hi], 0 < lo < hi, in data units: powers of
// ten (every 2nd, 5th, 10th... decade when there are more than max_ticks);
// with fewer than three decades inside, 1-2-5 × 10^k values (if they fit),
// and for a range narrower than that, NiceTicks.
std::vector<double> LogTicks(double lo, double hi, int max_ticks);
// Widens [lo, hi] outward to round values: multiples of NiceStep(span, 6),
// or whole decades when `log` (then 0 < lo required). An empty range (lo ==
// hi) is first widened around its value.
void PadRange(bool log, double* lo, double* hi);
// `value` with as many decimals as a 1-2-5 `step` needs (step 0.05: "0.15",
// step 10: "30"); scientific ("2e-7", "1.5e9") for steps below 1e-4 or
// values of 1e9 and more.
std::string FormatTick(double value, double step);
// The value at `fraction` (0..1, nearest rank) of `values`, which it reorders.
double Percentile(std::vector<double>* values, double fraction);
// Counts of `samples` in `bins` equal bins over [lo, hi] (equal in log10 x
// when `log`); x == hi goes in the last bin; non-finite samples, samples
// outside [lo, hi] and, when `log`, non-positive ones are skipped.
std::vector<double> HistogramCounts(const std::vector<double>& samples, double lo, double hi,
                                    int bins, bool log);
// The colour range of a map (see MapStyle): [−L, L] when diverging. Throws
// InputError (starting with `label`) if the field has no finite value.
void MapColorRange(const GridField& field, const MapStyle& style, const std::string& label,
                   double* lo, double* hi);

// ---- Cairo plumbing ----
struct CairoDeleter {
  void operator()(cairo_surface_t* surface) const { cairo_surface_destroy(surface); }
  void operator()(cairo_t* cr) const { cairo_destroy(cr); }
};
using SurfacePtr = std::unique_ptr<cairo_surface_t, CairoDeleter>;
using ContextPtr = std::unique_ptr<cairo_t, CairoDeleter>;
struct Canvas {
  SurfacePtr surface;
  ContextPtr cr;
};
// Throws InputError "<label>: drawing failed: <cairo's reason>" unless ok.
void CheckCairo(cairo_status_t status, const std::string& label);
// A white RGB canvas of width × height pixels.
Canvas MakeCanvas(int width, int height, const std::string& label);
// Encodes the canvas as PNG and writes it atomically to `path`.
void SavePng(const Canvas& canvas, const std::string& path, const std::string& label);

// ---- Text, axes and layout ----
enum class Font { kTitle, kLabel, kTick, kLegend };
void SetFont(cairo_t* cr, Font font);
double TextWidth(cairo_t* cr, const std::string& text);
double FontHeight(cairo_t* cr);  // ascent + descent of the current font
// Draws `text` so that the point (x, y) sits at fraction (ax, ay) of its box
// (0,0 = top left, 0.5,0.5 = centre); `vertical` reads bottom to top, with
// (ax, ay) taken along and across the rotated text.
void DrawText(cairo_t* cr, const std::string& text, double x, double y, double ax, double ay,
              bool vertical = false);

struct Rect {
  double left = 0, top = 0, width = 0, height = 0;
  double right() const { return left + width; }
  double bottom() const { return top + height; }
};

// One axis: the range [lo, hi] in data units (0 < lo on a log axis), its
// ticks in data units and their labels.
struct Axis {
  double lo = 0, hi = 1;
  bool log = false;
  std::vector<double> ticks;
  std::vector<std::string> labels;
  // Fraction 0..1 of the way from lo to hi (linear or in log10).
  double Fraction(double value) const;
};
// Picks ticks for an axis `length` pixels long: as many as fit without the
// labels crowding (horizontal labels side by side, vertical axes ~40 px
// apart), and their labels.
void ChooseTicks(cairo_t* cr, double length, bool horizontal, Axis* axis);
double XPixel(const Rect& plot, const Axis& x, double value);
double YPixel(const Rect& plot, const Axis& y, double value);

// Margins of a figure with `text`, left of and below a plot area whose y
// ticks are known.
double TopMargin(cairo_t* cr, const FigureText& text);
double BottomMargin(cairo_t* cr, const FigureText& text);
double LeftMargin(cairo_t* cr, const FigureText& text, const Axis& y);
// Lays out a chart on a width × height canvas: the plot area and the ticks.
Rect LayoutChart(cairo_t* cr, int width, int height, const FigureText& text, Axis* x, Axis* y);
// Optional light grid at the ticks (under the data).
void DrawGrid(cairo_t* cr, const Rect& plot, const Axis& x, const Axis& y);
// The plot frame, outward tick marks, tick labels, title and axis labels.
void DrawAxes(cairo_t* cr, const Rect& plot, int canvas_width, const Axis& x, const Axis& y,
              const FigureText& text);

}  // namespace surfreg
