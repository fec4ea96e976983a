// Peak memory of one whole comparison, surfreg::Measure, on two N-point
// clouds (the inputs of measure_bench), one comparison per process so that
// the process's peak RSS is the comparison's (plus the two surfaces) and
// nothing else.
//
//   measure_memory N [uniform|jittered] [limit_bytes]
//
// With a limit, exits 3 when the whole-process peak RSS exceeds it (ctest
// runs it at N = 1e6 with the budget: 1 GB = 1073741824 bytes for
// two 1e6-point clouds).
//
// Prints "key: value" lines (parsed by run_measure_bench.sh).
#include <sys/resource.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <vector>

#include "measure/measures.h"
#include "measure/surface.h"
#include "tests/testing/point_sets.h"

namespace {

// Same inputs as measure_bench (see there).
constexpr uint64_t kSeedA = 0x5eed2d;
constexpr uint64_t kSeedB = 0xb0b2d;
constexpr double kJitter = 0.25;

long PeakRssKiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;  // KiB on Linux
}

double HeightA(double x, double y) { return std::sin(6.0 * x) * std::cos(5.0 * y); }
double HeightB(double x, double y) { return HeightA(x, y) + 0.01 + 0.02 * x; }

// One cloud made into a Surface; the raw points are freed on return, as a
// reader would.
surfreg::Surface MakeCloudSurface(bool jittered, long long n, bool is_b) {
  std::vector<surfreg::Point2> xy;
  if (!jittered) {
    xy = surfreg::testing::UniformPoints(static_cast<std::size_t>(n), is_b ? kSeedB : kSeedA);
  } else {
    const int side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
    const double h = 1.0 / side;
    const double offset = is_b ? 0.75 : 0.25;  // half a cell apart, both inside [0, 1]
    xy = surfreg::testing::JitteredGridPoints(side, side, kJitter, is_b ? kSeedB : kSeedA);
    for (surfreg::Point2& p : xy) p = {(p.x + offset) * h, (p.y + offset) * h};
  }
  std::vector<std::array<double, 3>> points(xy.size());
  for (std::size_t i = 0; i < xy.size(); ++i) {
    points[i] = {xy[i].x, xy[i].y, is_b ? HeightB(xy[i].x, xy[i].y) : HeightA(xy[i].x, xy[i].y)};
  }
  return surfreg::MakeSurface(points, {}, is_b ? "B" : "A");
}

int Usage(const char* argv0) {
  std::fprintf(stderr, "usage: %s N [uniform|jittered] [limit_bytes]\n", argv0);
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 4) return Usage(argv[0]);
  char* end = nullptr;
  const long long n = std::strtoll(argv[1], &end, 10);
  if (*end != '\0' || n < 9) return Usage(argv[0]);
  const char* distribution = argc >= 3 ? argv[2] : "uniform";
  const bool jittered = std::strcmp(distribution, "jittered") == 0;
  if (!jittered && std::strcmp(distribution, "uniform") != 0) return Usage(argv[0]);
  double limit = 0.0;
  if (argc == 4) {
    limit = std::strtod(argv[3], &end);
    if (*end != '\0' || !(limit >= 0.0)) return Usage(argv[0]);
  }

  const surfreg::Surface a = MakeCloudSurface(jittered, n, false);
  const surfreg::Surface b = MakeCloudSurface(jittered, n, true);
  const long before_kib = PeakRssKiB();

  surfreg::MeasureSummary summary;
  try {
    summary = surfreg::Measure(a, b);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "Measure threw: %s\n", e.what());
    return 1;
  }
  const long after_kib = PeakRssKiB();

  const double count = static_cast<double>(a.size() + b.size());
  const double peak_bytes = after_kib * 1024.0;
  std::printf("distribution: %s\n", distribution);
  std::printf("points: %zu\n", a.size() + b.size());
  std::printf("rho_d: %.9g\n", summary.rho_d);
  std::printf("cells: %lld\n", static_cast<long long>(summary.n_cells));
  std::printf("seconds: %.3f\n", summary.timings.total);
  std::printf("peak_rss_before_kib: %ld\n", before_kib);
  std::printf("peak_rss_after_kib: %ld\n", after_kib);
  // Peak extra memory of the call (its copies, meshes, locations, overlay)...
  std::printf("increase_bytes_per_point: %.1f\n", (after_kib - before_kib) * 1024.0 / count);
  // ...and of the whole process, surfaces and runtime included.
  std::printf("peak_bytes_per_point: %.1f\n", peak_bytes / count);
  std::printf("peak_bytes: %.0f\n", peak_bytes);
  std::printf("limit_bytes: %.0f\n", limit);
  if (limit > 0.0 && peak_bytes > limit) {
    std::fprintf(stderr, "peak RSS %.0f bytes exceeds the limit %.0f\n", peak_bytes, limit);
    return 3;
  }
  return 0;
}
