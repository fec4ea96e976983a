#include "registration/axial_cost.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "measure/weights.h"

namespace surfreg {
namespace {

// (−∂F/∂x, −∂F/∂y, 1) of the plane through three points.
Eigen::Vector3d UpNormal(const Point2& p0, const Point2& p1, const Point2& p2, double z0,
                         double z1, double z2) {
  const double ax = p1.x - p0.x, ay = p1.y - p0.y, az = z1 - z0;
  const double bx = p2.x - p0.x, by = p2.y - p0.y, bz = z2 - z0;
  const double det = ax * by - ay * bx;  // > 0: counter-clockwise, not folded
  const double gx = (az * by - ay * bz) / det;
  const double gy = (ax * bz - az * bx) / det;
  return Eigen::Vector3d(-gx, -gy, 1.0);
}

void Store(const Eigen::Vector3d& rotation_part, const Eigen::Vector3d& translation_part,
           std::array<double, 6>* row) {
  for (int k = 0; k < 3; ++k) {
    (*row)[k] = rotation_part[k];
    (*row)[3 + k] = translation_part[k];
  }
}

}  // namespace

void ComputeAxialResiduals(const PairState& state, const AxialSettings& settings, bool jacobians,
                           AxialResiduals* out) {
  const ReferenceSide& a = state.reference();
  const MovingSide& b = state.moving();
  const Triangulation& mesh_b = state.moving_mesh();
  const std::size_t na = a.xy.size(), nb = b.points.size();
  out->r.assign(na + nb, 0.0);
  out->active.assign(na + nb, 0);
  if (jacobians) out->jacobian.assign(na + nb, std::array<double, 6>{});
  const Eigen::Matrix3d mt = state.derivative().m.transpose();
  const std::vector<Point2>& bxy = state.moved_xy();
  const std::vector<double>& bz = state.moved_z();
  const std::vector<Eigen::Vector3d>& bq = state.moved_q();
  const bool masked = !settings.mask.empty();
  const bool normal = settings.normal_distance;
  const std::vector<double>& mu = a.weight;
  const bool weighted = !mu.empty();
  // μ per node, and dμ_j/dθ per B node (for the normalization's derivative).
  std::vector<double> node_weight(weighted ? na + nb : 0, 0.0);
  std::vector<std::array<double, 6>> d_weight(weighted && jacobians ? nb : 0,
                                              std::array<double, 6>{});

  int64_t overlap = 0;
  for (std::size_t i = 0; i < na; ++i) {
    const Location& loc = state.a_in_b()[i];
    // Nodes of either surface's junk (measure/domain.h) are not in Ω.
    if (!a.domain_vertex[i] || !state.OnMovingSurface(loc)) continue;
    ++overlap;
    if (masked && !InsidePolygon(settings.mask, a.xy[i])) continue;
    if (weighted && !(mu[i] > 0.0)) continue;
    const int32_t* v = &mesh_b.triangles[3 * loc.triangle];
    const auto& l = loc.barycentric;
    const double root = weighted ? std::sqrt(mu[i]) : 1.0;  // μ_i is fixed: a constant factor
    if (weighted) node_weight[i] = mu[i];
    const double gap = l[0] * bz[v[0]] + l[1] * bz[v[1]] + l[2] * bz[v[2]] - a.z[i];
    Eigen::Vector3d n(0.0, 0.0, 1.0);
    if (jacobians || normal) n = UpNormal(bxy[v[0]], bxy[v[1]], bxy[v[2]], bz[v[0]], bz[v[1]], bz[v[2]]);
    const double cosine = normal ? 1.0 / n.norm() : 1.0;
    out->r[i] = root * cosine * gap;
    out->active[i] = 1;
    if (!jacobians) continue;
    const Eigen::Vector3d q = l[0] * bq[v[0]] + l[1] * bq[v[1]] + l[2] * bq[v[2]];
    Eigen::Vector3d d_rotation = -(mt * n.cross(q)) * cosine;
    // The moved triangle's unit normal u = n/|n| turns with the rotation
    // (du = Mδω × u) and the cosine is u_z: d(cos)/dω = Mᵀ(u × e_z).
    if (normal) d_rotation += gap * cosine * (mt * n.cross(Eigen::Vector3d::UnitZ()));
    Store(d_rotation * root, n * (cosine * root), &out->jacobian[i]);
  }
  for (std::size_t j = 0; j < nb; ++j) {
    const Location& loc = state.b_in_a()[j];
    if (!state.moving_node_active(j) || !state.OnReferenceSurface(loc)) continue;
    ++overlap;
    if (masked && !InsidePolygon(settings.mask, bxy[j])) continue;
    const int32_t* v = &a.mesh.triangles[3 * loc.triangle];
    const auto& l = loc.barycentric;
    double w = 1.0;
    if (weighted) {
      w = l[0] * mu[v[0]] + l[1] * mu[v[1]] + l[2] * mu[v[2]];
      if (!(w > 0.0)) continue;
    }
    const std::size_t k = na + j;
    Eigen::Vector3d n(0.0, 0.0, 1.0);
    if (jacobians || normal) {
      n = UpNormal(a.xy[v[0]], a.xy[v[1]], a.xy[v[2]], a.z[v[0]], a.z[v[1]], a.z[v[2]]);
    }
    // A's slope is constant within its triangle: the cosine is a constant factor.
    const double cosine = normal ? 1.0 / n.norm() : 1.0;
    const double r = cosine * (l[0] * a.z[v[0]] + l[1] * a.z[v[1]] + l[2] * a.z[v[2]] - bz[j]);
    const double root = std::sqrt(w);
    out->r[k] = root * r;
    out->active[k] = 1;
    if (weighted) node_weight[k] = w;
    if (!jacobians) continue;
    Eigen::Vector3d d_rotation = cosine * (mt * n.cross(bq[j])), d_translation = -cosine * n;
    if (weighted) {
      // μ(x'_j) is linear on the A triangle: its gradient g moves with x'_j.
      const Eigen::Vector3d up =
          UpNormal(a.xy[v[0]], a.xy[v[1]], a.xy[v[2]], mu[v[0]], mu[v[1]], mu[v[2]]);
      const Eigen::Vector3d g(-up.x(), -up.y(), 0.0);
      const Eigen::Vector3d dw_rotation = -(mt * g.cross(bq[j]));
      Store(dw_rotation, g, &d_weight[j]);
      const double half = r / (2.0 * root);
      d_rotation = root * d_rotation + half * dw_rotation;
      d_translation = root * d_translation + half * g;
    }
    Store(d_rotation, d_translation, &out->jacobian[k]);
  }
  out->overlap_count = overlap;

  int64_t active = 0;
  for (uint8_t flag : out->active) active += flag;
  out->trim_threshold = 0.0;
  if (settings.trim_fraction > 0.0 && active > 0) {
    std::vector<double> magnitudes;
    magnitudes.reserve(active);
    for (std::size_t k = 0; k < out->r.size(); ++k) {
      if (out->active[k]) magnitudes.push_back(std::fabs(out->r[k]));
    }
    const std::size_t keep = static_cast<std::size_t>(
        std::ceil((1.0 - settings.trim_fraction) * static_cast<double>(magnitudes.size())));
    if (keep > 0 && keep < magnitudes.size()) {
      std::nth_element(magnitudes.begin(), magnitudes.begin() + (keep - 1), magnitudes.end());
      const double threshold = magnitudes[keep - 1];
      out->trim_threshold = threshold;
      for (std::size_t k = 0; k < out->r.size(); ++k) {
        if (out->active[k] && std::fabs(out->r[k]) > threshold) {
          out->active[k] = 0;
          out->r[k] = 0.0;
          if (jacobians) out->jacobian[k] = {};
          --active;
        }
      }
    }
  }
  out->active_count = active;
  // Σ μ over the active nodes, and its derivative (B's μ_j only).
  double total = static_cast<double>(active);
  Eigen::Matrix<double, 6, 1> d_total = Eigen::Matrix<double, 6, 1>::Zero();
  if (weighted) {
    total = 0.0;
    for (std::size_t k = 0; k < out->r.size(); ++k) {
      if (!out->active[k]) continue;
      total += node_weight[k];
      if (jacobians && k >= na) {
        d_total += Eigen::Map<const Eigen::Matrix<double, 6, 1>>(d_weight[k - na].data());
      }
    }
  }
  out->active_weight = total;
  if (settings.normalize_count > 0 && total > 0) {
    // r̃ = s r with s = sqrt(N / W(θ)): dr̃ = s dr + r ds, ds = −s dW / (2W).
    const double scale = std::sqrt(settings.normalize_count / total);
    const Eigen::Matrix<double, 6, 1> d_scale = -0.5 * scale / total * d_total;
    for (std::size_t k = 0; k < out->r.size(); ++k) {
      if (!out->active[k]) continue;
      if (jacobians) {
        for (int c = 0; c < 6; ++c) {
          out->jacobian[k][c] = scale * out->jacobian[k][c] + out->r[k] * d_scale[c];
        }
      }
      out->r[k] *= scale;
    }
  }
}

}  // namespace surfreg
