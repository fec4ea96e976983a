#include "faces/asymmetry_index.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include "faces/height_mesh.h"
#include "measure/input_error.h"
#include "measure/mask_region.h"
#include "measure/spatial_sort.h"

namespace surfreg {
namespace {

using faces_internal::HeightMesh;
using faces_internal::LocateHeight;
using faces_internal::MakeHeightMesh;

constexpr double kPi = 3.14159265358979323846;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// A corner of a clipped piece of a face triangle; every field is linear over
// the triangle, so interpolating along an edge is exact.
struct Corner {
  double x, y, d, s;  // local xy, difference, side of the plane n·p − offset
};
// A triangle clipped by at most 3 + 4 lines has at most 10 corners.
struct Piece {
  Corner c[12];
  int n = 0;
};

// Keeps the part of `in` where g ≥ 0 (Sutherland–Hodgman, one line).
template <typename G>
Piece Clip(const Piece& in, G&& g) {
  Piece out;
  for (int k = 0; k < in.n; ++k) {
    const Corner& a = in.c[k];
    const Corner& b = in.c[(k + 1) % in.n];
    const double ga = g(a), gb = g(b);
    if (ga >= 0) out.c[out.n++] = a;
    if ((ga >= 0) != (gb >= 0)) {
      const double t = ga / (ga - gb);
      out.c[out.n++] = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.d + t * (b.d - a.d),
                        a.s + t * (b.s - a.s)};
    }
  }
  return out;
}

struct Sums {
  double area = 0, d = 0, d2 = 0, abs = 0, max_abs = 0;
};

// ∫1, ∫d, ∫d² of the piece (convex, counter-clockwise) by a fan of triangles.
void Integrate(const Piece& p, Sums* sums, double* abs_sign_integral, double sign) {
  for (int k = 1; k + 1 < p.n; ++k) {
    const Corner &a = p.c[0], &b = p.c[k], &c = p.c[k + 1];
    const double area = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    const double mean = (a.d + b.d + c.d) / 3;
    if (abs_sign_integral != nullptr) {
      *abs_sign_integral += sign * area * mean;
      continue;
    }
    sums->area += area;
    sums->d += area * mean;
    sums->d2 += area / 6 * (a.d * a.d + b.d * b.d + c.d * c.d + a.d * b.d + b.d * c.d + c.d * a.d);
  }
}

void Accumulate(const Piece& p, Sums* sums) {
  if (p.n < 3) return;
  Integrate(p, sums, nullptr, 1);
  Integrate(Clip(p, [](const Corner& c) { return c.d; }), sums, &sums->abs, 1);
  Integrate(Clip(p, [](const Corner& c) { return -c.d; }), sums, &sums->abs, -1);
  for (int k = 0; k < p.n; ++k) sums->max_abs = std::max(sums->max_abs, std::abs(p.c[k].d));
}

// What decides a region: a y band, a side of the plane, or a polygon's triangles.
struct RegionShape {
  enum Kind { kWhole, kBand, kSide, kPolygon } kind = kWhole;
  double lo = 0, hi = 0;                      // kBand, local y
  double side = 1;                            // kSide: +1 left, −1 right
  std::vector<std::array<Point2, 3>> pieces;  // kPolygon, local, counter-clockwise
  std::vector<Point2> outline;                // kPolygon, for the node test
};

bool NodeInside(const RegionShape& r, const Point2& p, double s) {
  switch (r.kind) {
    case RegionShape::kWhole:
      return true;
    case RegionShape::kBand:
      return p.y >= r.lo && p.y <= r.hi;
    case RegionShape::kSide:
      return r.side * s >= 0;
    case RegionShape::kPolygon:
      return InsidePolygon(r.outline, p);
  }
  return false;
}

// The triangle `t` (three corners) within the region, each piece passed to f.
template <typename F>
void ForEachPiece(const RegionShape& r, const Piece& t, F&& f) {
  switch (r.kind) {
    case RegionShape::kWhole:
      f(t);
      return;
    case RegionShape::kBand: {
      const double lo = r.lo, hi = r.hi;
      f(Clip(Clip(t, [lo](const Corner& c) { return c.y - lo; }),
             [hi](const Corner& c) { return hi - c.y; }));
      return;
    }
    case RegionShape::kSide: {
      const double side = r.side;
      f(Clip(t, [side](const Corner& c) { return side * c.s; }));
      return;
    }
    case RegionShape::kPolygon: {
      double lo_x = t.c[0].x, hi_x = lo_x, lo_y = t.c[0].y, hi_y = lo_y;
      for (int k = 1; k < 3; ++k) {
        lo_x = std::min(lo_x, t.c[k].x), hi_x = std::max(hi_x, t.c[k].x);
        lo_y = std::min(lo_y, t.c[k].y), hi_y = std::max(hi_y, t.c[k].y);
      }
      for (const auto& q : r.pieces) {
        if (std::max({q[0].x, q[1].x, q[2].x}) < lo_x ||
            std::min({q[0].x, q[1].x, q[2].x}) > hi_x ||
            std::max({q[0].y, q[1].y, q[2].y}) < lo_y ||
            std::min({q[0].y, q[1].y, q[2].y}) > hi_y) {
          continue;
        }
        Piece p = t;
        for (int e = 0; e < 3 && p.n >= 3; ++e) {
          const Point2 a = q[e], b = q[(e + 1) % 3];
          p = Clip(p, [a, b](const Corner& c) {
            return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
          });
        }
        f(p);
      }
      return;
    }
  }
}

bool ValidRegionName(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  }
  return true;
}

// σ_n from the face's roughness: each vertex against the least-squares plane
// of its Delaunay neighbours, the residual scaled by that fit's leverage,
// then 1.4826 × the median absolute value (curvature and real features are
// few and large: the median ignores them).
double EstimateNoise(const HeightMesh& f) {
  const std::size_t n = f.xy.size();
  std::vector<int32_t> start(n + 1, 0), items;
  const auto& tri = f.mesh.triangles;
  for (int32_t v : tri) start[v + 1] += 2;
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  items.resize(start[n]);
  std::vector<int32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < tri.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      const int32_t v = tri[t + k];
      items[fill[v]++] = tri[t + (k + 1) % 3];
      items[fill[v]++] = tri[t + (k + 2) % 3];
    }
  }
  std::vector<double> scaled;
  scaled.reserve(n);
  for (std::size_t v = 0; v < n; ++v) {
    auto* first = items.data() + start[v];
    auto* last = items.data() + start[v + 1];
    std::sort(first, last);
    last = std::unique(first, last);
    const int k = static_cast<int>(last - first);
    if (k < 4) continue;
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atz = Eigen::Vector3d::Zero();
    for (auto* j = first; j != last; ++j) {
      const Eigen::Vector3d row(1.0, f.xy[*j].x - f.xy[v].x, f.xy[*j].y - f.xy[v].y);
      ata += row * row.transpose();
      atz += row * f.z[*j];
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * ata.trace())) {
      continue;
    }
    const Eigen::Vector3d coef = ldlt.solve(atz);
    const double leverage = ldlt.solve(Eigen::Vector3d(1, 0, 0))(0);  // e0ᵀ(AᵀA)⁻¹e0 at the vertex
    scaled.push_back(std::abs(f.z[v] - coef(0)) / std::sqrt(1.0 + leverage));
  }
  if (scaled.empty()) return 0.0;
  auto mid = scaled.begin() + static_cast<std::ptrdiff_t>(scaled.size() / 2);
  std::nth_element(scaled.begin(), mid, scaled.end());
  return 1.482602218505602 * *mid;
}

}  // namespace

const std::vector<std::string>& StandardRegionNames() {
  static const std::vector<std::string>* names =
      new std::vector<std::string>{"upper_third", "middle_third", "lower_third", "left", "right"};
  return *names;
}

const RegionIndex* AsymmetryIndices::Find(const std::string& name) const {
  if (name == whole.name) return &whole;
  for (const RegionIndex& r : regions) {
    if (r.name == name) return &r;
  }
  return nullptr;
}

AsymmetryIndices ComputeAsymmetryIndices(const Surface& face, const SymmetryPlane& plane,
                                         const AsymmetryIndexOptions& options) {
  ValidateSurface(face);
  // Regions first: a mistake is reported before any work.
  std::vector<std::string> names = {"face"};
  if (options.standard_regions) {
    names.insert(names.end(), StandardRegionNames().begin(), StandardRegionNames().end());
  }
  for (const FaceRegion& region : options.regions) {
    if (!ValidRegionName(region.name)) {
      throw InputError("asymmetry region '" + region.name +
                       "': a name is letters, digits and '_' only");
    }
    if (std::find(names.begin(), names.end(), region.name) != names.end() ||
        (!options.standard_regions &&
         std::find(StandardRegionNames().begin(), StandardRegionNames().end(), region.name) !=
             StandardRegionNames().end())) {
      throw InputError("asymmetry region '" + region.name + "': the name is used twice (or is " +
                       "a standard region's or 'face')");
    }
    names.push_back(region.name);
    std::string error;
    if (!ValidMaskRings(
            {region.polygon}, [&](std::size_t) { return "asymmetry region '" + region.name + "'"; },
            &error)) {
      throw InputError(error);
    }
  }

  const std::size_t n = face.size();
  const Surface mirror = ReflectSurface(face, plane);
  const Eigen::Vector3d shift(mirror.origin[0] - face.origin[0], mirror.origin[1] - face.origin[1],
                              mirror.origin[2] - face.origin[2]);
  std::vector<Point2> mirror_xy(n);
  std::vector<double> mirror_z(n);
  for (std::size_t i = 0; i < n; ++i) {
    mirror_xy[i] = {mirror.xy[i].x + shift.x(), mirror.xy[i].y + shift.y()};
    mirror_z[i] = mirror.z[i] + shift.z();
  }
  const HeightMesh f = MakeHeightMesh(face.xy, face.z);
  const HeightMesh m = MakeHeightMesh(std::move(mirror_xy), mirror_z);

  // The plane in the face's local frame: n·p = offset_local.
  const Eigen::Vector3d normal(plane.normal[0], plane.normal[1], plane.normal[2]);
  const Eigen::Vector3d origin(face.origin[0], face.origin[1], face.origin[2]);
  const double offset_local = plane.offset - normal.dot(origin);
  // Tilt directions: towards y (about z) and the third axis (≈ towards z).
  Eigen::Vector3d u = Eigen::Vector3d::UnitY() - normal.y() * normal;
  if (u.norm() < 0.3) u = Eigen::Vector3d::UnitZ() - normal.z() * normal;
  u.normalize();
  const Eigen::Vector3d v = normal.cross(u);

  AsymmetryIndices out;
  out.noise_sigma = options.noise_sigma >= 0 ? options.noise_sigma : EstimateNoise(f);
  std::vector<double> d(n, kNaN), noise_var(n, 0.0), side(n, 0.0);
  std::vector<Eigen::Vector3d> jacobian(n, Eigen::Vector3d::Zero());
  // Where each node's mirror value comes from: the mirror triangle's
  // vertices (face samples reflected) and their barycentric weights, so
  // that noise is propagated with the correlation it has (one sample's
  // height enters its own d and, mirrored, the d of the nodes around its
  // mirror image).
  std::vector<std::array<int32_t, 3>> mirror_vertex(n, {-1, -1, -1});
  std::vector<std::array<double, 3>> mirror_weight(n, {0.0, 0.0, 0.0});
  // ∂S(q)/∂(a, b, e) for the plane n ∝ n0 + a u + b v, offset + e, at 0.
  // The tilts pivot about the input origin, the centre of a face in its frame.
  const auto mirror_motion = [&](const Eigen::Vector3d& q, int parameter) -> Eigen::Vector3d {
    const double signed_distance = normal.dot(q) - offset_local;
    if (parameter == 2) return 2.0 * normal;
    const Eigen::Vector3d& dn = parameter == 0 ? u : v;
    return -2.0 * (dn.dot(q + origin) * normal + signed_distance * dn);
  };
  const double sigma2 = out.noise_sigma * out.noise_sigma;
  int32_t start = 0;
  for (int32_t i : SpatialOrder(face.xy, /*brio=*/false, 0)) {
    const Point2 p = face.xy[i];
    const double zf = f.z[f.mesh.vertex_of_input[i]];
    side[i] = normal.dot(Eigen::Vector3d(p.x, p.y, zf)) - offset_local;
    const Location loc = LocateHeight(m, p, &start);
    if (!loc.found()) continue;
    d[i] = zf - InterpolateAt(m.mesh, m.z, loc);
    const int32_t* tv = &m.mesh.triangles[3 * loc.triangle];
    // The mirror triangle's gradient, for the moved interpolant.
    const Point2 &a = m.xy[tv[0]], &b = m.xy[tv[1]], &c = m.xy[tv[2]];
    const double det = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    const double dzb = m.z[tv[1]] - m.z[tv[0]], dzc = m.z[tv[2]] - m.z[tv[0]];
    const double gx = (dzb * (c.y - a.y) - dzc * (b.y - a.y)) / det;
    const double gy = (dzc * (b.x - a.x) - dzb * (c.x - a.x)) / det;
    double lambda2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double w = loc.barycentric[k];
      lambda2 += w * w;
      mirror_vertex[i][k] = tv[k];
      mirror_weight[i][k] = w;
      // Mirror vertex tv[k] is face sample tv[k] reflected (vertex index = input index).
      const Eigen::Vector3d q(face.xy[tv[k]].x, face.xy[tv[k]].y, face.z[tv[k]]);
      for (int j = 0; j < 3; ++j) {
        const Eigen::Vector3d dS = mirror_motion(q, j);
        jacobian[i](j) -= w * (dS.z() - gx * dS.x() - gy * dS.y());
      }
    }
    noise_var[i] = sigma2 * (1.0 + lambda2);
  }

  // The overlap: the face's data-domain triangles whose corners all have a difference.
  std::vector<int32_t> overlap;
  double y_lo = std::numeric_limits<double>::infinity(), y_hi = -y_lo;
  const auto& tri = f.mesh.triangles;
  // Vertex v of the face mesh is input sample v (duplicates merged into it).
  for (int32_t t = 0; t < f.mesh.num_triangles(); ++t) {
    const int32_t* tv = &tri[3 * t];
    if (f.domain[t] == 0 || std::isnan(d[tv[0]]) || std::isnan(d[tv[1]]) || std::isnan(d[tv[2]]))
      continue;
    overlap.push_back(t);
    for (int k = 0; k < 3; ++k)
      y_lo = std::min(y_lo, f.xy[tv[k]].y), y_hi = std::max(y_hi, f.xy[tv[k]].y);
  }
  if (overlap.empty()) {
    throw InputError(face.source + ": the face does not overlap its mirror image about the plane");
  }
  // Σ_k (∂Q/∂z_k)² σ_n² for a quantity Q with ∂Q/∂d_i = g_i: sample k's
  // height enters d_k (+1) and the d_i whose mirror triangle has k as a
  // corner (−λ), so the sums are per sample, not per node.
  std::vector<double> by_sample(n);
  const auto noise_variance = [&](const std::function<double(std::size_t)>& g) {
    std::fill(by_sample.begin(), by_sample.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double gi = g(i);
      if (gi == 0) continue;
      by_sample[i] += gi;
      for (int k = 0; k < 3; ++k) {
        if (mirror_vertex[i][k] >= 0) by_sample[mirror_vertex[i][k]] -= gi * mirror_weight[i][k];
      }
    }
    double sum = 0;
    for (double c : by_sample) sum += c * c;
    return sigma2 * sum;
  };

  // The plane's covariance. The plane minimizes ∫|d|, a least-absolute-
  // deviations fit: its gradient Σ a_i sign(d_i) J_i (a_i the node's area)
  // responds to noise through the smoothed slope of sign, 2φ(d_i/σ_i)/σ_i
  // (σ_i the noise of d_i): its covariance B is that response propagated
  // per sample (above), its mean slope H = Σ a_i 2φ(d_i/σ_i)/σ_i J_i J_iᵀ,
  // and the plane's covariance H⁻¹ B H⁻¹. Only nodes whose |d| is within a
  // few σ of 0 hold the plane.
  std::vector<double> node_area(n, 0.0);
  for (int32_t t : overlap) {
    const int32_t* tv = &tri[3 * t];
    const Point2 &a = f.xy[tv[0]], &b = f.xy[tv[1]], &c = f.xy[tv[2]];
    const double area = 0.5 * std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    for (int k = 0; k < 3; ++k) node_area[tv[k]] += area / 3;
  }
  Eigen::Matrix3d slope = Eigen::Matrix3d::Zero(), spread = Eigen::Matrix3d::Zero();
  std::vector<double> response(n, 0.0);  // a_i 2φ(d_i/σ_i)/σ_i
  for (std::size_t i = 0; i < n; ++i) {
    if (node_area[i] == 0 || !(noise_var[i] > 0)) continue;
    const double sigma = std::sqrt(noise_var[i]), ratio = d[i] / sigma;
    const double density = std::exp(-0.5 * ratio * ratio) / std::sqrt(2 * kPi);
    response[i] = node_area[i] * 2 * density / sigma;
    slope += response[i] * jacobian[i] * jacobian[i].transpose();
  }
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      // B_ab from the per-sample responses of components a and b: by
      // polarization, (V(a + b) − V(a − b)) / 4.
      const double plus = noise_variance([&](std::size_t i) { return response[i] * (jacobian[i](a) + jacobian[i](b)); });
      const double minus = a == b ? 0.0 : noise_variance([&](std::size_t i) {
        return response[i] * (jacobian[i](a) - jacobian[i](b));
      });
      spread(a, b) = spread(b, a) = a == b ? plus / 4 : (plus - minus) / 4;
    }
  }
  Eigen::Matrix3d plane_cov = Eigen::Matrix3d::Zero();  // no noise: the plane is exact
  if (slope.trace() > 0) {
    const Eigen::LDLT<Eigen::Matrix3d> slope_ldlt(slope);
    plane_cov = Eigen::Matrix3d::Constant(kNaN);
    if (slope_ldlt.info() == Eigen::Success && slope_ldlt.vectorD().minCoeff() > 1e-12 * slope.trace()) {
      const Eigen::Matrix3d inverse = slope_ldlt.solve(Eigen::Matrix3d::Identity());
      plane_cov = inverse * spread * inverse;
    }
  }
  out.plane_sigma = {std::sqrt(plane_cov(0, 0)) * 180 / kPi, std::sqrt(plane_cov(1, 1)) * 180 / kPi,
                     std::sqrt(plane_cov(2, 2))};

  const double third = (y_hi - y_lo) / 3;
  const double band[4] = {y_lo, y_lo + third, y_hi - third, y_hi};
  for (int k = 0; k < 4; ++k) out.thirds_y[k] = band[k] + face.origin[1];

  std::vector<RegionShape> shapes(names.size());
  std::size_t next = 1;
  if (options.standard_regions) {
    for (int k = 0; k < 3; ++k) {
      shapes[next + k].kind = RegionShape::kBand;
      shapes[next + k].lo = band[2 - k];
      shapes[next + k].hi = band[3 - k];
    }
    shapes[next + 3].kind = shapes[next + 4].kind = RegionShape::kSide;
    shapes[next + 4].side = -1;
    next += 5;
  }
  for (const FaceRegion& region : options.regions) {
    RegionShape& shape = shapes[next++];
    shape.kind = RegionShape::kPolygon;
    for (const auto& q : region.polygon) {
      shape.outline.push_back({q[0] - face.origin[0], q[1] - face.origin[1]});
    }
    shape.pieces = TriangulatePolygon(shape.outline);
  }

  std::vector<double> weight(n);
  for (std::size_t r = 0; r < names.size(); ++r) {
    Sums sums;
    std::fill(weight.begin(), weight.end(), 0.0);
    for (int32_t t : overlap) {
      const int32_t* tv = &tri[3 * t];
      Piece piece;
      piece.n = 3;
      for (int k = 0; k < 3; ++k) {
        piece.c[k] = {f.xy[tv[k]].x, f.xy[tv[k]].y, d[tv[k]], side[tv[k]]};
      }
      ForEachPiece(shapes[r], piece, [&](const Piece& p) {
        const double before = sums.area;
        Accumulate(p, &sums);
        // Each corner's share, for the propagation (the hat functions' integrals, approximately).
        const double share = (sums.area - before) / 3;
        for (int k = 0; k < 3; ++k) weight[tv[k]] += share;
      });
    }
    RegionIndex& index = r == 0 ? out.whole : (out.regions.emplace_back(), out.regions.back());
    index.name = names[r];
    index.area = sums.area;
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isnan(d[i]) && NodeInside(shapes[r], face.xy[i], side[i])) ++index.nodes;
    }
    if (!(sums.area > 0)) continue;  // a region off the overlap: all zero
    index.volume = sums.d;
    index.mean = sums.d / sums.area;
    index.rms = std::sqrt(std::max(0.0, sums.d2 / sums.area));
    index.mean_abs = sums.abs / sums.area;
    index.max_abs = sums.max_abs;
    // σ: the noise per sample, the plane through each index's gradient.
    const double rms_scale = index.rms > 0 ? 1 / (sums.area * index.rms) : 0.0;
    const auto gradient_volume = [&](std::size_t i) { return std::isnan(d[i]) ? 0.0 : weight[i]; };
    const auto gradient_rms = [&](std::size_t i) {
      return std::isnan(d[i]) ? 0.0 : weight[i] * d[i] * rms_scale;
    };
    const auto gradient_abs = [&](std::size_t i) {
      return std::isnan(d[i]) ? 0.0 : weight[i] * ((d[i] > 0) - (d[i] < 0)) / sums.area;
    };
    const double var_volume = noise_variance(gradient_volume);
    const double var_rms = noise_variance(gradient_rms);
    const double var_abs = noise_variance(gradient_abs);
    Eigen::Vector3d g_volume = Eigen::Vector3d::Zero(), g_rms = g_volume, g_abs = g_volume;
    for (std::size_t i = 0; i < n; ++i) {
      if (weight[i] == 0 || std::isnan(d[i])) continue;
      g_volume += gradient_volume(i) * jacobian[i];
      g_rms += gradient_rms(i) * jacobian[i];
      g_abs += gradient_abs(i) * jacobian[i];
    }
    const bool plane_known = !std::isnan(plane_cov(0, 0));
    const auto plane_var = [&](const Eigen::Vector3d& g) {
      return plane_known ? g.dot(plane_cov * g) : 0.0;
    };
    index.volume_sigma = std::sqrt(var_volume + plane_var(g_volume));
    index.mean_sigma = index.volume_sigma / sums.area;
    index.rms_sigma = std::sqrt(var_rms + plane_var(g_rms));
    index.mean_abs_sigma = std::sqrt(var_abs + plane_var(g_abs));
  }
  out.node_difference = std::move(d);
  return out;
}

}  // namespace surfreg
