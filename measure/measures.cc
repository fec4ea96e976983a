#include "measure/measures.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "measure/delaunay.h"
#include "measure/gap_volume.h"
#include "measure/grid_mesh.h"
#include "measure/grid_pair.h"
#include "measure/input_error.h"
#include "measure/locator.h"
#include "measure/predicates.h"
#include "measure/tasks.h"
#include "measure/overlay.h"
#include "measure/spanning_tree.h"
#include "measure/spatial_sort.h"
#include "measure/volume.h"
#include "measure/weights.h"

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point from) {
  return std::chrono::duration<double>(Clock::now() - from).count();
}

// One surface prepared for comparison: points in the common frame, its
// mesh, heights per vertex (duplicates averaged), EMST.
struct Prepared {
  std::vector<Point2> xy;
  std::vector<double> z;       // per input index; merged groups share their mean
  std::vector<double> weight;  // per input index, empty if none
  Triangulation mesh;
  std::vector<uint8_t> in_grid;  // a raster's: per mesh triangle, a grid triangle
  SpanningTree tree;
  double hull_area = 0.0;
  MeshDomain domain;
};

// Delaunay, and for a raster its cells forced in (measure/grid_mesh.h);
// `order` is the spatial sort (sorted k holds input order[k]).
void MeshOf(const Surface& s, const std::vector<int32_t>& order, const Execution& execution, Prepared& p) {
  DelaunayOptions delaunay;
  delaunay.execution = execution;
  p.mesh = Triangulate(p.xy, delaunay);
  if (!s.raster_grid()) return;
  std::vector<int32_t> cells = GridCellTriangles(s.raster_cell, s.source, execution);
  std::vector<int32_t> sorted_index(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted_index[order[k]] = static_cast<int32_t>(k);
  RemapGridTriangles(sorted_index, &cells);
  p.in_grid = EnforceGrid(p.xy, cells, &p.mesh);
}

void MergeDuplicateHeights(Prepared& s) {
  if (s.mesh.num_duplicates == 0) return;
  const std::size_t n = s.z.size();
  std::vector<double> sum(n, 0.0), wsum(n, 0.0);
  std::vector<int32_t> count(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int32_t v = s.mesh.vertex_of_input[i];
    sum[v] += s.z[i];
    ++count[v];
    if (!s.weight.empty()) wsum[v] += s.weight[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    const int32_t v = s.mesh.vertex_of_input[i];
    s.z[i] = sum[v] / count[v];
    if (!s.weight.empty()) s.weight[i] = wsum[v] / count[v];
  }
}

// Returns the order: sorted index k holds input index order[k].
std::vector<int32_t> SortSpatially(Prepared& s, const Execution& execution) {
  std::vector<int32_t> order = SpatialOrder(s.xy, /*brio=*/false, 0, execution);
  const int64_t n = static_cast<int64_t>(order.size());
  auto permute = [&](auto& values) {
    if (values.empty()) return;
    auto sorted = values;
    ForEachChunk(execution, n, ChunksFor(n, 1 << 16), [&](int, int64_t first, int64_t last) {
      for (int64_t k = first; k < last; ++k) sorted[k] = values[order[k]];
    });
    values.swap(sorted);
  };
  permute(s.xy);
  permute(s.z);
  permute(s.weight);
  return order;
}

// A surface whose domain is empty has nothing to compare.
void CheckDomain(const Surface& s, double domain_area, const DomainRule& rule, const char* name) {
  if (domain_area > 0.0) return;
  throw InputError((s.source.empty() ? std::string(name) : s.source) + ": no part of it is data (" +
                   (rule.grid ? "no raster cell has all four corners valid"
                              : "every triangle bridges a gap or is an outline sliver") +
                   "); 'domain: hull' measures over the convex hull instead");
}

}  // namespace

bool MeasureOptions::IsValid(std::string* error) const {
  if (!(min_overlap_fraction >= 0.0 && min_overlap_fraction < 1.0)) {
    *error = "min_overlap_fraction must be in [0, 1)";
    return false;
  }
  if (!(level_of_detection >= 0.0 && std::isfinite(level_of_detection))) {
    *error = "level_of_detection must be a finite number >= 0";
    return false;
  }
  if (detect_change && volume != VolumeMode::kOverlay) {
    *error = "change detection (cut/fill beyond a level of detection) needs the overlay volume mode";
    return false;
  }
  if (mask_mode == MaskMode::kExclude && weight != WeightMode::kMask) {
    *error = "mask_mode exclude needs a mask";
    return false;
  }
  if (weight == WeightMode::kMask) return ValidMaskRings(mask, error);
  return true;
}

const char* VolumeModeName(VolumeMode mode) {
  return mode == VolumeMode::kOverlay ? "overlay" : "union";
}

const char* WeightModeName(WeightMode mode) {
  switch (mode) {
    case WeightMode::kUniform: return "uniform";
    case WeightMode::kPerPoint: return "per_point";
    case WeightMode::kMask: return "mask";
  }
  return "?";
}

// One surface in A's local frame (B shifted by the origins' difference), in
// Hilbert order (every later stage then walks memory locally), meshed, its
// duplicates merged, its data domain (by its own rule: raster samples, cells)
// and spanning tree. `progress` and `timings` (may be null) follow its stages.
template <typename Progress>
void PrepareSide(const Surface& s, const double shift[3], DomainRule rule, const Progress& progress,
                 const Execution& execution, MeasureTimings* timings, Prepared* p, std::vector<int32_t>* order) {
  *p = Prepared{s.xy, s.z, s.weight, {}, {}, {}, 0.0, {}};
  if (shift[0] != 0.0 || shift[1] != 0.0 || shift[2] != 0.0) {
    for (Point2& q : p->xy) q = {q.x + shift[0], q.y + shift[1]};
    for (double& z : p->z) z += shift[2];
  }
  *order = SortSpatially(*p, execution);
  progress("triangulating", 0.05);
  Clock::time_point stage = Clock::now();
  MeshOf(s, *order, execution, *p);
  MergeDuplicateHeights(*p);
  p->hull_area = MeshArea(p->xy, p->mesh);
  if (timings != nullptr) timings->triangulate = Seconds(stage);
  // The domain and the spanning tree both read only the mesh: side by side.
  progress("data domains and spanning trees", 0.27);
  rule.grid = s.raster_grid();
  RunBoth(
      execution,
      [&] {
        const Clock::time_point start = Clock::now();
        p->domain = MakeMeshDomain(p->xy, p->mesh, rule, &p->in_grid, execution);
        if (timings != nullptr) timings->domain = Seconds(start);
      },
      [&] {
        const Clock::time_point start = Clock::now();
        p->tree = EuclideanMst(p->xy, p->mesh, execution);
        if (timings != nullptr) timings->spanning_tree = Seconds(start);
      });
}

struct MeasureReference::Impl {
  const Surface* surface = nullptr;
  DomainRule rule;
  Prepared prepared;
  std::vector<int32_t> order;
};

struct PreparedPair {
  Prepared a, b;
  std::vector<int32_t> order_a, order_b;  // sorted index k holds input index order[k]
};

// Both surfaces prepared (PrepareSide), on two threads when parallel; A
// copied from `given` if it was prepared before (MeasureReference).

template <typename Progress>
void PreparePair(const Surface& a, const Surface& b, const MeasureOptions& options, const Progress& progress,
                 const MeasureReference::Impl* given, PreparedPair* pair, MeasureSummary* summary) {
  const double no_shift[3] = {0.0, 0.0, 0.0};
  const double shift[3] = {b.origin[0] - a.origin[0], b.origin[1] - a.origin[1], b.origin[2] - a.origin[2]};
  const auto quiet = [](const char*, double) {};
  const Execution execution = ExecutionFor(options.threads);
  if (given != nullptr) {
    pair->a = given->prepared;
    pair->order_a = given->order;
    PrepareSide(b, shift, options.domain, progress, execution, &summary->timings, &pair->b, &pair->order_b);
  } else {
    RunBoth(execution,
            [&] {
              PrepareSide(b, shift, options.domain, progress, execution, &summary->timings, &pair->b,
                          &pair->order_b);
            },
            [&] { PrepareSide(a, no_shift, options.domain, quiet, execution, nullptr, &pair->a, &pair->order_a); });
  }
  summary->n_duplicates_a = pair->a.mesh.num_duplicates;
  summary->n_duplicates_b = pair->b.mesh.num_duplicates;
  if (!options.allow_empty_overlap) {
    DomainRule rule_a = options.domain, rule_b = options.domain;
    rule_a.grid = a.raster_grid();
    rule_b.grid = b.raster_grid();
    CheckDomain(a, pair->a.domain.area, rule_a, "surface A");
    CheckDomain(b, pair->b.domain.area, rule_b, "surface B");
  }
}

// Ω's nodes (a corner of its own domain lying in the other's closed
// domain) and every located node's gap; ρ'd over Ω's distinct nodes.
// Interpolated in a canonical corner order, so that a node's gap is the same
// double in any window's mesh (tiled_measure.h).
struct NodeStage {
  NodeGaps gaps;
  std::vector<uint8_t> omega_a, omega_b;
  std::vector<uint8_t> counted_b;  // B's nodes ρ'd counts (for dz_b), with keep_node_gaps
};

NodeStage GapsAtNodes(const Prepared& pa, const Prepared& pb, const std::vector<Location>& a_in_b,
                      const std::vector<Location>& b_in_a, const WeightField& mu, bool keep_node_gaps,
                      const Execution& execution, MeasureSummary* out) {
  MeasureSummary& summary = *out;
  NodeStage stage_out;
  NodeGaps& gaps = stage_out.gaps;
  std::vector<uint8_t>& omega_a = stage_out.omega_a;
  std::vector<uint8_t>& omega_b = stage_out.omega_b;
  std::vector<uint8_t>& counted_b = stage_out.counted_b;
  gaps.a.assign(pa.xy.size(), 0.0);
  gaps.b.assign(pb.xy.size(), 0.0);
  // A node is in Ω when it is a corner of its own domain and lies in the
  // other's (closed) domain.
  omega_a.assign(pa.xy.size(), 0);
  omega_b.assign(pb.xy.size(), 0);
  // Ω and the gaps node by node in chunks; the sums below in node order
  // (the same bits on any thread count).
  const auto each_node = [&](std::size_t n, const auto& body) {
    const int64_t count = static_cast<int64_t>(n);
    ForEachChunk(execution, count, ChunksFor(count, 8192), [&](int, int64_t first, int64_t last) {
      for (int64_t k = first; k < last; ++k) body(static_cast<std::size_t>(k));
    });
  };
  each_node(pa.xy.size(), [&](std::size_t i) {
    if (!a_in_b[i].found()) return;
    omega_a[i] = pa.domain.vertices[pa.mesh.vertex_of_input[i]] && pb.domain.Contains(pb.mesh, a_in_b[i]);
    gaps.a[i] = InterpolateCanonical(pb.xy, pb.mesh, pb.z, a_in_b[i], pa.xy[i]) - pa.z[i];
  });
  each_node(pb.xy.size(), [&](std::size_t j) {
    if (!b_in_a[j].found()) return;
    omega_b[j] = pb.domain.vertices[pb.mesh.vertex_of_input[j]] && pa.domain.Contains(pa.mesh, b_in_a[j]);
    gaps.b[j] = pb.z[j] - InterpolateCanonical(pa.xy, pa.mesh, pa.z, b_in_a[j], pb.xy[j]);
  });
  double gap_sum = 0.0, node_weight = 0.0;
  if (keep_node_gaps) counted_b.assign(pb.xy.size(), 0);
  for (std::size_t i = 0; i < pa.xy.size(); ++i) {
    if (!a_in_b[i].found()) continue;
    if (!omega_a[i] || pa.mesh.vertex_of_input[i] != static_cast<int32_t>(i)) continue;
    const double w = mu.AtNodeA(i);
    gap_sum += w * std::fabs(gaps.a[i]);
    node_weight += w;
    ++summary.n_overlap_nodes;
  }
  for (std::size_t j = 0; j < pb.xy.size(); ++j) {
    if (!b_in_a[j].found()) continue;
    if (!omega_b[j] || pb.mesh.vertex_of_input[j] != static_cast<int32_t>(j)) continue;
    if (b_in_a[j].where == Where::kOnVertex) continue;  // the same node of G1 ∪ G2 as A's
    if (!counted_b.empty()) counted_b[j] = 1;
    const double w = mu.AtNodeB(j);
    gap_sum += w * std::fabs(gaps.b[j]);
    node_weight += w;
    ++summary.n_overlap_nodes;
  }
  summary.rho_d_axial = node_weight > 0.0 ? gap_sum / node_weight : 0.0;

  return stage_out;
}

// Refuses an empty or sliver overlap (unless allowed), naming both surfaces.
void CheckOverlap(const Surface& a, const Surface& b, double domain_area_a, double domain_area_b,
                  const VolumeResult& volume, const MeasureOptions& options) {
  // The domains' areas: the hulls' with DomainKind::kHull.
  const double smaller = std::min(domain_area_a, domain_area_b);
  const char* what = options.domain.kind == DomainKind::kHull ? "hull" : "data domain";
  if (!options.allow_empty_overlap &&
      (!(volume.area > options.min_overlap_fraction * smaller) || volume.cells == 0)) {
    char numbers[160];
    std::snprintf(numbers, sizeof numbers,
                  " (overlap area %.3g, %.3g%% of the smaller %s; the minimum is %.3g%%)",
                  volume.area, smaller > 0.0 ? 100.0 * volume.area / smaller : 0.0, what,
                  100.0 * options.min_overlap_fraction);
    throw InputError((a.source.empty() ? std::string("surface A") : a.source) + " and " +
                     (b.source.empty() ? std::string("surface B") : b.source) +
                     (volume.area > 0.0 ? " overlap only in a sliver" : " do not overlap") +
                     numbers);
  }
}

// dz and node areas at A's samples, dz at B's counted ones, in input order.
void KeepNodeGaps(const PreparedPair& pair, const NodeStage& nodes, MeasureSummary* out) {
  MeasureSummary& summary = *out;
  const Prepared& pa = pair.a;
  const Prepared& pb = pair.b;
  const std::vector<int32_t>& order_a = pair.order_a;
  const std::vector<int32_t>& order_b = pair.order_b;
  const std::vector<uint8_t>& omega_a = nodes.omega_a;
  const std::vector<uint8_t>& counted_b = nodes.counted_b;
  const NodeGaps& gaps = nodes.gaps;
  summary.dz_a.assign(pa.xy.size(), std::nan(""));
  for (std::size_t k = 0; k < pa.xy.size(); ++k) {
    if (omega_a[k]) summary.dz_a[order_a[k]] = gaps.a[k];
  }
  // Mesh corners are sorted indices (duplicates point at the kept one).
  std::vector<double> area(pa.xy.size(), 0.0);
  for (int32_t t = 0; t < pa.mesh.num_triangles(); ++t) {
    if (!pa.domain.whole && !pa.domain.triangles[t]) continue;
    const int32_t* v = &pa.mesh.triangles[3 * t];
    if (!omega_a[v[0]] || !omega_a[v[1]] || !omega_a[v[2]]) continue;
    const double third = Orient2D(pa.xy[v[0]], pa.xy[v[1]], pa.xy[v[2]]) / 6.0;
    for (int i = 0; i < 3; ++i) area[v[i]] += third;
  }
  summary.node_area_a.assign(pa.xy.size(), 0.0);
  for (std::size_t k = 0; k < pa.xy.size(); ++k) summary.node_area_a[order_a[k]] = area[k];
  summary.dz_b.assign(pb.xy.size(), std::nan(""));
  for (std::size_t k = 0; k < pb.xy.size(); ++k) {
    if (counted_b[k]) summary.dz_b[order_b[k]] = gaps.b[k];
  }
}

// The summary's volumes, areas and change from the volume stage.
// Hull and domain areas first.
void SetVolumeFields(const VolumeResult& volume, const std::array<double, 4>& areas,
                     const MeasureOptions& options, MeasureSummary* out) {
  MeasureSummary& summary = *out;
  summary.rho_d = volume.gap.abs;
  summary.overlap_area = volume.area;
  summary.hull_area_a = areas[0];
  summary.hull_area_b = areas[1];
  summary.domain_kind = options.domain.kind;
  summary.domain_area_a = areas[2];
  summary.domain_area_b = areas[3];
  summary.excluded_area_a = areas[0] - areas[2];
  summary.excluded_area_b = areas[1] - areas[3];
  summary.weight_integral = volume.gap.weight;
  summary.signed_volume = volume.gap.signed_volume;
  summary.volume_above = volume.gap.above;
  summary.volume_below = volume.gap.below;
  summary.mean_abs_dz = volume.gap.weight > 0.0 ? volume.gap.abs / volume.gap.weight : 0.0;
  summary.rho_s = summary.rho_d > 0.0 ? 1.0 / summary.rho_d : 1.0;
  summary.n_cells = volume.cells;
  summary.level_of_detection = options.level_of_detection;
  summary.fill_detected = volume.change.fill;
  summary.cut_detected = volume.change.cut;
  summary.fill_area = volume.change.fill_area;
  summary.cut_area = volume.change.cut_area;
}

MeasureReference::MeasureReference(const Surface& a, const MeasureOptions& options) : impl_(new Impl) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("measure options: " + error);
  ValidateSurface(a);
  impl_->surface = &a;
  impl_->rule = options.domain;
  const double no_shift[3] = {0.0, 0.0, 0.0};
  PrepareSide(a, no_shift, options.domain, [](const char*, double) {}, ExecutionFor(options.threads), nullptr,
              &impl_->prepared, &impl_->order);
  DomainRule rule = options.domain;
  rule.grid = a.raster_grid();
  if (!options.allow_empty_overlap) CheckDomain(a, impl_->prepared.domain.area, rule, "surface A");
}

MeasureReference::~MeasureReference() = default;

const Surface& MeasureReference::surface() const { return *impl_->surface; }

PreparedSurface MeasureReference::prepared() const {
  const Prepared& p = impl_->prepared;
  PreparedSurface out;
  out.xy = &p.xy;
  out.z = &p.z;
  out.weight = &p.weight;
  out.order = &impl_->order;
  out.mesh = &p.mesh;
  out.tree = &p.tree;
  out.domain = &p.domain;
  out.hull_area = p.hull_area;
  return out;
}

namespace {

// Two rasters on one grid, by their cells (grid_pair.h); false for the
// general path.
template <typename Progress>
bool MeasureGrids(const Surface& a, const Surface& b, const MeasureOptions& options,
                  const Progress& progress, MeasureSummary* out) {
  const Clock::time_point stage = Clock::now();
  GridPairResult grid;
  if (!MeasureOnSameGrid(a, b, options, &grid) && !MeasureOnOffsetGrids(a, b, options, &grid) &&
      !MeasureOnMovedGrid(a, b, options, &grid)) {
    return false;
  }
  progress("volume (one grid)", 0.6);
  MeasureSummary& summary = *out;
  if (!options.allow_empty_overlap) {
    DomainRule rule = options.domain;
    rule.grid = true;
    CheckDomain(a, grid.domain_area_a, rule, "surface A");
    CheckDomain(b, grid.domain_area_b, rule, "surface B");
  }
  CheckOverlap(a, b, grid.domain_area_a, grid.domain_area_b, grid.volume, options);
  SetVolumeFields(grid.volume, {grid.hull_area_a, grid.hull_area_b, grid.domain_area_a, grid.domain_area_b},
                  options, &summary);
  summary.rho_d_axial = grid.rho_d_axial;
  summary.n_overlap_nodes = grid.n_overlap_nodes;
  if (options.keep_node_gaps) {
    summary.dz_a = std::move(grid.dz_a);
    summary.node_area_a = std::move(grid.node_area_a);
    if (grid.dz_b.empty()) {
      summary.dz_b.assign(b.size(), std::nan(""));  // every node of B in Ω is one of A's
    } else {
      summary.dz_b = std::move(grid.dz_b);
    }
  }
  summary.timings.volume = Seconds(stage);
  return true;
}

bool SameRule(const DomainRule& x, const DomainRule& y) {
  return x.kind == y.kind && x.max_edge_spacings == y.max_edge_spacings &&
         x.min_boundary_thinness == y.min_boundary_thinness && x.grid == y.grid;
}

MeasureSummary MeasureWith(const Surface& a, const Surface& b, const MeasureOptions& options,
                           const MeasureReference::Impl* given) {
  const Clock::time_point start = Clock::now();
  std::string error;
  if (!options.IsValid(&error)) throw InputError("measure options: " + error);
  if (given == nullptr) ValidateSurface(a, ExecutionFor(options.threads));
  ValidateSurface(b, ExecutionFor(options.threads));
  if (options.weight == WeightMode::kPerPoint && a.weight.empty() && b.weight.empty()) {
    throw InputError("per-point weights requested, but neither surface has weights");
  }
  // Stage shares of a typical long run's time (two 1e6-point clouds, 2
  // threads): sorting 5%, triangulating 22%, domains 18%, trees 12%,
  // locating 5%, the volume (overlay) the other 40%.
  const int64_t points = static_cast<int64_t>(a.size() + b.size());
  const auto progress = [&options, start, points](const char* stage, double done) {
    if (options.on_progress) options.on_progress({stage, done, Seconds(start), points});
  };
  MeasureSummary summary;
  summary.volume_mode = options.volume;
  summary.n_points_a = static_cast<int64_t>(a.size());
  summary.n_points_b = static_cast<int64_t>(b.size());

  if (MeasureGrids(a, b, options, progress, &summary)) {
    summary.timings.total = Seconds(start);
    return summary;
  }
  PreparedPair pair;
  PreparePair(a, b, options, progress, given, &pair, &summary);
  const Prepared& pa = pair.a;
  const Prepared& pb = pair.b;
  const Execution execution = ExecutionFor(options.threads);

  progress("locating each cloud in the other", 0.57);
  Clock::time_point stage = Clock::now();
  LocateAllStats stats_a, stats_b;
  std::vector<Location> a_in_b, b_in_a;
  RunBoth(execution, [&] { a_in_b = LocateAll(pb.xy, pb.mesh, pa.xy, pa.mesh, pa.tree, &stats_a, execution); },
          [&] { b_in_a = LocateAll(pa.xy, pa.mesh, pb.xy, pb.mesh, pb.tree, &stats_b, execution); });
  summary.walk_steps = stats_a.steps + stats_b.steps;
  summary.timings.locate = Seconds(stage);

  // Weight field μ, then the gap at every node inside Ω: ρ'd.
  stage = Clock::now();
  const WeightField mu = MakeWeightField(options, a, pa.xy, pa.mesh, pa.weight, pb.xy, pb.mesh,
                                         pb.weight, a_in_b, b_in_a);
  const NodeStage nodes = GapsAtNodes(pa, pb, a_in_b, b_in_a, mu, options.keep_node_gaps, execution, &summary);
  const NodeGaps& gaps = nodes.gaps;
  const std::vector<uint8_t>& omega_a = nodes.omega_a;
  const std::vector<uint8_t>& omega_b = nodes.omega_b;
  summary.timings.interpolate = Seconds(stage);

  progress("volume", 0.60);
  stage = Clock::now();
  VolumeResult volume;
  const OmegaDomains omega{&pa.domain, &pb.domain, &omega_a, &omega_b};
  if (options.volume == VolumeMode::kOverlay) {
    volume = OverlayVolume(pa.xy, pa.mesh, pa.z, a_in_b, pb.xy, pb.mesh, pb.z, b_in_a, mu, execution,
                           options.detect_change ? options.level_of_detection : -1.0, omega);
  } else {
    volume = UnionVolume(pa.xy, pa.mesh, a_in_b, gaps.a, pb.xy, pb.mesh, b_in_a, gaps.b, mu, omega);
  }
  summary.timings.volume = Seconds(stage);

  CheckOverlap(a, b, pa.domain.area, pb.domain.area, volume, options);
  SetVolumeFields(volume, {pa.hull_area, pb.hull_area, pa.domain.area, pb.domain.area}, options, &summary);
  if (options.keep_node_gaps) KeepNodeGaps(pair, nodes, &summary);
  summary.timings.total = Seconds(start);
  return summary;
}

}  // namespace

MeasureSummary Measure(const Surface& a, const Surface& b, const MeasureOptions& options) {
  return MeasureWith(a, b, options, nullptr);
}

MeasureSummary Measure(const MeasureReference& a, const Surface& b, const MeasureOptions& options) {
  if (!SameRule(a.impl().rule, options.domain)) {
    throw std::invalid_argument("Measure: the reference was prepared for another domain rule");
  }
  return MeasureWith(a.surface(), b, options, &a.impl());
}

std::string MeasureSummary::BriefReport(const std::string& units) const {
  const char* u = units.c_str();
  char text[1600];
  std::snprintf(
      text, sizeof text,
      "rho_d (volume between)   %.9g %s^3\n"
      "rho'_d (mean node gap)   %.9g %s\n"
      "rho_s (1 / rho_d)        %.9g\n"
      "overlap area             %.9g %s^2\n"
      "%-24s %.9g / %.9g %s^2 (excluded from the hulls %.9g / %.9g)\n"
      "mean |dz|                %.9g %s\n"
      "signed volume (B - A)    %.9g %s^3\n"
      "B above A (fill)         %.9g %s^3\n"
      "B below A (cut)          %.9g %s^3\n"
      "points A / B             %lld / %lld (duplicates merged %lld / %lld)\n"
      "overlap nodes            %lld\n"
      "%s cells            %lld\n"
      "time (s)                 triangulate %.3f, domain %.3f, tree %.3f, locate %.3f, "
      "interpolate %.3f, volume %.3f, total %.3f\n",
      rho_d, u, rho_d_axial, u, rho_s, overlap_area, u,
      domain_kind == DomainKind::kHull ? "hull areas A / B" : "data domain areas A / B",
      domain_area_a, domain_area_b, u, excluded_area_a, excluded_area_b, mean_abs_dz, u,
      signed_volume, u, volume_above, u, volume_below, u, static_cast<long long>(n_points_a),
      static_cast<long long>(n_points_b),
      static_cast<long long>(n_duplicates_a), static_cast<long long>(n_duplicates_b),
      static_cast<long long>(n_overlap_nodes), VolumeModeName(volume_mode),
      static_cast<long long>(n_cells), timings.triangulate, timings.domain, timings.spanning_tree,
      timings.locate,
      timings.interpolate, timings.volume, timings.total);
  return text;
}

}  // namespace surfreg
