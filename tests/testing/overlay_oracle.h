#pragma once
// Brute-force oracles for the overlay volume (tests/degenerate_geometry_test.cc):
// two independent ways to integrate |F̂_B − F̂_A| over Ω = Conv(A) ∩ Conv(B)
// on given triangulations, neither using the overlay's search nor the walk:
//  - ClippedIntegrals: every pair of triangles clipped (O(N_A·N_B)), each
//    piece integrated by the long-double reference of volume_reference.h;
//  - Quadrature: a centroid rule on Ω with brute-force point location.
// Side decisions use exact orientation signs (exact_rational.h); crossing
// points and values are rounded (long double).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"
#include "measure/surface.h"
#include "tests/testing/delaunay_checks.h"
#include "tests/testing/exact_rational.h"
#include "tests/testing/volume_reference.h"

namespace surfreg::testing {

using Polygon = std::vector<Point2>;

// A surface as the measure sees it: points, heights, triangulation.
struct Mesh {
  std::vector<Point2> xy;
  std::vector<double> z;
  Triangulation tri;
};

inline std::array<Point2, 3> Corners(const Mesh& m, int32_t t) {
  return {m.xy[m.tri.triangles[3 * t]], m.xy[m.tri.triangles[3 * t + 1]],
          m.xy[m.tri.triangles[3 * t + 2]]};
}

// F̂ on triangle t at q, from q's barycentric coordinates (long double).
inline long double ValueOn(const Mesh& m, int32_t t, const Point2& q) {
  const int32_t* v = &m.tri.triangles[3 * t];
  const Point2 &p0 = m.xy[v[0]], &p1 = m.xy[v[1]], &p2 = m.xy[v[2]];
  const long double ax = p1.x - static_cast<long double>(p0.x),
                    ay = p1.y - static_cast<long double>(p0.y);
  const long double bx = p2.x - static_cast<long double>(p0.x),
                    by = p2.y - static_cast<long double>(p0.y);
  const long double qx = q.x - static_cast<long double>(p0.x),
                    qy = q.y - static_cast<long double>(p0.y);
  const long double det = ax * by - ay * bx;
  const long double l1 = (qx * by - qy * bx) / det, l2 = (ax * qy - ay * qx) / det;
  const long double z0 = m.z[v[0]];
  return z0 + l1 * (m.z[v[1]] - z0) + l2 * (m.z[v[2]] - z0);
}

// Signed area of a polygon (fan from its first corner).
inline long double Area(const Polygon& p) {
  long double twice = 0;
  for (std::size_t k = 1; k + 1 < p.size(); ++k) {
    twice += (static_cast<long double>(p[k].x) - p[0].x) *
                 (static_cast<long double>(p[k + 1].y) - p[0].y) -
             (static_cast<long double>(p[k].y) - p[0].y) *
                 (static_cast<long double>(p[k + 1].x) - p[0].x);
  }
  return twice / 2;
}

// The part of convex `poly` on the closed left of the line a → b: which side
// a corner is on is decided exactly; crossing points are rounded.
inline Polygon ClipLeft(const Polygon& poly, const Point2& a, const Point2& b) {
  Polygon out;
  const std::size_t n = poly.size();
  auto det = [&](const Point2& r) {
    return (static_cast<long double>(b.x) - a.x) * (static_cast<long double>(r.y) - a.y) -
           (static_cast<long double>(b.y) - a.y) * (static_cast<long double>(r.x) - a.x);
  };
  for (std::size_t k = 0; k < n; ++k) {
    const Point2 &r = poly[k], &s = poly[(k + 1) % n];
    const int sr = FilteredOrientSign(a, b, r), ss = FilteredOrientSign(a, b, s);
    if (sr >= 0) out.push_back(r);
    if (sr * ss < 0) {
      const long double dr = det(r), ds = det(s);
      const long double t = std::clamp<long double>(dr / (dr - ds), 0, 1);
      out.push_back({static_cast<double>(r.x + t * (static_cast<long double>(s.x) - r.x)),
                     static_cast<double>(r.y + t * (static_cast<long double>(s.y) - r.y))});
    }
  }
  return out;
}

inline Polygon ClipConvex(Polygon subject, const Polygon& clip) {
  for (std::size_t k = 0; k < clip.size() && subject.size() >= 3; ++k) {
    subject = ClipLeft(subject, clip[k], clip[(k + 1) % clip.size()]);
  }
  return subject.size() >= 3 ? subject : Polygon{};
}

inline Polygon Hull(const std::vector<Point2>& xy) {
  Polygon hull;
  for (int32_t i : ConvexHullWithCollinear(xy)) hull.push_back(xy[i]);
  return hull;
}

struct Integrals {
  long double abs = 0, above = 0, below = 0, signed_volume = 0, area = 0;
};

// ∇F̂ on triangle t.
inline std::array<long double, 2> Gradient(const Mesh& m, int32_t t) {
  const int32_t* v = &m.tri.triangles[3 * t];
  const Point2 &p0 = m.xy[v[0]], &p1 = m.xy[v[1]], &p2 = m.xy[v[2]];
  const long double ax = p1.x - static_cast<long double>(p0.x),
                    ay = p1.y - static_cast<long double>(p0.y);
  const long double bx = p2.x - static_cast<long double>(p0.x),
                    by = p2.y - static_cast<long double>(p0.y);
  const long double da = m.z[v[1]] - static_cast<long double>(m.z[v[0]]),
                    db = m.z[v[2]] - static_cast<long double>(m.z[v[0]]);
  const long double det = ax * by - ay * bx;
  return {(da * by - db * ay) / det, (ax * db - bx * da) / det};
}

// Oracle (1): all pairs of triangles clipped, d linear on each piece.
inline Integrals ClippedIntegrals(const Mesh& a, const Mesh& b) {
  struct Box {
    double x0, x1, y0, y1;
  };
  auto boxes = [](const Mesh& m) {
    std::vector<Box> out;
    for (int32_t t = 0; t < m.tri.num_triangles(); ++t) {
      const auto c = Corners(m, t);
      out.push_back({std::min({c[0].x, c[1].x, c[2].x}), std::max({c[0].x, c[1].x, c[2].x}),
                     std::min({c[0].y, c[1].y, c[2].y}), std::max({c[0].y, c[1].y, c[2].y})});
    }
    return out;
  };
  const std::vector<Box> ba = boxes(a), bb = boxes(b);
  Integrals sum;
  for (int32_t ta = 0; ta < a.tri.num_triangles(); ++ta) {
    const auto ca = Corners(a, ta);
    for (int32_t tb = 0; tb < b.tri.num_triangles(); ++tb) {
      if (ba[ta].x1 < bb[tb].x0 || bb[tb].x1 < ba[ta].x0 || ba[ta].y1 < bb[tb].y0 ||
          bb[tb].y1 < ba[ta].y0) {
        continue;
      }
      const auto cb = Corners(b, tb);
      const Polygon cell = ClipConvex(Polygon(ca.begin(), ca.end()), Polygon(cb.begin(), cb.end()));
      if (cell.empty()) continue;
      std::vector<double> d;
      for (const Point2& q : cell)
        d.push_back(static_cast<double>(ValueOn(b, tb, q) - ValueOn(a, ta, q)));
      for (std::size_t k = 1; k + 1 < cell.size(); ++k) {
        const long double s = Area({cell[0], cell[k], cell[k + 1]});
        if (!(s > 0)) continue;
        const RefResult r =
            Reference(static_cast<double>(s), {d[0], d[k], d[k + 1]}, {1.0, 1.0, 1.0});
        sum.abs += r.abs, sum.above += r.above, sum.below += r.below;
        sum.signed_volume += r.signed_volume, sum.area += s;
      }
    }
  }
  return sum;
}

// Point location by brute force: triangles binned by bounding box (no
// walking, no adjacency), each candidate decided by exact orientation tests
// on its closure; the first triangle (by index) that holds the point wins.
class BruteLocator {
 public:
  explicit BruteLocator(const Mesh& m) : m_(m) {
    x0_ = y0_ = INFINITY;
    double x1 = -INFINITY, y1 = -INFINITY;
    for (const Point2& p : m.xy)
      x0_ = std::min(x0_, p.x), y0_ = std::min(y0_, p.y), x1 = std::max(x1, p.x),
      y1 = std::max(y1, p.y);
    bins_ = std::max(1, static_cast<int>(std::sqrt(m.tri.num_triangles())));
    w_ = (x1 - x0_) / bins_, h_ = (y1 - y0_) / bins_;
    cells_.resize(static_cast<std::size_t>(bins_) * bins_);
    for (int32_t t = 0; t < m.tri.num_triangles(); ++t) {
      const auto c = Corners(m, t);
      const int i0 = Bin(std::min({c[0].x, c[1].x, c[2].x}), x0_, w_),
                i1 = Bin(std::max({c[0].x, c[1].x, c[2].x}), x0_, w_);
      const int j0 = Bin(std::min({c[0].y, c[1].y, c[2].y}), y0_, h_),
                j1 = Bin(std::max({c[0].y, c[1].y, c[2].y}), y0_, h_);
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) cells_[j * bins_ + i].push_back(t);
      }
    }
  }
  // The triangle whose closure holds q, or -1.
  int32_t Find(const Point2& q) const {
    for (int32_t t : cells_[Bin(q.y, y0_, h_) * bins_ + Bin(q.x, x0_, w_)]) {
      const auto c = Corners(m_, t);
      if (FilteredOrientSign(c[0], c[1], q) >= 0 && FilteredOrientSign(c[1], c[2], q) >= 0 &&
          FilteredOrientSign(c[2], c[0], q) >= 0) {
        return t;
      }
    }
    return -1;
  }

 private:
  int Bin(double v, double lo, double w) const {
    return w > 0 ? std::clamp(static_cast<int>(std::floor((v - lo) / w)), 0, bins_ - 1) : 0;
  }
  const Mesh& m_;
  double x0_, y0_, w_, h_;
  int bins_;
  std::vector<std::vector<int32_t>> cells_;
};

struct QuadratureResult {
  double value = 0;  // ≈ ∫_Ω |F̂_B − F̂_A|
  double bound = 0;  // bound on |value − integral| (see Quadrature)
  int outside = 0;   // centroids found in neither mesh (must be 0)
};

// Oracle (2): the centroid rule of |d| = |F̂_B − F̂_A| on Ω (the clipped
// hulls), fanned into triangles, each cut into k² similar ones, F̂ located by
// brute force. Ω's boundary is followed exactly. Error bound: where the three
// corners of a sub-triangle τ lie in one triangle of A and one of B with one
// sign of d, |d| is linear on τ (the triangles are convex) and the centroid
// rule is exact; elsewhere |∫_τ|d| − |τ|·|d(c)|| ≤ |τ|·L_τ·max|x − c|, L_τ
// the largest |∇F̂_B − ∇F̂_A| on τ. L_τ is taken over the triangles met at
// τ's corners and centroid, doubled: rigorous unless τ holds a vertex of a
// mesh whose other triangles are steeper. (A global Lipschitz constant is
// rigorous but useless: rotated grids have hull slivers of width ~1e-16
// with |∇F̂| up to ~1e15, which carry no area.) O(h²): only τ crossed by a kink
// (mesh edges, zero lines of d) count.
inline QuadratureResult Quadrature(const Mesh& a, const Mesh& b, const Polygon& omega, int points,
                                   double zmax) {
  const BruteLocator la(a), lb(b);
  std::vector<std::array<long double, 2>> grad_a, grad_b;
  for (int32_t t = 0; t < a.tri.num_triangles(); ++t) grad_a.push_back(Gradient(a, t));
  for (int32_t t = 0; t < b.tri.num_triangles(); ++t) grad_b.push_back(Gradient(b, t));
  QuadratureResult r;
  const long double total = Area(omega);
  std::vector<int> fan;
  for (std::size_t f = 1; f + 1 < omega.size(); ++f) {
    const long double area = Area({omega[0], omega[f], omega[f + 1]});
    // Slivers from (nearly) collinear hull corners: at most |d| ≤ 2·zmax.
    if (area > 1e-9L * total) {
      fan.push_back(static_cast<int>(f));
    } else {
      r.bound += static_cast<double>(std::fabs(area)) * 2 * zmax;
    }
  }
  const int k = std::max(4, static_cast<int>(std::sqrt(points / (1.5 * fan.size()))));
  struct Node {
    int32_t ta, tb;
    double d;
  };
  std::vector<Node> nodes(static_cast<std::size_t>(k + 1) * (k + 1));
  long double sum = 0, bound = 0;
  for (int f : fan) {
    const Point2 p = omega[0], u{omega[f].x - p.x, omega[f].y - p.y},
                 v{omega[f + 1].x - p.x, omega[f + 1].y - p.y};
    const long double piece =
        Area({omega[0], omega[f], omega[f + 1]}) / (static_cast<long double>(k) * k);
    auto at = [&](double s, double t) {
      return Point2{p.x + (s / k) * u.x + (t / k) * v.x, p.y + (s / k) * u.y + (t / k) * v.y};
    };
    auto locate = [&](const Point2& q) {
      Node n{la.Find(q), lb.Find(q), std::nan("")};
      if (n.ta >= 0 && n.tb >= 0)
        n.d = static_cast<double>(ValueOn(b, n.tb, q) - ValueOn(a, n.ta, q));
      return n;
    };
    for (int i = 0; i <= k; ++i) {
      for (int j = 0; i + j <= k; ++j) nodes[i * (k + 1) + j] = locate(at(i, j));
    }
    auto add = [&](double s, double t, const Node& n0, const Node& n1, const Node& n2) {
      const Point2 c = at(s, t);
      const Node nc = locate(c);
      if (std::isnan(nc.d)) {
        ++r.outside;
        return;
      }
      sum += piece * std::fabs(nc.d);
      const bool one_cell = n0.ta == n1.ta && n0.ta == n2.ta && n0.tb == n1.tb && n0.tb == n2.tb &&
                            n0.ta >= 0 && n0.tb >= 0;
      const bool one_sign =
          (n0.d >= 0 && n1.d >= 0 && n2.d >= 0) || (n0.d <= 0 && n1.d <= 0 && n2.d <= 0);
      if (!(one_cell && one_sign)) {
        // max |x − c| over τ: the corners of an upward and a downward
        // sub-triangle around c (a superset of τ's corners).
        double reach = 0;
        for (const Point2& q : {at(s - 1.0 / 3, t - 1.0 / 3), at(s + 2.0 / 3, t - 1.0 / 3),
                                at(s - 1.0 / 3, t + 2.0 / 3), at(s + 1.0 / 3, t + 1.0 / 3),
                                at(s - 2.0 / 3, t + 1.0 / 3), at(s + 1.0 / 3, t - 2.0 / 3)}) {
          reach = std::max(reach, std::hypot(q.x - c.x, q.y - c.y));
        }
        long double lipschitz = 0;
        for (int32_t ta : {n0.ta, n1.ta, n2.ta, nc.ta}) {
          for (int32_t tb : {n0.tb, n1.tb, n2.tb, nc.tb}) {
            if (ta < 0 || tb < 0) continue;
            lipschitz = std::max(lipschitz, std::hypot(grad_b[tb][0] - grad_a[ta][0],
                                                       grad_b[tb][1] - grad_a[ta][1]));
          }
        }
        bound += piece * 2 * lipschitz * reach;
      }
    };
    for (int i = 0; i < k; ++i) {
      for (int j = 0; i + j < k; ++j) {
        const Node &n00 = nodes[i * (k + 1) + j], &n10 = nodes[(i + 1) * (k + 1) + j],
                   &n01 = nodes[i * (k + 1) + j + 1];
        add(i + 1.0 / 3, j + 1.0 / 3, n00, n10, n01);  // upward sub-triangle
        if (i + j < k - 1)
          add(i + 2.0 / 3, j + 2.0 / 3, n10, n01, nodes[(i + 1) * (k + 1) + j + 1]);  // downward
      }
    }
  }
  r.value = static_cast<double>(sum);
  r.bound += static_cast<double>(bound);
  return r;
}

}  // namespace surfreg::testing
