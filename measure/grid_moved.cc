// A raster against another raster's cells anywhere (grid_pair.h,
// MeasureOnMovedGrid): A on a lattice, B meshed on its own cells by the one
// rule but its samples anywhere — a raster moved by a rigid motion, turned,
// or of another spacing. A's triangles are the regions of three families of
// lines in A's index space (columns x = k, rows y = k, diagonals x − y = k),
// so each B triangle, cut by the lines that cross it, falls into its
// overlay cells with B ∩ A's triangle, without a walk or a search: the
// general overlay's cells. Nodes are located with exact orientation tests;
// a node on an edge of the other (an exact zero) leaves the pair to the
// general path.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

#include "measure/convex_hull.h"
#include "measure/grid_cells.h"
#include "measure/grid_pair.h"
#include "measure/predicates.h"
#include "measure/tasks.h"
#include "measure/volume.h"

namespace surfreg {

using namespace grid_cells;

namespace {

// A convex polygon in A's index space: a B triangle cut by lines. Each cut
// of a convex polygon adds at most one corner to a side; the capacity
// leaves room for the rounding of slivers (a split of a polygon past half
// of it is not made: see Split).
constexpr int kCapacity = 24;
struct Corner {  // no initializers: a polygon's unused room is never written
  double x, y;
};
struct Polygon {
  int n = 0;
  Corner p[kCapacity];
};

// The three families of A's lines in its index space: columns x = k,
// rows y = k, diagonals x − y = k (the rule's diagonal from a cell's
// corner (0, 0) to (1, 1)); f(p) of each.
template <int Family>
double LineValue(const Corner& p) {
  if (Family == 0) return p.x;
  if (Family == 1) return p.y;
  return p.x - p.y;
}

// `in` split by the line f(p) = k of a family: the part f <= k to `low`,
// f >= k to `high` (Sutherland–Hodgman on one line, both sides).
template <int Family>
void Split(const Polygon& in, double k, Polygon* low, Polygon* high) {
  if (2 * in.n > kCapacity) {  // only a sliver of rounding gets here: kept whole
    *low = in;
    high->n = 0;
    return;
  }
  double f[kCapacity];
  for (int i = 0; i < in.n; ++i) f[i] = LineValue<Family>(in.p[i]) - k;
  low->n = high->n = 0;
  for (int i = 0; i < in.n; ++i) {
    const int j = i + 1 == in.n ? 0 : i + 1;
    const Corner& p = in.p[i];
    const double fp = f[i], fq = f[j];
    if (fp <= 0.0) low->p[low->n++] = p;
    if (fp >= 0.0) high->p[high->n++] = p;
    if ((fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0)) {
      const Corner& q = in.p[j];
      const double t = fp / (fp - fq);
      const Corner x{p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
      low->p[low->n++] = x;
      high->p[high->n++] = x;
    }
  }
}

// The integrals of a convex polygon (index units of area `area_scale`) on
// which d, linear, keeps one side of 0 and of ±lod (lod < 0: of 0 only):
// the fan's means in closed form, as IntegrateTriangleOfArea gives them.
// False if d does not.
bool IntegrateOneSide(const Polygon& poly, const double d[], double area_scale, double lod,
                      VolumeResult* v) {
  double d_min = d[0], d_max = d[0];
  for (int m = 1; m < poly.n; ++m) d_min = std::min(d_min, d[m]), d_max = std::max(d_max, d[m]);
  const bool positive = d_min >= 0.0, negative = d_max <= 0.0;
  // Beyond ±lod where d is (a polygon cut at d = lod has corners at lod).
  const bool above = d_min >= lod && d_max > lod, below = d_max <= -lod && d_min < -lod;
  const bool inside = -lod <= d_min && d_max <= lod;
  if (!(positive || negative) || !(lod < 0.0 || above || below || inside)) return false;
  double integral = 0.0, whole = 0.0;
  const Corner& p0 = poly.p[0];
  for (int m = 1; m + 1 < poly.n; ++m) {
    const double area = 0.5 * area_scale *
                        std::fabs((poly.p[m].x - p0.x) * (poly.p[m + 1].y - p0.y) -
                                  (poly.p[m].y - p0.y) * (poly.p[m + 1].x - p0.x));
    if (!(area > 0.0)) continue;
    integral += area / 3 * ((d[0] + d[m]) + d[m + 1]);
    whole += area;
  }
  v->gap.weight += whole;
  v->gap.signed_volume += integral;
  v->gap.abs += std::fabs(integral);
  (negative ? v->gap.below : v->gap.above) += std::fabs(integral);
  v->area += whole;
  if (lod >= 0.0 && above) v->change.fill += integral, v->change.fill_area += whole;
  if (lod >= 0.0 && below) v->change.cut -= integral, v->change.cut_area += whole;
  return true;
}

// `in` (d at its corners) split where d = level: d <= level to `low`,
// d >= level to `high`; new corners get d = level exactly.
void SplitAtLevel(const Polygon& in, const double d[], double level, Polygon* low, double* d_low,
                  Polygon* high, double* d_high) {
  low->n = high->n = 0;
  for (int i = 0; i < in.n; ++i) {
    const int j = i + 1 == in.n ? 0 : i + 1;
    const double fp = d[i] - level, fq = d[j] - level;
    if (fp <= 0.0) d_low[low->n] = d[i], low->p[low->n++] = in.p[i];
    if (fp >= 0.0) d_high[high->n] = d[i], high->p[high->n++] = in.p[i];
    if ((fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0)) {
      const double t = fp / (fp - fq);
      const Corner x{in.p[i].x + t * (in.p[j].x - in.p[i].x),
                     in.p[i].y + t * (in.p[j].y - in.p[i].y)};
      d_low[low->n] = level, low->p[low->n++] = x;
      d_high[high->n] = level, high->p[high->n++] = x;
    }
  }
}

// The polygon cut at the levels [k, 3) of `levels` (ascending), each part
// then on one side of all of them.
void IntegrateByLevels(const Polygon& poly, const double d[], const double levels[3], int k,
                       int count, double area_scale, double lod, VolumeResult* v) {
  if (poly.n < 3) return;
  if (IntegrateOneSide(poly, d, area_scale, lod, v)) return;
  if (k == count || 2 * poly.n > kCapacity) {  // rounding only: the fan's triangles
    for (int m = 1; m + 1 < poly.n; ++m) {
      const Corner& p0 = poly.p[0];
      const double area = 0.5 * area_scale *
                          std::fabs((poly.p[m].x - p0.x) * (poly.p[m + 1].y - p0.y) -
                                    (poly.p[m].y - p0.y) * (poly.p[m + 1].x - p0.x));
      const double gaps[3] = {d[0], d[m], d[m + 1]};
      IntegrateTriangleOfArea(area, gaps, lod, v);
    }
    return;
  }
  Polygon low, high;
  double d_low[kCapacity], d_high[kCapacity];
  SplitAtLevel(poly, d, levels[k], &low, d_low, &high, d_high);
  IntegrateByLevels(low, d_low, levels, k + 1, count, area_scale, lod, v);
  IntegrateByLevels(high, d_high, levels, k + 1, count, area_scale, lod, v);
}

// One overlay cell's integrals: a convex piece with d at its corners, in
// closed form on each part of it between the levels −lod, 0, lod (most
// pieces are one part). False for a sliver of rounding where a B corner
// lies on one of A's lines (no cell, as in the offset grids' pattern).
bool IntegratePiece(const Polygon& piece, const double d[], double area_scale, double lod,
                    VolumeResult* v) {
  double total = 0.0;
  const Corner& p0 = piece.p[0];
  for (int m = 1; m + 1 < piece.n; ++m) {
    total += std::fabs((piece.p[m].x - p0.x) * (piece.p[m + 1].y - p0.y) -
                       (piece.p[m].y - p0.y) * (piece.p[m + 1].x - p0.x));
  }
  if (!(total > 2e-12)) return false;
  if (!IntegrateOneSide(piece, d, area_scale, lod, v)) {
    const double levels[3] = {-lod, 0.0, lod};
    if (lod > 0.0) {
      IntegrateByLevels(piece, d, levels, 0, 3, area_scale, lod, v);
    } else {
      IntegrateByLevels(piece, d, levels + 1, 0, 1, area_scale, lod, v);
    }
  }
  ++v->cells;
  return true;
}

// Cuts `poly` by every line of the families from `Family` on that crosses
// its interior and hands each piece to emit.
template <int Family, typename Emit>
void Cut(const Polygon& poly, const Emit& emit) {
  if (poly.n < 3) return;
  if constexpr (Family == 3) {
    emit(poly);
  } else {
    double lo = LineValue<Family>(poly.p[0]), hi = lo;
    for (int i = 1; i < poly.n; ++i) {
      const double f = LineValue<Family>(poly.p[i]);
      lo = std::min(lo, f), hi = std::max(hi, f);
    }
    // The part beyond each line goes on; two buffers in turn, no copies.
    Polygon low, buffers[2];
    const Polygon* rest = &poly;
    int spare = 0;
    for (double k = std::floor(lo) + 1.0; k < hi; k += 1.0) {
      Split<Family>(*rest, k, &low, &buffers[spare]);
      Cut<Family + 1>(low, emit);
      rest = &buffers[spare];
      spare ^= 1;
    }
    Cut<Family + 1>(*rest, emit);
  }
}

// Sums of one chunk of B's rows: the cells, A's nodes found in its
// triangles, and B's nodes.
struct MovedChunk {
  ChunkSums a_side, b_side;
};

}  // namespace

bool MeasureOnMovedGrid(const Surface& a, const Surface& b, const MeasureOptions& options,
                        GridPairResult* out) {
  if (!options.grid_shortcut || !a.raster_grid() || !b.raster_grid() ||
      options.volume != VolumeMode::kOverlay || options.domain.kind != DomainKind::kData ||
      options.weight != WeightMode::kUniform) {
    return false;
  }
  GridSide sa, sb;
  const Execution execution = ExecutionFor(options.threads);
  if (!IndexSides(a, b, execution, &sa, &sb)) return false;
  const double magnitude = std::max(Magnitude(a, execution), Magnitude(b, execution));
  GridAffine ga;
  double tolerance = 0;
  if (!FitAffine(a, magnitude, &ga, &tolerance, execution)) return false;
  const double cross = ga.u.x * ga.v.y - ga.u.y * ga.v.x;
  // B on a lattice whose lines run along A's (another spacing, an offset on
  // a line): lines and nodes that coincide, where rounding would make
  // slivers the exact overlay has not. The general path's.
  GridAffine gb;
  double tolerance_b = 0;
  if (FitAffine(b, magnitude, &gb, &tolerance_b, execution)) {
    const auto parallel = [](const Point2& p, const Point2& q) {
      return std::fabs(p.x * q.y - p.y * q.x) <= 1e-9 * std::hypot(p.x, p.y) * std::hypot(q.x, q.y);
    };
    if ((parallel(ga.u, gb.u) && parallel(ga.v, gb.v)) ||
        (parallel(ga.u, gb.v) && parallel(ga.v, gb.u))) {
      return false;
    }
  }
  const double sign = cross > 0.0 ? 1.0 : -1.0;
  sa.cell_area = sb.cell_area = std::fabs(cross);
  GridPairResult& result = *out;
  result = GridPairResult();
  // MarkBoth also refuses a B whose cells turn against A's (a mirrored B is
  // the general path's).
  if (!MarkBoth(&sa, &sb, sign, execution, &result.domain_area_a, &result.domain_area_b))
    return false;

  // A's index space: a point's (x, y) with A's sample (c, r) at (c, r).
  const double x0 = static_cast<double>(ga.c0 - sa.index.c0),
               y0 = static_cast<double>(ga.r0 - sa.index.r0);
  const auto to_index = [&](const Point2& p) {
    const double ex = p.x - ga.origin.x, ey = p.y - ga.origin.y;
    return Point2{x0 + (ex * ga.v.y - ey * ga.v.x) / cross,
                  y0 + (ga.u.x * ey - ga.u.y * ex) / cross};
  };
  const auto a_complete = [&](int64_t c, int64_t r) {
    const uint8_t* row = sa.CompleteRow(r);
    return row != nullptr && c >= 0 && c < sa.index.columns && row[c] != 0;
  };

  const double lod = options.detect_change ? options.level_of_detection : -1.0;
  const bool keep = options.keep_node_gaps;
  const double area_scale = std::fabs(cross);
  std::unique_ptr<std::atomic<uint8_t>[]> found(new std::atomic<uint8_t>[a.size()]);
  for (std::size_t i = 0; i < a.size(); ++i) found[i].store(0, std::memory_order_relaxed);
  std::atomic<bool> general{false};  // an exact tie or a fold: the general path's
  if (keep) result.dz_a.assign(a.size(), std::nan("")), result.dz_b.assign(b.size(), std::nan(""));

  // One B triangle (corners k, rule triangle h of its cell): A's nodes in
  // it and its overlay cells.
  const auto triangle = [&](const int32_t k[4], int h, const Point2 t[4], MovedChunk* sums) {
    const int* rule = kRule[h];
    const Point2 xy[3] = {sb.Xy(k[rule[0]]), sb.Xy(k[rule[1]]), sb.Xy(k[rule[2]])};
    const double z[3] = {sb.Z(k[rule[0]]), sb.Z(k[rule[1]]), sb.Z(k[rule[2]])};
    const Point2 ti[3] = {t[rule[0]], t[rule[1]], t[rule[2]]};
    double lo_x = ti[0].x, hi_x = lo_x, lo_y = ti[0].y, hi_y = lo_y;
    for (int m = 1; m < 3; ++m) {
      lo_x = std::min(lo_x, ti[m].x), hi_x = std::max(hi_x, ti[m].x);
      lo_y = std::min(lo_y, ti[m].y), hi_y = std::max(hi_y, ti[m].y);
    }
    // A's nodes: the lattice points of the box (widened past rounding),
    // each decided exactly.
    constexpr double kWiden = 1e-7;
    const int64_t c_lo = std::max<int64_t>(0, static_cast<int64_t>(std::ceil(lo_x - kWiden)));
    const int64_t c_hi =
        std::min<int64_t>(sa.index.columns - 1, static_cast<int64_t>(std::floor(hi_x + kWiden)));
    const int64_t r_lo = std::max<int64_t>(0, static_cast<int64_t>(std::ceil(lo_y - kWiden)));
    const int64_t r_hi =
        std::min<int64_t>(sa.index.rows - 1, static_cast<int64_t>(std::floor(hi_y + kWiden)));
    for (int64_t r = r_lo; r <= r_hi; ++r) {
      const int32_t* row = sa.SampleRow(r);
      const uint8_t* above = sa.CompleteRow(r - 1);
      const uint8_t* flags = sa.CompleteRow(r);
      for (int64_t c = c_lo; c <= c_hi; ++c) {
        const int32_t i = row[c];
        if (i < 0 || !sa.DomainVertex(above, flags, c)) continue;
        const Point2& p = a.xy[i];
        // Most points of the box are outside: each test as soon as made.
        const double o0 = Orient2D(xy[1], xy[2], p) * sign;
        if (o0 < 0.0) continue;
        const double o1 = Orient2D(xy[2], xy[0], p) * sign;
        if (o1 < 0.0) continue;
        const double o2 = Orient2D(xy[0], xy[1], p) * sign;
        if (o2 < 0.0) continue;
        if (o0 == 0.0 || o1 == 0.0 || o2 == 0.0 ||
            found[i].exchange(1, std::memory_order_relaxed) != 0) {
          general.store(true, std::memory_order_relaxed);
          return;
        }
        const double zi = a.z[i];  // the gap from the corners' gaps: no cancellation of heights
        const double d = (o0 * (z[0] - zi) + o1 * (z[1] - zi) + o2 * (z[2] - zi)) / (o0 + o1 + o2);
        if (keep) result.dz_a[i] = d;
        sums->a_side.gap_sum += std::fabs(d);
        sums->a_side.node_weight += 1.0;
        ++sums->a_side.nodes;
      }
    }
    // B's height over index space: z = zb0 + gx (x − x_0) + gy (y − y_0).
    const double ex1 = ti[1].x - ti[0].x, ey1 = ti[1].y - ti[0].y;
    const double ex2 = ti[2].x - ti[0].x, ey2 = ti[2].y - ti[0].y;
    const double det = ex1 * ey2 - ey1 * ex2;
    if (det == 0.0) return;
    const double dz1 = z[1] - z[0], dz2 = z[2] - z[0];
    const double gx = (dz1 * ey2 - dz2 * ey1) / det, gy = (ex1 * dz2 - ex2 * dz1) / det;
    Polygon poly;
    poly.n = 3;
    for (int m = 0; m < 3; ++m) poly.p[m] = {ti[m].x, ti[m].y};
    Cut<0>(poly, [&](const Polygon& piece) {
      // A point inside the piece (convex): its first three corners' mean.
      const double mx = (piece.p[0].x + piece.p[1].x + piece.p[2].x) / 3.0;
      const double my = (piece.p[0].y + piece.p[1].y + piece.p[2].y) / 3.0;
      const int64_t c = static_cast<int64_t>(std::floor(mx)),
                    r = static_cast<int64_t>(std::floor(my));
      if (!a_complete(c, r)) return;
      const double cx = static_cast<double>(c), cy = static_cast<double>(r);
      const int ha = mx - cx > my - cy ? 0 : 1;
      // d = F_B − F_A as one linear function of the index point: F_A from
      // its triangle's corners (RuleWeights), both less B's first height.
      int32_t ka[4];
      GridSide::Corners(sa.SampleRow(r), sa.SampleRow(r + 1), c, ka);
      const double base = z[0];
      const double z0 = sa.Z(ka[0]) - base, zm = sa.Z(ka[ha == 0 ? 1 : 3]) - base,
                   z2 = sa.Z(ka[2]) - base;
      // F_A − base = z0 + ax (x − c) + ay (y − r)
      const double ax = ha == 0 ? zm - z0 : z2 - zm, ay = ha == 0 ? z2 - zm : zm - z0;
      double d[kCapacity];
      for (int m = 0; m < piece.n; ++m) {
        const Corner& v = piece.p[m];
        d[m] =
            gx * (v.x - ti[0].x) + gy * (v.y - ti[0].y) - (z0 + ax * (v.x - cx) + ay * (v.y - cy));
      }
      IntegratePiece(piece, d, area_scale, lod, &sums->a_side.volume);
    });
  };

  // B's node j (a vertex of its domain, t its point in A's index space):
  // located in A's complete cells around t, exactly.
  const auto b_node = [&](int32_t j, const Point2& t, MovedChunk* sums) {
    const Point2 p = sb.Xy(j);
    const int64_t c0 = static_cast<int64_t>(std::floor(t.x)),
                  r0 = static_cast<int64_t>(std::floor(t.y));
    // The cell under the index point first; its neighbours when rounding
    // put the point across a line.
    static constexpr int kAround[9][2] = {{0, 0},   {-1, 0}, {1, 0},  {0, -1}, {0, 1},
                                          {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
    for (const auto& around : kAround) {
      const int64_t c = c0 + around[0], r = r0 + around[1];
      if (!a_complete(c, r)) continue;
      int32_t k[4];
      GridSide::Corners(sa.SampleRow(r), sa.SampleRow(r + 1), c, k);
      for (int h = 0; h < 2; ++h) {
        const int* rule = kRule[h];
        const Point2& q0 = a.xy[k[rule[0]]];
        const Point2& q1 = a.xy[k[rule[1]]];
        const Point2& q2 = a.xy[k[rule[2]]];
        const double o0 = Orient2D(q1, q2, p) * sign, o1 = Orient2D(q2, q0, p) * sign,
                     o2 = Orient2D(q0, q1, p) * sign;
        if (o0 < 0.0 || o1 < 0.0 || o2 < 0.0) continue;
        if (o0 == 0.0 || o1 == 0.0 || o2 == 0.0) {
          general.store(true, std::memory_order_relaxed);
          return;
        }
        const double zj = sb.Z(j);
        const double d = (o0 * (zj - a.z[k[rule[0]]]) + o1 * (zj - a.z[k[rule[1]]]) +
                          o2 * (zj - a.z[k[rule[2]]])) /
                         (o0 + o1 + o2);
        if (keep) result.dz_b[j] = d;
        sums->b_side.gap_sum += std::fabs(d);
        sums->b_side.node_weight += 1.0;
        ++sums->b_side.nodes;
        return;
      }
    }
  };

  // By chunks of B's rows: each row's cells (both triangles) and nodes.
  const int chunks = RowChunks(sb.index.rows);
  std::vector<MovedChunk> parts(chunks);
  ForEachChunk(execution, sb.index.rows, chunks, [&](int h, int64_t begin, int64_t end) {
    MovedChunk sums;  // on this thread's stack: no line shared with another chunk's
    // B's samples of two rows in A's index space: each moved once, not once
    // per cell it is a corner of.
    std::vector<Point2> t_here(static_cast<std::size_t>(sb.index.columns)),
        t_below(t_here.size());
    const auto to_index_row = [&](const int32_t* row, std::vector<Point2>* t) {
      for (int64_t c = 0; c < sb.index.columns; ++c)
        if (row[c] >= 0) (*t)[static_cast<std::size_t>(c)] = to_index(sb.Xy(row[c]));
    };
    to_index_row(sb.SampleRow(begin), &t_here);
    for (int64_t r = begin; r < end && !general.load(std::memory_order_relaxed); ++r) {
      const int32_t* here = sb.SampleRow(r);
      const int32_t* below = sb.SampleRow(r + 1);
      const uint8_t* above_flags = sb.CompleteRow(r - 1);
      const uint8_t* flags = sb.CompleteRow(r);
      if (below != nullptr) to_index_row(below, &t_below);
      for (int64_t c = 0; c < sb.index.columns; ++c) {
        if (here[c] >= 0 && sb.DomainVertex(above_flags, flags, c)) b_node(here[c], t_here[static_cast<std::size_t>(c)], &sums);
        if (below == nullptr || !flags[c]) continue;
        int32_t k[4];
        GridSide::Corners(here, below, c, k);
        const std::size_t u = static_cast<std::size_t>(c);
        const Point2 t[4] = {t_here[u], t_here[u + 1], t_below[u + 1], t_below[u]};
        triangle(k, 0, t, &sums);
        triangle(k, 1, t, &sums);
      }
      t_here.swap(t_below);
    }
    parts[h] = sums;
  });
  if (general.load()) return false;

  std::vector<ChunkSums> sums(chunks);
  for (int h = 0; h < chunks; ++h) {  // B's nodes after A's, as the other grid paths sum them
    sums[h] = parts[h].a_side;
    sums[h].gap_sum += parts[h].b_side.gap_sum;
    sums[h].node_weight += parts[h].b_side.node_weight;
    sums[h].nodes += parts[h].b_side.nodes;
  }
  std::vector<uint8_t> omega_a(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) omega_a[i] = found[i].load(std::memory_order_relaxed);
  FinishResult(sums, sa, sb, omega_a, keep, execution, &result);
  // B's hull from its samples that may be on it.
  result.hull_area_b = PolygonArea(ConvexHull(HullCandidates(b, sb.index, execution)));
  return true;
}

}  // namespace surfreg
