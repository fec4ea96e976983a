#include "registration/volume_cost.h"

#include <algorithm>
#include <cmath>
#include <thread>
#include <utility>

#include <Eigen/Geometry>

#include "measure/gap_volume.h"
#include "measure/overlay.h"
#include "measure/volume.h"
#include "measure/weights.h"
#include "registration/overlay_topology.h"
#include "registration/volume_accumulator.h"
#include "registration/volume_kernel_simd.h"

namespace surfreg {

using volume_internal::FanSums;
using volume_internal::SumFan;
using volume_internal::TwiceArea;
using volume_internal::VolumeAccumulator;
using volume_internal::CellKernel;
using volume_internal::ForEachCellOfState;
using volume_internal::Gradient2;
using volume_internal::Moment;
using volume_internal::TriangleExtra;
using volume_internal::TriangleRecord;

VolumeCostValue EvaluateVolumeCost(const PairState& state, bool gradient, bool parallel,
                                   const MaskRegion* mask) {
  VolumeAccumulator first(state, gradient, mask), second(state, gradient, mask);
  ForEachCellOfState(state, parallel, first, second);
  VolumeCostValue total = first.value;
  total.abs += second.value.abs;
  total.area += second.value.area;
  total.d_abs += second.value.d_abs;
  total.d_area += second.value.d_area;
  total.cells += second.value.cells;
  return total;
}

// ------------------------------------------------------------ incremental

namespace {

// A location as far as the overlay's combinatorics see it.
struct PackedLocation {
  int32_t triangle = -1;
  Where where = Where::kOutside;
  int8_t index = -1;
  bool operator!=(const PackedLocation& o) const {
    return triangle != o.triangle || where != o.where || index != o.index;
  }
};

inline PackedLocation Pack(const Location& l) { return {l.triangle, l.where, l.index}; }

// ∇ of the plane through three points (as PlaneThrough).
inline Gradient2 GradientOf(const Point2& p0, const Point2& p1, const Point2& p2, double z0,
                            double z1, double z2) {
  const Plane plane = PlaneThrough(p0, p1, p2, z0, z1, z2);
  return {plane.gx, plane.gy};
}

}  // namespace

struct VolumeCostCache::Impl {
  double max_dirty_fraction;
  VolumeCostCacheStats stats;
  // What the topology was built for.
  const PairState* state = nullptr;
  const ReferenceSide* reference = nullptr;
  const MovingSide* moving = nullptr;
  int remeshes = -1;
  bool built = false;
  bool fell_back = false;  // the previous evaluation took the plain full path
  std::array<double, 6> fallback_theta{};  // at this pose
  OverlayTopology topology;
  std::vector<PackedLocation> last_a, last_b;  // at the previous evaluation
  // A, fixed: the triangles around each vertex.
  std::vector<int32_t> star_begin, star;
  // Triangle records (volume_kernel_simd.h): A's fixed, B's per
  // evaluation; both kernels and the gradient read ∇F and the hull bit there.
  std::vector<TriangleRecord> record_a, record_b;
  std::vector<TriangleExtra> extra_a, extra_b;
  std::vector<volume_internal::WeightPlane> weight_a;  // μ per A triangle; empty: no weights
  std::vector<uint8_t> mark;
  std::vector<int32_t> dirty;
  std::vector<std::pair<int32_t, int32_t>> seeds;
  // Per thread and B triangle: Σ s|P| and Σ s|P|(c − p0) over the sign parts
  // P of its cells (s = sign of d on P, c its centroid, p0 T_B's corner 0):
  // all the gradient needs of the interior, as ∂_θF̂_B' is affine on T_B.
  std::vector<Moment> moments[2];

  void Bind(const PairState& s);
  void BindWeights();
  void MarkDirty(const PairState& s);
  template <bool kWeighted>
  void Integrate(const PairState& s, bool gradient, int32_t lo, int32_t hi, int part,
                 VolumeCostValue* out);
  void IntegrateSimd(CellKernel kernel, const PairState& s, bool gradient, int32_t lo, int32_t hi,
                     int part, VolumeCostValue* out);
  void Generic(const PairState& s, bool gradient, const MaskRegion* mask,
               int32_t lo, int32_t hi, VolumeCostValue* out);
};

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
  for (int32_t t = 0; t < nt; ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    const auto& xy = reference->xy;
    const auto& z = reference->z;
    const Gradient2 g = GradientOf(xy[v[0]], xy[v[1]], xy[v[2]], z[v[0]], z[v[1]], z[v[2]]);
    volume_internal::MakeRecord(xy.data(), z.data(), v, g.gx, g.gy, false, &record_a[t], &extra_a[t]);
  }
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
  weight_a.resize(mesh.num_triangles());
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    const Plane mu = PlaneThrough(xy[v[0]], xy[v[1]], xy[v[2]], w[v[0]], w[v[1]], w[v[2]]);
    weight_a[t] = {mu.z0, mu.gx, mu.gy};
  }
}

// The A triangles whose cells may have changed since the last evaluation:
// around every vertex whose location in the other mesh changed (a vertex
// crossing an edge of the other mesh is the only event that changes which
// pairs meet and which edges cross). A B vertex moves straight in A's fixed
// frame: the triangles it left and entered (with the edge or vertex it was
// on), and, if those are not neighbours, everything around both.
void VolumeCostCache::Impl::MarkDirty(const PairState& s) {
  const Triangulation& mesh_a = reference->mesh;
  mark.assign(mesh_a.num_triangles(), 0);
  seeds.clear();
  auto mark_star = [&](int32_t v) {
    for (int32_t k = star_begin[v]; k < star_begin[v + 1]; ++k) mark[star[k]] = 1;
  };
  const auto& a_in_b = s.a_in_b();
  for (std::size_t v = 0; v < a_in_b.size(); ++v) {
    const PackedLocation now = Pack(a_in_b[v]);
    if (now != last_a[v] && (now.where != Where::kOutside || last_a[v].where != Where::kOutside)) {
      mark_star(static_cast<int32_t>(v));
    }
  }
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
  for (std::size_t u = 0; u < b_in_a.size(); ++u) {
    const PackedLocation now = Pack(b_in_a[u]);
    const PackedLocation before = last_b[u];
    // Outside A's hull before and after: where the walk left the mesh
    // changes, the overlay does not.
    if (!(now != before) || (now.where == Where::kOutside && before.where == Where::kOutside)) continue;
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

// The unmasked cost over the cells of A's triangles [lo, hi): as
// VolumeAccumulator, but the interior gradient is left in `moments`.
// d = F̂_B' − F_A is linear on a cell, and so is μ (fixed with A's triangle);
// most cells lie on one side of d = 0, so that case takes one pass over the
// corners; only the cells d = 0 crosses are split into their two sign parts.
template <bool kWeighted>
void VolumeCostCache::Impl::Integrate(const PairState& s, bool gradient, int32_t lo, int32_t hi,
                                      int part, VolumeCostValue* out) {
  const Triangulation& mesh_a = reference->mesh;
  const Triangulation& mesh_b = s.moving_mesh();
  const auto& xa = reference->xy;
  const auto& za = reference->z;
  const auto& xb = s.moved_xy();
  const auto& zb = s.moved_z();
  const int32_t* triangles_b = mesh_b.triangles.data();
  const TriangleRecord* records_b = record_b.data();
  const TriangleExtra* extras_b = extra_b.data();
  Moment* moment = moments[part].data();
  VolumeAccumulator boundary(s, gradient, nullptr);
  OverlayCell cell;
  double abs = 0, area_sum = 0;
  int64_t cells = 0;
  // The endpoints of edge i (opposite corner i) in global index order, as
  // CellCorners orders them (so a crossing is the same point in every cell).
  static constexpr int kFirst[3] = {1, 2, 0}, kSecond[3] = {2, 0, 1};
  for (int32_t ta = lo; ta < hi; ++ta) {
    const int32_t count = topology.count_of(ta);
    if (count == 0) continue;
    const TopologyCell* list = topology.cells_of(ta);
    const int32_t* ia = &mesh_a.triangles[3 * ta];
    // Corners 0-2: T_A's, 3-5: T_B's (per cell).
    double cx6[6], cy6[6];
    for (int k = 0; k < 3; ++k) cx6[k] = xa[ia[k]].x, cy6[k] = xa[ia[k]].y;
    double e0x[3], e0y[3], ex[3], ey[3];
    for (int i = 0; i < 3; ++i) {
      int p0 = kFirst[i], p1 = kSecond[i];
      if (ia[p0] > ia[p1]) std::swap(p0, p1);
      e0x[i] = cx6[p0], e0y[i] = cy6[p0];
      ex[i] = cx6[p1] - cx6[p0], ey[i] = cy6[p1] - cy6[p0];
    }
    const Gradient2 ga = {record_a[ta].gx, record_a[ta].gy};
    const double za0 = za[ia[0]];
    // μ relative to T_A's corner 0 (Bind's plane).
    const volume_internal::WeightPlane mu = kWeighted ? weight_a[ta] : volume_internal::WeightPlane{};
    cells += count;
    for (int32_t c = 0; c < count; ++c) {
      const TopologyCell& tc = list[c];
      const int32_t tb = tc.triangle_b;
      const int32_t* ib = triangles_b + 3 * tb;
      for (int k = 0; k < 3; ++k) cx6[3 + k] = xb[ib[k]].x, cy6[3 + k] = xb[ib[k]].y;
      int q0[3], q1[3];
      for (int j = 0; j < 3; ++j) {
        const bool swap = ib[kFirst[j]] > ib[kSecond[j]];
        q0[j] = 3 + (swap ? kSecond[j] : kFirst[j]);
        q1[j] = 3 + (swap ? kFirst[j] : kSecond[j]);
      }
      const int n = tc.num_corners;
      const TriangleRecord& fb = records_b[tb];
      // Relative to T_B's corner 0: d = d0 + ∇d · (x, y), μ = μ0 + ∇μ · (x, y).
      const double bx = cx6[3], by = cy6[3];
      const double d0 = zb[ib[0]] - (za0 + ga.gx * (bx - cx6[0]) + ga.gy * (by - cy6[0]));
      const double dgx = fb.gx - ga.gx, dgy = fb.gy - ga.gy;
      const double mu0 = kWeighted ? mu.m0 + mu.gx * (bx - cx6[0]) + mu.gy * (by - cy6[0]) : 1.0;
      double x[8], y[8], d[8], m[8];
      double d_lo = 0, d_hi = 0;
      for (int k = 0; k < n; ++k) {
        // Every corner as if a crossing (cheap, no branch), then the vertex
        // corners picked instead: as CellCorners, without its switch.
        const uint8_t code = tc.corner[k];
        const int i = (code >> 2) & 3, j = (code >> 4) & 3, kind = code & 3;
        const int r = q0[j], w = q1[j];
        const double vr = ex[i] * (cy6[r] - e0y[i]) - ey[i] * (cx6[r] - e0x[i]);
        const double vs = ex[i] * (cy6[w] - e0y[i]) - ey[i] * (cx6[w] - e0x[i]);
        const double denominator = vr - vs;
        double t = denominator != 0.0 ? vr / denominator : 0.5;
        t = std::min(1.0, std::max(0.0, t));
        const int vertex = kind == kCornerB ? 3 + i : i;
        const bool cross = kind == kCornerCross;
        const double px = cross ? cx6[r] + t * (cx6[w] - cx6[r]) : cx6[vertex];
        const double py = cross ? cy6[r] + t * (cy6[w] - cy6[r]) : cy6[vertex];
        x[k] = px - bx;
        y[k] = py - by;
        d[k] = d0 + dgx * x[k] + dgy * y[k];
        if (kWeighted) m[k] = mu0 + mu.gx * x[k] + mu.gy * y[k];
        d_lo = k == 0 ? d[k] : std::min(d_lo, d[k]);
        d_hi = k == 0 ? d[k] : std::max(d_hi, d[k]);
      }
      auto add = [&](const FanSums& f, double sign) {
        abs += std::max(0.0, sign * f.wd);  // ∫_P μ|d|
        if (!gradient) return;
        Moment& m3 = moment[tb];
        m3.w += sign * f.w;
        m3.x += sign * f.wx;
        m3.y += sign * f.wy;
      };
      if (d_lo >= 0 || d_hi <= 0) {  // one sign part: the whole cell
        const FanSums f = SumFan<kWeighted>(x, y, d, m, n);
        area_sum += f.w;
        // d ≡ 0 adds nothing inside, but a hull cell still moves the boundary (below).
        if (f.twice > 0 && !(d_hi == 0 && d_lo == 0)) add(f, d_hi > 0 ? 1.0 : -1.0);
      } else {
        // The parts where d ≥ 0 and d ≤ 0.
        double pos_x[10], pos_y[10], pos_d[10], pos_m[10], neg_x[10], neg_y[10], neg_d[10], neg_m[10];
        int np = 0, nn = 0;
        for (int k = 0; k < n; ++k) {
          const int l = k + 1 == n ? 0 : k + 1;
          if (d[k] >= 0) {
            pos_x[np] = x[k], pos_y[np] = y[k], pos_d[np] = d[k];
            if (kWeighted) pos_m[np] = m[k];
            ++np;
          }
          if (d[k] <= 0) {
            neg_x[nn] = x[k], neg_y[nn] = y[k], neg_d[nn] = d[k];
            if (kWeighted) neg_m[nn] = m[k];
            ++nn;
          }
          if ((d[k] > 0 && d[l] < 0) || (d[k] < 0 && d[l] > 0)) {
            const double t = d[k] / (d[k] - d[l]);
            const double cx = x[k] + t * (x[l] - x[k]), cy = y[k] + t * (y[l] - y[k]);
            pos_x[np] = cx, pos_y[np] = cy, pos_d[np] = 0.0;
            neg_x[nn] = cx, neg_y[nn] = cy, neg_d[nn] = 0.0;
            if (kWeighted) pos_m[np] = neg_m[nn] = m[k] + t * (m[l] - m[k]);
            ++np, ++nn;
          }
        }
        if (np >= 3) {
          const FanSums f = SumFan<kWeighted>(pos_x, pos_y, pos_d, pos_m, np);
          area_sum += f.w;
          if (f.twice > 0) add(f, 1.0);
        }
        if (nn >= 3) {
          const FanSums f = SumFan<kWeighted>(neg_x, neg_y, neg_d, neg_m, nn);
          area_sum += f.w;
          if (f.twice > 0) add(f, -1.0);
        }
      }
      if (gradient && (extras_b[tb].bits & volume_internal::kHullBit) != 0) {
        cell.triangle_a = ta;
        cell.triangle_b = tb;
        cell.num_vertices = n;
        boundary.AddBoundaryOf(cell);
      }
    }
  }
  out->abs = abs;
  out->area = area_sum;
  out->cells = cells;
  out->d_abs = boundary.value.d_abs;
  out->d_area = boundary.value.d_area;
}

// As Integrate<kWeighted>, vectorized across cells by `kernel`
// (volume_kernel_simd.h); the hull cells' boundary term stays scalar.
void VolumeCostCache::Impl::IntegrateSimd(CellKernel kernel, const PairState& s, bool gradient,
                                          int32_t lo, int32_t hi, int part, VolumeCostValue* out) {
  VolumeAccumulator boundary(s, gradient, nullptr);
  volume_internal::CellKernelInput in;
  in.cells = topology.cells();
  in.cell_begin = topology.begins();
  in.cell_count = topology.counts();
  in.record_a = record_a.data(), in.extra_a = extra_a.data();
  in.weight_a = weight_a.empty() ? nullptr : weight_a.data();
  in.record_b = record_b.data(), in.extra_b = extra_b.data();
  in.context = &boundary;
  in.on_hull = [](void* context, int32_t ta, int32_t tb, int n) {
    OverlayCell cell;  // rare: a hull B triangle's cells only
    cell.triangle_a = ta;
    cell.triangle_b = tb;
    cell.num_vertices = n;
    static_cast<VolumeAccumulator*>(context)->AddBoundaryOf(cell);
  };
  volume_internal::CellKernelOutput result;
  volume_internal::IntegrateCellsSimd(kernel, in, lo, hi, gradient,
                                      gradient ? moments[part].data() : nullptr, &result);
  out->abs = result.abs;
  out->area = result.area;
  out->cells = result.cells;
  out->d_abs = boundary.value.d_abs;
  out->d_area = boundary.value.d_area;
}

// A mask: every cell through the full path's accumulator (which also takes weights).
void VolumeCostCache::Impl::Generic(const PairState& s, bool gradient,
                                    const MaskRegion* mask, int32_t lo,
                                    int32_t hi, VolumeCostValue* out) {
  const Triangulation& mesh_a = reference->mesh;
  const Triangulation& mesh_b = s.moving_mesh();
  const auto& xa = reference->xy;
  const auto& xb = s.moved_xy();
  VolumeAccumulator accumulate(s, gradient, mask);
  OverlayCell cell;
  Point2* p = cell.vertices.data();
  for (int32_t ta = lo; ta < hi; ++ta) {
    const int32_t* ia = &mesh_a.triangles[3 * ta];
    const Point2 a[3] = {xa[ia[0]], xa[ia[1]], xa[ia[2]]};
    for (int32_t c = 0; c < topology.count_of(ta); ++c) {
      const TopologyCell& tc = topology.cells_of(ta)[c];
      const int32_t* ib = &mesh_b.triangles[3 * tc.triangle_b];
      const Point2 b[3] = {xb[ib[0]], xb[ib[1]], xb[ib[2]]};
      CellCorners(tc, a, ia, b, ib, p);
      double twice = 0;
      for (int k = 1; k + 1 < tc.num_corners; ++k) twice += TwiceArea(p[0], p[k], p[k + 1]);
      if (!(twice > 0)) continue;
      cell.triangle_a = ta;
      cell.triangle_b = tc.triangle_b;
      cell.num_vertices = tc.num_corners;
      cell.area = 0.5 * twice;
      accumulate(cell);
    }
  }
  *out = accumulate.value;
}

VolumeCostCache::VolumeCostCache(double max_dirty_fraction) : impl_(std::make_unique<Impl>()) {
  impl_->max_dirty_fraction = max_dirty_fraction;
}
VolumeCostCache::~VolumeCostCache() = default;
void VolumeCostCache::Reset() { impl_->built = false; }
const VolumeCostCacheStats& VolumeCostCache::stats() const { return impl_->stats; }

namespace {

// Runs f(lo, hi, part) over [0, n) on one or two threads (fixed split).
template <class F>
void Split(int32_t n, bool parallel, F&& f) {
  if (!parallel) {
    f(0, n, 0);
    return;
  }
  std::thread worker([&] { f(n / 2, n, 1); });
  f(0, n / 2, 0);
  worker.join();
}

void AddInto(const VolumeCostValue& v, VolumeCostValue* total) {
  total->abs += v.abs;
  total->area += v.area;
  total->d_abs += v.d_abs;
  total->d_area += v.d_area;
  total->cells += v.cells;
}

}  // namespace

VolumeCostValue VolumeCostCache::Evaluate(const PairState& s, bool gradient, bool parallel,
                                          const MaskRegion* mask) {
  Impl& m = *impl_;
  if (m.state != &s || m.reference != &s.reference() || m.moving != &s.moving()) m.Bind(s);
  const Triangulation& mesh_a = m.reference->mesh;
  const Triangulation& mesh_b = s.moving_mesh();
  const int32_t na = mesh_a.num_triangles(), nb = mesh_b.num_triangles();
  bool build = !m.built || m.remeshes != s.surface_version();
  if (!build) {
    m.MarkDirty(s);
    build = m.dirty.size() > m.max_dirty_fraction * na;
    if (build && (!m.fell_back || s.theta() == m.fallback_theta)) {
      // Far from the topology's pose: Build + labelling would cost more
      // than the plain full path, and a solver often comes back (a
      // rejected trial step), so keep the topology and its pose and
      // evaluate plainly. Too far at another pose right after: the solver
      // has moved on; build.
      m.fell_back = true;
      m.fallback_theta = s.theta();
      const VolumeCostValue plain = EvaluateVolumeCost(s, gradient, parallel, mask);
      ++m.stats.evaluations;
      ++m.stats.fallbacks;
      m.stats.triangles += na;
      m.stats.cells += plain.cells;
      return plain;
    }
  }
  m.fell_back = false;
  if (build) {
    m.topology.Build(m.reference->xy, mesh_a, s.a_in_b(), s.moved_xy(), mesh_b, s.b_in_a(), parallel,
                     m.reference->domain.data(), s.active_b().data());
    m.built = true;
    m.remeshes = s.surface_version();
    ++m.stats.full_builds;
  } else if (!m.dirty.empty()) {
    const TopologyStats t = m.topology.Repair(m.reference->xy, mesh_a, s.a_in_b(), s.moved_xy(),
                                              mesh_b, m.dirty, m.seeds, parallel,
                                              m.reference->domain.data(), s.active_b().data());
    m.stats.triangles_searched += t.triangles_searched;
  }
  m.last_a.resize(s.a_in_b().size());
  m.last_b.resize(s.b_in_a().size());
  for (std::size_t v = 0; v < m.last_a.size(); ++v) m.last_a[v] = Pack(s.a_in_b()[v]);
  for (std::size_t u = 0; u < m.last_b.size(); ++u) m.last_b[u] = Pack(s.b_in_a()[u]);
  ++m.stats.evaluations;
  m.stats.triangles += na;

  VolumeCostValue parts[2];
  if (mask != nullptr) {
    Split(na, parallel, [&](int32_t lo, int32_t hi, int part) {
      m.Generic(s, gradient, mask, lo, hi, &parts[part]);
    });
    AddInto(parts[1], &parts[0]);
    m.stats.cells += parts[0].cells;
    return parts[0];
  }
  // ∇F̂_B' on each moved B triangle, then the cells.
  const bool weighted = !m.reference->weight.empty();
  // A vector kernel where the CPU has one (weighted or not); the
  // environment variable SURFREG_CELL_KERNEL may choose another.
  static const CellKernel kernel = volume_internal::SelectedCellKernel();
  // Weights added or dropped since Bind: their planes again.
  if (m.weight_a.size() != (weighted ? static_cast<std::size_t>(na) : 0u)) m.BindWeights();
  const bool vectorized = kernel != CellKernel::kScalar;
  m.record_b.resize(nb);
  m.extra_b.resize(nb);
  const auto& xy = s.moved_xy();
  const auto& z = s.moved_z();
  Split(nb, parallel, [&](int32_t lo, int32_t hi, int) {
    for (int32_t t = lo; t < hi; ++t) {
      const int32_t* v = &mesh_b.triangles[3 * t];
      const Gradient2 g = GradientOf(xy[v[0]], xy[v[1]], xy[v[2]], z[v[0]], z[v[1]], z[v[2]]);
      // An edge of B's surface: the boundary term's cells (the moving part of ∂Ω).
      const bool hull = s.MovingBoundaryEdge(t, 0) || s.MovingBoundaryEdge(t, 1) ||
                        s.MovingBoundaryEdge(t, 2);
      volume_internal::MakeRecord(xy.data(), z.data(), v, g.gx, g.gy, hull, &m.record_b[t],
                                  &m.extra_b[t]);
    }
  });
  if (gradient) {
    for (auto& moment : m.moments) moment.resize(nb, Moment{0.0, 0.0, 0.0});  // zeroed after each use
  }
  Split(na, parallel, [&](int32_t lo, int32_t hi, int part) {
    if (vectorized) {
      m.IntegrateSimd(kernel, s, gradient, lo, hi, part, &parts[part]);
    } else if (weighted) {
      m.Integrate<true>(s, gradient, lo, hi, part, &parts[part]);
    } else {
      m.Integrate<false>(s, gradient, lo, hi, part, &parts[part]);
    }
  });
  AddInto(parts[1], &parts[0]);
  VolumeCostValue total = parts[0];
  m.stats.cells += total.cells;
  if (!gradient) return total;
  // The interior gradient from each B triangle's moments: with q affine on
  // T_B, Σ s|P| q(c) = W q0 + Q C; rows as VolumeAccumulator::AddPart.
  const auto& q = s.moved_q();
  Eigen::Vector3d rotation[2], translation[2];
  Split(nb, parallel, [&](int32_t lo, int32_t hi, int part) {
    Eigen::Vector3d r = Eigen::Vector3d::Zero(), tr = Eigen::Vector3d::Zero();
    for (int32_t t = lo; t < hi; ++t) {
      Moment& m0 = m.moments[0][t];
      double w = m0.w, cx = m0.x, cy = m0.y;
      m0 = {0.0, 0.0, 0.0};
      if (parallel) {  // one thread leaves moments[1] zero: not worth a pass over memory
        Moment& m1 = m.moments[1][t];
        w += m1.w, cx += m1.x, cy += m1.y;
        m1 = {0.0, 0.0, 0.0};
      }
      if (w == 0 && cx == 0 && cy == 0) continue;
      const int32_t* v = &mesh_b.triangles[3 * t];
      const double ax = xy[v[1]].x - xy[v[0]].x, ay = xy[v[1]].y - xy[v[0]].y;
      const double bx = xy[v[2]].x - xy[v[0]].x, by = xy[v[2]].y - xy[v[0]].y;
      const double det = ax * by - ay * bx;
      const double l1 = (by * cx - bx * cy) / det, l2 = (ax * cy - ay * cx) / det;
      const Eigen::Vector3d sum = w * q[v[0]] + l1 * (q[v[1]] - q[v[0]]) + l2 * (q[v[2]] - q[v[0]]);
      const Eigen::Vector3d normal(-m.record_b[t].gx, -m.record_b[t].gy, 1.0);
      r += normal.cross(sum);
      tr += w * normal;
    }
    rotation[part] = r;
    translation[part] = tr;
  });
  if (!parallel) rotation[1] = translation[1] = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d mt = s.derivative().m.transpose();
  total.d_abs.head<3>() -= mt * (rotation[0] + rotation[1]);
  total.d_abs.tail<3>() += translation[0] + translation[1];
  return total;
}

}  // namespace surfreg
