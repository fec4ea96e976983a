// The Delaunay triangulation of a large point set built in vertical slabs,
// one task each, and stitched along the seams.
//
// Why it is exact: with the perturbed in-circle test (predicates.h) the
// triangulation is unique, and a triangle is in it exactly when no input
// point lies in its circle; the same holds within any subset. So
//   - a triangle of a slab's triangulation whose circle lies strictly between
//     the neighbouring slabs' nearest points ("final") is a triangle of the
//     whole triangulation;
//   - every other triangle of the whole has all its corners among the seam
//     vertices: those of the slabs' non-final triangles and of their hulls (a
//     vertex inside its slab's hull whose triangles are all final has its
//     whole star already);
//   - so the seam vertices' own triangulation holds every missing triangle.
//     They fill the region the final triangles leave, which is bounded by the
//     final triangles' outer edges: found by a flood from those edges.
// A count check (2V - 2 - hull edges triangles) guards the stitch; the tests
// compare it with the one-thread build to the bit.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "measure/delaunay_internal.h"
#include "measure/input_error.h"

namespace surfreg {
namespace delaunay_internal {
namespace {

inline int Next(int i) { return i == 2 ? 0 : i + 1; }
inline int Prev(int i) { return i == 0 ? 2 : i - 1; }
inline uint64_t EdgeKey(int32_t from, int32_t to) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(from)) << 32) | static_cast<uint32_t>(to);
}

struct Slab {
  std::vector<int32_t> input;  // input indices, increasing
  std::vector<Point2> points;  // their points
  double min_x = 0.0, max_x = 0.0;
  SlabPart part;
  int32_t first = 0;  // index of its first final triangle in the whole
  bool failed = false;
};

// An outer edge of a final triangle: the stitch's triangle across it holds
// the reversed edge `key` (to -> from).
struct Frontier {
  uint64_t key;
  int32_t final_triangle;
  int32_t edge;         // of final_triangle
  int32_t across = -1;  // seam triangle across, -1 on the hull of the whole
};

// The frontier by key: open addressing, a power of two at least twice its size.
class FrontierIndex {
 public:
  explicit FrontierIndex(const std::vector<Frontier>& frontier) : frontier_(frontier) {
    std::size_t size = 16;
    while (size < 2 * frontier.size()) size *= 2;
    mask_ = size - 1;
    slot_.assign(size, -1);
    for (std::size_t k = 0; k < frontier.size(); ++k) {
      std::size_t h = Hash(frontier[k].key);
      while (slot_[h] >= 0) h = (h + 1) & mask_;
      slot_[h] = static_cast<int32_t>(k);
    }
  }
  // The frontier entry with `key`, or -1.
  int32_t Find(uint64_t key) const {
    for (std::size_t h = Hash(key);; h = (h + 1) & mask_) {
      const int32_t k = slot_[h];
      if (k < 0 || frontier_[k].key == key) return k;
    }
  }

 private:
  std::size_t Hash(uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> 20) & mask_;
  }
  const std::vector<Frontier>& frontier_;
  std::vector<int32_t> slot_;
  std::size_t mask_ = 0;
};

// Cuts the input at quantiles of x (from a strided sample) into slabs with
// no x shared between two (so duplicates stay together); each slab's list
// keeps input order. False when fewer than two slabs come out.
bool CutIntoSlabs(const std::vector<Point2>& points, int wanted, const Execution& execution,
                  std::vector<Slab>* slabs) {
  const int64_t n = static_cast<int64_t>(points.size());
  const int64_t stride = std::max<int64_t>(1, n / (1024 * static_cast<int64_t>(wanted)));
  std::vector<double> sample;
  for (int64_t i = 0; i < n; i += stride) sample.push_back(points[i].x);
  std::sort(sample.begin(), sample.end());
  std::vector<double> splits;
  for (int k = 1; k < wanted; ++k) {
    const double s = sample[sample.size() * k / wanted];
    if (splits.empty() || s > splits.back()) splits.push_back(s);
  }
  const int count = static_cast<int>(splits.size()) + 1;
  if (count < 2) return false;
  const int chunks = ChunksFor(n, 1 << 16);
  std::vector<uint8_t> slab_of(n);
  std::vector<int64_t> fill(static_cast<std::size_t>(chunks) * count, 0);
  ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      // std::upper_bound's index without its unpredictable branches.
      const double x = points[i].x;
      int s = 0;
      for (const double split : splits) s += !(x < split);
      slab_of[i] = static_cast<uint8_t>(s);
      ++fill[static_cast<std::size_t>(c) * count + s];
    }
  });
  slabs->assign(count, Slab());
  for (int s = 0; s < count; ++s) {
    int64_t at = 0;
    for (int c = 0; c < chunks; ++c) {
      const int64_t k = fill[static_cast<std::size_t>(c) * count + s];
      fill[static_cast<std::size_t>(c) * count + s] = at;
      at += k;
    }
    if (at < 3) return false;
    (*slabs)[s].input.resize(at);
    (*slabs)[s].points.resize(at);
  }
  ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const int s = slab_of[i];
      const int64_t k = fill[static_cast<std::size_t>(c) * count + s]++;
      (*slabs)[s].input[k] = static_cast<int32_t>(i);
      (*slabs)[s].points[k] = points[i];
    }
  });
  ForEachChunk(execution, count, count, [&](int s, int64_t, int64_t) {
    Slab& slab = (*slabs)[s];
    slab.min_x = std::numeric_limits<double>::infinity();
    slab.max_x = -slab.min_x;
    for (const Point2& p : slab.points) {
      slab.min_x = std::min(slab.min_x, p.x);
      slab.max_x = std::max(slab.max_x, p.x);
    }
  });
  return true;
}

// Triangulates slab s: its final triangles and its seam.
void BuildSlab(const DelaunayOptions& options, int s, std::vector<Slab>* slabs) {
  Slab& slab = (*slabs)[s];
  const double inf = std::numeric_limits<double>::infinity();
  const double lo = s > 0 ? (*slabs)[s - 1].max_x : -inf;
  const double hi = s + 1 < static_cast<int>(slabs->size()) ? (*slabs)[s + 1].min_x : inf;
  try {
    TriangulateSlab(slab.points, slab.input, options, lo, hi, &slab.part);
  } catch (const InputError&) {
    slab.failed = true;  // collinear or repeated: the whole is built on one thread
    return;
  }
  slab.points = std::vector<Point2>();  // no longer needed
}

}  // namespace

bool TriangulateInSlabs(const std::vector<Point2>& points, const DelaunayOptions& options,
                        Triangulation* out, int64_t slab_points) {
  const int64_t n = static_cast<int64_t>(points.size());
  const Execution& execution = options.execution;
  const int wanted =
      static_cast<int>(std::min<int64_t>(n / std::max<int64_t>(1, slab_points), kMaxChunks));
  if (wanted < 2 || n > std::numeric_limits<int32_t>::max() / 8) return false;
  std::vector<Slab> slabs;
  if (!CutIntoSlabs(points, wanted, execution, &slabs)) return false;
  const int count = static_cast<int>(slabs.size());
  DelaunayOptions one = options;
  one.execution = Execution{1};
  ForEachChunk(execution, count, count,
               [&](int s, int64_t, int64_t) { BuildSlab(one, s, &slabs); });
  int32_t num_final = 0;
  std::size_t frontier_size = 0, seam_size = 0;
  for (Slab& slab : slabs) {
    if (slab.failed) return false;
    slab.first = num_final;
    num_final += slab.part.num_final;
    frontier_size += slab.part.frontier.size();
    seam_size += slab.part.seam.size();
  }
  // No final triangle (e.g. cocircular points): the seam is everything.
  if (num_final == 0) return false;
  std::vector<int32_t> seam;
  seam.reserve(seam_size);
  for (const Slab& slab : slabs)
    seam.insert(seam.end(), slab.part.seam.begin(), slab.part.seam.end());
  std::sort(seam.begin(), seam.end());

  // The final triangles' outer edges, by the key the seam's triangulation
  // sees them by (slab after slab: the order does not matter).
  std::vector<Frontier> frontier;
  frontier.reserve(frontier_size);
  for (const Slab& slab : slabs) {
    for (const SlabPart::Edge& e : slab.part.frontier) {
      frontier.push_back({EdgeKey(e.to, e.from), slab.first + e.triangle, e.edge});
    }
  }
  const FrontierIndex frontier_index(frontier);

  // The seam's triangulation; the triangles the final ones leave are those
  // reached from across a frontier edge without crossing one.
  std::vector<Point2> seam_points(seam.size());
  for (std::size_t k = 0; k < seam.size(); ++k) seam_points[k] = points[seam[k]];
  Triangulation stitch;
  try {
    stitch = TriangulateOneThread(seam_points, one);
  } catch (const InputError&) {
    return false;
  }
  const int32_t stitch_triangles = stitch.num_triangles();
  std::vector<int32_t> wall(3 * static_cast<std::size_t>(stitch_triangles), -1);  // frontier index
  std::vector<int32_t> missing_id(stitch_triangles, -1);
  std::vector<int32_t> stack;
  for (int32_t t = 0; t < stitch_triangles; ++t) {
    for (int i = 0; i < 3; ++i) {
      const int32_t from = seam[stitch.triangles[3 * t + Next(i)]];
      const int32_t to = seam[stitch.triangles[3 * t + Prev(i)]];
      const int32_t f = frontier_index.Find(EdgeKey(from, to));
      if (f >= 0) {
        frontier[f].across = t;
        wall[3 * t + i] = f;
        stack.push_back(t);
      }
    }
  }
  int32_t num_missing = 0;
  while (!stack.empty()) {
    const int32_t t = stack.back();
    stack.pop_back();
    if (missing_id[t] >= 0) continue;
    missing_id[t] = 0;
    for (int i = 0; i < 3; ++i) {
      const int32_t u = stitch.neighbors[3 * t + i];
      if (wall[3 * t + i] < 0 && u >= 0 && missing_id[u] < 0) stack.push_back(u);
    }
  }
  for (int32_t& m : missing_id) {
    if (m >= 0) m = num_final + num_missing++;
  }

  // The whole: each slab's final triangles in its own order, slab after
  // slab, then the stitch's in its order.
  const int64_t total = static_cast<int64_t>(num_final) + num_missing;
  Triangulation result;
  result.triangles.resize(3 * total);
  result.neighbors.resize(3 * total);
  result.vertex_triangle.assign(n, -1);
  result.vertex_of_input.resize(n);
  ForEachChunk(execution, n, ChunksFor(n, 1 << 16), [&](int, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) result.vertex_of_input[i] = static_cast<int32_t>(i);
  });
  std::atomic<bool> consistent{true};
  ForEachChunk(execution, count, count, [&](int s, int64_t, int64_t) {
    const Slab& slab = slabs[s];
    const SlabPart& part = slab.part;
    const int32_t first = slab.first;
    std::copy(part.triangles.begin(), part.triangles.end(),
              result.triangles.begin() + 3 * static_cast<int64_t>(first));
    int32_t* neighbors = result.neighbors.data() + 3 * static_cast<int64_t>(first);
    for (std::size_t k = 0; k < part.neighbors.size(); ++k) {
      const int32_t u = part.neighbors[k];
      neighbors[k] = u >= 0 ? u + first : -1;  // frontier: below
    }
    for (std::size_t k = 0; k < slab.input.size(); ++k) {
      const int32_t f = part.first_final[k];
      result.vertex_triangle[slab.input[k]] = f >= 0 ? f + first : -1;
    }
    if (part.num_duplicates == 0) return;  // each its own vertex: below
    for (std::size_t k = 0; k < slab.input.size(); ++k) {
      result.vertex_of_input[slab.input[k]] = part.kept[k];
    }
  });
  for (const Frontier& f : frontier) {
    const int32_t m = f.across >= 0 ? missing_id[f.across] : -1;
    if (f.across >= 0 && m < 0) consistent = false;
    result.neighbors[3 * f.final_triangle + f.edge] = m;
  }
  for (int32_t t = 0; t < stitch_triangles; ++t) {
    const int32_t m = missing_id[t];
    if (m < 0) continue;
    for (int i = 0; i < 3; ++i) {
      const int32_t v = seam[stitch.triangles[3 * t + i]];
      result.triangles[3 * m + i] = v;
      if (result.vertex_triangle[v] < 0) result.vertex_triangle[v] = m;
      const int32_t w = wall[3 * t + i];
      const int32_t u = stitch.neighbors[3 * t + i];
      if (w >= 0) {
        result.neighbors[3 * m + i] = frontier[w].final_triangle;
      } else if (u >= 0) {
        result.neighbors[3 * m + i] = missing_id[u];
        if (missing_id[u] < 0) consistent = false;
      } else {
        result.neighbors[3 * m + i] = -1;
      }
    }
  }
  // Every distinct point a vertex: V vertices with H on the hull make
  // 2V - 2 - H triangles.
  for (const Slab& slab : slabs) result.num_duplicates += slab.part.num_duplicates;
  int64_t hull_edges = 0;
  for (int32_t u : result.neighbors) hull_edges += u < 0;
  if (!consistent || total != 2 * (n - result.num_duplicates) - 2 - hull_edges) return false;
  *out = std::move(result);
  return true;
}

}  // namespace delaunay_internal
}  // namespace surfreg
