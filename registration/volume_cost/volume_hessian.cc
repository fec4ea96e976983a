#include "registration/volume_cost/volume_hessian.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Geometry>

#include "measure/gap_volume.h"
#include "registration/volume_cost/volume_accumulator.h"

namespace surfreg {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

// Sums the line term over the cells it is given (one per thread).
class alignas(64) ZeroLineSum {  // a cache line of its own (one per chunk)
 public:
  ZeroLineSum(const PairState& state, const MaskRegion* mask)
      : state_(state), mask_(mask),
        weight_(state.reference().weight.empty() ? nullptr : &state.reference().weight),
        mt_(state.derivative().m.transpose()) {}

  void operator()(const OverlayCell& cell) {
    if (!state_.reference().domain[cell.triangle_a] || !state_.active_b()[cell.triangle_b]) return;
    SetTriangles(cell);
    if (mask_ == nullptr) {
      AddPiece(cell.vertices.data(), cell.num_vertices, 1.0);
      return AddEdges(nullptr, 1.0);
    }
    const Point2* p = cell.vertices.data();
    Point2 lo = p[0], hi = p[0];
    for (int k = 1; k < cell.num_vertices; ++k) {
      lo = {std::min(lo.x, p[k].x), std::min(lo.y, p[k].y)};
      hi = {std::max(hi.x, p[k].x), std::max(hi.y, p[k].y)};
    }
    Point2 piece[12];
    ForEachMaskTriangle(*mask_, lo, hi, [&](int32_t k) {
      const int m = ClipByTriangle(p, cell.num_vertices, mask_->triangles[k], piece);
      if (m < 3) return;
      AddPiece(piece, m, mask_->sign[k]);  // a hole's triangle takes back its ring's
      AddEdges(&mask_->triangles[k], mask_->sign[k]);
    });
  }

  Matrix6 hessian = Matrix6::Zero();

 private:
  void SetTriangles(const OverlayCell& cell) {
    if (cell.triangle_a != last_a_) {
      last_a_ = cell.triangle_a;
      volume_internal::ReferenceTriangle(state_.reference(), weight_, cell.triangle_a, &fa_, ta_, &mu_);
    }
    if (cell.triangle_b == last_b_) return;
    last_b_ = cell.triangle_b;
    tb_ = volume_internal::MovedTriangleOf(state_, cell.triangle_b);
    for (int i = 0; i < 3; ++i) kink_[i] = Kink(cell.triangle_b, i);
  }

  // The jump of ∇F̂_B' · ν across edge i of moved B triangle t (ν its normal;
  // either side's: the jump's sign does not depend on which), 0 on B's boundary.
  double Kink(int32_t t, int i) const {
    if (state_.MovingBoundaryEdge(t, i)) return 0.0;
    const Triangulation& mesh = state_.moving_mesh();
    const int32_t next = mesh.neighbors[3 * t + i];
    const int32_t* v = &mesh.triangles[3 * next];
    const auto& xy = state_.moved_xy();
    const auto& z = state_.moved_z();
    const Plane other = PlaneThrough(xy[v[0]], xy[v[1]], xy[v[2]], z[v[0]], z[v[1]], z[v[2]]);
    const int32_t* own = &mesh.triangles[3 * t];
    const Point2 e0 = xy[own[(i + 1) % 3]], e1 = xy[own[(i + 2) % 3]];
    const double ex = e1.x - e0.x, ey = e1.y - e0.y, length = std::hypot(ex, ey);
    if (!(length > 0)) return 0.0;
    // Outward (to `next`): the interior is on the left of e0 → e1.
    return ((other.gx - tb_.height.gx) * ey - (other.gy - tb_.height.gy) * ex) / length;
  }

  double Mu(const Point2& p) const { return weight_ == nullptr ? 1.0 : mu_.At(p); }

  // g = ∂_θF̂_B' at p: rotation rows −Mᵀ(n × q), translation rows n.
  Vector6 G(const Point2& p) const {
    Vector6 g;
    g.head<3>() = -(mt_ * tb_.normal.cross(tb_.QAt(p)));
    g.tail<3>() = tb_.normal;
    return g;
  }

  // A convex piece of a cell (mask sign `sign`): the segment where d = 0
  // crosses it.
  void AddPiece(const Point2* p, int n, double sign) {
    const double gx = tb_.height.gx - fa_.gx, gy = tb_.height.gy - fa_.gy;
    const double slope = std::sqrt(gx * gx + gy * gy);
    if (!(slope > 0)) return;
    double d[12];
    for (int k = 0; k < n; ++k) d[k] = tb_.height.At(p[k]) - fa_.At(p[k]);
    // The zero segment's ends: crossings inside edges, and corners where
    // d = 0 (a zero along a whole edge is shared with the neighbour: taken
    // by the cell on its d > 0 side only, so once).
    Point2 end[2];
    int ends = 0;
    for (int k = 0; k < n && ends < 2; ++k) {
      const int l = k + 1 == n ? 0 : k + 1;
      if (d[k] == 0) {
        if (d[l] == 0 && !(d[(k + 2) % n] > 0)) return;
        end[ends++] = p[k];
      } else if ((d[k] > 0 && d[l] < 0) || (d[k] < 0 && d[l] > 0)) {
        const double s = d[k] / (d[k] - d[l]);
        end[ends++] = {p[k].x + s * (p[l].x - p[k].x), p[k].y + s * (p[l].y - p[k].y)};
      }
    }
    if (ends < 2) return;
    const double length = std::hypot(end[1].x - end[0].x, end[1].y - end[0].y);
    if (!(length > 0)) return;
    const Point2 mid{0.5 * (end[0].x + end[1].x), 0.5 * (end[0].y + end[1].y)};
    // μ g gᵀ is quadratic (cubic with weights) along the segment: Simpson is exact.
    const Vector6 g0 = G(end[0]), gm = G(mid), g1 = G(end[1]);
    const double scale = sign * 2.0 * length / (6.0 * slope);
    hessian += scale * (Mu(end[0]) * g0 * g0.transpose() + 4.0 * Mu(mid) * gm * gm.transpose() +
                        Mu(end[1]) * g1 * g1.transpose());
  }

  // ∫ μ sign(d) ∂_θg over this cell's share of B's edges: g jumps by
  // −κ ν·u_xy across an edge of kink κ that moves at ν·u_xy, so ∂_θg holds
  // κ w wᵀ δ_edge with w = ν·u_xy (rows: Mᵀ(q × ν), ν). Each cell takes half
  // of its B triangle's edges within its A triangle (and mask triangle): the
  // cells on both sides of an edge make it whole.
  void AddEdges(const std::array<Point2, 3>* mask_triangle, double sign) {
    const Triangulation& mesh_b = state_.moving_mesh();
    const int32_t* v = &mesh_b.triangles[3 * last_b_];
    const auto& xy = state_.moved_xy();
    const auto& q = state_.moved_q();
    for (int i = 0; i < 3; ++i) {
      if (kink_[i] == 0) continue;
      const int32_t va = v[(i + 1) % 3], vb = v[(i + 2) % 3];
      const Point2 e0 = xy[va], e1 = xy[vb];
      double s0 = 0.0, s1 = 1.0;
      if (!volume_internal::ClipSegment(e0, e1, ta_, mask_triangle, &s0, &s1)) continue;
      const double ex = e1.x - e0.x, ey = e1.y - e0.y;
      const double length = std::hypot(ex, ey);
      const Eigen::Vector3d nu(ey / length, -ex / length, 0.0);
      auto point = [&](double s) { return Point2{e0.x + s * ex, e0.y + s * ey}; };
      auto d = [&](double s) { const Point2 p = point(s); return tb_.height.At(p) - fa_.At(p); };
      auto w = [&](double s) {
        Vector6 out;
        out.head<3>() = mt_ * ((1 - s) * q[va] + s * q[vb]).cross(nu);
        out.tail<3>() = nu;
        return out;
      };
      double cuts[3];
      const int pieces = volume_internal::SignPieces(d(s0), d(s1), s0, s1, cuts);
      for (int k = 0; k < pieces; ++k) {
        const double a0 = cuts[k], a1 = cuts[k + 1], am = 0.5 * (a0 + a1);
        const double side = d(am) > 0 ? 1.0 : d(am) < 0 ? -1.0 : 0.0;
        if (side == 0) continue;
        const Vector6 w0 = w(a0), wm = w(am), w1 = w(a1);
        hessian += sign * side * 0.5 * kink_[i] * (a1 - a0) * length / 6.0 *
                   (Mu(point(a0)) * w0 * w0.transpose() + 4.0 * Mu(point(am)) * wm * wm.transpose() +
                    Mu(point(a1)) * w1 * w1.transpose());
      }
    }
  }

  const PairState& state_;
  const MaskRegion* mask_;
  const std::vector<double>* weight_;
  Eigen::Matrix3d mt_;
  int32_t last_a_ = -1, last_b_ = -1;
  Plane fa_, mu_;
  Point2 ta_[3];
  double kink_[3] = {0, 0, 0};  // of the current B triangle's edges
  volume_internal::MovedTriangle tb_;
};

}  // namespace

Matrix6 InteriorVolumeHessian(const PairState& state, const Execution& execution, const MaskRegion* mask) {
  std::vector<ZeroLineSum> parts(volume_internal::StateChunks(state), ZeroLineSum(state, mask));
  volume_internal::ForEachCellOfState(state, execution, parts);
  Matrix6 hessian = parts[0].hessian;
  for (std::size_t c = 1; c < parts.size(); ++c) hessian += parts[c].hessian;
  return hessian;
}

}  // namespace surfreg
