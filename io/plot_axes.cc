// Colours, ticks, colour ranges, text and axes shared by the figures of
// io/plot.cc.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "io/plot_internal.h"

namespace surfreg {
namespace {

constexpr double kPad = 12;        // space at the canvas edges
constexpr double kTickLength = 5;  // outward tick marks
constexpr double kTickGap = 4;     // between a tick mark and its label
constexpr int kMaxTicks = 12;
// Percentiles of more values than this use an evenly strided sample: a
// display range needs no exact order statistics of a 10^8-cell grid.
constexpr std::size_t kMaxRangeSamples = 1000000;

Rgb FromBytes(int r, int g, int b) { return {r / 255.0, g / 255.0, b / 255.0}; }

// Linear interpolation in a table of colour stops spread evenly over [0, 1].
template <std::size_t N>
Rgb Interpolate(const std::array<Rgb, N>& stops, double t) {
  if (!(t > 0)) return stops.front();  // also NaN
  if (t >= 1) return stops.back();
  const double position = t * (N - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(position), N - 2);
  const double f = position - i;
  const Rgb& a = stops[i];
  const Rgb& b = stops[i + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

double Pow10(double exponent) { return std::pow(10.0, exponent); }

// A 1-2-5 step m × 10^k, kept apart so that multiples are exact decimals
// (3 × 0.2 is computed as 6 / 10 = 0.6, not 0.6000000000000001).
struct Step {
  int m = 1, k = 0;
  double Times(double i) const { return k >= 0 ? i * m * Pow10(k) : i * m / Pow10(-k); }
  double value() const { return Times(1); }
  Step Finer() const { return m == 5 ? Step{2, k} : m == 2 ? Step{1, k} : Step{5, k - 1}; }
};

Step NiceStepOf(double span, int max_intervals) {
  const double raw = std::abs(span) / std::max(1, max_intervals);
  if (!(raw > 0) || !std::isfinite(raw)) return {};
  const int k = static_cast<int>(std::floor(std::log10(raw)));
  for (int m : {1, 2, 5}) {
    if (Step{m, k}.value() >= raw * (1 - 1e-9)) return {m, k};
  }
  return {1, k + 1};
}

// The multiples of `step` in [lo, hi], ends included up to rounding.
std::vector<double> MultiplesOf(const Step& step, double lo, double hi) {
  const double s = step.value();
  const double first = std::ceil(lo / s - 1e-9), last = std::floor(hi / s + 1e-9);
  std::vector<double> ticks;
  // A step too fine for the values' precision (or overflowing) has no
  // distinct multiples to show; and counting past 2^53 would never end.
  if (!(s > 0) || !(std::abs(first) < 1e15 && std::abs(last) < 1e15) || last - first > 1e4) {
    return ticks;
  }
  for (double i = first; i <= last; i += 1) ticks.push_back(i == 0 ? 0.0 : step.Times(i));
  return ticks;
}

// 10^e for a whole e, as an exact decimal (1e-3, not pow's nearby double).
double Decade(double e) { return Step{1, static_cast<int>(e)}.value(); }

// Labels of log ticks with uneven spacing get the decimals their own
// magnitude needs; evenly spaced ticks share the step's.
bool EvenlySpaced(const std::vector<double>& ticks) {
  if (ticks.size() < 3) return false;
  const double step = ticks[1] - ticks[0];
  for (std::size_t i = 2; i < ticks.size(); ++i) {
    if (std::abs(ticks[i] - ticks[i - 1] - step) > 1e-6 * std::abs(step)) return false;
  }
  return true;
}

bool IsDecade(double t) {
  const double e = std::log10(t);
  return std::abs(e - std::round(e)) < 1e-9;
}

void SetLabels(Axis* axis) {
  axis->labels.clear();
  const bool even = !axis->log || EvenlySpaced(axis->ticks);
  // Decades beyond 0.001..10000 read best as powers of ten, all alike.
  if (axis->log && !even && !axis->ticks.empty() &&
      std::all_of(axis->ticks.begin(), axis->ticks.end(), IsDecade) &&
      (axis->ticks.front() < 1e-3 || axis->ticks.back() > 1e4)) {
    for (double t : axis->ticks) {
      axis->labels.push_back("10^" + std::to_string(std::lround(std::log10(t))));
    }
    return;
  }
  const double step = axis->ticks.size() > 1 ? axis->ticks[1] - axis->ticks[0] : 0;
  for (double t : axis->ticks) {
    double s = step;
    if (!even || s <= 0) s = t != 0 ? Pow10(std::floor(std::log10(std::abs(t)) + 1e-9)) : 1;
    axis->labels.push_back(FormatTick(t, s));
  }
}

constexpr double kSuperscript = 0.75;  // exponent size relative to its base

// "10^-5" (how SetLabels writes decades): drawn as 10 with a raised exponent.
bool IsPowerOfTen(const std::string& text, std::string* exponent) {
  if (text.size() < 4 || text.compare(0, 3, "10^") != 0) return false;
  const std::size_t digits = text[3] == '-' ? 4 : 3;
  if (text.size() == digits) return false;
  for (std::size_t i = digits; i < text.size(); ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
  }
  *exponent = text.substr(3);
  return true;
}

double FontSize(cairo_t* cr) {
  cairo_matrix_t matrix;
  cairo_get_font_matrix(cr, &matrix);
  return matrix.yy;
}

// Shrinks the current font until `text` is at most `max_width` wide.
void FitFont(cairo_t* cr, const std::string& text, double size, double max_width) {
  for (; size > 8; size -= 1) {
    cairo_set_font_size(cr, size);
    if (TextWidth(cr, text) <= max_width) return;
  }
  cairo_set_font_size(cr, 8);
}

cairo_status_t AppendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

// ---- Colours ----
Rgb DivergingColor(double t) {
  static const std::array<Rgb, 11> kRdBu = {
      FromBytes(5, 48, 97),     FromBytes(33, 102, 172),  FromBytes(67, 147, 195),
      FromBytes(146, 197, 222), FromBytes(209, 229, 240), FromBytes(247, 247, 247),
      FromBytes(253, 219, 199), FromBytes(244, 165, 130), FromBytes(214, 96, 77),
      FromBytes(178, 24, 43),   FromBytes(103, 0, 31)};
  return Interpolate(kRdBu, (t + 1) / 2);
}

Rgb SequentialColor(double t) {
  static const std::array<Rgb, 9> kViridis = {
      FromBytes(68, 1, 84),    FromBytes(71, 44, 122),  FromBytes(59, 81, 139),
      FromBytes(44, 113, 142), FromBytes(33, 144, 141), FromBytes(39, 173, 129),
      FromBytes(92, 200, 99),  FromBytes(170, 220, 50), FromBytes(253, 231, 37)};
  return Interpolate(kViridis, t);
}

Rgb SeriesColor(int index) {
  static const std::array<Rgb, 8> kOkabeIto = {FromBytes(0, 114, 178),   FromBytes(213, 94, 0),
                                               FromBytes(0, 158, 115),   FromBytes(230, 159, 0),
                                               FromBytes(204, 121, 167), FromBytes(86, 180, 233),
                                               FromBytes(0, 0, 0),       FromBytes(240, 228, 66)};
  return kOkabeIto[static_cast<std::size_t>(std::abs(index)) % kOkabeIto.size()];
}

// ---- Numbers ----
double NiceStep(double span, int max_intervals) { return NiceStepOf(span, max_intervals).value(); }

std::vector<double> NiceTicks(double lo, double hi, int max_ticks) {
  if (!(hi > lo)) return {lo};
  max_ticks = std::max(2, max_ticks);
  Step step = NiceStepOf(hi - lo, max_ticks - 1);
  std::vector<double> ticks = MultiplesOf(step, lo, hi);
  // That step fits even when the range ends fall badly; a range that ends
  // mid-step (or a step wider than the range, which may miss it) often
  // takes finer ones: the finest whose ticks still number max_ticks.
  for (int i = 0; i < 8; ++i) {  // each finer step more than doubles the count
    step = step.Finer();
    std::vector<double> finer = MultiplesOf(step, lo, hi);
    if (finer.size() > static_cast<std::size_t>(max_ticks) || finer.empty()) break;
    ticks = std::move(finer);
  }
  return ticks;
}

std::vector<double> LogTicks(double lo, double hi, int max_ticks) {
  max_ticks = std::max(2, max_ticks);
  const double a = std::ceil(std::log10(lo) - 1e-9), b = std::floor(std::log10(hi) + 1e-9);
  std::vector<double> ticks;
  if (b - a + 1 >= 3) {  // enough decades: powers of ten, thinned 1-2-5
    const double every = std::max(1.0, NiceStep(b - a, max_ticks - 1));
    for (double e = std::ceil(a / every) * every; e <= b; e += every) ticks.push_back(Decade(e));
    return ticks;
  }
  for (double e = std::floor(std::log10(lo) + 1e-9); e <= b; e += 1) {
    for (int m : {1, 2, 5}) {
      const double v = Step{m, static_cast<int>(e)}.value();
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) ticks.push_back(v);
    }
  }
  if (ticks.size() > static_cast<std::size_t>(max_ticks) && b >= a) {
    ticks.clear();
    for (double e = a; e <= b; e += 1) ticks.push_back(Decade(e));
  }
  if (ticks.size() < 2) return NiceTicks(lo, hi, max_ticks);
  return ticks;
}

void PadRange(bool log, double* lo, double* hi) {
  if (log) {
    *lo = Decade(std::floor(std::log10(*lo) + 1e-9));
    *hi = Decade(std::ceil(std::log10(*hi) - 1e-9));
    if (!(*hi > *lo)) {
      *lo /= 10;
      *hi *= 10;
    }
    return;
  }
  // Empty, or too narrow to label at double precision: widen around it.
  if (!(*hi - *lo > 1e-12 * std::max(std::abs(*lo), std::abs(*hi)))) {
    const double mid = *lo / 2 + *hi / 2, d = mid != 0 ? 0.1 * std::abs(mid) : 1;
    *lo = mid - d;
    *hi = mid + d;
  }
  const double step = NiceStep(*hi - *lo, 6);
  *lo = std::floor(*lo / step + 1e-9) * step;
  *hi = std::ceil(*hi / step - 1e-9) * step;
}

std::string FormatTick(double value, double step) {
  step = std::abs(step);
  if (std::abs(value) < 1e-9 * step || value == 0) return "0";
  const double magnitude = step > 0 ? std::floor(std::log10(step) + 1e-9) : 0;
  char buffer[64];
  if (step < 1e-4 || std::abs(value) >= 1e9) {
    const int exponent = static_cast<int>(std::floor(std::log10(std::abs(value)) + 1e-9));
    const int digits = std::clamp(exponent - static_cast<int>(magnitude), 0, 8);
    const double mantissa = value / Pow10(exponent);
    std::snprintf(buffer, sizeof buffer, "%.*fe%d", digits, mantissa, exponent);
  } else {
    std::snprintf(buffer, sizeof buffer, "%.*f", std::max(0, -static_cast<int>(magnitude)), value);
  }
  return buffer;
}

double Percentile(std::vector<double>* values, double fraction) {
  if (values->empty()) return 0;
  const double position = std::clamp(fraction, 0.0, 1.0) * (values->size() - 1);
  const auto nth = values->begin() + static_cast<std::ptrdiff_t>(std::lround(position));
  std::nth_element(values->begin(), nth, values->end());
  return *nth;
}

std::vector<double> HistogramCounts(const std::vector<double>& samples, double lo, double hi,
                                    int bins, bool log) {
  std::vector<double> counts(static_cast<std::size_t>(std::max(bins, 0)), 0.0);
  if (bins < 1 || !(hi > lo) || (log && !(lo > 0))) return counts;
  const double t_lo = log ? std::log10(lo) : lo, t_hi = log ? std::log10(hi) : hi;
  for (double x : samples) {
    if (!std::isfinite(x) || x < lo || x > hi) continue;
    const double t = log ? std::log10(x) : x;
    const int bin = std::min(bins - 1, static_cast<int>((t - t_lo) / (t_hi - t_lo) * bins));
    ++counts[static_cast<std::size_t>(std::max(0, bin))];
  }
  return counts;
}

void MapColorRange(const GridField& field, const MapStyle& style, const std::string& label,
                   double* lo, double* hi) {
  std::size_t finite = 0;
  double min = std::numeric_limits<double>::infinity(), max = -min;
  for (double v : field.values) {
    if (!std::isfinite(v)) continue;
    ++finite;
    min = std::min(min, v);
    max = std::max(max, v);
  }
  if (finite == 0) throw InputError(label + ": the map has no finite value");
  if (style.diverging && style.limit > 0) {
    *lo = -style.limit;
    *hi = style.limit;
    return;
  }
  if (!style.diverging && style.value_min < style.value_max) {
    *lo = style.value_min;
    *hi = style.value_max;
    return;
  }
  std::vector<double> sample;
  const std::size_t every = finite / kMaxRangeSamples + 1;
  sample.reserve(finite / every + 1);
  std::size_t seen = 0;
  for (double v : field.values) {
    if (std::isfinite(v) && seen++ % every == 0)
      sample.push_back(style.diverging ? std::abs(v) : v);
  }
  if (style.diverging) {
    double limit = Percentile(&sample, 0.98);
    if (!(limit > 0)) limit = std::max(std::abs(min), std::abs(max));
    if (!(limit > 0)) limit = 1;
    *lo = -limit;
    *hi = limit;
    return;
  }
  *lo = Percentile(&sample, 0.01);
  *hi = Percentile(&sample, 0.99);
  if (!(*hi > *lo)) {
    *lo = min;
    *hi = max;
  }
  if (!(*hi > *lo)) {  // constant field: a range around its value
    const double d = *lo != 0 ? 0.1 * std::abs(*lo) : 1;
    *lo -= d;
    *hi += d;
  }
}

// ---- Cairo plumbing ----
void CheckCairo(cairo_status_t status, const std::string& label) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw InputError(label + ": drawing failed: " + cairo_status_to_string(status));
  }
}

Canvas MakeCanvas(int width, int height, const std::string& label) {
  Canvas canvas;
  canvas.surface.reset(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height));
  CheckCairo(cairo_surface_status(canvas.surface.get()), label);
  canvas.cr.reset(cairo_create(canvas.surface.get()));
  CheckCairo(cairo_status(canvas.cr.get()), label);
  cairo_set_source_rgb(canvas.cr.get(), 1, 1, 1);
  cairo_paint(canvas.cr.get());
  return canvas;
}

void SavePng(const Canvas& canvas, const std::string& path, const std::string& label) {
  CheckCairo(cairo_status(canvas.cr.get()), label);
  cairo_surface_flush(canvas.surface.get());
  std::string png;
  CheckCairo(cairo_surface_write_to_png_stream(canvas.surface.get(), AppendToString, &png), label);
  WriteFileAtomically(path, png, label);
}

// ---- Text, axes and layout ----
void SetFont(cairo_t* cr, Font font) {
  cairo_select_font_face(cr, "sans", CAIRO_FONT_SLANT_NORMAL,
                         font == Font::kTitle ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  const double sizes[] = {18, 14, 12, 12};
  cairo_set_font_size(cr, sizes[static_cast<int>(font)]);
}

double PlainWidth(cairo_t* cr, const std::string& text) {
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  return extents.x_advance;
}

double TextWidth(cairo_t* cr, const std::string& text) {
  std::string exponent;
  if (!IsPowerOfTen(text, &exponent)) return PlainWidth(cr, text);
  const double size = FontSize(cr), base = PlainWidth(cr, "10");
  cairo_set_font_size(cr, kSuperscript * size);
  const double raised = PlainWidth(cr, exponent);
  cairo_set_font_size(cr, size);
  return base + raised;
}

double FontHeight(cairo_t* cr) {
  cairo_font_extents_t extents;
  cairo_font_extents(cr, &extents);
  return extents.ascent + extents.descent;
}

void DrawText(cairo_t* cr, const std::string& text, double x, double y, double ax, double ay,
              bool vertical) {
  if (text.empty()) return;
  cairo_font_extents_t font;
  cairo_font_extents(cr, &font);
  const double width = TextWidth(cr, text), height = font.ascent + font.descent;
  cairo_save(cr);
  cairo_translate(cr, x, y);
  if (vertical) cairo_rotate(cr, -M_PI / 2);
  const double baseline = -ay * height + font.ascent;
  cairo_move_to(cr, -ax * width, baseline);
  std::string exponent;
  if (IsPowerOfTen(text, &exponent)) {
    cairo_show_text(cr, "10");
    cairo_rel_move_to(cr, 0, -0.4 * font.ascent);
    cairo_set_font_size(cr, kSuperscript * FontSize(cr));
    cairo_show_text(cr, exponent.c_str());
  } else {
    cairo_show_text(cr, text.c_str());
  }
  cairo_restore(cr);
}

double Axis::Fraction(double value) const {
  if (log) return (std::log10(value) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
  return (value - lo) / (hi - lo);
}

double XPixel(const Rect& plot, const Axis& x, double value) {
  return plot.left + x.Fraction(value) * plot.width;
}
double YPixel(const Rect& plot, const Axis& y, double value) {
  return plot.bottom() - y.Fraction(value) * plot.height;
}

void ChooseTicks(cairo_t* cr, double length, bool horizontal, Axis* axis) {
  SetFont(cr, Font::kTick);
  const double font_height = FontHeight(cr);
  int max_ticks = std::clamp(static_cast<int>(length / (horizontal ? 70 : 50)), 2, kMaxTicks);
  for (;; --max_ticks) {
    axis->ticks = axis->log ? LogTicks(axis->lo, axis->hi, max_ticks)
                            : NiceTicks(axis->lo, axis->hi, max_ticks);
    SetLabels(axis);
    if (max_ticks <= 2 || axis->ticks.size() < 2) return;
    double widest = 0, closest = length;
    for (std::size_t i = 0; i < axis->ticks.size(); ++i) {
      widest = std::max(widest, TextWidth(cr, axis->labels[i]));
      if (i > 0) {
        closest = std::min(closest, length * (axis->Fraction(axis->ticks[i]) -
                                              axis->Fraction(axis->ticks[i - 1])));
      }
    }
    if (closest >= (horizontal ? widest + 16 : font_height + 12)) return;
  }
}

double TopMargin(cairo_t* cr, const FigureText& text) {
  SetFont(cr, Font::kTitle);
  return std::round(kPad + (text.title.empty() ? 8 : FontHeight(cr) + 12));
}

double BottomMargin(cairo_t* cr, const FigureText& text) {
  SetFont(cr, Font::kTick);
  double margin = kTickLength + kTickGap + FontHeight(cr) + kPad;
  SetFont(cr, Font::kLabel);
  if (!text.x_label.empty()) margin += 8 + FontHeight(cr);
  return std::round(margin);
}

double LeftMargin(cairo_t* cr, const FigureText& text, const Axis& y) {
  SetFont(cr, Font::kTick);
  double widest = 0;
  for (const std::string& label : y.labels) widest = std::max(widest, TextWidth(cr, label));
  SetFont(cr, Font::kLabel);
  const double label = text.y_label.empty() ? 0 : FontHeight(cr) + 10;
  return std::round(kPad + label + widest + kTickGap + kTickLength);
}

Rect LayoutChart(cairo_t* cr, int width, int height, const FigureText& text, Axis* x, Axis* y) {
  Rect plot;
  plot.top = TopMargin(cr, text);
  plot.height = std::max(20.0, height - plot.top - BottomMargin(cr, text));
  ChooseTicks(cr, plot.height, false, y);
  plot.left = LeftMargin(cr, text, *y);
  double right = 24;
  for (int pass = 0; pass < 3; ++pass) {  // the end labels must fit on the canvas
    plot.width = std::max(20.0, width - plot.left - right);
    ChooseTicks(cr, plot.width, true, x);
    if (x->labels.empty()) break;
    const double first = TextWidth(cr, x->labels.front()) / 2 + 4;
    const double last = TextWidth(cr, x->labels.back()) / 2 + 4;
    if (first <= plot.left && last <= right) break;
    plot.left = std::max(plot.left, std::ceil(first));
    right = std::max(right, std::ceil(last));
  }
  return plot;
}

void DrawGrid(cairo_t* cr, const Rect& plot, const Axis& x, const Axis& y) {
  cairo_save(cr);
  cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
  cairo_set_line_width(cr, 1);
  for (double t : x.ticks) {
    const double px = std::floor(XPixel(plot, x, t)) + 0.5;
    cairo_move_to(cr, px, plot.top);
    cairo_line_to(cr, px, plot.bottom());
  }
  for (double t : y.ticks) {
    const double py = std::floor(YPixel(plot, y, t)) + 0.5;
    cairo_move_to(cr, plot.left, py);
    cairo_line_to(cr, plot.right(), py);
  }
  cairo_stroke(cr);
  cairo_restore(cr);
}

void DrawAxes(cairo_t* cr, const Rect& plot, int canvas_width, const Axis& x, const Axis& y,
              const FigureText& text) {
  cairo_save(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 1);
  // The frame lies just outside the plot area so that it hides no data.
  cairo_rectangle(cr, plot.left - 0.5, plot.top - 0.5, plot.width + 1, plot.height + 1);
  for (double t : x.ticks) {
    const double px = std::floor(XPixel(plot, x, t)) + 0.5;
    cairo_move_to(cr, px, plot.bottom() + 0.5);
    cairo_line_to(cr, px, plot.bottom() + 0.5 + kTickLength);
  }
  for (double t : y.ticks) {
    const double py = std::floor(YPixel(plot, y, t)) + 0.5;
    cairo_move_to(cr, plot.left - 0.5, py);
    cairo_line_to(cr, plot.left - 0.5 - kTickLength, py);
  }
  cairo_stroke(cr);

  SetFont(cr, Font::kTick);
  const double label_top = plot.bottom() + kTickLength + kTickGap;
  for (std::size_t i = 0; i < x.ticks.size(); ++i) {
    DrawText(cr, x.labels[i], XPixel(plot, x, x.ticks[i]), label_top, 0.5, 0);
  }
  double widest = 0;
  for (std::size_t i = 0; i < y.ticks.size(); ++i) {
    DrawText(cr, y.labels[i], plot.left - kTickLength - kTickGap, YPixel(plot, y, y.ticks[i]), 1,
             0.5);
    widest = std::max(widest, TextWidth(cr, y.labels[i]));
  }
  const double x_label_top = label_top + FontHeight(cr) + 8;

  const double room = canvas_width - 2 * kPad;
  SetFont(cr, Font::kTitle);
  FitFont(cr, text.title, 18, room);
  const double title_width = TextWidth(cr, text.title);
  const double centre = std::clamp(plot.left + plot.width / 2, kPad + title_width / 2,
                                   canvas_width - kPad - title_width / 2);
  DrawText(cr, text.title, centre, kPad, 0.5, 0);
  SetFont(cr, Font::kLabel);
  FitFont(cr, text.x_label, 14, room);
  DrawText(cr, text.x_label, plot.left + plot.width / 2, x_label_top, 0.5, 0);
  SetFont(cr, Font::kLabel);
  FitFont(cr, text.y_label, 14, plot.height + plot.top);
  // Next to the tick labels (as LeftMargin reserves), wherever the plot is.
  const double y_label_left = plot.left - kTickLength - kTickGap - widest - 10 - FontHeight(cr);
  DrawText(cr, text.y_label, std::max(2.0, y_label_left), plot.top + plot.height / 2, 0.5, 0, true);
  cairo_restore(cr);
}

}  // namespace surfreg
