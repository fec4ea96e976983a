#include "io/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "io/plot_internal.h"

namespace surfreg {

bool PngFiguresBuilt() { return true; }
void RequirePngFigures(const std::string&) {}
namespace {

constexpr double kPad = 12;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

[[noreturn]] void Fail(const std::string& label, const std::string& what) {
  throw InputError(label + ": " + what);
}

void CheckStyle(const ChartStyle& style, const std::string& label) {
  if (style.width < 200 || style.width > 8000 || style.height < 200 || style.height > 8000) {
    Fail(label, "figure size " + std::to_string(style.width) + "x" + std::to_string(style.height) +
                    " px is outside 200..8000");
  }
  if (!(style.x_min <= style.x_max) || !(style.y_min <= style.y_max)) {
    Fail(label, "axis range with min > max (or NaN)");
  }
  if ((style.log_x && style.x_min < style.x_max && !(style.x_min > 0)) ||
      (style.log_y && style.y_min < style.y_max && !(style.y_min > 0))) {
    Fail(label, "a logarithmic axis needs a positive range");
  }
}

// The axis over the style's range when given, else over the data padded.
Axis MakeAxis(bool log, double style_lo, double style_hi, double data_lo, double data_hi) {
  Axis axis;
  axis.log = log;
  if (style_lo < style_hi) {
    axis.lo = style_lo;
    axis.hi = style_hi;
  } else {
    axis.lo = data_lo;
    axis.hi = data_hi;
    PadRange(log, &axis.lo, &axis.hi);
  }
  return axis;
}

bool Drawable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

// Keeps far-off points (explicit axis ranges) within Cairo's fixed-point range.
double ClampPixel(double p) { return std::clamp(p, -1e6, 1e6); }

std::uint32_t Pack(const Rgb& c) {
  const auto byte = [](double v) {
    return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255));
  };
  return byte(c.r) << 16 | byte(c.g) << 8 | byte(c.b);
}

Rgb MapColor(double value, bool diverging, double lo, double hi) {
  if (!std::isfinite(value)) return kNoDataColor;
  return diverging ? DivergingColor(value / hi) : SequentialColor((value - lo) / (hi - lo));
}

// The field as a w × h image: each pixel the mean of the finite cells it
// covers (w <= columns, h <= rows), so every cell is read once.
SurfacePtr RenderField(const GridField& field, int w, int h, const MapStyle& style, double lo,
                       double hi, const std::string& label) {
  SurfacePtr image(cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h));
  CheckCairo(cairo_surface_status(image.get()), label);
  cairo_surface_flush(image.get());
  unsigned char* data = cairo_image_surface_get_data(image.get());
  const int stride = cairo_image_surface_get_stride(image.get());
  std::vector<std::int64_t> column_start(static_cast<std::size_t>(w) + 1);
  for (int i = 0; i <= w; ++i) column_start[i] = static_cast<std::int64_t>(i) * field.columns / w;
  std::vector<double> sum(static_cast<std::size_t>(w)), count(static_cast<std::size_t>(w));
  for (int j = 0; j < h; ++j) {
    std::fill(sum.begin(), sum.end(), 0.0);
    std::fill(count.begin(), count.end(), 0.0);
    const std::int64_t r0 = static_cast<std::int64_t>(j) * field.rows / h;
    const std::int64_t r1 = static_cast<std::int64_t>(j + 1) * field.rows / h;
    for (std::int64_t r = r0; r < r1; ++r) {
      const double* row = field.values.data() + r * field.columns;
      for (int i = 0; i < w; ++i) {
        for (std::int64_t c = column_start[i]; c < column_start[i + 1]; ++c) {
          if (std::isfinite(row[c])) {
            sum[i] += row[c];
            count[i] += 1;
          }
        }
      }
    }
    auto* pixels = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(j) * stride);
    for (int i = 0; i < w; ++i) {
      pixels[i] = Pack(MapColor(count[i] > 0 ? sum[i] / count[i] : kNaN, style.diverging, lo, hi));
    }
  }
  cairo_surface_mark_dirty(image.get());
  return image;
}

// A vertical colour bar (low at the bottom) with ticks and its label.
void DrawColorBar(cairo_t* cr, const Rect& bar, const Axis& axis, const MapStyle& style) {
  const int rows = static_cast<int>(bar.height);
  for (int k = 0; k < rows; ++k) {
    const double value = axis.hi - (k + 0.5) / rows * (axis.hi - axis.lo);
    const Rgb c = MapColor(value, style.diverging, axis.lo, axis.hi);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_rectangle(cr, bar.left, bar.top + k, bar.width, 1);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, bar.left - 0.5, bar.top - 0.5, bar.width + 1, bar.height + 1);
  for (double t : axis.ticks) {
    const double py = std::floor(YPixel(bar, axis, t)) + 0.5;
    cairo_move_to(cr, bar.right() + 0.5, py);
    cairo_line_to(cr, bar.right() + 5.5, py);
  }
  cairo_stroke(cr);
  SetFont(cr, Font::kTick);
  double widest = 0;
  for (std::size_t i = 0; i < axis.ticks.size(); ++i) {
    DrawText(cr, axis.labels[i], bar.right() + 9, YPixel(bar, axis, axis.ticks[i]), 0, 0.5);
    widest = std::max(widest, TextWidth(cr, axis.labels[i]));
  }
  SetFont(cr, Font::kLabel);
  DrawText(cr, style.colorbar_label, bar.right() + 19 + widest, bar.top + bar.height / 2, 0.5, 0,
           true);
}

void CheckField(const GridField& field, const std::string& label) {
  if (field.columns < 1 || field.rows < 1 ||
      field.values.size() != static_cast<std::size_t>(field.columns) * field.rows) {
    Fail(label, "map of " + std::to_string(field.columns) + "x" + std::to_string(field.rows) +
                    " cells has " + std::to_string(field.values.size()) + " values");
  }
  if (!(field.x_min < field.x_max) || !(field.y_min < field.y_max) ||
      !std::isfinite(field.x_max - field.x_min) || !std::isfinite(field.y_max - field.y_min)) {
    Fail(label, "map extent is empty or not finite");
  }
}

// ---- Charts ----
void MarkerPath(cairo_t* cr, double x, double y, int shape) {
  const double r = 4;
  switch (shape % 5) {
    case 0:
      cairo_new_sub_path(cr);
      cairo_arc(cr, x, y, r, 0, 2 * M_PI);
      break;
    case 1:
      cairo_rectangle(cr, x - 0.85 * r, y - 0.85 * r, 1.7 * r, 1.7 * r);
      break;
    case 2:
    case 4: {
      const double s = shape % 5 == 2 ? 1 : -1;  // triangle up or down
      cairo_move_to(cr, x, y - s * 1.15 * r);
      cairo_line_to(cr, x + r, y + s * 0.75 * r);
      cairo_line_to(cr, x - r, y + s * 0.75 * r);
      cairo_close_path(cr);
      break;
    }
    default:
      cairo_move_to(cr, x, y - 1.2 * r);
      cairo_line_to(cr, x + 1.2 * r, y);
      cairo_line_to(cr, x, y + 1.2 * r);
      cairo_line_to(cr, x - 1.2 * r, y);
      cairo_close_path(cr);
  }
}

void ClipTo(cairo_t* cr, const Rect& rect) {
  cairo_rectangle(cr, rect.left, rect.top, rect.width, rect.height);
  cairo_clip(cr);
}

void SetColor(cairo_t* cr, int index, double alpha = 1) {
  const Rgb c = SeriesColor(index);
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

// Draws one series; appends the pixels it covers (points, and samples
// along its lines) to `covered` for the legend's placement.
void DrawSeries(cairo_t* cr, const Rect& plot, const Axis& x, const Axis& y, const Series& s,
                int index, std::vector<std::pair<double, double>>* covered) {
  std::vector<std::pair<double, double>> points;  // NaN marks a gap
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (Drawable(s.x[i], x.log) && Drawable(s.y[i], y.log)) {
      points.emplace_back(ClampPixel(XPixel(plot, x, s.x[i])), ClampPixel(YPixel(plot, y, s.y[i])));
    } else if (!points.empty() && !std::isnan(points.back().first)) {
      points.emplace_back(kNaN, kNaN);
    }
  }
  cairo_save(cr);  // lines stop at the frame; markers on it stay whole
  ClipTo(cr, plot);
  SetColor(cr, index);
  cairo_set_line_width(cr, 2);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  std::size_t drawn = 0;
  bool pen_down = false;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [px, py] = points[i];
    if (std::isnan(px)) {
      pen_down = false;
      continue;
    }
    ++drawn;
    covered->emplace_back(px, py);
    if (pen_down && s.line) {
      const auto [qx, qy] = points[i - 1];
      const int steps = static_cast<int>(std::min(200.0, std::hypot(px - qx, py - qy) / 8));
      for (int k = 1; k < steps; ++k) {
        covered->emplace_back(qx + (px - qx) * k / steps, qy + (py - qy) * k / steps);
      }
      cairo_line_to(cr, px, py);
    } else {
      cairo_move_to(cr, px, py);
    }
    pen_down = true;
  }
  if (s.line) cairo_stroke(cr);
  cairo_new_path(cr);
  cairo_restore(cr);
  SetColor(cr, index);
  if (!s.markers && !(drawn == 1 || !s.line)) return;
  for (const auto& [px, py] : points) {
    if (!std::isnan(px)) MarkerPath(cr, px, py, index);
  }
  cairo_fill(cr);
}

// The legend in the corner of the plot area that covers the fewest of the
// `covered` pixels; `boxes` draws filled swatches (histograms).
void DrawLegend(cairo_t* cr, const Rect& plot, const std::vector<Series>& series, bool boxes,
                const std::vector<std::pair<double, double>>& covered) {
  SetFont(cr, Font::kLegend);
  double widest = 0;
  int rows = 0;
  for (const Series& s : series) {
    if (s.name.empty()) continue;
    widest = std::max(widest, TextWidth(cr, s.name));
    ++rows;
  }
  if (rows == 0) return;
  const double row_height = FontHeight(cr) + 4, swatch = 28, inset = 8;
  const double width = 8 + swatch + 6 + widest + 8, height = rows * row_height + 8;
  Rect box{0, 0, width, height};
  std::size_t fewest = std::numeric_limits<std::size_t>::max();
  for (int corner = 0; corner < 4; ++corner) {  // top right, top left, bottom right, bottom left
    const double left = corner % 2 == 0 ? plot.right() - inset - width : plot.left + inset;
    const double top = corner < 2 ? plot.top + inset : plot.bottom() - inset - height;
    const std::size_t inside = std::count_if(covered.begin(), covered.end(), [&](const auto& p) {
      return p.first >= left - 4 && p.first <= left + width + 4 && p.second >= top - 4 &&
             p.second <= top + height + 4;
    });
    if (inside < fewest) {
      fewest = inside;
      box = {std::round(left), std::round(top), width, height};
    }
  }
  cairo_set_source_rgba(cr, 1, 1, 1, 0.88);
  cairo_rectangle(cr, box.left, box.top, box.width, box.height);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_line_width(cr, 1);
  cairo_stroke(cr);
  double y = box.top + 4 + row_height / 2;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    if (s.name.empty()) continue;
    const int index = static_cast<int>(i);
    const double x0 = box.left + 8;
    if (boxes) {
      cairo_rectangle(cr, x0 + 0.5, y - 5.5, swatch - 1, 11);
      SetColor(cr, index, 0.25);
      cairo_fill_preserve(cr);
      SetColor(cr, index);
      cairo_set_line_width(cr, 2);
      cairo_stroke(cr);
    } else {
      SetColor(cr, index);
      if (s.line || !s.markers) {
        cairo_set_line_width(cr, 2);
        cairo_move_to(cr, x0, y);
        cairo_line_to(cr, x0 + swatch, y);
        cairo_stroke(cr);
      }
      if (s.markers || !s.line || s.x.size() == 1) {
        MarkerPath(cr, x0 + swatch / 2, y, index);
        cairo_fill(cr);
      }
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    DrawText(cr, s.name, x0 + swatch + 6, y, 0, 0.5);
    y += row_height;
  }
}

// Lays out, draws axes and legend around `draw_data` and saves the figure.
template <typename DrawData>
void DrawChart(const std::string& path, const std::vector<Series>& series, bool boxes, Axis x,
               Axis y, const FigureText& text, const ChartStyle& style, const std::string& label,
               DrawData draw_data) {
  Canvas canvas = MakeCanvas(style.width, style.height, label);
  cairo_t* cr = canvas.cr.get();
  const Rect plot = LayoutChart(cr, style.width, style.height, text, &x, &y);
  DrawGrid(cr, plot, x, y);
  std::vector<std::pair<double, double>> covered;
  cairo_save(cr);
  ClipTo(cr, {plot.left - 6, plot.top - 6, plot.width + 12, plot.height + 12});
  draw_data(cr, plot, x, y, &covered);
  cairo_restore(cr);
  DrawAxes(cr, plot, style.width, x, y, text);
  DrawLegend(cr, plot, series, boxes, covered);
  SavePng(canvas, path, label);
}

}  // namespace

void WriteMapPng(const std::string& path, const GridField& field, const FigureText& text,
                 const MapStyle& style, const std::string& label) {
  CheckOutputPath(path, label);
  CheckField(field, label);
  if (!(style.limit >= 0) || !(style.value_min <= style.value_max)) {
    Fail(label, "map colour range: limit < 0 or value_min > value_max");
  }
  Axis bar;
  MapColorRange(field, style, label, &bar.lo, &bar.hi);
  // The plot area keeps the data's aspect ratio (equal metres per pixel).
  const double aspect = (field.x_max - field.x_min) / (field.y_max - field.y_min);
  double w = 720, h = 720 / aspect;
  if (h > 540) {
    h = 540;
    w = 540 * aspect;
  }
  Rect plot{0, 0, std::round(std::clamp(w, 120.0, 720.0)), std::round(std::clamp(h, 120.0, 540.0))};
  Axis x, y;
  x.lo = field.x_min, x.hi = field.x_max, y.lo = field.y_min, y.hi = field.y_max;
  Canvas scratch = MakeCanvas(1, 1, label);  // for measuring text before the size is known
  cairo_t* m = scratch.cr.get();
  ChooseTicks(m, plot.width, true, &x);
  ChooseTicks(m, plot.height, false, &y);
  ChooseTicks(m, plot.height, false, &bar);
  plot.top = TopMargin(m, text);
  plot.left = LeftMargin(m, text, y);
  SetFont(m, Font::kTick);
  if (!x.labels.empty())
    plot.left = std::max(plot.left, std::ceil(TextWidth(m, x.labels[0]) / 2 + 4));
  double bar_labels = 0;
  for (const std::string& l : bar.labels) bar_labels = std::max(bar_labels, TextWidth(m, l));
  Rect bar_rect{plot.right() + 24, plot.top, 18, plot.height};
  SetFont(m, Font::kLabel);
  double right = bar_rect.right() + 9 + bar_labels + kPad;
  if (!style.colorbar_label.empty()) right += 10 + FontHeight(m);
  SetFont(m, Font::kTitle);
  // Narrow maps are centred on a canvas wide enough for the title.
  const double min_width = std::min(900.0, std::max(480.0, TextWidth(m, text.title) + 2 * kPad));
  const double shift = std::max(0.0, std::floor((min_width - right) / 2));
  plot.left += shift;
  bar_rect.left += shift;
  const int width = static_cast<int>(std::ceil(right + 2 * shift));
  const int height = static_cast<int>(std::ceil(plot.bottom() + BottomMargin(m, text)));

  Canvas canvas = MakeCanvas(width, height, label);
  cairo_t* cr = canvas.cr.get();
  const int image_w = std::min(field.columns, static_cast<int>(plot.width));
  const int image_h = std::min(field.rows, static_cast<int>(plot.height));
  SurfacePtr image = RenderField(field, image_w, image_h, style, bar.lo, bar.hi, label);
  cairo_save(cr);
  cairo_rectangle(cr, plot.left, plot.top, plot.width, plot.height);
  cairo_clip(cr);
  cairo_translate(cr, plot.left, plot.top);
  cairo_scale(cr, plot.width / image_w, plot.height / image_h);
  cairo_set_source_surface(cr, image.get(), 0, 0);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_restore(cr);
  if (!style.outlines.empty()) {
    cairo_save(cr);
    cairo_rectangle(cr, plot.left, plot.top, plot.width, plot.height);
    cairo_clip(cr);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    cairo_set_line_width(cr, 1.2);
    const double dash[2] = {5.0, 3.0};
    cairo_set_dash(cr, dash, 2, 0.0);
    const double sx = plot.width / (field.x_max - field.x_min), sy = plot.height / (field.y_max - field.y_min);
    for (const auto& line : style.outlines) {
      for (std::size_t k = 0; k < line.size(); ++k) {
        const double px = plot.left + (line[k][0] - field.x_min) * sx;
        const double py = plot.top + (field.y_max - line[k][1]) * sy;
        if (k == 0) {
          cairo_move_to(cr, px, py);
        } else {
          cairo_line_to(cr, px, py);
        }
      }
      cairo_stroke(cr);
    }
    cairo_restore(cr);
  }
  DrawAxes(cr, plot, width, x, y, text);
  DrawColorBar(cr, bar_rect, bar, style);
  SavePng(canvas, path, label);
}

void WriteChartPng(const std::string& path, const std::vector<Series>& series,
                   const FigureText& text, const ChartStyle& style, const std::string& label) {
  CheckOutputPath(path, label);
  CheckStyle(style, label);
  if (series.empty()) Fail(label, "chart has no series");
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  for (const Series& s : series) {
    if (s.x.size() != s.y.size()) {
      Fail(label, "series '" + s.name + "' has " + std::to_string(s.x.size()) + " x values but " +
                      std::to_string(s.y.size()) + " y values");
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!Drawable(s.x[i], style.log_x) || !Drawable(s.y[i], style.log_y)) continue;
      x_lo = std::min(x_lo, s.x[i]), x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i]), y_hi = std::max(y_hi, s.y[i]);
    }
  }
  if (!(x_lo <= x_hi)) {
    Fail(label, style.log_x || style.log_y
                    ? "chart has no finite point with positive values on its log axes"
                    : "chart has no finite point");
  }
  const Axis x = MakeAxis(style.log_x, style.x_min, style.x_max, x_lo, x_hi);
  const Axis y = MakeAxis(style.log_y, style.y_min, style.y_max, y_lo, y_hi);
  DrawChart(path, series, false, x, y, text, style, label,
            [&](cairo_t* cr, const Rect& plot, const Axis& ax, const Axis& ay,
                std::vector<std::pair<double, double>>* covered) {
              for (std::size_t i = 0; i < series.size(); ++i) {
                DrawSeries(cr, plot, ax, ay, series[i], static_cast<int>(i), covered);
              }
            });
}

void WriteHistogramPng(const std::string& path, const std::vector<Series>& series, int bins,
                       const FigureText& text, const ChartStyle& style, const std::string& label) {
  CheckOutputPath(path, label);
  CheckStyle(style, label);
  if (bins < 1 || bins > 100000)
    Fail(label, "histogram bins " + std::to_string(bins) + " not in 1..100000");
  if (series.empty()) Fail(label, "histogram has no series");
  const bool log = style.log_x;
  double lo = style.x_min, hi = style.x_max;
  if (!(lo < hi)) {  // automatic: 1st..99th percentile (of log10 x on a log axis)
    std::vector<double> all;
    for (const Series& s : series) {
      for (double v : s.x) {
        if (Drawable(v, log)) all.push_back(log ? std::log10(v) : v);
      }
    }
    if (all.empty())
      Fail(label,
           log ? "histogram has no positive finite sample" : "histogram has no finite sample");
    lo = Percentile(&all, 0.01);
    hi = Percentile(&all, 0.99);
    if (!(hi > lo)) {
      lo = *std::min_element(all.begin(), all.end());
      hi = *std::max_element(all.begin(), all.end());
    }
    if (!(hi > lo)) {  // all samples equal: bins centred on the value
      const double d = log ? 0.5 : (lo != 0 ? 0.1 * std::abs(lo) : 1);
      lo -= d;
      hi += d;
    }
    if (log) lo = std::pow(10.0, lo), hi = std::pow(10.0, hi);
    PadRange(log, &lo, &hi);
  }
  std::vector<std::vector<double>> counts;
  double most = 0;
  for (const Series& s : series) {
    counts.push_back(HistogramCounts(s.x, lo, hi, bins, log));
    most = std::max(most, *std::max_element(counts.back().begin(), counts.back().end()));
  }
  Axis x;
  x.lo = lo, x.hi = hi, x.log = log;
  const Axis y =
      MakeAxis(style.log_y, style.y_min, style.y_max, style.log_y ? 0.5 : 0, std::max(most, 1.0));
  FigureText labelled = text;
  if (labelled.y_label.empty()) labelled.y_label = "count";
  DrawChart(path, series, true, x, y, labelled, style, label,
            [&](cairo_t* cr, const Rect& plot, const Axis& ax, const Axis& ay,
                std::vector<std::pair<double, double>>* covered) {
              const double t_lo = log ? std::log10(lo) : lo, t_hi = log ? std::log10(hi) : hi;
              const auto edge = [&](int b) {
                const double t = t_lo + (t_hi - t_lo) * b / bins;
                return XPixel(plot, ax, log ? std::pow(10.0, t) : t);
              };
              const double base = plot.bottom();
              ClipTo(cr, plot);
              const int every = std::max(1, bins / 200);  // legend samples: bounded count
              for (std::size_t i = 0; i < counts.size(); ++i) {
                cairo_move_to(cr, edge(0), base);
                for (int b = 0; b < bins; ++b) {
                  const double c = counts[i][static_cast<std::size_t>(b)];
                  const double top = Drawable(c, ay.log) ? ClampPixel(YPixel(plot, ay, c)) : base;
                  cairo_line_to(cr, edge(b), top);
                  cairo_line_to(cr, edge(b + 1), top);
                  if (b % every != 0) continue;
                  for (double px = edge(b); px <= edge(b + 1); px += 8) {
                    for (double py = top; py <= base; py += 8) covered->emplace_back(px, py);
                  }
                }
                cairo_line_to(cr, edge(bins), base);
                cairo_close_path(cr);
                SetColor(cr, static_cast<int>(i), 0.25);
                cairo_fill_preserve(cr);
                SetColor(cr, static_cast<int>(i));
                cairo_set_line_width(cr, 2);
                cairo_stroke(cr);
              }
              const double dashes[] = {6.0, 4.0};
              cairo_set_dash(cr, dashes, 2, 0.0);
              cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
              cairo_set_line_width(cr, 1.5);
              for (double mark : style.x_marks) {
                if (!std::isfinite(mark) || mark < lo || mark > hi || (log && mark <= 0)) continue;
                const double px = XPixel(plot, ax, mark);
                cairo_move_to(cr, px, plot.top);
                cairo_line_to(cr, px, base);
                cairo_stroke(cr);
              }
              cairo_set_dash(cr, nullptr, 0, 0.0);
            });
}

}  // namespace surfreg
