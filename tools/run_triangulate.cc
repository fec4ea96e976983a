// surfreg triangulate FILE [--json]: read + Delaunay, with counts and timings.
#include <glog/logging.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

#include "measure/delaunay.h"
#include "tools/commands.h"
#include "tools/io/surface_reader.h"
#include "tools/json_writer.h"

namespace surfreg {
namespace {

struct TriangulateReport {
  std::string file;
  std::array<double, 3> origin = {0.0, 0.0, 0.0};
  int64_t n_points = 0;
  int64_t n_duplicates = 0;
  int64_t n_triangles = 0;
  int64_t n_hull_edges = 0;
  double read_s = 0.0;
  double triangulate_s = 0.0;
  double total_s = 0.0;

  int64_t n_vertices() const { return n_points - n_duplicates; }
  // Guarded so that a too-fast clock never divides by zero.
  double points_per_s() const { return n_points / std::max(triangulate_s, 1e-9); }
};

// Shortest text that reads back as the same double (origins are exact values).
std::string Exact(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

void PrintJson(const TriangulateReport& r) {
  JsonObject timings;
  timings.Fixed("read", r.read_s, 6)
      .Fixed("triangulate", r.triangulate_s, 6)
      .Fixed("total", r.total_s, 6);
  JsonObject json;
  json.String("file", r.file)
      .Raw("origin", JsonArray({Exact(r.origin[0]), Exact(r.origin[1]), Exact(r.origin[2])}))
      .Int("n_points", r.n_points)
      .Int("n_vertices", r.n_vertices())
      .Int("n_duplicates", r.n_duplicates)
      .Int("n_triangles", r.n_triangles)
      .Int("n_hull_edges", r.n_hull_edges)
      .Object("timings", timings)
      .Fixed("points_per_second", r.points_per_s(), 0);
  std::printf("%s\n", json.str().c_str());
}

void PrintText(const TriangulateReport& r) {
  std::printf("file:              %s\n", r.file.c_str());
  std::printf("origin:            %s %s %s  (added to local coordinates)\n",
              Exact(r.origin[0]).c_str(), Exact(r.origin[1]).c_str(), Exact(r.origin[2]).c_str());
  std::printf("input points:      %lld\n", static_cast<long long>(r.n_points));
  std::printf("vertices:          %lld\n", static_cast<long long>(r.n_vertices()));
  std::printf("duplicates merged: %lld\n", static_cast<long long>(r.n_duplicates));
  std::printf("triangles:         %lld\n", static_cast<long long>(r.n_triangles));
  std::printf("hull edges:        %lld\n", static_cast<long long>(r.n_hull_edges));
  std::printf("time read:         %.6f s\n", r.read_s);
  std::printf("time triangulate:  %.6f s\n", r.triangulate_s);
  std::printf("time total:        %.6f s\n", r.total_s);
  std::printf("throughput:        %.3g points/s (triangulate)\n", r.points_per_s());
}

double Seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

int RunTriangulate(const std::vector<std::string>& args) {
  if (args.empty()) throw UsageError("triangulate: missing FILE");
  if (args.size() > 1) throw UsageError("triangulate: too many arguments");
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const Surface surface = ReadSurface(args[0]);
  const Clock::time_point read = Clock::now();
  const Triangulation triangulation = Triangulate(surface.xy);
  const Clock::time_point done = Clock::now();

  TriangulateReport report;
  report.file = args[0];
  report.origin = surface.origin;
  report.n_points = static_cast<int64_t>(surface.size());
  report.n_duplicates = triangulation.num_duplicates;
  report.n_triangles = triangulation.num_triangles();
  report.n_hull_edges =
      std::count(triangulation.neighbors.begin(), triangulation.neighbors.end(), -1);
  report.read_s = Seconds(read - start);
  report.triangulate_s = Seconds(done - read);
  report.total_s = Seconds(done - start);
  LOG(INFO) << "triangulated " << report.n_points << " points of " << report.file << " in "
            << report.total_s << " s";
  if (FLAGS_json) {
    PrintJson(report);
  } else {
    PrintText(report);
  }
  return 0;
}

}  // namespace surfreg
