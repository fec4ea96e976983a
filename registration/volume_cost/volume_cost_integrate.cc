// The cell loops of VolumeCostCache (volume_cost_cache.h): the scalar
// kernel (weighted or not), the vector kernels' driver, and the masked path.
#include <algorithm>
#include <cmath>
#include <utility>

#include "registration/volume_cost/volume_cost_cache.h"

namespace surfreg {

using volume_internal::HullSink;

namespace {
// A cell's Σ s∫_P μ and Σ s∫_P μ(x − p0) over its sign parts P.
struct CellMoment {
  double w = 0, x = 0, y = 0;
};
}  // namespace

// One cell's integrals from its n corners (relative to T_B's corner 0, d
// and μ there; d within [d_lo, d_hi]): the whole cell when d keeps one sign
// on it, else its parts where d ≥ 0 and d ≤ 0. Adds ∫μ|d| and ∫μ, and with
// `gradient` its CellMoment to `moment`.
template <bool kWeighted>
inline void AddCell(const double* x, const double* y, const double* d, const double* m, int n, double d_lo,
                    double d_hi, bool gradient, double* abs, double* area_sum, CellMoment* moment) {
  auto add = [&](const FanSums& f, double sign) {
    *abs += std::max(0.0, sign * f.wd);  // ∫_P μ|d|
    if (!gradient) return;
    CellMoment& m3 = *moment;
    m3.w += sign * f.w;
    m3.x += sign * f.wx;
    m3.y += sign * f.wy;
  };
  if (d_lo >= 0 || d_hi <= 0) {  // one sign part: the whole cell
    const FanSums f = SumFan<kWeighted>(x, y, d, m, n);
    *area_sum += f.w;
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
      *area_sum += f.w;
      if (f.twice > 0) add(f, 1.0);
    }
    if (nn >= 3) {
      const FanSums f = SumFan<kWeighted>(neg_x, neg_y, neg_d, neg_m, nn);
      *area_sum += f.w;
      if (f.twice > 0) add(f, -1.0);
    }
  }
}

// The unmasked cost over the cells of A's triangles [lo, hi): as
// VolumeAccumulator, but the interior gradient as InteriorSums (each cell's
// share from its own sums and its B triangle, volume_kernel_simd.h).
// d = F̂_B' − F_A is linear on a cell, and so is μ (fixed with A's triangle);
// most cells lie on one side of d = 0, so that case takes one pass over the
// corners; only the cells d = 0 crosses are split into their two sign parts.
template <bool kWeighted>
void VolumeCostCache::Impl::Integrate(const PairState& s, bool gradient, const Eigen::Vector3d& offset,
                                      int32_t lo, int32_t hi, int part, ChunkValue* out) {
  const TriangleExtra* extras_b = extra_b.data();
  VolumeAccumulator boundary(s, gradient, nullptr);
  HullSink sink = SinkFor(&boundary, part);
  volume_internal::PartBins* bins = binning ? &part_bins[part] : nullptr;
  volume_internal::InteriorSums interior;
  OverlayCell cell;
  double abs = 0, area_sum = 0;
  int64_t cells = 0;
  ForEachPosedCell<kWeighted>(s, lo, hi, [&](const PosedCell& c) {
    ++cells;
    CellMoment moment;
    AddCell<kWeighted>(c.x, c.y, c.d, c.m, c.n, c.d_lo, c.d_hi, gradient, &abs, &area_sum, &moment);
    if (!gradient) return;
    const TriangleRecord& rb = record_b[c.tb];
    const double qx = rb.x[0] - offset.x(), qy = rb.y[0] - offset.y(), qz = extras_b[c.tb].z0 - offset.z();
    volume_internal::AddInteriorShare(moment.w, moment.x, moment.y, rb.gx, rb.gy, qx, qy, qz, interior.rotation,
                                      interior.translation);
    if (bins != nullptr) {
      const int32_t b = bin_of_b[c.tb];
      double* sums = &bins->interior[6 * static_cast<std::size_t>(b)];
      volume_internal::AddInteriorShare(moment.w, moment.x, moment.y, rb.gx, rb.gy, qx, qy, qz, sums, sums + 3);
      bins->used[b] = 1;
    }
    if ((extras_b[c.tb].bits & volume_internal::kHullBit) != 0) {
      cell.triangle_a = c.ta;
      cell.triangle_b = c.tb;
      cell.num_vertices = c.n;
      sink.Add(cell);
    }
  });
  out->value.abs = abs;
  out->value.area = area_sum;
  out->value.cells = cells;
  out->value.d_abs = boundary.value.d_abs;
  out->value.d_area = boundary.value.d_area;
  out->interior = interior;
}

// As Integrate<kWeighted>, vectorized across cells by `kernel`
// (volume_kernel_simd.h); the hull cells' boundary term stays scalar.
void VolumeCostCache::Impl::IntegrateSimd(CellKernel kernel, const PairState& s, bool gradient,
                                          const Eigen::Vector3d& offset, int32_t lo, int32_t hi, int part,
                                          ChunkValue* out) {
  VolumeAccumulator boundary(s, gradient, nullptr);
  HullSink sink = SinkFor(&boundary, part);
  volume_internal::CellKernelInput in;
  in.cells = topology.cells();
  in.cell_begin = topology.begins();
  in.cell_count = topology.counts();
  in.record_a = record_a.data(), in.extra_a = extra_a.data();
  in.weight_a = weight_a.empty() ? nullptr : weight_a.data();
  in.record_b = record_b.data(), in.extra_b = extra_b.data();
  for (int k = 0; k < 3; ++k) in.offset[k] = offset[k];
  if (binning) {
    volume_internal::PartBins& bins = part_bins[part];
    in.bins = {bin_of_b.data(), bins.interior.data(), bins.used.data()};
  }
  in.context = &sink;
  in.on_hull = [](void* context, int32_t ta, int32_t tb, int n) {
    OverlayCell cell;  // rare: a hull B triangle's cells only
    cell.triangle_a = ta;
    cell.triangle_b = tb;
    cell.num_vertices = n;
    static_cast<HullSink*>(context)->Add(cell);
  };
  volume_internal::CellKernelOutput result;
  volume_internal::IntegrateCellsSimd(kernel, in, lo, hi, gradient, &result);
  out->value.abs = result.abs;
  out->value.area = result.area;
  out->value.cells = result.cells;
  out->value.d_abs = boundary.value.d_abs;
  out->value.d_area = boundary.value.d_area;
  out->interior = result.interior;
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

template void VolumeCostCache::Impl::Integrate<true>(const PairState&, bool, const Eigen::Vector3d&, int32_t,
                                                     int32_t, int, ChunkValue*);
template void VolumeCostCache::Impl::Integrate<false>(const PairState&, bool, const Eigen::Vector3d&, int32_t,
                                                      int32_t, int, ChunkValue*);

}  // namespace surfreg
