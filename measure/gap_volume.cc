#include "measure/gap_volume.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "measure/input_error.h"
#include "measure/overlay.h"

namespace surfreg {
namespace {

// Fan of a convex polygon with μ = 1 on it; returns the polygon's area.
double FanUniform(const Point2* p, int n, const Plane& d, GapIntegrals* gap) {
  const double d0 = d.At(p[0]);
  double d1 = d.At(p[1]);
  double total = 0.0;
  for (int k = 1; k + 1 < n; ++k) {
    const double d2 = d.At(p[k + 1]);
    const double area = 0.5 * TwiceArea(p[0], p[k], p[k + 1]);
    if (area > 0.0) {
      *gap += IntegrateGap(area, d0, d1, d2);
      total += area;
    }
    d1 = d2;
  }
  return total;
}

// The part of a convex polygon where the linear function g > 0 (corners to
// `out`, room for n + 1); returns their number (< 3: empty).
int ClipAbove(const Point2* p, int n, const Plane& g, Point2* out) {
  double value[12];
  double largest = -HUGE_VAL;
  for (int k = 0; k < n; ++k) value[k] = g.At(p[k]), largest = std::max(largest, value[k]);
  // {g > 0} is what counts: a piece where g <= 0 everywhere has none of it
  // (g = 0 on a whole piece, e.g. unchanged flat ground at L = 0).
  if (!(largest > 0.0)) return 0;
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const int l = k + 1 == n ? 0 : k + 1;
    if (value[k] >= 0.0) out[m++] = p[k];
    if ((value[k] > 0.0 && value[l] < 0.0) || (value[k] < 0.0 && value[l] > 0.0)) {
      const double s = value[k] / (value[k] - value[l]);
      out[m++] = {p[k].x + s * (p[l].x - p[k].x), p[k].y + s * (p[l].y - p[k].y)};
    }
  }
  return m;
}

// ∫ f μ and ∫ μ over a convex polygon, f and μ linear (μ = 1 when `mu` is
// null): per fan triangle ∫ f μ = S/12 (Σ f_i m_i + Σ f_i Σ m_i), exact.
void IntegrateLinear(const Point2* p, int n, const Plane& f, const Plane* mu, double* f_mu,
                     double* mu_area) {
  for (int k = 1; k + 1 < n; ++k) {
    const double area = 0.5 * TwiceArea(p[0], p[k], p[k + 1]);
    if (!(area > 0.0)) continue;
    const double fv[3] = {f.At(p[0]), f.At(p[k]), f.At(p[k + 1])};
    if (mu == nullptr) {
      *f_mu += area * (fv[0] + fv[1] + fv[2]) / 3.0;
      *mu_area += area;
      continue;
    }
    const double mv[3] = {mu->At(p[0]), mu->At(p[k]), mu->At(p[k + 1])};
    *f_mu += area / 12.0 *
             (fv[0] * mv[0] + fv[1] * mv[1] + fv[2] * mv[2] +
              (fv[0] + fv[1] + fv[2]) * (mv[0] + mv[1] + mv[2]));
    *mu_area += area * (mv[0] + mv[1] + mv[2]) / 3.0;
  }
}

// Fill and cut beyond ±lod on one convex piece.
void AddDetectedChange(const Point2* p, int n, const Plane& d, const Plane* mu, double lod,
                       DetectedChange* change) {
  Point2 part[14];
  const Plane above{d.x0, d.y0, d.z0 - lod, d.gx, d.gy};    // d − L ≥ 0
  const Plane below{d.x0, d.y0, -d.z0 - lod, -d.gx, -d.gy};  // −d − L ≥ 0
  const Plane minus_d{d.x0, d.y0, -d.z0, -d.gx, -d.gy};
  int m = ClipAbove(p, n, above, part);
  if (m >= 3) IntegrateLinear(part, m, d, mu, &change->fill, &change->fill_area);
  m = ClipAbove(p, n, below, part);
  if (m >= 3) IntegrateLinear(part, m, minus_d, mu, &change->cut, &change->cut_area);
}

void AddScaled(const GapIntegrals& g, double sign, GapIntegrals* to) {
  to->abs += sign * g.abs, to->above += sign * g.above, to->below += sign * g.below;
  to->signed_volume += sign * g.signed_volume, to->weight += sign * g.weight;
}

void AddScaled(const DetectedChange& c, double sign, DetectedChange* to) {
  to->fill += sign * c.fill, to->cut += sign * c.cut;
  to->fill_area += sign * c.fill_area, to->cut_area += sign * c.cut_area;
}

}  // namespace

// Sutherland-Hodgman, one edge of the triangle at a time.
int ClipByTriangle(const Point2* polygon, int n, const std::array<Point2, 3>& t, Point2* out) {
  Point2 buffer[2][12];
  std::copy(polygon, polygon + n, buffer[0]);
  int current = 0;
  for (int i = 0; i < 3 && n > 0; ++i) {
    const Point2& e0 = t[i];
    const Point2& e1 = t[(i + 1) % 3];
    const Point2* in = buffer[current];
    Point2* next = buffer[1 - current];
    double value[12];
    for (int k = 0; k < n; ++k) value[k] = TwiceArea(e0, e1, in[k]);
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const int l = k + 1 == n ? 0 : k + 1;
      if (value[k] >= 0.0) next[m++] = in[k];
      if ((value[k] > 0.0 && value[l] < 0.0) || (value[k] < 0.0 && value[l] > 0.0)) {
        const double s = value[k] / (value[k] - value[l]);
        next[m++] = {in[k].x + s * (in[l].x - in[k].x), in[k].y + s * (in[l].y - in[k].y)};
      }
    }
    n = m;
    current = 1 - current;
  }
  std::copy(buffer[current], buffer[current] + n, out);
  return n;
}

void IntegrateConvex(const Point2* polygon, int n, const Plane& d, const WeightField& mu,
                     const Plane& mu_plane, VolumeResult* result, double lod) {
  switch (mu.mode) {
    case WeightMode::kUniform:
      result->area += FanUniform(polygon, n, d, &result->gap);
      if (lod >= 0.0) AddDetectedChange(polygon, n, d, nullptr, lod, &result->change);
      break;
    case WeightMode::kPerPoint:
      for (int k = 1; k + 1 < n; ++k) {
        const Point2* t[3] = {&polygon[0], &polygon[k], &polygon[k + 1]};
        const double area = 0.5 * TwiceArea(*t[0], *t[1], *t[2]);
        if (!(area > 0.0)) continue;
        result->area += area;
        const double dv[3] = {d.At(*t[0]), d.At(*t[1]), d.At(*t[2])};
        const double mv[3] = {mu_plane.At(*t[0]), mu_plane.At(*t[1]), mu_plane.At(*t[2])};
        result->gap += IntegrateGapWeighted(area, dv, mv);
      }
      if (lod >= 0.0) AddDetectedChange(polygon, n, d, &mu_plane, lod, &result->change);
      break;
    case WeightMode::kMask: {
      for (int k = 1; k + 1 < n; ++k) {  // |Ω| is unweighted: the whole cell counts
        result->area += 0.5 * std::max(0.0, TwiceArea(polygon[0], polygon[k], polygon[k + 1]));
      }
      double lo_x = polygon[0].x, hi_x = lo_x, lo_y = polygon[0].y, hi_y = lo_y;
      for (int k = 1; k < n; ++k) {
        lo_x = std::min(lo_x, polygon[k].x), hi_x = std::max(hi_x, polygon[k].x);
        lo_y = std::min(lo_y, polygon[k].y), hi_y = std::max(hi_y, polygon[k].y);
      }
      Point2 piece[12];
      const MaskRegion& mask = mu.mask();
      ForEachMaskTriangle(mask, {lo_x, lo_y}, {hi_x, hi_y}, [&](int32_t k) {
        const int m = ClipByTriangle(polygon, n, mask.triangles[k], piece);
        if (m < 3) return;
        // A hole's triangle (sign −1) takes back what its ring's gave.
        GapIntegrals gap;
        FanUniform(piece, m, d, &gap);
        AddScaled(gap, mask.sign[k], &result->gap);
        if (lod >= 0.0) {
          DetectedChange change;
          AddDetectedChange(piece, m, d, nullptr, lod, &change);
          AddScaled(change, mask.sign[k], &result->change);
        }
      });
      break;
    }
  }
}

namespace {

// Integrates overlay cells as they come; one per thread.
// A cache line of its own: each chunk's writes its sums cell by cell.
class alignas(64) CellIntegrator {
 public:
  CellIntegrator(const std::vector<Point2>& xy_a, const Triangulation& mesh_a,
                 const std::vector<double>& z_a, const std::vector<Point2>& xy_b,
                 const Triangulation& mesh_b, const std::vector<double>& z_b,
                 const WeightField& mu, double lod, const OmegaDomains& domains)
      : xy_a_(xy_a), mesh_a_(mesh_a), z_a_(z_a), xy_b_(xy_b), mesh_b_(mesh_b), z_b_(z_b), mu_(mu),
        lod_(lod),
        in_a_(domains.a == nullptr || domains.a->whole ? nullptr : &domains.a->triangles),
        in_b_(domains.b == nullptr || domains.b->whole ? nullptr : &domains.b->triangles) {}

  void operator()(const OverlayCell& cell) {
    if ((in_a_ != nullptr && !(*in_a_)[cell.triangle_a]) ||
        (in_b_ != nullptr && !(*in_b_)[cell.triangle_b])) {
      return;  // not data on one side: outside Ω
    }
    ++result.cells;
    if (cell.triangle_a != last_a_) {  // all cells of one A triangle come in a row
      last_a_ = cell.triangle_a;
      fa_ = PlaneOf(xy_a_, mesh_a_, z_a_, cell.triangle_a);
    }
    const Plane fb = PlaneOf(xy_b_, mesh_b_, z_b_, cell.triangle_b);
    // d = F̂_B − F̂_A as one plane about A's reference corner.
    const Plane d{fa_.x0, fa_.y0, fb.At({fa_.x0, fa_.y0}) - fa_.z0, fb.gx - fa_.gx, fb.gy - fa_.gy};
    const Plane mu_plane = mu_.mode == WeightMode::kPerPoint
                               ? mu_.CellPlane(cell.triangle_a, cell.triangle_b)
                               : Plane();
    IntegrateConvex(cell.vertices.data(), cell.num_vertices, d, mu_, mu_plane, &result, lod_);
  }

  VolumeResult result;

 private:
  static Plane PlaneOf(const std::vector<Point2>& xy, const Triangulation& mesh,
                       const std::vector<double>& z, int32_t t) {
    const int32_t* v = &mesh.triangles[3 * t];
    return PlaneThrough(xy[v[0]], xy[v[1]], xy[v[2]], z[v[0]], z[v[1]], z[v[2]]);
  }

  const std::vector<Point2>& xy_a_;
  const Triangulation& mesh_a_;
  const std::vector<double>& z_a_;
  const std::vector<Point2>& xy_b_;
  const Triangulation& mesh_b_;
  const std::vector<double>& z_b_;
  const WeightField& mu_;
  const double lod_;
  const std::vector<uint8_t>* in_a_;  // null: every triangle
  const std::vector<uint8_t>* in_b_;
  int32_t last_a_ = -1;
  Plane fa_;
};

}  // namespace

VolumeResult OverlayVolume(const std::vector<Point2>& xy_a, const Triangulation& mesh_a,
                           const std::vector<double>& z_a, const std::vector<Location>& a_in_b,
                           const std::vector<Point2>& xy_b, const Triangulation& mesh_b,
                           const std::vector<double>& z_b, const std::vector<Location>& b_in_a,
                           const WeightField& mu, const Execution& execution, double lod,
                           const OmegaDomains& domains) {
  // A visitor per chunk, added in chunk order: the same sums on any number
  // of threads (overlay.h).
  const int chunks = OverlayChunks(mesh_a);
  std::vector<CellIntegrator> parts(chunks, CellIntegrator(xy_a, mesh_a, z_a, xy_b, mesh_b, z_b, mu, lod, domains));
  ForEachOverlayCellInChunks(xy_a, mesh_a, a_in_b, xy_b, mesh_b, b_in_a, chunks,
                             [&](int c, const OverlayCell& cell) { parts[c](cell); }, execution);
  VolumeResult result = parts[0].result;
  for (int c = 1; c < chunks; ++c) {
    result.gap += parts[c].result.gap;
    result.change += parts[c].result.change;
    result.area += parts[c].result.area;
    result.cells += parts[c].result.cells;
  }
  return result;
}

VolumeResult UnionVolume(const std::vector<Point2>& xy_a, const Triangulation& mesh_a,
                         const std::vector<Location>& a_in_b, const std::vector<double>& gaps_a,
                         const std::vector<Point2>& xy_b, const Triangulation& mesh_b,
                         const std::vector<Location>& b_in_a, const std::vector<double>& gaps_b,
                         const WeightField& mu, const OmegaDomains& domains) {
  // The nodes of A ∪ B inside Ω, each with its gap and weight, and where a
  // walk to a point near it starts in A and in B.
  std::vector<Point2> nodes;
  std::vector<double> gap, weight;
  std::vector<int32_t> start_a, start_b;
  for (std::size_t i = 0; i < xy_a.size(); ++i) {
    const bool in = domains.nodes_a != nullptr ? (*domains.nodes_a)[i] != 0 : a_in_b[i].found();
    if (!in || mesh_a.vertex_of_input[i] != static_cast<int32_t>(i)) continue;
    nodes.push_back(xy_a[i]);
    gap.push_back(gaps_a[i]);
    weight.push_back(mu.AtNodeA(i));
    start_a.push_back(mesh_a.vertex_triangle[i]);
    start_b.push_back(a_in_b[i].triangle);
  }
  for (std::size_t j = 0; j < xy_b.size(); ++j) {
    const bool in = domains.nodes_b != nullptr ? (*domains.nodes_b)[j] != 0 : b_in_a[j].found();
    if (!in || mesh_b.vertex_of_input[j] != static_cast<int32_t>(j)) continue;
    nodes.push_back(xy_b[j]);
    gap.push_back(gaps_b[j]);
    weight.push_back(mu.AtNodeB(j));
    start_a.push_back(b_in_a[j].triangle);
    start_b.push_back(mesh_b.vertex_triangle[j]);
  }
  const bool check_a = domains.a != nullptr && !domains.a->whole;
  const bool check_b = domains.b != nullptr && !domains.b->whole;
  Triangulation mesh;
  try {
    mesh = Triangulate(nodes);
  } catch (const InputError&) {
    return VolumeResult();  // fewer than 3 nodes, or all on a line: no area (caller reports)
  }
  VolumeResult result;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    const Point2 corners[3] = {nodes[v[0]], nodes[v[1]], nodes[v[2]]};
    const double area = 0.5 * TwiceArea(corners[0], corners[1], corners[2]);
    if (!(area > 0.0)) continue;
    if (check_a || check_b) {
      // The exact centroid, never rounded: on a grid it often lies on an
      // edge of a mesh, on Ω's boundary, and a rounded one falls on either
      // side depending on the frame (A's or B's origin), which made
      // Measure(A, B) and Measure(B, A) keep different triangles.
      const std::array<Point2, 3> triangle = {corners[0], corners[1], corners[2]};
      if (check_a &&
          !domains.a->Contains(mesh_a, LocateCentroid(xy_a, mesh_a, triangle, start_a[v[0]]))) {
        continue;
      }
      if (check_b &&
          !domains.b->Contains(mesh_b, LocateCentroid(xy_b, mesh_b, triangle, start_b[v[0]]))) {
        continue;
      }
    }
    ++result.cells;
    if (mu.mode == WeightMode::kUniform) {
      GapIntegrals g = IntegrateGap(area, gap[v[0]], gap[v[1]], gap[v[2]]);
      g.abs = AbsVolumePaper(area, gap[v[0]], gap[v[1]], gap[v[2]]);
      result.gap += g;
      result.area += area;
      continue;
    }
    const Plane d = PlaneThrough(corners[0], corners[1], corners[2], gap[v[0]], gap[v[1]], gap[v[2]]);
    const Plane m =
        PlaneThrough(corners[0], corners[1], corners[2], weight[v[0]], weight[v[1]], weight[v[2]]);
    IntegrateConvex(corners, 3, d, mu, m, &result);
  }
  return result;
}

}  // namespace surfreg
