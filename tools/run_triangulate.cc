// surfreg triangulate FILE [--domain=data|hull] [--threads=N|all] [--json]: read + Delaunay
// (a raster: with its cells forced in, measure/grid_mesh.h), with counts, the data domain (measure/domain.h) and timings.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

#include "measure/delaunay.h"
#include "measure/domain.h"
#include "measure/grid_mesh.h"
#include "measure/tasks.h"
#include "tools/align_config.h"
#include "tools/commands.h"
#include "io/surface_reader.h"
#include "tools/json_writer.h"
#include "tools/key_flags.h"


namespace surfreg {
namespace {

struct TriangulateReport {
  std::string file;
  std::array<double, 3> origin = {0.0, 0.0, 0.0};
  int64_t n_points = 0;
  int64_t n_duplicates = 0;
  int64_t n_triangles = 0;
  int64_t n_hull_edges = 0;
  DomainKind domain = DomainKind::kData;
  bool raster_grid = false;  // the domain rule of raster cells
  int64_t n_domain_triangles = 0;
  double hull_area = 0.0, domain_area = 0.0;
  double read_s = 0.0;
  double triangulate_s = 0.0;
  double domain_s = 0.0;
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
      .Fixed("domain", r.domain_s, 6)
      .Fixed("total", r.total_s, 6);
  JsonObject json;
  json.String("file", r.file)
      .Raw("origin", JsonArray({Exact(r.origin[0]), Exact(r.origin[1]), Exact(r.origin[2])}))
      .Int("n_points", r.n_points)
      .Int("n_vertices", r.n_vertices())
      .Int("n_duplicates", r.n_duplicates)
      .Int("n_triangles", r.n_triangles)
      .Int("n_hull_edges", r.n_hull_edges)
      .String("domain", DomainKindName(r.domain))
      .String("domain_rule", r.raster_grid ? "raster_cells" : "scattered")
      .Int("n_domain_triangles", r.n_domain_triangles)
      .Number("hull_area", r.hull_area)
      .Number("domain_area", r.domain_area)
      .Number("excluded_area", r.hull_area - r.domain_area)
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
  std::printf("domain:            %s  (%s)\n", DomainKindName(r.domain),
              r.domain == DomainKind::kHull ? "the whole convex hull"
              : r.raster_grid              ? "raster cells with four valid corners"
                                           : "without triangles that bridge gaps, outline slivers");
  std::printf("domain triangles:  %lld\n", static_cast<long long>(r.n_domain_triangles));
  std::printf("hull area:         %.10g units²\n", r.hull_area);
  std::printf("domain area:       %.10g units²  (excluded from the hull: %.10g)\n", r.domain_area,
              r.hull_area - r.domain_area);
  std::printf("time read:         %.6f s\n", r.read_s);
  std::printf("time triangulate:  %.6f s\n", r.triangulate_s);
  std::printf("time domain:       %.6f s\n", r.domain_s);
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
  DomainRule rule = DomainRuleFromFlags(KeyFlag("domain"), KeyFlag("domain_max_edge_spacings"),
                                        KeyFlag("domain_min_thinness"));
  const Execution execution = ExecutionFor(ThreadsFlag());
  ReadOptions read_options;
  read_options.threads = execution.threads;
  const Surface surface = ReadSurface(args[0], read_options);
  rule.grid = surface.raster_grid();
  const Clock::time_point read = Clock::now();
  DelaunayOptions delaunay;
  delaunay.execution = execution;
  Triangulation triangulation = Triangulate(surface.xy, delaunay);
  std::vector<uint8_t> in_grid;  // a raster: its cells forced in (measure/grid_mesh.h)
  if (rule.grid) {
    in_grid = EnforceGrid(surface.xy, GridCellTriangles(surface.raster_cell, surface.source),
                          &triangulation);
  }
  const Clock::time_point triangulated = Clock::now();
  const std::vector<uint8_t> in_domain = DataDomain(surface.xy, triangulation, rule, &in_grid, execution);
  const Clock::time_point done = Clock::now();

  TriangulateReport report;
  report.file = args[0];
  report.origin = surface.origin;
  report.n_points = static_cast<int64_t>(surface.size());
  report.n_duplicates = triangulation.num_duplicates;
  report.n_triangles = triangulation.num_triangles();
  report.n_hull_edges =
      std::count(triangulation.neighbors.begin(), triangulation.neighbors.end(), -1);
  report.domain = rule.kind;
  report.raster_grid = surface.raster_grid();
  report.n_domain_triangles = std::count(in_domain.begin(), in_domain.end(), 1);
  report.hull_area = MeshArea(surface.xy, triangulation);
  report.domain_area = DomainArea(surface.xy, triangulation, in_domain);
  report.read_s = Seconds(read - start);
  report.triangulate_s = Seconds(triangulated - read);
  report.domain_s = Seconds(done - triangulated);
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
