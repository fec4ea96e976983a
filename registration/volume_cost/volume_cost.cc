#include "registration/volume_cost/volume_cost.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "measure/bucket_scatter.h"
#include "measure/gap_volume.h"
#include "measure/overlay.h"
#include "measure/volume.h"
#include "measure/weights.h"
#include "registration/volume_cost/volume_cost_cache.h"

namespace surfreg {

VolumeCostValue EvaluateVolumeCost(const PairState& state, bool gradient, const Execution& execution,
                                   const MaskRegion* mask) {
  std::vector<VolumeAccumulator> parts(StateChunks(state), VolumeAccumulator(state, gradient, mask));
  ForEachCellOfState(state, execution, parts);
  VolumeCostValue total = parts[0].value;
  for (std::size_t c = 1; c < parts.size(); ++c) {
    const VolumeCostValue& v = parts[c].value;
    total.abs += v.abs;
    total.area += v.area;
    total.d_abs += v.d_abs;
    total.d_area += v.d_area;
    total.cells += v.cells;
  }
  return total;
}

// ------------------------------------------------------------ incremental

using volume_internal::GradientOf;
using volume_internal::Pack;
using volume_internal::PackedLocation;
using volume_internal::PartBins;
using volume_internal::Vector6;


void VolumeCostCache::Impl::Bind(const PairState& s) {
  state = &s;
  reference = &s.reference();
  moving = &s.moving();
  const Triangulation& mesh = reference->mesh;
  const int32_t nt = mesh.num_triangles();
  star_begin.assign(reference->xy.size() + 1, 0);
  for (int32_t v : mesh.triangles) ++star_begin[v + 1];
  for (std::size_t v = 0; v + 1 < star_begin.size(); ++v) star_begin[v + 1] += star_begin[v];
  star.resize(mesh.triangles.size());
  std::vector<int32_t> fill(star_begin.begin(), star_begin.end() - 1);
  for (int32_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) star[fill[mesh.triangles[3 * t + k]]++] = t;
  }
  // Each A triangle's corners and ∇F_A, read by both cell kernels.
  record_a.resize(nt);
  extra_a.resize(nt);
  ForEachChunk(s.execution(), nt, ChunksFor(nt, 4096), [&](int, int64_t first, int64_t last) {
    const auto& xy = reference->xy;
    const auto& z = reference->z;
    for (int64_t t = first; t < last; ++t) {
      const int32_t* v = &mesh.triangles[3 * t];
      const Gradient2 g = GradientOf(xy[v[0]], xy[v[1]], xy[v[2]], z[v[0]], z[v[1]], z[v[2]]);
      volume_internal::MakeRecord(xy.data(), z.data(), v, g.gx, g.gy, false, &record_a[t], &extra_a[t]);
    }
  });
  BindWeights();
  built = false;
}

// μ's plane on each A triangle (both kernels read them): the weights are
// fixed with the reference; empty without weights.
void VolumeCostCache::Impl::BindWeights() {
  weight_a.clear();
  if (reference->weight.empty()) return;
  const Triangulation& mesh = reference->mesh;
  const auto& w = reference->weight;
  const auto& xy = reference->xy;
  const int32_t nt = mesh.num_triangles();
  weight_a.resize(nt);
  ForEachChunk(state->execution(), nt, ChunksFor(nt, 4096), [&](int, int64_t first, int64_t last) {
    for (int64_t t = first; t < last; ++t) {
      const int32_t* v = &mesh.triangles[3 * t];
      const Plane mu = PlaneThrough(xy[v[0]], xy[v[1]], xy[v[2]], w[v[0]], w[v[1]], w[v[2]]);
      weight_a[t] = {mu.z0, mu.gx, mu.gy};
    }
  });
}

// The A triangles whose cells may have changed since the last evaluation:
// around every vertex whose location in the other mesh changed (a vertex
// crossing an edge of the other mesh is the only event that changes which
// pairs meet and which edges cross). A B vertex moves straight in A's fixed
// frame: the triangles it left and entered (with the edge or vertex it was
// on), and, if those are not neighbours, everything around both.
void VolumeCostCache::Impl::MarkDirty(const PairState& s, const Execution& execution) {
  const Triangulation& mesh_a = reference->mesh;
  mark.assign(mesh_a.num_triangles(), 0);
  seeds.clear();
  auto mark_star = [&](int32_t v) {
    for (int32_t k = star_begin[v]; k < star_begin[v + 1]; ++k) mark[star[k]] = 1;
  };
  // The vertices whose location changed, found by chunks (most did not),
  // in order; then marked around, one after another.
  const auto changed = [&](int64_t n, const auto& moved, std::vector<int32_t>* out) {
    BucketSlots slots(ChunksFor(n, kItemChunk), 1);
    const auto bucket = [&](int64_t v) { return moved(v) ? 0 : -1; };
    CountIntoBuckets(execution, n, slots, bucket);
    out->resize(static_cast<std::size_t>(slots.start[1]));
    ScatterIntoBuckets(execution, n, slots, bucket,
                       [out](int64_t v, int64_t at) { (*out)[at] = static_cast<int32_t>(v); });
  };
  const auto& a_in_b = s.a_in_b();
  changed(static_cast<int64_t>(a_in_b.size()), [&](int64_t v) {
    const PackedLocation now = Pack(a_in_b[v]);
    return now != last_a[v] && (now.where != Where::kOutside || last_a[v].where != Where::kOutside);
  }, &changed_a);
  for (int32_t v : changed_a) mark_star(v);
  const auto& b_in_a = s.b_in_a();
  auto mark_location = [&](const PackedLocation& l) {
    if (l.triangle < 0) return;
    mark[l.triangle] = 1;
    if (l.where == Where::kOnEdge) {
      const int32_t next = mesh_a.neighbors[3 * l.triangle + l.index];
      if (next >= 0) mark[next] = 1;
    } else if (l.where == Where::kOnVertex) {
      mark_star(mesh_a.triangles[3 * l.triangle + l.index]);
    }
  };
  // Outside A's hull before and after: where the walk left the mesh
  // changes, the overlay does not.
  changed(static_cast<int64_t>(b_in_a.size()), [&](int64_t u) {
    const PackedLocation now = Pack(b_in_a[u]);
    const PackedLocation before = last_b[u];
    return now != before && !(now.where == Where::kOutside && before.where == Where::kOutside);
  }, &changed_b);
  for (int32_t u : changed_b) {
    const PackedLocation now = Pack(b_in_a[u]);
    const PackedLocation before = last_b[u];
    mark_location(before);
    mark_location(now);
    if (now.triangle >= 0 && before.triangle >= 0 && now.triangle != before.triangle) {
      bool adjacent = false;
      for (int i = 0; i < 3; ++i) adjacent |= mesh_a.neighbors[3 * before.triangle + i] == now.triangle;
      if (!adjacent) {
        for (int k = 0; k < 3; ++k) {
          mark_star(mesh_a.triangles[3 * before.triangle + k]);
          mark_star(mesh_a.triangles[3 * now.triangle + k]);
        }
      }
    }
    const int32_t tb = s.moving_mesh().vertex_triangle[u];
    if (b_in_a[u].found() && tb >= 0) seeds.push_back({now.triangle, tb});
  }
  dirty.clear();
  for (int32_t t = 0; t < mesh_a.num_triangles(); ++t) {
    if (mark[t]) dirty.push_back(t);
  }
  std::sort(seeds.begin(), seeds.end());
}


VolumeCostCache::VolumeCostCache(double max_dirty_fraction, CellKernelChoice kernel)
    : impl_(std::make_unique<Impl>()) {
  impl_->max_dirty_fraction = max_dirty_fraction;
  impl_->cell_kernel = volume_internal::ResolveCellKernel(kernel);
}
VolumeCostCache::~VolumeCostCache() = default;
void VolumeCostCache::Reset() { impl_->built = false; }
const VolumeCostCacheStats& VolumeCostCache::stats() const { return impl_->stats; }

namespace {

// The integration's chunks of A's triangles (bounds from their count only:
// the same sums on any number of threads).
int IntegrationChunks(int32_t num_a_triangles) { return ChunksFor(num_a_triangles, 4096); }

void AddInto(const VolumeCostValue& v, VolumeCostValue* total) {
  total->abs += v.abs;
  total->area += v.area;
  total->d_abs += v.d_abs;
  total->d_area += v.d_area;
  total->cells += v.cells;
}

}  // namespace

int GradientBins::Index(double x, double y) const {
  const int i = std::clamp(static_cast<int>(std::floor((x - x0) / side)), 0, n - 1);
  const int j = std::clamp(static_cast<int>(std::floor((y - y0) / side)), 0, n - 1);
  return j * n + i;
}

// Brings the overlay's topology to the state's pose: built whole (first
// call, a remesh, far from the last pose twice), repaired around what moved;
// false: far from the topology's pose, which is kept for the plain full path.
bool VolumeCostCache::Impl::UpdateTopology(const PairState& s, const Execution& execution) {
  const Triangulation& mesh_a = reference->mesh;
  const Triangulation& mesh_b = s.moving_mesh();
  bool build = !built || remeshes != s.surface_version();
  if (!build) {
    MarkDirty(s, execution);
    build = dirty.size() > max_dirty_fraction * mesh_a.num_triangles();
    if (build && !binning && (!fell_back || s.theta() == fallback_theta)) {
      // Far from the topology's pose: Build + labelling would cost more
      // than the plain full path, and a solver often comes back (a
      // rejected trial step), so keep the topology and its pose and
      // evaluate plainly. Too far at another pose right after: the solver
      // has moved on; build.
      fell_back = true;
      fallback_theta = s.theta();
      return false;
    }
  }
  fell_back = false;
  if (build) {
    topology.Build(reference->xy, mesh_a, s.a_in_b(), s.moved_xy(), mesh_b, s.b_in_a(), execution,
                   reference->domain.data(), s.active_b().data());
    built = true;
    remeshes = s.surface_version();
    ++stats.full_builds;
  } else if (!dirty.empty()) {
    const TopologyStats t = topology.Repair(reference->xy, mesh_a, s.a_in_b(), s.moved_xy(), mesh_b, dirty,
                                            seeds, execution, reference->domain.data(), s.active_b().data());
    stats.triangles_searched += t.triangles_searched;
  }
  const auto pack_all = [&](const auto& locations, std::vector<PackedLocation>* packed) {
    const int64_t n = static_cast<int64_t>(locations.size());
    packed->resize(locations.size());
    ForEachChunk(execution, n, ChunksFor(n, kItemChunk), [&](int, int64_t begin, int64_t end) {
      for (int64_t k = begin; k < end; ++k) (*packed)[k] = Pack(locations[k]);
    });
  };
  pack_all(s.a_in_b(), &last_a);
  pack_all(s.b_in_a(), &last_b);
  return true;
}

// ∇F̂_B' and the hull bit on each moved B triangle (and its bin); with
// bins, `chunks` chunks' shares of them.
void VolumeCostCache::Impl::RecordMovedTriangles(const PairState& s, const Execution& execution, int chunks,
                                                 const GradientBins* bins) {
  const Triangulation& mesh_b = s.moving_mesh();
  const int32_t nb = mesh_b.num_triangles();
  record_b.resize(nb);
  extra_b.resize(nb);
  if (binning) {
    bin_of_b.resize(nb);
    part_bins.resize(static_cast<std::size_t>(chunks));
    for (PartBins& part : part_bins) part.Reset(bins->n * bins->n);
  }
  const auto& xy = s.moved_xy();
  const auto& z = s.moved_z();
  // Each triangle's record on its own: any chunks.
  ForEachChunk(execution, nb, ChunksFor(nb, kItemChunk), [&](int, int64_t lo, int64_t hi) {
    for (int32_t t = static_cast<int32_t>(lo); t < hi; ++t) {
      const int32_t* v = &mesh_b.triangles[3 * t];
      const Gradient2 g = GradientOf(xy[v[0]], xy[v[1]], xy[v[2]], z[v[0]], z[v[1]], z[v[2]]);
      // An edge of B's surface: the boundary term's cells (the moving part of ∂Ω).
      const bool hull = s.MovingBoundaryEdge(t, 0) || s.MovingBoundaryEdge(t, 1) ||
                        s.MovingBoundaryEdge(t, 2);
      volume_internal::MakeRecord(xy.data(), z.data(), v, g.gx, g.gy, hull, &record_b[t], &extra_b[t]);
      if (binning) {
        bin_of_b[t] = bins->Index((xy[v[0]].x + xy[v[1]].x + xy[v[2]].x) / 3,
                                  (xy[v[0]].y + xy[v[1]].y + xy[v[2]].y) / 3);
      }
    }
  });
}

// Each chunk's bins into `bins`: the boundary term's shares, and the
// interior sums under the motion's −Mᵀ (rows as VolumeAccumulator::AddPart).
void VolumeCostCache::Impl::MergeBins(const Eigen::Matrix3d& mt, GradientBins* bins) const {
  for (const PartBins& part : part_bins) {
    for (std::size_t b = 0; b < part.used.size(); ++b) {
      if (!part.used[b]) continue;
      const double* sums = &part.interior[6 * b];
      Vector6 interior;
      interior << -mt * Eigen::Vector3d(sums[0], sums[1], sums[2]), sums[3], sums[4], sums[5];
      bins->d_abs[b] += part.d_abs[b] + interior;
      bins->d_area[b] += part.d_area[b];
      bins->used[b] = 1;
    }
  }
}

VolumeCostValue VolumeCostCache::Evaluate(const PairState& s, bool gradient, const Execution& execution,
                                          const MaskRegion* mask, GradientBins* bins) {
  Impl& m = *impl_;
  m.binning = bins != nullptr && gradient && mask == nullptr && bins->n > 0;
  if (bins != nullptr) {
    const int n = m.binning ? bins->n * bins->n : 0;
    bins->d_abs.assign(n, Vector6::Zero());
    bins->d_area.assign(n, Vector6::Zero());
    bins->used.assign(n, 0);
  }
  if (m.state != &s || m.reference != &s.reference() || m.moving != &s.moving()) m.Bind(s);
  const int32_t na = m.reference->mesh.num_triangles();
  ++m.stats.evaluations;
  m.stats.triangles += na;
  if (!m.UpdateTopology(s, execution)) {
    const VolumeCostValue plain = EvaluateVolumeCost(s, gradient, execution, mask);
    ++m.stats.fallbacks;
    m.stats.cells += plain.cells;
    return plain;
  }
  const int chunks = IntegrationChunks(na);
  m.chunk_values.resize(static_cast<std::size_t>(chunks));
  // Per chunk, then added in chunk order: the same on any number of threads.
  const auto sum_chunks = [&m, chunks](volume_internal::InteriorSums* interior) {
    VolumeCostValue total = m.chunk_values[0].value;
    for (int c = 1; c < chunks; ++c) AddInto(m.chunk_values[c].value, &total);
    if (interior == nullptr) return total;
    *interior = m.chunk_values[0].interior;
    for (int c = 1; c < chunks; ++c) {
      for (int k = 0; k < 3; ++k) {
        interior->rotation[k] += m.chunk_values[c].interior.rotation[k];
        interior->translation[k] += m.chunk_values[c].interior.translation[k];
      }
    }
    return total;
  };
  if (mask != nullptr) {
    ForEachChunk(execution, na, chunks, [&](int part, int64_t lo, int64_t hi) {
      m.Generic(s, gradient, mask, static_cast<int32_t>(lo), static_cast<int32_t>(hi), &m.chunk_values[part].value);
    });
    const VolumeCostValue total = sum_chunks(nullptr);
    m.stats.cells += total.cells;
    return total;
  }
  const bool weighted = !m.reference->weight.empty();
  const CellKernel kernel = m.cell_kernel;  // a vector kernel where the CPU has one (weighted or not)
  // Weights added or dropped since Bind: their planes again.
  if (m.weight_a.size() != (weighted ? static_cast<std::size_t>(na) : 0u)) m.BindWeights();
  m.RecordMovedTriangles(s, execution, chunks, bins);
  const Eigen::Vector3d offset = s.motion_offset();  // T(p) = q + offset
  ForEachChunk(execution, na, chunks, [&](int part, int64_t begin, int64_t end) {
    const int32_t lo = static_cast<int32_t>(begin), hi = static_cast<int32_t>(end);
    ChunkValue* out = &m.chunk_values[part];
    if (kernel != CellKernel::kScalar) {
      m.IntegrateSimd(kernel, s, gradient, offset, lo, hi, part, out);
    } else if (weighted) {
      m.Integrate<true>(s, gradient, offset, lo, hi, part, out);
    } else {
      m.Integrate<false>(s, gradient, offset, lo, hi, part, out);
    }
  });
  volume_internal::InteriorSums interior;
  VolumeCostValue total = sum_chunks(gradient ? &interior : nullptr);
  m.stats.cells += total.cells;
  if (gradient) {
    // ∂/∂θ of the interior: −Mᵀ (n × Σ s∫μq) for the rotation, Σ s∫μ n for the translation.
    const Eigen::Matrix3d mt = s.derivative().m.transpose();
    total.d_abs.head<3>() -= mt * Eigen::Vector3d(interior.rotation[0], interior.rotation[1], interior.rotation[2]);
    total.d_abs.tail<3>() += Eigen::Vector3d(interior.translation[0], interior.translation[1], interior.translation[2]);
    if (m.binning) m.MergeBins(mt, bins);
  }
  return total;
}

}  // namespace surfreg
