#include "registration/axial_cost.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include <Eigen/Geometry>

#include "measure/tasks.h"
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

// What every node's residual reads, gathered once per evaluation.
struct NodeContext {
  NodeContext(const PairState& s, const AxialSettings& settings, bool with_jacobians, AxialResiduals* residuals)
      : state(s), a(s.reference()), mesh_b(s.moving_mesh()), na(a.xy.size()),
        mt(s.derivative().m.transpose()), bxy(s.moved_xy()), bz(s.moved_z()), bq(s.moved_q()),
        mask(settings.mask.get()), normal(settings.normal_distance), mu(a.weight), weighted(!mu.empty()),
        inner_a(s.reference_interior()), inner_b(s.moving_interior()), a_cosine(s.reference_cosine()),
        b_normal(s.moving_normal()), rotation(s.derivative().rotation), jacobians(with_jacobians),
        out(residuals), node_weight(residuals->node_weight), d_weight(residuals->d_weight) {}
  const PairState& state;
  const ReferenceSide& a;
  const Triangulation& mesh_b;
  const std::size_t na;
  const Eigen::Matrix3d mt;
  const std::vector<Point2>& bxy;
  const std::vector<double>& bz;
  const std::vector<Eigen::Vector3d>& bq;
  const MaskRegion* mask;
  const bool normal;
  const std::vector<double>& mu;
  const bool weighted;
  const std::vector<uint8_t>& inner_a;
  const std::vector<uint8_t>& inner_b;
  const std::vector<double>& a_cosine;
  const std::vector<Eigen::Vector3d>& b_normal;
  const Eigen::Matrix3d& rotation;
  const bool jacobians;
  AxialResiduals* out;
  // Each node's share of the normalization, μ τ², and its derivative (the
  // residuals' scratch).
  UninitializedVector<double>& node_weight;
  UninitializedVector<std::array<double, 6>>& d_weight;

  void ReferenceNode(std::size_t i);  // node i of A in Ω: its residual (and Jacobian, weight share)
  void MovingNode(std::size_t j);     // node j of B in Ω: likewise
};

// Its gap to the moved B (tapered, weighted).
void NodeContext::ReferenceNode(std::size_t i) {
  const Location& loc = state.a_in_b()[i];
  if (mask != nullptr && !InsideMask(*mask, a.xy[i])) return;
  if (weighted && !(mu[i] > 0.0)) return;
  const int32_t* v = &mesh_b.triangles[3 * loc.triangle];
  const auto& l = loc.barycentric;
  // The taper τ: B's inner-vertex flags interpolated on the moved triangle.
  const double taper = l[0] * inner_b[v[0]] + l[1] * inner_b[v[1]] + l[2] * inner_b[v[2]];
  if (!(taper > 0.0)) return;
  // normal_distance: the cosine of B''s slope, linear on the moved
  // triangle from its corners' moved unit normals (continuous from one
  // triangle to the next, unlike each triangle's own slope).
  double cosine = 1.0;
  Eigen::Vector3d u[3] = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()};
  if (normal) {
    for (int c = 0; c < 3; ++c) u[c] = rotation * b_normal[v[c]];
    cosine = l[0] * u[0].z() + l[1] * u[1].z() + l[2] * u[2].z();
    if (!(cosine > 0.0)) return;  // overturned: the weight has reached 0
  }
  const double root = weighted ? std::sqrt(mu[i]) : 1.0;  // μ_i is fixed: a constant factor
  const double mu_i = weighted ? mu[i] : 1.0;
  node_weight[i] = mu_i * taper * taper;
  const double gap = l[0] * bz[v[0]] + l[1] * bz[v[1]] + l[2] * bz[v[2]] - a.z[i];
  const double untapered = root * cosine * gap;
  out->r[i] = taper * untapered;
  out->active[i] = 1;
  if (!jacobians) return;
  const Eigen::Vector3d n = UpNormal(bxy[v[0]], bxy[v[1]], bxy[v[2]], bz[v[0]], bz[v[1]], bz[v[2]]);
  const Eigen::Vector3d q = l[0] * bq[v[0]] + l[1] * bq[v[1]] + l[2] * bq[v[2]];
  // A field f linear on the moved triangle, read at the fixed xy of node
  // i, moves as the height does, with (−∂f/∂x, −∂f/∂y, 0) in place of n.
  auto eulerian = [&](double f0, double f1, double f2) {
    const Eigen::Vector3d up = UpNormal(bxy[v[0]], bxy[v[1]], bxy[v[2]], f0, f1, f2);
    return Eigen::Vector3d(up.x(), up.y(), 0.0);
  };
  Eigen::Vector3d d_rotation = -(mt * n.cross(q)) * cosine, d_translation = n * cosine;
  if (normal) {
    // The corners' normals turn with the rotation (du = Mδω × u), and
    // their z is the cosine: d(u_z)/dω = Mᵀ(u × e_z).
    const Eigen::Vector3d n_cosine = eulerian(u[0].z(), u[1].z(), u[2].z());
    const Eigen::Vector3d turned = mt * (l[0] * u[0] + l[1] * u[1] + l[2] * u[2]).cross(Eigen::Vector3d::UnitZ());
    d_rotation += gap * (turned - mt * n_cosine.cross(q));
    d_translation += gap * n_cosine;
  }
  const Eigen::Vector3d n_taper = eulerian(inner_b[v[0]], inner_b[v[1]], inner_b[v[2]]);
  const Eigen::Vector3d dt_rotation = -(mt * n_taper.cross(q));
  Store(taper * root * d_rotation + untapered * dt_rotation,
        taper * root * d_translation + untapered * n_taper, &out->jacobian[i]);
  Store(2.0 * mu_i * taper * dt_rotation, 2.0 * mu_i * taper * n_taper, &d_weight[i]);
}

// Its gap to A (tapered, weighted by μ where it lands).
void NodeContext::MovingNode(std::size_t j) {
  const Location& loc = state.b_in_a()[j];
  if (mask != nullptr && !InsideMask(*mask, bxy[j])) return;
  const int32_t* v = &a.mesh.triangles[3 * loc.triangle];
  const auto& l = loc.barycentric;
  double w = 1.0;
  if (weighted) {
    w = l[0] * mu[v[0]] + l[1] * mu[v[1]] + l[2] * mu[v[2]];
    if (!(w > 0.0)) return;
  }
  // The taper τ: A's inner-vertex flags interpolated on A's triangle.
  const double taper = l[0] * inner_a[v[0]] + l[1] * inner_a[v[1]] + l[2] * inner_a[v[2]];
  if (!(taper > 0.0)) return;
  // normal_distance: the cosine of A's slope, linear on A's triangle.
  const double cosine =
      normal ? l[0] * a_cosine[v[0]] + l[1] * a_cosine[v[1]] + l[2] * a_cosine[v[2]] : 1.0;
  if (!(cosine > 0.0)) return;
  const std::size_t k = na + j;
  const double gap = l[0] * a.z[v[0]] + l[1] * a.z[v[1]] + l[2] * a.z[v[2]] - bz[j];
  const double r = cosine * gap;
  const double root = std::sqrt(w);
  out->r[k] = taper * root * r;
  out->active[k] = 1;
  node_weight[k] = w * taper * taper;
  if (!jacobians) return;
  const Eigen::Vector3d n = UpNormal(a.xy[v[0]], a.xy[v[1]], a.xy[v[2]], a.z[v[0]], a.z[v[1]], a.z[v[2]]);
  // A field linear on the A triangle (μ, τ, the cosine) has a gradient g
  // that moves with x'_j: d/dt = g, d/dω = −Mᵀ(g × q).
  auto gradient_of = [&](double f0, double f1, double f2) {
    const Eigen::Vector3d up = UpNormal(a.xy[v[0]], a.xy[v[1]], a.xy[v[2]], f0, f1, f2);
    return Eigen::Vector3d(-up.x(), -up.y(), 0.0);
  };
  Eigen::Vector3d d_rotation = cosine * (mt * n.cross(bq[j])), d_translation = -cosine * n;
  if (normal) {
    const Eigen::Vector3d g = gradient_of(a_cosine[v[0]], a_cosine[v[1]], a_cosine[v[2]]);
    d_rotation -= gap * (mt * g.cross(bq[j]));
    d_translation += gap * g;
  }
  Eigen::Vector3d dw_rotation = Eigen::Vector3d::Zero(), dw_translation = Eigen::Vector3d::Zero();
  if (weighted) {
    dw_translation = gradient_of(mu[v[0]], mu[v[1]], mu[v[2]]);
    dw_rotation = -(mt * dw_translation.cross(bq[j]));
    const double half = r / (2.0 * root);
    d_rotation = root * d_rotation + half * dw_rotation;
    d_translation = root * d_translation + half * dw_translation;
  }
  const Eigen::Vector3d dt_translation = gradient_of(inner_a[v[0]], inner_a[v[1]], inner_a[v[2]]);
  const Eigen::Vector3d dt_rotation = -(mt * dt_translation.cross(bq[j]));
  const double untapered = root * r;
  Store(taper * d_rotation + untapered * dt_rotation,
        taper * d_translation + untapered * dt_translation, &out->jacobian[k]);
  const double t2 = taper * taper;
  Store(t2 * dw_rotation + 2.0 * w * taper * dt_rotation,
        t2 * dw_translation + 2.0 * w * taper * dt_translation, &d_weight[k]);
}

// trim_fraction: the largest |r| dropped; then the count of active nodes.
void Trim(const AxialSettings& settings, bool jacobians, AxialResiduals* out) {
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
}

// normalize_count: r scaled to N / Σ μ τ² over the active nodes (and the
// Jacobian by the scale's derivative too).
void Normalize(const AxialSettings& settings, const NodeContext& ctx, AxialResiduals* out) {
  const bool jacobians = ctx.jacobians;
  const auto& node_weight = ctx.node_weight;
  const auto& d_weight = ctx.d_weight;
  // Σ μ τ² over the active nodes, and its derivative.
  double total = 0.0;
  Eigen::Matrix<double, 6, 1> d_total = Eigen::Matrix<double, 6, 1>::Zero();
  for (std::size_t k = 0; k < out->r.size(); ++k) {
    if (!out->active[k]) continue;
    total += node_weight[k];
    if (jacobians) d_total += Eigen::Map<const Eigen::Matrix<double, 6, 1>>(d_weight[k].data());
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

}  // namespace

void ComputeAxialResiduals(const PairState& state, const AxialSettings& settings, bool jacobians,
                           AxialResiduals* out) {
  const std::size_t na = state.reference().xy.size(), nb = state.moving().points.size();
  const Execution& execution = state.execution();
  AssignInChunks(execution, na + nb, 0.0, &out->r);
  AssignInChunks(execution, na + nb, uint8_t{0}, &out->active);
  if (jacobians) AssignInChunks(execution, na + nb, std::array<double, 6>{}, &out->jacobian);
  NodeContext ctx(state, settings, jacobians, out);
  AssignInChunks(execution, na + nb, 0.0, &ctx.node_weight);
  AssignInChunks(execution, jacobians ? na + nb : 0, std::array<double, 6>{}, &ctx.d_weight);
  // Each node writes only its own entries: chunks of nodes side by side.
  const int64_t n_a = settings.reference_nodes ? static_cast<int64_t>(na) : 0;
  const int64_t n_b = settings.moving_nodes ? static_cast<int64_t>(nb) : 0;
  const int chunks = ChunksFor(n_a + n_b, 2048);
  std::vector<int64_t> overlap(chunks, 0);
  // (Counted in a local: the chunks' slots share cache lines.)
  ForEachChunk(state.execution(), n_a + n_b, chunks, [&](int c, int64_t begin, int64_t end) {
    int64_t count = 0;
    for (int64_t k = begin; k < end; ++k) {
      if (k < n_a) {
        const std::size_t i = static_cast<std::size_t>(k);
        // Nodes of either surface's junk (measure/domain.h) are not in Ω.
        if (!ctx.a.domain_vertex[i] || !state.OnMovingSurface(state.a_in_b()[i])) continue;
        ++count;
        ctx.ReferenceNode(i);
      } else {
        const std::size_t j = static_cast<std::size_t>(k - n_a);
        if (!state.moving_node_active(j) || !state.OnReferenceSurface(state.b_in_a()[j])) continue;
        ++count;
        ctx.MovingNode(j);
      }
    }
    overlap[c] = count;
  });
  out->overlap_count = std::accumulate(overlap.begin(), overlap.end(), int64_t{0});
  Trim(settings, jacobians, out);
  Normalize(settings, ctx, out);
}

}  // namespace surfreg
