#pragma once
// Internal to the volume cost (volume_cost.h): the state VolumeCostCache
// keeps between evaluations, shared by volume_cost.cc (binding, dirty
// marking, the evaluation) and volume_cost_integrate.cc (the cell loops).
// Not a public interface.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "measure/locator.h"
#include "measure/uninitialized_vector.h"
#include "registration/volume_cost/overlay_topology.h"
#include "registration/volume_cost/volume_accumulator.h"
#include "registration/volume_cost/volume_cost.h"
#include "registration/volume_cost/volume_kernel_simd.h"

namespace surfreg {
namespace volume_internal {


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

using Vector6 = Eigen::Matrix<double, 6, 1>;

// One chunk's gradient shares per bin (GradientBins), merged at the end:
// the boundary term's, and the interior sums (6 per bin, as InteriorSums).
struct PartBins {
  std::vector<Vector6> d_abs, d_area;
  std::vector<double> interior;
  std::vector<uint8_t> used;
  void Reset(int n) {
    d_abs.assign(n, Vector6::Zero());
    d_area.assign(n, Vector6::Zero());
    interior.assign(6 * static_cast<std::size_t>(n), 0.0);
    used.assign(n, 0);
  }
};

// One cell's interior share (volume_kernel_simd.h) into 6 sums (as
// InteriorSums): its W, X, Y; its B triangle's ∇F̂ (gx, gy) and corner 0
// less the motion's offset (qx, qy, qz). The vector kernels' AddShare.
inline void AddInteriorShare(double w, double x, double y, double gx, double gy, double qx, double qy, double qz,
                             double* rotation, double* translation) {
  const double gxy = gx * gy;
  rotation[0] += (w * ((0.0 - gy * qz) - qy) - x * gxy) - y * (gy * gy + 1.0);
  rotation[1] += (w * (qx + gx * qz) + x * (gx * gx + 1.0)) + y * gxy;
  rotation[2] += (w * (gy * qx - gx * qy) + x * gy) - y * gx;
  translation[0] -= w * gx;
  translation[1] -= w * gy;
  translation[2] += w;
}

// A chunk's integrals (its own cache line: chunks run side by side).
struct alignas(64) ChunkValue {
  VolumeCostValue value;
  InteriorSums interior;
};

// Where a hull B triangle's cells put their boundary term: the accumulator,
// and with bins also the bin of that B triangle (the difference it made).
struct HullSink {
  VolumeAccumulator* boundary = nullptr;
  const int32_t* bin_of_b = nullptr;
  PartBins* bins = nullptr;
  void Add(const OverlayCell& cell) {
    if (bins == nullptr) return boundary->AddBoundaryOf(cell);
    const Vector6 d_abs = boundary->value.d_abs, d_area = boundary->value.d_area;
    boundary->AddBoundaryOf(cell);
    const int32_t b = bin_of_b[cell.triangle_b];
    bins->d_abs[b] += boundary->value.d_abs - d_abs;
    bins->d_area[b] += boundary->value.d_area - d_area;
    bins->used[b] = 1;
  }
};

// ∇ of the plane through three points (as PlaneThrough).
inline Gradient2 GradientOf(const Point2& p0, const Point2& p1, const Point2& p2, double z0,
                            double z1, double z2) {
  const Plane plane = PlaneThrough(p0, p1, p2, z0, z1, z2);
  return {plane.gx, plane.gy};
}


}  // namespace volume_internal

// The cell loops' corners (volume_cost_integrate.cc, volume_cost_hessian.cc).
// The endpoints of edge i (opposite corner i) in global index order, as
// CellCorners orders them (so a crossing is the same point in every cell).
constexpr int kFirst[3] = {1, 2, 0}, kSecond[3] = {2, 0, 1};

// What a cell's corners are computed from: T_A's corners (0-2) and the
// current T_B's (3-5), and T_A's edges in global index order.
struct CellFrame {
  double cx6[6], cy6[6];
  double e0x[3], e0y[3], ex[3], ey[3];
};

inline CellFrame FrameOfA(const int32_t* ia, const std::vector<Point2>& xa) {
  CellFrame f;
  for (int k = 0; k < 3; ++k) f.cx6[k] = xa[ia[k]].x, f.cy6[k] = xa[ia[k]].y;
  for (int i = 0; i < 3; ++i) {
    int p0 = kFirst[i], p1 = kSecond[i];
    if (ia[p0] > ia[p1]) std::swap(p0, p1);
    f.e0x[i] = f.cx6[p0], f.e0y[i] = f.cy6[p0];
    f.ex[i] = f.cx6[p1] - f.cx6[p0], f.ey[i] = f.cy6[p1] - f.cy6[p0];
  }
  return f;
}

// A cell's corner from its topology code (q0, q1: T_B's edges in global
// index order): every corner computed as if a crossing (cheap, no branch),
// then the vertex corners picked instead, as CellCorners without its switch.
inline Point2 CornerOf(uint8_t code, const CellFrame& f, const int* q0, const int* q1) {
  const int i = (code >> 2) & 3, j = (code >> 4) & 3, kind = code & 3;
  const int r = q0[j], w = q1[j];
  const double vr = f.ex[i] * (f.cy6[r] - f.e0y[i]) - f.ey[i] * (f.cx6[r] - f.e0x[i]);
  const double vs = f.ex[i] * (f.cy6[w] - f.e0y[i]) - f.ey[i] * (f.cx6[w] - f.e0x[i]);
  const double denominator = vr - vs;
  double t = denominator != 0.0 ? vr / denominator : 0.5;
  t = std::min(1.0, std::max(0.0, t));
  const int vertex = kind == kCornerB ? 3 + i : i;
  const bool cross = kind == kCornerCross;
  return {cross ? f.cx6[r] + t * (f.cx6[w] - f.cx6[r]) : f.cx6[vertex],
          cross ? f.cy6[r] + t * (f.cy6[w] - f.cy6[r]) : f.cy6[vertex]};
}

// A cell of the kept overlay at the current points, as the scalar cell
// loops see it: corners, d and μ relative to T_B's corner 0 (bx, by).
struct PosedCell {
  int32_t ta = -1, tb = -1;
  const int32_t* ib = nullptr;        // T_B's vertices
  const TopologyCell* cell = nullptr;  // its corner codes
  const CellFrame* frame = nullptr;    // T_A's corners 0-2, T_B's 3-5
  int n = 0;
  double bx = 0, by = 0;
  double dgx = 0, dgy = 0;  // ∇d
  double mu0 = 1;           // μ at T_B's corner 0 (1 without weights); ∇μ is the A triangle's
  double mu_gx = 0, mu_gy = 0;
  double x[8], y[8], d[8], m[8];  // m only with weights
  double d_lo = 0, d_hi = 0;
  double Mu(double px, double py) const { return mu0 + mu_gx * px + mu_gy * py; }
};

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
  std::vector<volume_internal::PackedLocation> last_a, last_b;  // at the previous evaluation
  // A, fixed: the triangles around each vertex.
  std::vector<int32_t> star_begin, star;
  // Triangle records (volume_kernel_simd.h): A's fixed, B's per
  // evaluation; both kernels and the gradient read ∇F and the hull bit there.
  // (Filled by chunks, so not zeroed first.)
  UninitializedVector<volume_internal::TriangleRecord> record_a, record_b;
  UninitializedVector<volume_internal::TriangleExtra> extra_a, extra_b;
  UninitializedVector<volume_internal::WeightPlane> weight_a;  // μ per A triangle; empty: no weights
  std::vector<uint8_t> mark;
  std::vector<int32_t> dirty, changed_a, changed_b;  // changed: MarkDirty's vertices that moved
  std::vector<std::pair<int32_t, int32_t>> seeds;
  // The integration's per chunk of A's triangles, added in chunk order.
  std::vector<volume_internal::ChunkValue> chunk_values;
  volume_internal::CellKernel cell_kernel = volume_internal::CellKernel::kScalar;
  // With GradientBins: each moved B triangle's bin, and each chunk's shares.
  std::vector<int32_t> bin_of_b;
  std::vector<volume_internal::PartBins> part_bins;
  bool binning = false;
  volume_internal::HullSink SinkFor(volume_internal::VolumeAccumulator* boundary, int part) {
    return {boundary, bin_of_b.data(), binning ? &part_bins[part] : nullptr};
  }

  void Bind(const PairState& s);
  void BindWeights();
  void MarkDirty(const PairState& s, const Execution& execution);
  bool UpdateTopology(const PairState& s, const Execution& execution);
  void RecordMovedTriangles(const PairState& s, const Execution& execution, int chunks, const GradientBins* bins);
  void MergeBins(const Eigen::Matrix3d& mt, GradientBins* bins) const;
  // Calls visit(const PosedCell&) for every cell of A's triangles [lo, hi).
  template <bool kWeighted, class Visit>
  void ForEachPosedCell(const PairState& s, int32_t lo, int32_t hi, Visit&& visit) const;
  // The cells of A's triangles [lo, hi) into `out` (the chunk `part`'s);
  // q = moved point − offset (pair_state.h).
  template <bool kWeighted>
  void Integrate(const PairState& s, bool gradient, const Eigen::Vector3d& offset, int32_t lo, int32_t hi,
                 int part, volume_internal::ChunkValue* out);
  void IntegrateSimd(volume_internal::CellKernel kernel, const PairState& s, bool gradient,
                     const Eigen::Vector3d& offset, int32_t lo, int32_t hi, int part,
                     volume_internal::ChunkValue* out);
  void Generic(const PairState& s, bool gradient, const MaskRegion* mask,
               int32_t lo, int32_t hi, VolumeCostValue* out);
  template <bool kWeighted>
  void Curvature(const PairState& s, int32_t lo, int32_t hi, Eigen::Matrix<double, 6, 6>* out) const;
};

template <bool kWeighted, class Visit>
void VolumeCostCache::Impl::ForEachPosedCell(const PairState& s, int32_t lo, int32_t hi, Visit&& visit) const {
  const Triangulation& mesh_a = reference->mesh;
  const int32_t* triangles_b = s.moving_mesh().triangles.data();
  const auto& xa = reference->xy;
  const auto& za = reference->z;
  const auto& xb = s.moved_xy();
  const auto& zb = s.moved_z();
  PosedCell c;
  for (int32_t ta = lo; ta < hi; ++ta) {
    const int32_t count = topology.count_of(ta);
    if (count == 0) continue;
    const TopologyCell* list = topology.cells_of(ta);
    const int32_t* ia = &mesh_a.triangles[3 * ta];
    CellFrame frame = FrameOfA(ia, xa);
    const double* cx6 = frame.cx6;
    const double* cy6 = frame.cy6;
    const double ga_x = record_a[ta].gx, ga_y = record_a[ta].gy;
    const double za0 = za[ia[0]];
    // μ relative to T_A's corner 0 (Bind's plane).
    const volume_internal::WeightPlane mu = kWeighted ? weight_a[ta] : volume_internal::WeightPlane{};
    c.ta = ta;
    c.frame = &frame;
    c.mu_gx = mu.gx, c.mu_gy = mu.gy;
    for (int32_t k = 0; k < count; ++k) {
      const TopologyCell& tc = list[k];
      const int32_t tb = tc.triangle_b;
      const int32_t* ib = triangles_b + 3 * tb;
      for (int v = 0; v < 3; ++v) frame.cx6[3 + v] = xb[ib[v]].x, frame.cy6[3 + v] = xb[ib[v]].y;
      int q0[3], q1[3];
      for (int j = 0; j < 3; ++j) {
        const bool swap = ib[kFirst[j]] > ib[kSecond[j]];
        q0[j] = 3 + (swap ? kSecond[j] : kFirst[j]);
        q1[j] = 3 + (swap ? kFirst[j] : kSecond[j]);
      }
      c.tb = tb, c.ib = ib, c.cell = &tc, c.n = tc.num_corners;
      const volume_internal::TriangleRecord& fb = record_b[tb];
      // Relative to T_B's corner 0: d = d0 + ∇d · (x, y), μ = μ0 + ∇μ · (x, y).
      c.bx = cx6[3], c.by = cy6[3];
      const double d0 = zb[ib[0]] - (za0 + ga_x * (c.bx - cx6[0]) + ga_y * (c.by - cy6[0]));
      c.dgx = fb.gx - ga_x, c.dgy = fb.gy - ga_y;
      c.mu0 = kWeighted ? mu.m0 + mu.gx * (c.bx - cx6[0]) + mu.gy * (c.by - cy6[0]) : 1.0;
      for (int v = 0; v < c.n; ++v) {
        const Point2 p = CornerOf(tc.corner[v], frame, q0, q1);
        c.x[v] = p.x - c.bx;
        c.y[v] = p.y - c.by;
        c.d[v] = d0 + c.dgx * c.x[v] + c.dgy * c.y[v];
        if (kWeighted) c.m[v] = c.mu0 + mu.gx * c.x[v] + mu.gy * c.y[v];
        c.d_lo = v == 0 ? c.d[v] : std::min(c.d_lo, c.d[v]);
        c.d_hi = v == 0 ? c.d[v] : std::max(c.d_hi, c.d[v]);
      }
      visit(static_cast<const PosedCell&>(c));
    }
  }
}

// The internal names both of the cache's files use.
using volume_internal::FanSums;
using volume_internal::SumFan;
using volume_internal::VolumeAccumulator;
using volume_internal::CellKernel;
using volume_internal::ForEachCellOfState;
using volume_internal::StateChunks;
using volume_internal::Gradient2;
using volume_internal::ChunkValue;
using volume_internal::TriangleExtra;
using volume_internal::TriangleRecord;

}  // namespace surfreg
