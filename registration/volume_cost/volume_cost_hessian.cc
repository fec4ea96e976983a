// VolumeCostCache::InteriorHessian: the two line terms of
// registration/volume_cost/volume_hessian.h over the overlay the cache keeps, cell by
// cell as the scalar kernel walks them (volume_cost_integrate.cc).
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "registration/volume_cost/volume_cost_cache.h"
#include "registration/volume_cost/volume_hessian.h"

namespace surfreg {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

// The edges of T_B (bit j: edge j, opposite corner j) a cell corner lies on.
inline int EdgesOfCorner(uint8_t code) {
  const int i = (code >> 2) & 3, j = (code >> 4) & 3;
  switch (code & 3) {
    case kCornerB: return 7 & ~(1 << i);  // a vertex of T_B: its two edges
    case kCornerCross: return 1 << j;
    default: return 0;  // a vertex of T_A
  }
}

// The moved B triangle's material point q (the point less the motion's
// offset) at (x, y) relative to its corner 0: on T_B's plane, so q = q0 +
// (x, y, gx x + gy y) with ∇F̂_B' = (gx, gy) (as the gradient's interior
// share, volume_cost_cache.h); the rows of g and w before the rotation
// rows' Mᵀ (applied once to the sum: H = T K Tᵀ, T = diag(Mᵀ, I)).
struct MovedFrame {
  Eigen::Vector3d q0, normal;  // normal = (−gx, −gy, 1)
  Eigen::Vector3d Q(double x, double y) const {
    return Eigen::Vector3d(q0.x() + x, q0.y() + y, q0.z() - normal.x() * x - normal.y() * y);
  }
  // g = ∂_θF̂_B' (rows: −n × q, n).
  Vector6 G(double x, double y) const {
    Vector6 g;
    g.head<3>() = -normal.cross(Q(x, y));
    g.tail<3>() = normal;
    return g;
  }
  // w = ν·u_xy for an edge of normal ν (rows: q × ν, ν).
  Vector6 W(double x, double y, const Eigen::Vector3d& nu) const {
    Vector6 w;
    w.head<3>() = Q(x, y).cross(nu);
    w.tail<3>() = nu;
    return w;
  }
};

// The upper triangle of a symmetric 6 × 6 sum.
struct Symmetric6 {
  double v[6][6] = {};
  void AddOuter(const Vector6& a, double scale) {
    for (int j = 0; j < 6; ++j) {
      const double s = scale * a[j];
      for (int i = 0; i <= j; ++i) v[i][j] += s * a[i];
    }
  }
  // ∫₀¹ μ(t) v vᵀ dt · scale with v = a + t b and μ = μ0 + t dμ ≥ 0 (times
  // a length): M0 (a + c b)(a + c b)ᵀ + (M2 − M1²/M0) b bᵀ, c = M1/M0,
  // Mk = ∫ μ t^k; exact, two rank-one updates (the second in the rotation
  // rows only: along a segment only q changes).
  void AddSegment(const Vector6& a, const Vector6& b, double mu0, double dmu, double scale) {
    const double m0 = mu0 + 0.5 * dmu, m1 = 0.5 * mu0 + dmu / 3.0, m2 = mu0 / 3.0 + 0.25 * dmu;
    if (!(m0 > 0)) return;
    const double c = m1 / m0;
    AddOuter(a + c * b, scale * m0);
    // b's translation rows are 0 (n and ν are constant along the segment).
    const double s = scale * (m2 - m1 * c);
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i <= j; ++i) v[i][j] += s * b[i] * b[j];
    }
  }
  Matrix6 Full() const {
    Matrix6 out;
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i <= j; ++i) out(i, j) = out(j, i) = v[i][j];
    }
    return out;
  }
};

}  // namespace

template <bool kWeighted>
void VolumeCostCache::Impl::Curvature(const PairState& s, int32_t lo, int32_t hi, Matrix6* out) const {
  const Triangulation& mesh_b = s.moving_mesh();
  const auto& q = s.moved_q();
  const std::vector<uint8_t>& active_b = s.active_b();
  MovedFrame frame_b;
  Symmetric6 h;
  ForEachPosedCell<kWeighted>(s, lo, hi, [&](const PosedCell& c) {
    const int32_t tb = c.tb;
    const int n = c.n;
    const double* x = c.x;
    const double* y = c.y;
    const double* d = c.d;
    const double* cx6 = c.frame->cx6;
    const double* cy6 = c.frame->cy6;
    const TriangleRecord& fb = record_b[tb];
    auto mu_at = [&](double px, double py) { return kWeighted ? c.Mu(px, py) : 1.0; };
    int zeros = 0;
    for (int k = 0; k < n; ++k) zeros += d[k] == 0;
    // Which of T_B's inner edges this cell counts (of an edge between two
    // cells, the one with the lower B triangle index takes it).
    int sides = 0;
    for (int j = 0; j < 3; ++j) {
      const int32_t next = mesh_b.neighbors[3 * tb + j];
      if (next > tb && active_b[next]) sides |= 1 << j;
    }
    // d = 0 crosses the cell, or lies along a side of it: that side is
    // taken by the cell on its d > 0 side only (once).
    const bool zero_line = c.d_hi > 0 && (c.d_lo < 0 || zeros >= 2);
    if (!zero_line && sides == 0) return;
    bool frame_set = false;
    auto set_frame = [&] {
      if (frame_set) return;
      frame_set = true;
      frame_b.q0 = q[c.ib[0]];
      frame_b.normal = Eigen::Vector3d(-fb.gx, -fb.gy, 1.0);
    };
    if (zero_line) {
      double ex[2], ey[2];
      int ends = 0;
      for (int k = 0; k < n && ends < 2; ++k) {
        const int l = k + 1 == n ? 0 : k + 1;
        if (d[k] == 0) {
          ex[ends] = x[k], ey[ends] = y[k], ++ends;
        } else if ((d[k] > 0 && d[l] < 0) || (d[k] < 0 && d[l] > 0)) {
          const double t = d[k] / (d[k] - d[l]);
          ex[ends] = x[k] + t * (x[l] - x[k]), ey[ends] = y[k] + t * (y[l] - y[k]), ++ends;
        }
      }
      const double dx = ends == 2 ? ex[1] - ex[0] : 0.0, dy = ends == 2 ? ey[1] - ey[0] : 0.0;
      const double length = std::sqrt(dx * dx + dy * dy);
      if (length > 0) {
        set_frame();
        const Vector6 g0 = frame_b.G(ex[0], ey[0]);
        const double mu_0 = mu_at(ex[0], ey[0]);
        h.AddSegment(g0, frame_b.G(ex[1], ey[1]) - g0, mu_0, mu_at(ex[1], ey[1]) - mu_0,
                     2.0 * length / std::sqrt(c.dgx * c.dgx + c.dgy * c.dgy));
      }
    }
    if (sides == 0) return;
    for (int k = 0; k < n; ++k) {
      const int l = k + 1 == n ? 0 : k + 1;
      const int on = EdgesOfCorner(c.cell->corner[k]) & EdgesOfCorner(c.cell->corner[l]) & sides;
      if (on == 0) continue;
      const int j = (on & 1) ? 0 : (on & 2) ? 1 : 2;
      const double sx = x[l] - x[k], sy = y[l] - y[k];
      const double length = std::sqrt(sx * sx + sy * sy);
      if (!(length > 0)) continue;
      set_frame();
      // ν pointing out of T_B (away from its corner j), and the kink κ.
      Eigen::Vector3d nu(sy / length, -sx / length, 0.0);
      if ((cx6[3 + j] - c.bx - x[k]) * nu.x() + (cy6[3 + j] - c.by - y[k]) * nu.y() > 0) nu = -nu;
      const TriangleRecord& other = record_b[mesh_b.neighbors[3 * tb + j]];
      const double kink = (other.gx - fb.gx) * nu.x() + (other.gy - fb.gy) * nu.y();
      if (kink == 0) continue;
      double cuts[3] = {0.0, 1.0, 1.0};
      int pieces = 1;
      if ((d[k] > 0 && d[l] < 0) || (d[k] < 0 && d[l] > 0)) {
        cuts[1] = d[k] / (d[k] - d[l]);
        pieces = 2;
      }
      for (int p = 0; p < pieces; ++p) {
        const double a0 = cuts[p], a1 = cuts[p + 1];
        const double dm = d[k] + 0.5 * (a0 + a1) * (d[l] - d[k]);
        if (dm == 0) continue;
        const double x0 = x[k] + a0 * sx, y0 = y[k] + a0 * sy, x1 = x[k] + a1 * sx, y1 = y[k] + a1 * sy;
        const Vector6 w0 = frame_b.W(x0, y0, nu);
        const double mu_0 = mu_at(x0, y0);
        h.AddSegment(w0, frame_b.W(x1, y1, nu) - w0, mu_0, mu_at(x1, y1) - mu_0,
                     (dm > 0 ? kink : -kink) * (a1 - a0) * length);
      }
    }
  });
  // T K Tᵀ, T = diag(Mᵀ, I).
  Matrix6 t = Matrix6::Identity();
  t.topLeftCorner<3, 3>() = s.derivative().m.transpose();
  *out = t * h.Full() * t.transpose();
}

Matrix6 VolumeCostCache::InteriorHessian(const PairState& s, const Execution& execution) const {
  const Impl& m = *impl_;
  if (!m.built || m.fell_back || m.state != &s || m.reference != &s.reference() ||
      m.remeshes != s.surface_version()) {
    return InteriorVolumeHessian(s, execution);  // no overlay kept for this state here
  }
  const int32_t na = m.reference->mesh.num_triangles();
  const bool weighted = !m.weight_a.empty();
  // Chunks of A's triangles (bounds from its size only), summed in order:
  // the same sum on any number of threads.
  const int chunks = ChunksFor(na, 4096);
  std::vector<Matrix6> parts(static_cast<std::size_t>(chunks), Matrix6::Zero());
  ForEachChunk(execution, na, chunks, [&](int part, int64_t lo, int64_t hi) {
    if (weighted) {
      m.Curvature<true>(s, static_cast<int32_t>(lo), static_cast<int32_t>(hi), &parts[part]);
    } else {
      m.Curvature<false>(s, static_cast<int32_t>(lo), static_cast<int32_t>(hi), &parts[part]);
    }
  });
  Matrix6 total = parts[0];
  for (int c = 1; c < chunks; ++c) total += parts[c];
  return total;
}

}  // namespace surfreg
