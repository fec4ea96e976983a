// Peak memory of surfreg::Triangulate, one input per process so that the
// process's peak RSS is the triangulation's (plus the input) and nothing else.
//
//   delaunay_memory N [uniform|jittered|grid] [max_bytes_per_point]
//
// With a limit, exits 3 when the whole-process peak per point exceeds it
// (ctest runs it so at N = 1e6 with the 250-byte budget).
//
// Prints "key: value" lines (parsed by run_delaunay_bench.sh).
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <vector>

#include "measure/delaunay.h"
#include "measure/surface.h"
#include "tests/testing/point_sets.h"

namespace {

constexpr uint64_t kSeed = 0x5eed2d;  // same inputs as delaunay_bench

long PeakRssKiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;  // KiB on Linux
}

int Usage(const char* argv0) {
  std::fprintf(stderr, "usage: %s N [uniform|jittered|grid] [max_bytes_per_point]\n", argv0);
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 4) return Usage(argv[0]);
  char* end = nullptr;
  const long long n = std::strtoll(argv[1], &end, 10);
  if (*end != '\0' || n < 3) return Usage(argv[0]);
  const char* distribution = argc >= 3 ? argv[2] : "uniform";
  const double limit = argc == 4 ? std::strtod(argv[3], nullptr) : 0.0;
  const int side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));

  std::vector<surfreg::Point2> points;
  if (std::strcmp(distribution, "uniform") == 0) {
    points = surfreg::testing::UniformPoints(static_cast<std::size_t>(n), kSeed);
  } else if (std::strcmp(distribution, "jittered") == 0) {
    points = surfreg::testing::JitteredGridPoints(side, side, 0.25, kSeed);
  } else if (std::strcmp(distribution, "grid") == 0) {
    points = surfreg::testing::GridPoints(side, side);
  } else {
    return Usage(argv[0]);
  }
  const long before_kib = PeakRssKiB();

  surfreg::Triangulation t;
  try {
    t = surfreg::Triangulate(points);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "Triangulate threw: %s\n", e.what());
    return 1;
  }
  const long after_kib = PeakRssKiB();

  const double count = static_cast<double>(points.size());
  std::printf("distribution: %s\n", distribution);
  std::printf("points: %zu\n", points.size());
  std::printf("triangles: %d\n", t.num_triangles());
  std::printf("peak_rss_before_kib: %ld\n", before_kib);
  std::printf("peak_rss_after_kib: %ld\n", after_kib);
  // Peak extra memory of one call (its copies, scratch and the result)...
  std::printf("increase_bytes_per_point: %.1f\n", (after_kib - before_kib) * 1024.0 / count);
  // ...and of the whole process, input and runtime included.
  const double peak_per_point = after_kib * 1024.0 / count;
  std::printf("peak_bytes_per_point: %.1f\n", peak_per_point);
  if (limit > 0.0 && peak_per_point > limit) {
    std::fprintf(stderr, "peak %.1f bytes per point exceeds the limit %.1f\n", peak_per_point, limit);
    return 3;
  }
  return 0;
}
