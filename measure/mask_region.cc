#include "measure/mask_region.h"

#include <algorithm>
#include <cmath>

#include "measure/input_error.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

double TwiceSignedArea(const std::vector<Point2>& polygon) {
  double twice = 0.0;
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
    twice += (polygon[k].x - polygon[0].x) * (polygon[k + 1].y - polygon[0].y) -
             (polygon[k].y - polygon[0].y) * (polygon[k + 1].x - polygon[0].x);
  }
  return twice;
}

// Closed segments pq and rs share a point (exact).
bool SegmentsMeet(const Point2& p, const Point2& q, const Point2& r, const Point2& s) {
  const double o1 = Orient2D(p, q, r), o2 = Orient2D(p, q, s);
  const double o3 = Orient2D(r, s, p), o4 = Orient2D(r, s, q);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) {
    return true;
  }
  auto on = [](const Point2& a, const Point2& b, const Point2& c, double o) {
    return o == 0.0 && std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) &&
           std::min(a.y, b.y) <= c.y && c.y <= std::max(a.y, b.y);
  };
  return on(p, q, r, o1) || on(p, q, s, o2) || on(r, s, p, o3) || on(r, s, q, o4);
}

// p inside or on triangle abc (counter-clockwise), exact.
bool InTriangle(const Point2& a, const Point2& b, const Point2& c, const Point2& p) {
  return Orient2D(a, b, p) >= 0.0 && Orient2D(b, c, p) >= 0.0 && Orient2D(c, a, p) >= 0.0;
}

// One ring edge's contribution to the even–odd test of p (the ray to +x):
// 1 = on the edge, -1 = crosses the ray, 0 = neither.
int EdgeTest(const Point2& a, const Point2& b, const Point2& p) {
  const double o = Orient2D(a, b, p);
  if (o == 0.0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
      std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y)) {
    return 1;
  }
  // Half-open crossing rule on edges that straddle the horizontal line.
  if ((a.y > p.y) != (b.y > p.y)) {
    const bool upward = b.y > a.y;
    if ((upward && o > 0.0) || (!upward && o < 0.0)) return -1;
  }
  return 0;
}

// Horizontal strips over the edges' y-ranges: two edges that meet, and an
// edge and a horizontal ray that meet, share a strip. The strip of a value
// is monotone in it, so an edge is in every strip its range touches.
struct Strips {
  double y0 = 0, h = 1;
  int count = 0;
  std::vector<int32_t> start, items;

  int Of(double y) const {
    const double s = (y - y0) / h;
    if (!(s > 0)) return 0;
    return s >= count ? count - 1 : static_cast<int>(s);
  }
};

Strips MakeStrips(const std::vector<std::array<Point2, 2>>& edges) {
  Strips s;
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& e : edges) {
    lo = std::min({lo, e[0].y, e[1].y});
    hi = std::max({hi, e[0].y, e[1].y});
  }
  s.y0 = lo;
  s.count = static_cast<int>(std::clamp<std::size_t>(edges.size(), 1, 1 << 20));
  s.h = hi > lo ? (hi - lo) / s.count : 1.0;
  s.start.assign(s.count + 1, 0);
  const auto range = [&s](const std::array<Point2, 2>& e) {
    return std::array<int, 2>{s.Of(std::min(e[0].y, e[1].y)), s.Of(std::max(e[0].y, e[1].y))};
  };
  for (const auto& e : edges) {
    const auto r = range(e);
    for (int k = r[0]; k <= r[1]; ++k) ++s.start[k + 1];
  }
  for (int k = 0; k < s.count; ++k) s.start[k + 1] += s.start[k];
  s.items.resize(s.start[s.count]);
  std::vector<int32_t> fill(s.start.begin(), s.start.end() - 1);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const auto r = range(edges[i]);
    for (int k = r[0]; k <= r[1]; ++k) s.items[fill[k]++] = static_cast<int32_t>(i);
  }
  return s;
}

struct RingEdges {
  std::vector<std::array<Point2, 2>> edges;
  std::vector<int32_t> ring, index;  // per edge: its ring and its number in it
};

RingEdges EdgesOf(const std::vector<std::vector<Point2>>& rings) {
  RingEdges out;
  for (std::size_t r = 0; r < rings.size(); ++r) {
    const std::size_t n = rings[r].size();
    for (std::size_t k = 0; k < n; ++k) {
      out.edges.push_back({rings[r][k], rings[r][(k + 1) % n]});
      out.ring.push_back(static_cast<int32_t>(r));
      out.index.push_back(static_cast<int32_t>(k));
    }
  }
  return out;
}

// Consecutive edges a→shared→far fold back (point the same way).
bool FoldsBack(const Point2& a, const Point2& shared, const Point2& far) {
  return Orient2D(a, shared, far) == 0.0 &&
         (far.x - shared.x) * (a.x - shared.x) + (far.y - shared.y) * (a.y - shared.y) > 0.0;
}

}  // namespace

const char* MaskModeName(MaskMode mode) {
  return mode == MaskMode::kExclude ? "exclude" : "include";
}

int MaskRegion::Column(double x) const {
  const double s = (x - lo.x) / cell_x;
  if (!(s > 0)) return 0;
  return s >= columns ? columns - 1 : static_cast<int>(s);
}

int MaskRegion::Row(double y) const {
  const double s = (y - lo.y) / cell_y;
  if (!(s > 0)) return 0;
  return s >= rows ? rows - 1 : static_cast<int>(s);
}

bool ValidMaskRings(const std::vector<MaskRing>& rings,
                    const std::function<std::string(std::size_t)>& name, std::string* error) {
  if (rings.empty()) {
    *error = "the mask has no rings";
    return false;
  }
  std::vector<std::vector<Point2>> p(rings.size());
  for (std::size_t r = 0; r < rings.size(); ++r) {
    const std::size_t n = rings[r].size();
    if (n < 3) {
      *error = name(r) + " has " + std::to_string(n) + " vertices; at least 3 are needed";
      return false;
    }
    for (std::size_t k = 0; k < n; ++k) {
      if (!std::isfinite(rings[r][k][0]) || !std::isfinite(rings[r][k][1])) {
        *error = name(r) + " vertex " + std::to_string(k + 1) + " is not finite";
        return false;
      }
      p[r].push_back({rings[r][k][0], rings[r][k][1]});
    }
    if (TwiceSignedArea(p[r]) == 0.0) {
      *error = name(r) + " has zero area";
      return false;
    }
  }
  const RingEdges e = EdgesOf(p);
  const Strips strips = MakeStrips(e.edges);
  const auto low_strip = [&](int32_t i) {
    return strips.Of(std::min(e.edges[i][0].y, e.edges[i][1].y));
  };
  for (int s = 0; s < strips.count; ++s) {
    for (int32_t u = strips.start[s]; u < strips.start[s + 1]; ++u) {
      for (int32_t v = u + 1; v < strips.start[s + 1]; ++v) {
        int32_t i = strips.items[u], j = strips.items[v];
        if (std::max(low_strip(i), low_strip(j)) != s) continue;  // checked in an earlier strip
        if (i > j) std::swap(i, j);
        const auto &a = e.edges[i], &b = e.edges[j];
        const std::size_t ri = e.ring[i], rj = e.ring[j];
        if (ri == rj) {
          const int32_t n = static_cast<int32_t>(p[ri].size());
          const int32_t ki = e.index[i], kj = e.index[j];
          if (kj == ki + 1 || (ki == 0 && kj == n - 1)) {
            // Consecutive edges may only share their common vertex.
            const bool next = kj == ki + 1;
            if (next ? FoldsBack(a[0], a[1], b[1]) : FoldsBack(a[1], a[0], b[0])) {
              *error = name(ri) + " folds back on itself at vertex " +
                       std::to_string((next ? kj : 0) + 1);
              return false;
            }
            continue;
          }
          if (SegmentsMeet(a[0], a[1], b[0], b[1])) {
            *error = name(ri) + " edges " + std::to_string(ki + 1) + " and " +
                     std::to_string(kj + 1) + " cross: the polygon must be simple";
            return false;
          }
        } else if (SegmentsMeet(a[0], a[1], b[0], b[1])) {
          *error = name(ri) + " and " + name(rj) + " cross or touch (edges " +
                   std::to_string(e.index[i] + 1) + " and " + std::to_string(e.index[j] + 1) +
                   "): rings must be disjoint or nested";
          return false;
        }
      }
    }
  }
  return true;
}

bool ValidMaskRings(const std::vector<MaskRing>& rings, std::string* error) {
  const bool one = rings.size() == 1;
  return ValidMaskRings(
      rings, [one](std::size_t r) { return one ? std::string("mask polygon") : "mask ring " + std::to_string(r + 1); },
      error);
}

std::vector<std::array<Point2, 3>> TriangulatePolygon(std::vector<Point2> polygon) {
  if (TwiceSignedArea(polygon) < 0.0) std::reverse(polygon.begin(), polygon.end());
  const std::size_t n = polygon.size();
  std::vector<std::array<Point2, 3>> triangles;
  if (n < 3) return triangles;
  const std::vector<Point2>& v = polygon;
  std::vector<std::size_t> next(n), prev(n);
  for (std::size_t i = 0; i < n; ++i) next[i] = (i + 1) % n, prev[i] = (i + n - 1) % n;
  std::vector<char> removed(n, 0);
  // Only a reflex (or straight) vertex can lie in a candidate ear; a convex
  // vertex stays convex as ears are cut, so the list only shrinks.
  std::vector<std::size_t> reflex;
  for (std::size_t i = 0; i < n; ++i) {
    if (Orient2D(v[prev[i]], v[i], v[next[i]]) <= 0.0) reflex.push_back(i);
  }
  std::size_t left = n, i = 0, misses = 0;
  while (left > 3) {
    const std::size_t a = prev[i], b = next[i];
    const double turn = Orient2D(v[a], v[i], v[b]);
    bool ear = turn > 0.0;
    for (std::size_t k = 0; ear && k < reflex.size();) {
      const std::size_t r = reflex[k];
      if (removed[r] || Orient2D(v[prev[r]], v[r], v[next[r]]) > 0.0) {
        reflex[k] = reflex.back();  // no longer reflex: drop it
        reflex.pop_back();
        continue;
      }
      if (r != a && r != i && r != b && InTriangle(v[a], v[i], v[b], v[r])) ear = false;
      ++k;
    }
    if (turn == 0.0 || ear) {  // a straight vertex goes without a triangle
      if (ear) triangles.push_back({v[a], v[i], v[b]});
      removed[i] = 1;
      next[a] = b, prev[b] = a;
      --left;
      misses = 0;
      // Skip the next vertex: cutting every other vertex in turn keeps the
      // triangles compact (restarting at one vertex would fan out slivers).
      i = next[b];
      continue;
    }
    if (++misses > left) throw InputError("mask polygon could not be triangulated (is it simple?)");
    i = b;
  }
  const std::size_t a = prev[i], b = next[i];
  if (Orient2D(v[a], v[i], v[b]) > 0.0) triangles.push_back({v[a], v[i], v[b]});
  return triangles;
}

bool InsidePolygon(const std::vector<Point2>& polygon, const Point2& p) {
  const std::size_t n = polygon.size();
  bool inside = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const int t = EdgeTest(polygon[j], polygon[i], p);
    if (t == 1) return true;  // on the boundary
    if (t == -1) inside = !inside;
  }
  return inside;
}

namespace {

// Each ring's depth: how many other rings hold it (their even–odd test says
// one of its vertices is inside; rings do not touch, so any vertex will do).
std::vector<int> RingDepths(const std::vector<std::vector<Point2>>& rings, const RingEdges& e,
                            const Strips& strips) {
  const std::size_t count = rings.size();
  std::vector<int> depth(count, 0);
  std::vector<char> parity(count, 0);
  std::vector<std::size_t> touched;
  for (std::size_t r = 0; r < count; ++r) {
    const Point2 p = rings[r][0];
    const int s = strips.Of(p.y);
    for (int32_t u = strips.start[s]; u < strips.start[s + 1]; ++u) {
      const int32_t k = strips.items[u];
      const std::size_t other = e.ring[k];
      if (other == r || EdgeTest(e.edges[k][0], e.edges[k][1], p) != -1) continue;
      if (parity[other] == 0 && std::find(touched.begin(), touched.end(), other) == touched.end()) {
        touched.push_back(other);
      }
      parity[other] ^= 1;
    }
    for (const std::size_t other : touched) depth[r] += parity[other], parity[other] = 0;
    touched.clear();
  }
  return depth;
}

// The triangles' buckets: about one per triangle, square-ish over the
// rings' box; each triangle listed in every bucket its box meets.
void BucketTriangles(MaskRegion* region) {
  MaskRegion& m = *region;
  m.lo = {INFINITY, INFINITY}, m.hi = {-INFINITY, -INFINITY};
  for (const auto& ring : m.rings) {
    for (const Point2& q : ring) {
      m.lo = {std::min(m.lo.x, q.x), std::min(m.lo.y, q.y)};
      m.hi = {std::max(m.hi.x, q.x), std::max(m.hi.y, q.y)};
    }
  }
  const double w = std::max(m.hi.x - m.lo.x, 1e-300), h = std::max(m.hi.y - m.lo.y, 1e-300);
  const double t = static_cast<double>(std::max<std::size_t>(m.triangles.size(), 1));
  m.columns = static_cast<int>(std::clamp(std::ceil(std::sqrt(t * w / h)), 1.0, 2048.0));
  m.rows = static_cast<int>(std::clamp(std::ceil(t / m.columns), 1.0, 2048.0));
  m.cell_x = w / m.columns, m.cell_y = h / m.rows;
  m.bucket_start.assign(static_cast<std::size_t>(m.columns) * m.rows + 1, 0);
  m.first_bucket.resize(m.triangles.size());
  std::vector<std::array<int, 4>> range(m.triangles.size());
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    const auto& q = m.triangles[k];
    range[k] = {m.Column(std::min({q[0].x, q[1].x, q[2].x})), m.Column(std::max({q[0].x, q[1].x, q[2].x})),
                m.Row(std::min({q[0].y, q[1].y, q[2].y})), m.Row(std::max({q[0].y, q[1].y, q[2].y}))};
    m.first_bucket[k] = {range[k][0], range[k][2]};
    for (int r = range[k][2]; r <= range[k][3]; ++r) {
      for (int c = range[k][0]; c <= range[k][1]; ++c) ++m.bucket_start[r * m.columns + c + 1];
    }
  }
  for (std::size_t b = 0; b + 1 < m.bucket_start.size(); ++b) m.bucket_start[b + 1] += m.bucket_start[b];
  m.bucket_items.resize(m.bucket_start.back());
  std::vector<int32_t> fill(m.bucket_start.begin(), m.bucket_start.end() - 1);
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    for (int r = range[k][2]; r <= range[k][3]; ++r) {
      for (int c = range[k][0]; c <= range[k][1]; ++c) {
        m.bucket_items[fill[r * m.columns + c]++] = static_cast<int32_t>(k);
      }
    }
  }
}

}  // namespace

MaskRegion MakeMaskRegion(const std::vector<MaskRing>& rings, MaskMode mode,
                          const std::array<double, 2>& origin, const std::vector<Point2>& cover) {
  MaskRegion m;
  for (const MaskRing& ring : rings) {
    std::vector<Point2> local;
    for (const auto& q : ring) local.push_back({q[0] - origin[0], q[1] - origin[1]});
    m.rings.push_back(std::move(local));
  }
  if (m.rings.empty()) return m;
  if (mode == MaskMode::kExclude) {
    // One ring around the rings and `cover` (with a margin, so it touches
    // none): everything but the rings' region is then in.
    double lx = INFINITY, ly = INFINITY, hx = -INFINITY, hy = -INFINITY;
    const auto grow = [&](const Point2& q) {
      lx = std::min(lx, q.x), ly = std::min(ly, q.y), hx = std::max(hx, q.x), hy = std::max(hy, q.y);
    };
    for (const auto& ring : m.rings) std::for_each(ring.begin(), ring.end(), grow);
    std::for_each(cover.begin(), cover.end(), grow);
    const double margin = std::max(0.05 * std::max(hx - lx, hy - ly), 1e-6 * (1 + std::max(
        {std::fabs(lx), std::fabs(ly), std::fabs(hx), std::fabs(hy)})));
    lx -= margin, ly -= margin, hx += margin, hy += margin;
    m.rings.push_back({{lx, ly}, {hx, ly}, {hx, hy}, {lx, hy}});
  }
  const RingEdges e = EdgesOf(m.rings);
  m.edges = e.edges;
  const Strips strips = MakeStrips(m.edges);
  m.strip_y0 = strips.y0, m.strip_h = strips.h, m.strips = strips.count;
  m.strip_start = strips.start, m.strip_items = strips.items;

  const std::size_t count = m.rings.size();
  m.depth = RingDepths(m.rings, e, strips);

  for (std::size_t r = 0; r < count; ++r) {
    const double sign = m.depth[r] % 2 == 0 ? 1.0 : -1.0;
    for (const auto& t : TriangulatePolygon(m.rings[r])) {
      m.triangles.push_back(t);
      m.sign.push_back(sign);
    }
  }

  BucketTriangles(&m);
  return m;
}

bool InsideMask(const MaskRegion& mask, const Point2& p) {
  if (mask.strips == 0 || p.x < mask.lo.x || p.x > mask.hi.x || p.y < mask.lo.y ||
      p.y > mask.hi.y) {
    return false;
  }
  double s = (p.y - mask.strip_y0) / mask.strip_h;
  const int strip = !(s > 0) ? 0 : s >= mask.strips ? mask.strips - 1 : static_cast<int>(s);
  bool inside = false;
  for (int32_t u = mask.strip_start[strip]; u < mask.strip_start[strip + 1]; ++u) {
    const auto& e = mask.edges[mask.strip_items[u]];
    const int t = EdgeTest(e[0], e[1], p);
    if (t == 1) return true;  // on a ring: the region is closed
    if (t == -1) inside = !inside;
  }
  return inside;
}

}  // namespace surfreg
