// Figures are checked by decoding the written PNG and looking at its pixels
// for facts that hold whatever the layout: which colours appear where, how
// tall a bar is relative to another. The tick and colour-range helpers are
// checked against hand-worked values.
#include "io/plot.h"

#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "io/plot_internal.h"

namespace surfreg {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Pixel {
  int r, g, b;
};

// A decoded PNG.
class Image {
 public:
  explicit Image(const std::string& path)
      : surface_(cairo_image_surface_create_from_png(path.c_str())) {}
  ~Image() { cairo_surface_destroy(surface_); }
  bool ok() const { return cairo_surface_status(surface_) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_); }
  int height() const { return cairo_image_surface_get_height(surface_); }
  Pixel at(int x, int y) const {
    const unsigned char* row =
        cairo_image_surface_get_data(surface_) + y * cairo_image_surface_get_stride(surface_);
    const std::uint32_t v = reinterpret_cast<const std::uint32_t*>(row)[x];
    return {static_cast<int>(v >> 16 & 255), static_cast<int>(v >> 8 & 255),
            static_cast<int>(v & 255)};
  }

 private:
  cairo_surface_t* surface_;
};

bool Near(const Pixel& p, int r, int g, int b, int tolerance = 3) {
  return std::abs(p.r - r) <= tolerance && std::abs(p.g - g) <= tolerance &&
         std::abs(p.b - b) <= tolerance;
}
bool Blue(const Pixel& p) { return p.b > p.r + 60; }
bool Red(const Pixel& p) { return p.r > p.b + 60; }
bool WhiteIsh(const Pixel& p) { return p.r > 230 && p.g > 230 && p.b > 230; }

std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "plot_test_" + std::to_string(getpid()) + "_" + name;
}
bool Exists(const std::string& path) { return std::ifstream(path).good(); }

// Runs `write` and expects an InputError whose message starts with "L".
template <typename F>
void ExpectInputError(F write, const std::string& what) {
  try {
    write();
    ADD_FAILURE() << "no InputError for " << what;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("L: ", 0), 0u) << e.what();
  }
}

// The longest run of pixels satisfying `test` along image row y.
template <typename Test>
int LongestRun(const Image& image, int y, Test test, int* run_start = nullptr) {
  int best = 0, run = 0;
  for (int x = 0; x < image.width(); ++x) {
    run = test(image.at(x, y)) ? run + 1 : 0;
    if (run > best) {
      best = run;
      if (run_start) *run_start = x - run + 1;
    }
  }
  return best;
}

// The longest run of one colour (±3) along any image row.
int LongestRunOf(const Image& image, int r, int g, int b) {
  int best = 0;
  for (int y = 0; y < image.height(); ++y) {
    best = std::max(best, LongestRun(image, y, [&](const Pixel& p) { return Near(p, r, g, b); }));
  }
  return best;
}

// ---- Ticks and numbers ----
TEST(NiceTicks, HandWorkedExamples) {
  EXPECT_EQ(NiceTicks(0, 1, 6), (std::vector<double>{0, 0.2, 0.4, 0.6, 0.8, 1.0}));
  EXPECT_EQ(NiceTicks(-3.7, 12.1, 10), (std::vector<double>{-2, 0, 2, 4, 6, 8, 10, 12}));
  EXPECT_EQ(NiceTicks(0, 100, 3), (std::vector<double>{0, 50, 100}));
  EXPECT_EQ(NiceTicks(5, 5, 6), (std::vector<double>{5}));
  EXPECT_DOUBLE_EQ(NiceStep(7, 7), 1);
  EXPECT_DOUBLE_EQ(NiceStep(7.1, 7), 2);
  EXPECT_DOUBLE_EQ(NiceStep(0.0031, 3), 0.002);
}

// The largest 1, 2 or 5 × 10^k that divides t (t != 0).
double LargestRoundDivisor(double t) {
  for (int k = 20; k >= -20; --k) {
    for (int m : {5, 2, 1}) {
      const double s = m * std::pow(10.0, k), q = t / s;
      if (std::abs(q) >= 0.5 && std::abs(q - std::round(q)) < 1e-9 * std::abs(q)) return s;
    }
  }
  return 0;
}

TEST(NiceTicks, RandomRangesGiveRoundCoveringTicks) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> exponent(-6, 6), unit(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, exponent(random));
    double lo = unit(random) * scale, hi = unit(random) * scale;
    if (lo > hi) std::swap(lo, hi);
    if (!(hi > lo)) continue;
    const int max_ticks = 2 + trial % 10;
    const std::vector<double> ticks = NiceTicks(lo, hi, max_ticks);
    ASSERT_GE(ticks.size(), 1u);
    ASSERT_LE(ticks.size(), static_cast<std::size_t>(max_ticks));
    if (ticks.size() == 1 && ticks[0] == 0) continue;  // zero is round; no step to check
    const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : LargestRoundDivisor(ticks[0]);
    if (ticks.size() == 1) {
      EXPECT_GE(step, (hi - lo) / 2.5) << lo << " " << hi;
    }
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 ||
                std::abs(mantissa - 5) < 1e-6)
        << step;
    EXPECT_GE(ticks.front(), lo - 1e-9 * step);
    EXPECT_LT(ticks.front() - lo, step * (1 + 1e-9));
    EXPECT_LE(ticks.back(), hi + 1e-9 * step);
    EXPECT_LT(hi - ticks.back(), step * (1 + 1e-9));
    for (double t : ticks) EXPECT_NEAR(t / step, std::round(t / step), 1e-6);
  }
}

// Regression: ranges at the limit of double precision once made the tick
// loop run forever; now they give no or few ticks and padding widens them.
TEST(NiceTicks, DegenerateRangesTerminate) {
  EXPECT_LE(NiceTicks(1.0, std::nextafter(1.0, 2.0), 6).size(), 6u);
  EXPECT_LE(NiceTicks(0, 5e-324, 6).size(), 6u);
  EXPECT_LE(NiceTicks(-1e308, 1e308, 6).size(), 6u);
  EXPECT_LE(NiceTicks(1e300, 1e300 * (1 + 1e-15), 6).size(), 6u);
  double lo = 1.0, hi = std::nextafter(1.0, 2.0);
  PadRange(false, &lo, &hi);
  EXPECT_LT(lo, 0.95);
  EXPECT_GT(hi, 1.05);
  EXPECT_GE(NiceTicks(lo, hi, 6).size(), 2u);
}

TEST(LogTicks, DecadesAndNarrowRanges) {
  EXPECT_EQ(LogTicks(1e-3, 1e3, 10), (std::vector<double>{1e-3, 1e-2, 1e-1, 1, 10, 100, 1000}));
  // 21 decades, at most 6 ticks: every 5th decade.
  EXPECT_EQ(LogTicks(1e-10, 1e10, 6), (std::vector<double>{1e-10, 1e-5, 1, 1e5, 1e10}));
  EXPECT_EQ(LogTicks(1, 10, 8), (std::vector<double>{1, 2, 5, 10}));
  EXPECT_EQ(LogTicks(2, 30, 8), (std::vector<double>{2, 5, 10, 20}));
  EXPECT_EQ(LogTicks(3, 8, 8), (std::vector<double>{3, 4, 5, 6, 7, 8}));  // linear fallback
}

TEST(PadRange, RoundsOutward) {
  double lo = 0.05, hi = 0.95;
  PadRange(false, &lo, &hi);
  EXPECT_DOUBLE_EQ(lo, 0);
  EXPECT_DOUBLE_EQ(hi, 1);
  lo = 3, hi = 3;  // empty range: widened around the value
  PadRange(false, &lo, &hi);
  EXPECT_LT(lo, 3);
  EXPECT_GT(hi, 3);
  lo = 0.003, hi = 42;
  PadRange(true, &lo, &hi);
  EXPECT_DOUBLE_EQ(lo, 1e-3);
  EXPECT_DOUBLE_EQ(hi, 100);
  lo = 10, hi = 10;
  PadRange(true, &lo, &hi);
  EXPECT_DOUBLE_EQ(lo, 1);
  EXPECT_DOUBLE_EQ(hi, 100);
}

TEST(FormatTick, DecimalsFollowTheStep) {
  EXPECT_EQ(FormatTick(0.15, 0.05), "0.15");
  EXPECT_EQ(FormatTick(1, 0.5), "1.0");
  EXPECT_EQ(FormatTick(30, 10), "30");
  EXPECT_EQ(FormatTick(-2e-17, 0.2), "0");  // rounding noise is not "-0.0"
  EXPECT_EQ(FormatTick(4500000, 500), "4500000");
  EXPECT_EQ(FormatTick(2e-7, 1e-7), "2e-7");
  EXPECT_EQ(FormatTick(1.5e9, 5e8), "1.5e9");
}

TEST(HistogramCounts, EdgesNaNAndOutliers) {
  const std::vector<double> samples = {0, 0.5, 1, 9.99, 10, -1, 11, kNaN, 5};
  EXPECT_EQ(HistogramCounts(samples, 0, 10, 10, false),
            (std::vector<double>{2, 1, 0, 0, 0, 1, 0, 0, 0, 2}));
  // Log bins: decades 1-10, 10-100; 0 and negatives skipped.
  EXPECT_EQ(HistogramCounts({-1, 0, 1, 5, 50, 100}, 1, 100, 2, true), (std::vector<double>{2, 2}));
}

TEST(MapColorRange, AutomaticExplicitAndConstant) {
  GridField field;
  field.columns = 100, field.rows = 1;
  for (int i = 1; i <= 100; ++i) field.values.push_back(i % 2 ? i : -i);
  double lo, hi;
  MapStyle style;
  MapColorRange(field, style, "L", &lo, &hi);
  EXPECT_DOUBLE_EQ(hi, 98);  // 98th percentile of |v| = 1..100 (nearest rank)
  EXPECT_DOUBLE_EQ(lo, -98);
  style.limit = 2;
  MapColorRange(field, style, "L", &lo, &hi);
  EXPECT_EQ(lo, -2);
  EXPECT_EQ(hi, 2);
  style = MapStyle();
  style.diverging = false;
  style.value_min = 10, style.value_max = 20;
  MapColorRange(field, style, "L", &lo, &hi);
  EXPECT_EQ(lo, 10);
  EXPECT_EQ(hi, 20);

  field.values.assign(100, 5.0);  // constant: a range around the value
  MapColorRange(field, MapStyle(), "L", &lo, &hi);
  EXPECT_DOUBLE_EQ(lo, -5);
  EXPECT_DOUBLE_EQ(hi, 5);
  style = MapStyle();
  style.diverging = false;
  MapColorRange(field, style, "L", &lo, &hi);
  EXPECT_LT(lo, 5);
  EXPECT_GT(hi, 5);
  field.values.assign(100, 0.0);
  MapColorRange(field, MapStyle(), "L", &lo, &hi);
  EXPECT_DOUBLE_EQ(hi, 1);
  field.values.assign(100, kNaN);
  EXPECT_THROW(MapColorRange(field, MapStyle(), "L", &lo, &hi), InputError);
}

TEST(Colors, EndsAndMiddle) {
  const Rgb blue = DivergingColor(-1), white = DivergingColor(0), red = DivergingColor(5);
  EXPECT_NEAR(blue.r * 255, 5, 0.5);  // ColorBrewer RdBu #053061 .. #f7f7f7 .. #67001f
  EXPECT_NEAR(blue.b * 255, 97, 0.5);
  EXPECT_NEAR(white.g * 255, 247, 0.5);
  EXPECT_NEAR(red.r * 255, 103, 0.5);
  EXPECT_LT(SequentialColor(0).g, SequentialColor(1).g);  // dark to light
  EXPECT_NEAR(SeriesColor(0).b * 255, 178, 0.5);          // Okabe-Ito blue first
  EXPECT_NEAR(SeriesColor(9).r * 255, 213, 0.5);          // cycles
}

// ---- Maps ----
// Where a colour lies along ColorBrewer's RdBu (0 = dark blue #053061, 1 =
// dark red #67001f): the parameter of the nearest point on the polyline
// through its 11 classes.
double RdBuPosition(const Pixel& p) {
  static const int kStops[11][3] = {{5, 48, 97},     {33, 102, 172},  {67, 147, 195},
                                    {146, 197, 222}, {209, 229, 240}, {247, 247, 247},
                                    {253, 219, 199}, {244, 165, 130}, {214, 96, 77},
                                    {178, 24, 43},   {103, 0, 31}};
  double best = 1e300, position = 0;
  for (int i = 0; i < 10; ++i) {
    double d[3], q[3], dd = 0, dq = 0;
    for (int k = 0; k < 3; ++k) {
      d[k] = kStops[i + 1][k] - kStops[i][k];
      q[k] = (k == 0 ? p.r : k == 1 ? p.g : p.b) - kStops[i][k];
      dd += d[k] * d[k];
      dq += d[k] * q[k];
    }
    const double f = std::clamp(dq / dd, 0.0, 1.0);
    double distance = 0;
    for (int k = 0; k < 3; ++k) distance += (q[k] - f * d[k]) * (q[k] - f * d[k]);
    if (distance < best) best = distance, position = (i + f) / 10;
  }
  return position;
}

// A field of −1 (left third), 0 (middle third) and +1 (right third), with
// its top quarter of rows missing.
GridField ThreeBands(int columns, int rows) {
  GridField field;
  field.columns = columns, field.rows = rows;
  field.x_min = 1000, field.x_max = 1000 + 10.0 * columns;
  field.y_min = 5000, field.y_max = 5000 + 10.0 * rows;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const double v = c < columns / 3 ? -1 : (c < 2 * columns / 3 ? 0 : 1);
      field.values.push_back(r < rows / 4 ? kNaN : v);
    }
  }
  return field;
}

TEST(WriteMapPng, DivergingBandsNoDataAndColorBar) {
  const std::string path = TempPath("map.png");
  const FigureText text{"dz", "easting (m)", "northing (m)"};
  MapStyle style;
  style.colorbar_label = "dz (m)";
  WriteMapPng(path, ThreeBands(90, 40), text, style, "L");
  std::ifstream file(path, std::ios::binary);
  char signature[8];
  file.read(signature, 8);
  EXPECT_EQ(std::string(signature, 8), "\x89PNG\r\n\x1a\n");
  const Image image(path);
  ASSERT_TRUE(image.ok());
  // Aspect 90:40 fits 720 px wide; the canvas adds margins and the bar.
  EXPECT_GT(image.width(), 720);
  EXPECT_LT(image.width(), 1000);
  EXPECT_GT(image.height(), 320);
  EXPECT_LT(image.height(), 500);

  // A row through the lower part of the map: blue, white-ish, red in order,
  // each about a third of the 720 px plot area.
  int blue_x = 0, white_x = 0, red_x = 0, y_row = -1;
  for (int y = image.height() / 2; y < image.height() && y_row < 0; ++y) {
    if (LongestRun(image, y, Blue, &blue_x) > 200) y_row = y;
  }
  ASSERT_GE(y_row, 0) << "no long blue run";
  EXPECT_GT(LongestRun(image, y_row, Red, &red_x), 200);
  EXPECT_GT(LongestRun(image, y_row, WhiteIsh, &white_x), 200);
  EXPECT_LT(blue_x, white_x);
  EXPECT_LT(white_x, red_x);
  EXPECT_LT(red_x, image.width() * 3 / 4);
  // Values at the range ends take the end colours exactly (limit = 1).
  EXPECT_TRUE(Near(image.at(blue_x + 100, y_row), 5, 48, 97));
  EXPECT_TRUE(Near(image.at(red_x + 100, y_row), 103, 0, 31));

  // Above the blue band, the missing rows are no-data grey.
  int grey = 0;
  for (int y = 0; y < y_row; ++y) grey += Near(image.at(blue_x + 100, y), 190, 190, 190, 1);
  EXPECT_GT(grey, 50);

  // The colour bar: a column right of the map running from blue at the
  // bottom to red at the top, its position along RdBu never decreasing.
  bool found = false;
  for (int x = red_x + 240; x < image.width() && !found; ++x) {
    int top = -1, bottom = -1;
    for (int y = 0; y < image.height(); ++y) {
      if (!WhiteIsh(image.at(x, y)) && !Near(image.at(x, y), 0, 0, 0, 80)) {
        if (top < 0) top = y;
        bottom = y;
      }
    }
    if (top < 0 || bottom - top < 200 || !Red(image.at(x, top + 2)) ||
        !Blue(image.at(x, bottom - 2))) {
      continue;
    }
    bool monotonic =
        RdBuPosition(image.at(x, bottom - 2)) < 0.05 && RdBuPosition(image.at(x, top + 2)) > 0.95;
    for (int y = top + 2; y < bottom - 2; ++y) {
      if (RdBuPosition(image.at(x, y + 1)) > RdBuPosition(image.at(x, y)) + 0.01) monotonic = false;
    }
    found = monotonic;
  }
  EXPECT_TRUE(found) << "no colour bar";
  std::remove(path.c_str());
}

TEST(WriteMapPng, ConstantFieldAndValuesBeyondTheLimit) {
  GridField field = ThreeBands(30, 20);
  for (double& v : field.values) v = std::isnan(v) ? v : 7.0;
  const std::string path = TempPath("constant.png");
  WriteMapPng(path, field, {"constant", "x (m)", "y (m)"}, MapStyle(), "L");
  Image constant(path);
  ASSERT_TRUE(constant.ok());
  EXPECT_GT(LongestRunOf(constant, 103, 0, 31), 400);  // the whole map width: the +end colour

  // Explicit limit 0.5 < |values| = 1: end colours on both sides.
  MapStyle style;
  style.limit = 0.5;
  WriteMapPng(path, ThreeBands(90, 40), {"", "", ""}, style, "L");
  Image clipped(path);
  ASSERT_TRUE(clipped.ok());
  EXPECT_GT(LongestRunOf(clipped, 5, 48, 97), 200);
  EXPECT_GT(LongestRunOf(clipped, 103, 0, 31), 200);
  std::remove(path.c_str());
}

TEST(WriteMapPng, LargeGridIsAveragedDown) {
  GridField field;
  field.columns = 3000, field.rows = 2000;  // 6 M cells, more pixels than the plot area
  field.x_min = 0, field.x_max = 3000, field.y_min = 0, field.y_max = 2000;
  field.values.resize(6000000);
  for (int r = 0; r < 2000; ++r) {
    for (int c = 0; c < 3000; ++c) field.values[r * 3000 + c] = c < 1500 ? -1 : 1;
  }
  MapStyle style;
  style.diverging = false;
  const std::string path = TempPath("large.png");
  WriteMapPng(path, field, {"large", "x (m)", "y (m)"}, style, "L");
  const Image image(path);
  ASSERT_TRUE(image.ok());
  EXPECT_LT(image.width(), 1100);
  // Sequential: −1 is viridis' dark end, +1 its yellow end.
  const int y = image.height() / 2;
  EXPECT_GT(LongestRun(image, y, [](const Pixel& p) { return Near(p, 68, 1, 84); }), 300);
  EXPECT_GT(LongestRun(image, y, [](const Pixel& p) { return Near(p, 253, 231, 37); }), 300);
  std::remove(path.c_str());
}

TEST(WriteMapPng, BadInputs) {
  const std::string path = TempPath("bad_map.png");
  GridField nan_field = ThreeBands(4, 4);
  nan_field.values.assign(16, kNaN);
  ExpectInputError([&] { WriteMapPng(path, nan_field, {}, MapStyle(), "L"); }, "all NaN");
  GridField wrong_size = ThreeBands(4, 4);
  wrong_size.values.pop_back();
  ExpectInputError([&] { WriteMapPng(path, wrong_size, {}, MapStyle(), "L"); }, "sizes");
  GridField flat = ThreeBands(4, 4);
  flat.x_max = flat.x_min;
  ExpectInputError([&] { WriteMapPng(path, flat, {}, MapStyle(), "L"); }, "empty extent");
  MapStyle negative;
  negative.limit = -1;
  ExpectInputError([&] { WriteMapPng(path, ThreeBands(4, 4), {}, negative, "L"); }, "limit");
  const std::string missing = TempPath("no_such_dir") + "/map.png";
  ExpectInputError([&] { WriteMapPng(missing, ThreeBands(4, 4), {}, MapStyle(), "L"); },
                   "missing directory");
  EXPECT_FALSE(Exists(path));
  EXPECT_FALSE(Exists(missing));
}

// ---- Charts ----
TEST(WriteChartPng, TwoSeriesHaveBothPaletteColours) {
  std::vector<Series> series(2);
  series[0].name = "lm";
  series[1].name = "dogleg";
  series[1].markers = true;
  for (int i = 0; i <= 10; ++i) {
    series[0].x.push_back(i), series[0].y.push_back(1);
    series[1].x.push_back(i), series[1].y.push_back(2);
  }
  const std::string path = TempPath("chart.png");
  WriteChartPng(path, series, {"success", "offset (m)", "rate"}, ChartStyle(), "L");
  const Image image(path);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), 900);
  EXPECT_EQ(image.height(), 600);
  // Okabe-Ito blue and vermillion, horizontal lines across most of the width.
  EXPECT_GT(LongestRunOf(image, 0, 114, 178), 500);
  EXPECT_GT(LongestRunOf(image, 213, 94, 0), 500);
  std::remove(path.c_str());
}

TEST(WriteChartPng, OnePointLogAxesAndErrors) {
  const std::string path = TempPath("chart2.png");
  Series one;
  one.name = "single";
  one.x = {3}, one.y = {4};
  WriteChartPng(path, {one}, {"one point", "x", "y"}, ChartStyle(), "L");
  Image single(path);
  ASSERT_TRUE(single.ok());
  int marker = 0;
  for (int y = 0; y < single.height(); ++y) {
    for (int x = 0; x < single.width(); ++x) marker += Near(single.at(x, y), 0, 114, 178);
  }
  EXPECT_GT(marker, 20);  // the point and its legend swatch

  ChartStyle log;
  log.log_x = log.log_y = true;
  Series errors;
  errors.line = false;
  errors.markers = true;
  errors.x = {1e-3, 0.1, 10, -1, 0, kNaN};
  errors.y = {1e-6, 1e-3, 1, 5, 5, 5};
  WriteChartPng(path, {errors}, {"error vs time", "time (s)", "error (m)"}, log, "L");
  EXPECT_TRUE(Image(path).ok());
  std::remove(path.c_str());

  Series ulp;  // y values one ULP apart: the axis is widened, not stuck
  ulp.x = {0, 1}, ulp.y = {1.0, std::nextafter(1.0, 2.0)};
  WriteChartPng(path, {ulp}, {"flat", "x", "y"}, ChartStyle(), "L");
  EXPECT_TRUE(Image(path).ok());
  std::remove(path.c_str());

  Series negative;
  negative.x = {-1, 0}, negative.y = {1, 2};
  ExpectInputError([&] { WriteChartPng(path, {negative}, {}, log, "L"); }, "all skipped");
  ExpectInputError([&] { WriteChartPng(path, {}, {}, ChartStyle(), "L"); }, "no series");
  Series mismatch;
  mismatch.x = {1, 2}, mismatch.y = {1};
  ExpectInputError([&] { WriteChartPng(path, {mismatch}, {}, ChartStyle(), "L"); }, "sizes");
  ChartStyle tiny;
  tiny.width = 10;
  ExpectInputError([&] { WriteChartPng(path, {one}, {}, tiny, "L"); }, "size");
  ExpectInputError(
      [&] { WriteChartPng(TempPath("none") + "/c.png", {one}, {}, ChartStyle(), "L"); },
      "missing directory");
  EXPECT_FALSE(Exists(path));
}

// ---- Histograms ----
// Tinted pixels per image column: the translucent fill of palette blue.
std::vector<int> BlueColumnHeights(const Image& image) {
  std::vector<int> heights(image.width(), 0);
  for (int x = 0; x < image.width(); ++x) {
    for (int y = 0; y < image.height(); ++y) {
      const Pixel p = image.at(x, y);
      heights[x] += p.b > p.r + 25 && p.g > p.r;
    }
  }
  return heights;
}

TEST(WriteHistogramPng, BarHeightsFollowCounts) {
  Series s;
  s.name = "dz";
  s.x.assign(1000, 2.5);            // bin 2 of [0, 10)
  s.x.insert(s.x.end(), 500, 7.5);  // bin 7
  s.x.insert(s.x.end(), 3, kNaN);   // skipped
  ChartStyle style;
  style.x_min = 0, style.x_max = 10;
  const std::string path = TempPath("hist.png");
  WriteHistogramPng(path, {s}, 10, {"dz", "dz (m)", ""}, style, "L");
  const Image image(path);
  ASSERT_TRUE(image.ok());
  const std::vector<int> heights = BlueColumnHeights(image);
  // The bar of 1000 fills the y axis (0..1000); the one of 500 half of it.
  const int w = image.width();
  const int tall = *std::max_element(heights.begin(), heights.begin() + w / 2);
  const int half = *std::max_element(heights.begin() + w / 2, heights.end());
  EXPECT_GT(tall, 400);
  EXPECT_NEAR(static_cast<double>(tall) / half, 2.0, 0.06);
  // Each bar is one bin (a tenth of the ~840 px axis) wide.
  int wide = 0;
  for (int h : heights) wide += h > tall * 0.9;
  EXPECT_GT(wide, 60);
  EXPECT_LT(wide, 100);
  std::remove(path.c_str());
}

TEST(WriteHistogramPng, AllEqualSamplesAndErrors) {
  Series s;
  s.x.assign(1000, 3.0);
  const std::string path = TempPath("hist2.png");
  WriteHistogramPng(path, {s}, 21, {"equal", "x", ""}, ChartStyle(), "L");
  const Image image(path);
  ASSERT_TRUE(image.ok());
  const std::vector<int> heights = BlueColumnHeights(image);
  int wide = 0, tall = 0;
  for (int h : heights) tall = std::max(tall, h);
  for (int h : heights) wide += h > tall * 0.9;
  EXPECT_GT(tall, 400);            // one full-height bar ...
  EXPECT_LT(wide, 900 / 21 + 10);  // ... one bin wide
  std::remove(path.c_str());

  Series nan;
  nan.x = {kNaN, kNaN};
  ExpectInputError([&] { WriteHistogramPng(path, {nan}, 10, {}, ChartStyle(), "L"); }, "NaN");
  ExpectInputError([&] { WriteHistogramPng(path, {s}, 0, {}, ChartStyle(), "L"); }, "bins");
  ExpectInputError([&] { WriteHistogramPng(path, {}, 10, {}, ChartStyle(), "L"); }, "empty");
  ChartStyle log;
  log.log_x = true;
  Series negative;
  negative.x = {-1, 0};
  ExpectInputError([&] { WriteHistogramPng(path, {negative}, 10, {}, log, "L"); }, "log");
  EXPECT_FALSE(Exists(path));
}

}  // namespace
}  // namespace surfreg
