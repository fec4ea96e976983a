#pragma once
// Internal to the volume cost (volume_cost.h): the integrals over one
// overlay cell (value, gradient, weights, mask, B's moving boundary), shared
// by the full evaluation and the incremental one. Not a public interface.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "measure/gap_volume.h"
#include "measure/overlay.h"
#include "measure/volume.h"
#include "measure/weights.h"
#include "registration/pair_state.h"
#include "registration/volume_cost/volume_cost.h"

namespace surfreg {
namespace volume_internal {

using Vector6 = Eigen::Matrix<double, 6, 1>;

// ∫ over a convex polygon (fan from corner 0) of μ, μd, μx and μy, with d
// and μ linear (μ ≡ 1 unless kWeighted): per fan triangle of area S with
// corner values f_i, g_i, ∫fg = S/12 (Σ f_i g_i + Σf_i Σg_i).
struct FanSums {
  double twice = 0;          // twice the area
  double w = 0, wd = 0;      // ∫μ, ∫μd
  double wx = 0, wy = 0;     // ∫μx, ∫μy
};

template <bool kWeighted>
inline FanSums SumFan(const double* x, const double* y, const double* d, const double* m, int n) {
  FanSums s;
  double w = 0, wd = 0, wx = 0, wy = 0;
  for (int k = 1; k + 1 < n; ++k) {
    const double t = (x[k] - x[0]) * (y[k + 1] - y[0]) - (y[k] - y[0]) * (x[k + 1] - x[0]);
    s.twice += t;
    const double sd = d[0] + d[k] + d[k + 1];
    const double sx = x[0] + x[k] + x[k + 1], sy = y[0] + y[k] + y[k + 1];
    if (kWeighted) {
      const double sm = m[0] + m[k] + m[k + 1];
      w += t * sm;
      wd += t * (m[0] * d[0] + m[k] * d[k] + m[k + 1] * d[k + 1] + sm * sd);
      wx += t * (m[0] * x[0] + m[k] * x[k] + m[k + 1] * x[k + 1] + sm * sx);
      wy += t * (m[0] * y[0] + m[k] * y[k] + m[k + 1] * y[k + 1] + sm * sy);
    } else {
      wd += t * sd;
      wx += t * sx;
      wy += t * sy;
    }
  }
  if (kWeighted) {
    s.w = w * (1.0 / 6.0);
    s.wd = wd * (1.0 / 24.0), s.wx = wx * (1.0 / 24.0), s.wy = wy * (1.0 / 24.0);
  } else {
    s.w = 0.5 * s.twice;
    s.wd = wd * (1.0 / 6.0), s.wx = wx * (1.0 / 6.0), s.wy = wy * (1.0 / 6.0);
  }
  return s;
}

// Area and centroid of a convex polygon.
inline void AreaCentroid(const Point2* p, int n, double* area, Point2* centroid) {
  double twice = 0, cx = 0, cy = 0;
  for (int k = 1; k + 1 < n; ++k) {
    const double t = TwiceArea(p[0], p[k], p[k + 1]);
    twice += t;
    cx += t * (p[0].x + p[k].x + p[k + 1].x);
    cy += t * (p[0].y + p[k].y + p[k + 1].y);
  }
  *area = 0.5 * twice;
  *centroid = twice > 0 ? Point2{cx / (3 * twice), cy / (3 * twice)} : p[0];
}

// ∫ (x − c)(x − c)ᵀ over a convex polygon, c its centroid: per fan triangle
// with corners v_k relative to c, S/12 (Σ v_k v_kᵀ + (Σ v_k)(Σ v_k)ᵀ), exact.
inline Eigen::Matrix2d SecondMoment(const Point2* p, int n, const Point2& c) {
  Eigen::Matrix2d total = Eigen::Matrix2d::Zero();
  const Eigen::Vector2d v0(p[0].x - c.x, p[0].y - c.y);
  for (int k = 1; k + 1 < n; ++k) {
    const Eigen::Vector2d v1(p[k].x - c.x, p[k].y - c.y), v2(p[k + 1].x - c.x, p[k + 1].y - c.y);
    const double area = 0.5 * (v1.x() - v0.x()) * (v2.y() - v0.y()) -
                        0.5 * (v1.y() - v0.y()) * (v2.x() - v0.x());
    const Eigen::Vector2d sum = v0 + v1 + v2;
    total += area / 12.0 * (v0 * v0.transpose() + v1 * v1.transpose() + v2 * v2.transpose() +
                            sum * sum.transpose());
  }
  return total;
}

// The part [s0, s1] of the segment e0 → e1 inside the counter-clockwise
// triangle `t` (and `also`, if given); false when nothing of it is.
inline bool ClipSegment(const Point2& e0, const Point2& e1, const Point2* t,
                        const std::array<Point2, 3>* also, double* s0, double* s1) {
  const int clip_edges = also != nullptr ? 6 : 3;
  for (int k = 0; k < clip_edges && *s0 < *s1; ++k) {
    const Point2& c0 = k < 3 ? t[k] : (*also)[k - 3];
    const Point2& c1 = k < 3 ? t[(k + 1) % 3] : (*also)[(k - 2) % 3];
    const double f0 = TwiceArea(c0, c1, e0), f1 = TwiceArea(c0, c1, e1);
    if (f0 >= 0 && f1 >= 0) continue;
    if (f0 < 0 && f1 < 0) return false;
    const double s = f0 / (f0 - f1);
    if (f0 < 0) *s0 = std::max(*s0, s); else *s1 = std::min(*s1, s);
  }
  return *s1 > *s0;
}

// [s0, s1] cut where a linear d (d0 at s0, d1 at s1) changes sign: writes
// the pieces' ends to cuts[0..pieces] and returns the number of pieces.
inline int SignPieces(double d0, double d1, double s0, double s1, double cuts[3]) {
  cuts[0] = s0, cuts[1] = s1, cuts[2] = s1;
  if (!((d0 > 0 && d1 < 0) || (d0 < 0 && d1 > 0))) return 1;
  cuts[1] = s0 + (s1 - s0) * d0 / (d0 - d1);
  return 2;
}

// The moved B triangle as a linear map: height, and the material point q
// (relative to c + t) above any xy.
struct MovedTriangle {
  Point2 p0;
  double inv[4] = {0, 0, 0, 0};  // inverse of [p1 − p0, p2 − p0]
  Eigen::Vector3d q0 = Eigen::Vector3d::Zero(), dq1 = Eigen::Vector3d::Zero(), dq2 = Eigen::Vector3d::Zero();
  Plane height;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // (−∇F, 1)

  Eigen::Vector3d QAt(const Point2& x) const { return q0 + QStep(x.x - p0.x, x.y - p0.y); }
  // The change of q over an xy step (dx, dy): q is affine in xy.
  Eigen::Vector3d QStep(double dx, double dy) const {
    const double l1 = inv[0] * dx + inv[1] * dy, l2 = inv[2] * dx + inv[3] * dy;
    return l1 * dq1 + l2 * dq2;
  }
};

// Moved B triangle t at the state's pose.
inline MovedTriangle MovedTriangleOf(const PairState& state, int32_t t) {
  const int32_t* v = &state.moving_mesh().triangles[3 * t];
  const auto& xy = state.moved_xy();
  const auto& z = state.moved_z();
  const auto& q = state.moved_q();
  MovedTriangle tb;
  tb.p0 = xy[v[0]];
  const double ax = xy[v[1]].x - xy[v[0]].x, ay = xy[v[1]].y - xy[v[0]].y;
  const double bx = xy[v[2]].x - xy[v[0]].x, by = xy[v[2]].y - xy[v[0]].y;
  const double det = ax * by - ay * bx;
  tb.inv[0] = by / det, tb.inv[1] = -bx / det, tb.inv[2] = -ay / det, tb.inv[3] = ax / det;
  tb.q0 = q[v[0]];
  tb.dq1 = q[v[1]] - q[v[0]];
  tb.dq2 = q[v[2]] - q[v[0]];
  tb.height = PlaneThrough(xy[v[0]], xy[v[1]], xy[v[2]], z[v[0]], z[v[1]], z[v[2]]);
  tb.normal = Eigen::Vector3d(-tb.height.gx, -tb.height.gy, 1.0);
  return tb;
}

// A's triangle t: its height plane, its corners, and μ's plane (μ is linear
// on A's triangle and fixed with it; left as is without weights).
inline void ReferenceTriangle(const ReferenceSide& a, const std::vector<double>* weight, int32_t t, Plane* height,
                              Point2 corners[3], Plane* mu) {
  const int32_t* v = &a.mesh.triangles[3 * t];
  *height = PlaneThrough(a.xy[v[0]], a.xy[v[1]], a.xy[v[2]], a.z[v[0]], a.z[v[1]], a.z[v[2]]);
  for (int k = 0; k < 3; ++k) corners[k] = a.xy[v[k]];
  if (weight != nullptr) {
    const std::vector<double>& w = *weight;
    *mu = PlaneThrough(a.xy[v[0]], a.xy[v[1]], a.xy[v[2]], w[v[0]], w[v[1]], w[v[2]]);
  }
}

// A cache line of its own: one per chunk, each adding to its sums cell by cell.
class alignas(64) VolumeAccumulator {
 public:
  VolumeAccumulator(const PairState& state, bool gradient,
              const MaskRegion* mask)
      : state_(state), gradient_(gradient), mask_(mask),
        weight_(state.reference().weight.empty() ? nullptr : &state.reference().weight) {
    mt_ = state.derivative().m.transpose();
  }

  // Only the boundary term of a cell (no mask): for callers that integrate
  // the interior themselves.
  void AddBoundaryOf(const OverlayCell& cell) {
    if (!OnSurfaces(cell)) return;
    SetContext(cell);
    if (gradient_ && has_hull_edge_) AddBoundary(cell.triangle_b, nullptr);
  }

  void operator()(const OverlayCell& cell) {
    if (!OnSurfaces(cell)) return;
    SetContext(cell);
    ++value.cells;
    if (mask_ == nullptr) {
      AddPolygon(cell.vertices.data(), cell.num_vertices, cell.area);
      if (gradient_ && has_hull_edge_) AddBoundary(cell.triangle_b, nullptr);
      return;
    }
    AddMasked(cell);
  }

  VolumeCostValue value;

 private:
  // Cells of junk triangles (measure/domain.h) are not part of Ω.
  bool OnSurfaces(const OverlayCell& cell) const {
    return state_.reference().domain[cell.triangle_a] && state_.active_b()[cell.triangle_b];
  }

  void SetContext(const OverlayCell& cell) {
    if (cell.triangle_a != last_a_) {
      last_a_ = cell.triangle_a;
      ReferenceTriangle(state_.reference(), weight_, cell.triangle_a, &fa_, ta_, &mu_);
    }
    if (cell.triangle_b != last_b_) {
      last_b_ = cell.triangle_b;
      SetMovedTriangle(cell.triangle_b);
    }
  }

  void AddMasked(const OverlayCell& cell) {
    const Point2* p = cell.vertices.data();
    double lo_x = p[0].x, hi_x = lo_x, lo_y = p[0].y, hi_y = lo_y;
    for (int k = 1; k < cell.num_vertices; ++k) {
      lo_x = std::min(lo_x, p[k].x), hi_x = std::max(hi_x, p[k].x);
      lo_y = std::min(lo_y, p[k].y), hi_y = std::max(hi_y, p[k].y);
    }
    Point2 piece[12];
    ForEachMaskTriangle(*mask_, {lo_x, lo_y}, {hi_x, hi_y}, [&](int32_t k) {
      const std::array<Point2, 3>& t = mask_->triangles[k];
      const int m = ClipByTriangle(p, cell.num_vertices, t, piece);
      if (m < 3) return;
      double area;
      Point2 centroid;
      AreaCentroid(piece, m, &area, &centroid);
      if (!(area > 0)) return;
      sign_ = mask_->sign[k];  // a hole's triangle takes back what its ring's gave
      AddPolygon(piece, m, area);
      if (gradient_ && has_hull_edge_) AddBoundary(cell.triangle_b, &t);
      sign_ = 1.0;
    });
  }

  void SetMovedTriangle(int32_t t) {
    tb_ = MovedTriangleOf(state_, t);
    has_hull_edge_ = false;
    for (int k = 0; k < 3; ++k) has_hull_edge_ |= state_.MovingBoundaryEdge(t, k);
  }

  // A convex piece of a cell (of area `area`): split by the sign of d
  // (linear on it). With weights, ∫μ|d| and ∫μ come from the closed forms
  // of volume.h on the piece's fan (as Measure computes them) and the parts
  // carry only the gradient.
  void AddPolygon(const Point2* p, int n, double area) {
    double dv[12];
    for (int k = 0; k < n; ++k) dv[k] = tb_.height.At(p[k]) - fa_.At(p[k]);
    if (weight_ == nullptr) {
      value.area += sign_ * area;
    } else {
      for (int k = 1; k + 1 < n; ++k) {
        const double fan = 0.5 * TwiceArea(p[0], p[k], p[k + 1]);
        if (!(fan > 0)) continue;
        const double d[3] = {dv[0], dv[k], dv[k + 1]};
        const double m[3] = {mu_.At(p[0]), mu_.At(p[k]), mu_.At(p[k + 1])};
        const GapIntegrals gap = IntegrateGapWeighted(fan, d, m);
        value.abs += sign_ * gap.abs;
        value.area += sign_ * gap.weight;
      }
      if (!gradient_) return;
    }
    Point2 pos[14], neg[14];
    int np = 0, nn = 0;
    for (int k = 0; k < n; ++k) {
      const int l = k + 1 == n ? 0 : k + 1;
      if (dv[k] >= 0) pos[np++] = p[k];
      if (dv[k] <= 0) neg[nn++] = p[k];
      if ((dv[k] > 0 && dv[l] < 0) || (dv[k] < 0 && dv[l] > 0)) {
        const double s = dv[k] / (dv[k] - dv[l]);
        const Point2 cut{p[k].x + s * (p[l].x - p[k].x), p[k].y + s * (p[l].y - p[k].y)};
        pos[np++] = cut;
        neg[nn++] = cut;
      }
    }
    AddPart(pos, np, +1.0);
    AddPart(neg, nn, -1.0);
  }

  // ∫ over one sign part: |d| (exact: d is linear), and sign · ∂_θF̂_B'.
  // With weights, ∫ μ sign ∂_θF̂_B' only: with G(x) = ∂_θF̂_B' (affine) and
  // Σ the part's second moment about its centroid c,
  //   ∫ μ G = |part| μ(c) G(c) + DG Σ ∇μ,
  // exact for the product of two affine functions (∫ (x − c) = 0); DG is
  // non-zero only in the rotation rows, through q.
  void AddPart(const Point2* p, int n, double sign) {
    if (n < 3) return;
    double area;
    Point2 c;
    AreaCentroid(p, n, &area, &c);
    if (!(area > 0)) return;
    if (weight_ == nullptr) {
      const double d = tb_.height.At(c) - fa_.At(c);
      value.abs += sign_ * area * std::max(0.0, sign * d);
    }
    if (!gradient_) return;
    const Eigen::Vector3d q = tb_.QAt(c);
    if (weight_ != nullptr) {
      // ∫ μ q = |part| μ(c) q(c) + Q Σ ∇μ (Q = ∂q/∂xy), and ∫ μ = |part| μ(c).
      const Eigen::Vector2d m = SecondMoment(p, n, c) * Eigen::Vector2d(mu_.gx, mu_.gy);
      const double mu_area = mu_.At(c) * area;
      const Eigen::Vector3d mu_q = mu_area * q + tb_.QStep(m.x(), m.y());
      value.d_abs.head<3>() += sign_ * sign * -(mt_ * tb_.normal.cross(mu_q));
      value.d_abs.tail<3>() += sign_ * sign * mu_area * tb_.normal;
      return;
    }
    const double w = sign_ * sign * area;
    value.d_abs.head<3>() += w * -(mt_ * tb_.normal.cross(q));
    value.d_abs.tail<3>() += w * tb_.normal;
  }

  // The edges of B's surface (its hull, or next to junk) of this cell's B
  // triangle, within its A triangle (and the mask triangle, if any): the
  // moving part of ∂Ω.
  void AddBoundary(int32_t t, const std::array<Point2, 3>* mask_triangle) {
    const Triangulation& mesh_b = state_.moving_mesh();
    const int32_t* v = &mesh_b.triangles[3 * t];
    const auto& xy = state_.moved_xy();
    const auto& q = state_.moved_q();
    for (int i = 0; i < 3; ++i) {
      if (!state_.MovingBoundaryEdge(t, i)) continue;
      const int32_t va = v[(i + 1) % 3], vb = v[(i + 2) % 3];  // interior on the left
      const Point2 e0 = xy[va], e1 = xy[vb];
      double s0 = 0.0, s1 = 1.0;
      if (!ClipSegment(e0, e1, ta_, mask_triangle, &s0, &s1)) continue;
      const double ex = e1.x - e0.x, ey = e1.y - e0.y;
      const double length = std::hypot(ex, ey);
      const Eigen::Vector3d m(ey / length, -ex / length, 0.0);  // outward normal
      auto point = [&](double s) { return Point2{e0.x + s * ex, e0.y + s * ey}; };
      auto g = [&](double s) {
        const Eigen::Vector3d qs = (1 - s) * q[va] + s * q[vb];
        Vector6 out;
        out.head<3>() = -(mt_ * m.cross(qs));
        out.tail<3>() = m;
        return out;
      };
      auto d = [&](double s) { const Point2 p = point(s); return tb_.height.At(p) - fa_.At(p); };
      // μ along the edge (1 without weights): μ g is quadratic, μ|d| g cubic
      // on each sign piece; Simpson is exact for both.
      auto mu = [&](double s) { return weight_ == nullptr ? 1.0 : mu_.At(point(s)); };
      if (weight_ == nullptr) {
        value.d_area += sign_ * (s1 - s0) * length * g(0.5 * (s0 + s1));
      } else {
        const double sm = 0.5 * (s0 + s1);
        value.d_area += sign_ * (s1 - s0) * length / 6.0 *
                        (mu(s0) * g(s0) + 4.0 * mu(sm) * g(sm) + mu(s1) * g(s1));
      }
      // ∫|d| g ds, split where d changes sign; Simpson is exact for the quadratic.
      double cuts[3];
      const int pieces = volume_internal::SignPieces(d(s0), d(s1), s0, s1, cuts);
      for (int k = 0; k < pieces; ++k) {
        const double a0 = cuts[k], a1 = cuts[k + 1], am = 0.5 * (a0 + a1);
        value.d_abs += sign_ * (a1 - a0) * length / 6.0 *
                       (mu(a0) * std::fabs(d(a0)) * g(a0) +
                        4.0 * mu(am) * std::fabs(d(am)) * g(am) +
                        mu(a1) * std::fabs(d(a1)) * g(a1));
      }
    }
  }

  const PairState& state_;
  const bool gradient_;
  const MaskRegion* mask_;
  double sign_ = 1.0;  // of the mask triangle being integrated (+1 without a mask)
  const std::vector<double>* weight_;  // A's per-node μ, or null (μ = 1); owned by the state
  Plane mu_;                           // μ on the current A triangle
  Eigen::Matrix3d mt_;
  int32_t last_a_ = -1, last_b_ = -1;
  Plane fa_;
  Point2 ta_[3];
  MovedTriangle tb_;
  bool has_hull_edge_ = false;
};

// Every cell of the overlay of A and the state's moved B, chunk c's to
// parts[c] (ForEachOverlayCellInChunks): sums made per part and added in
// part order do not depend on the thread count.
template <class Visitor>
void ForEachCellOfState(const PairState& state, const Execution& execution, std::vector<Visitor>& parts) {
  const ReferenceSide& a = state.reference();
  ForEachOverlayCellInChunks(a.xy, a.mesh, state.a_in_b(), state.moved_xy(), state.moving_mesh(), state.b_in_a(),
                             static_cast<int>(parts.size()),
                             [&](int c, const OverlayCell& cell) { parts[c](cell); }, execution);
}

// The number of parts for ForEachCellOfState: a function of A's size only.
inline int StateChunks(const PairState& state) { return OverlayChunks(state.reference().mesh); }

}  // namespace volume_internal
}  // namespace surfreg
