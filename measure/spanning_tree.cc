#include "measure/spanning_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "measure/bucket_scatter.h"

namespace surfreg {
namespace {

struct Edge {
  uint64_t key;  // bits of the squared length: a non-negative double orders like its bits
  int32_t u, v;
};

// Stable LSD radix sort on the 64-bit key, 16 bits a pass, in chunks: each
// chunk counts its keys, and a bucket's chunks are laid out in chunk order,
// so the result is the one sequential stable sort, on any number of threads.
// Its 4 x 65536 bucket sweeps cost more than sorting a small cloud's edges
// outright (found by fuzz_measure: 0.4 ms of a 0.45 ms measure of two
// 25-point clouds), so small inputs take a stable comparison sort: the same
// order exactly.
void RadixSortEdges(std::unique_ptr<Edge[]>& edges, int64_t n, const Execution& execution) {
  if (n < 4096) {
    std::stable_sort(edges.get(), edges.get() + n, [](const Edge& a, const Edge& b) { return a.key < b.key; });
    return;
  }
  BucketSlots slots(ChunksFor(n, 1 << 18), 65536);
  std::unique_ptr<Edge[]> buffer(new Edge[static_cast<std::size_t>(n)]);  // first touched by the scatter
  for (int shift = 0; shift < 64; shift += 16) {
    const Edge* from = edges.get();
    Edge* to = buffer.get();
    const auto digit = [from, shift](int64_t k) { return static_cast<int>((from[k].key >> shift) & 0xFFFF); };
    CountIntoBuckets(execution, n, slots, digit);
    if (slots.start[1] == n) continue;  // all in bucket 0: the pass changes nothing
    ScatterIntoBuckets(execution, n, slots, digit, [from, to](int64_t k, int64_t at) { to[at] = from[k]; });
    edges.swap(buffer);
  }
}

int32_t Find(std::vector<int32_t>& up, int32_t x) {
  while (up[x] != x) {
    up[x] = up[up[x]];  // path halving
    x = up[x];
  }
  return x;
}

// Which sorted edges may be in the tree, found in parallel (empty: all).
// The vertices are cut into ranges (a Hilbert-sorted surface's are
// spatially compact); each range's own edges go through Kruskal on their
// own, and an edge it rejects closes a cycle of edges earlier in the sorted
// order (length, then position), so it is that cycle's last and no minimum
// spanning tree's edge. Kruskal over the ranges' forests and the edges
// between ranges, in the same order, then makes the very tree (and sums)
// that Kruskal over all edges makes. Leaves `up` and `size` as they were.
std::vector<uint8_t> SlabForestEdges(const Edge* edges, int64_t m, int32_t n, const Execution& execution,
                                     std::vector<int32_t>* up, std::vector<int32_t>* size) {
  const int ranges = ChunksFor(n, 1 << 16);
  if (ranges == 1) return {};
  const auto range_of = [&](int32_t v) {
    return static_cast<int>((static_cast<int64_t>(v + 1) * ranges - 1) / n);
  };
  std::vector<uint8_t> candidate(static_cast<std::size_t>(m), 0);
  // Each range's edges, in sorted order (a stable scatter by range); the
  // edges between ranges are candidates for the last pass.
  BucketSlots slots(ChunksFor(m, 1 << 16), ranges);
  const auto range_within = [&](int64_t k) {
    const int ru = range_of(edges[k].u);
    return ru == range_of(edges[k].v) ? ru : -1;
  };
  CountIntoBuckets(execution, m, slots, [&](int64_t k) {
    const int r = range_within(k);
    if (r < 0) candidate[k] = 1;
    return r;
  });
  const std::vector<int64_t>& range_start = slots.start;
  std::vector<int64_t> position(static_cast<std::size_t>(range_start[ranges]));
  ScatterIntoBuckets(execution, m, slots, range_within, [&](int64_t k, int64_t at) { position[at] = k; });
  // Each range's Kruskal on its own vertices' entries of `up` and `size`.
  ForEachChunk(execution, ranges, ranges, [&](int r, int64_t, int64_t) {
    for (int64_t i = range_start[r]; i < range_start[r + 1]; ++i) {
      const Edge& e = edges[position[i]];
      int32_t a = Find(*up, e.u), b = Find(*up, e.v);
      if (a == b) continue;
      if ((*size)[a] < (*size)[b]) std::swap(a, b);
      (*up)[b] = a;
      (*size)[a] += (*size)[b];
      candidate[position[i]] = 1;
    }
    for (int64_t v = ChunkBegin(n, ranges, r); v < ChunkBegin(n, ranges, r + 1); ++v) {
      (*up)[v] = static_cast<int32_t>(v), (*size)[v] = 1;
    }
  });
  return candidate;
}

}  // namespace

SpanningTree EuclideanMst(const std::vector<Point2>& points, const Triangulation& mesh,
                          const Execution& execution) {
  const auto n = static_cast<int32_t>(points.size());
  // Each interior edge once, from its higher-numbered triangle; in triangle
  // order (ties in length go by it), gathered in chunks of triangles.
  const int32_t num_triangles = mesh.num_triangles();
  const int chunks = ChunksFor(num_triangles, 1 << 17);
  std::vector<int64_t> chunk_start(chunks + 1, 0);
  auto listed_here = [&](int64_t t, int i) {
    const int32_t other = mesh.neighbors[3 * t + i];
    return !(other >= 0 && other < t);
  };
  ForEachChunk(execution, num_triangles, chunks, [&](int c, int64_t begin, int64_t end) {
    int64_t k = 0;
    for (int64_t t = begin; t < end; ++t) {
      for (int i = 0; i < 3; ++i) k += listed_here(t, i);
    }
    chunk_start[c + 1] = k;
  });
  for (int c = 0; c < chunks; ++c) chunk_start[c + 1] += chunk_start[c];
  const int64_t m = chunk_start[chunks];
  std::unique_ptr<Edge[]> edges(new Edge[static_cast<std::size_t>(m)]);  // each chunk fills its own part
  ForEachChunk(execution, num_triangles, chunks, [&](int c, int64_t begin, int64_t end) {
    int64_t k = chunk_start[c];
    for (int64_t t = begin; t < end; ++t) {
      for (int i = 0; i < 3; ++i) {
        if (!listed_here(t, i)) continue;
        const int32_t u = mesh.triangles[3 * t + (i + 1) % 3];
        const int32_t v = mesh.triangles[3 * t + (i + 2) % 3];
        const double dx = points[u].x - points[v].x, dy = points[u].y - points[v].y;
        const double length2 = dx * dx + dy * dy;
        uint64_t key;
        std::memcpy(&key, &length2, sizeof key);
        edges[k++] = {key, u, v};
      }
    }
  });
  RadixSortEdges(edges, m, execution);

  SpanningTree tree;
  std::vector<int32_t> up(n), size(n, 1);
  for (int32_t i = 0; i < n; ++i) up[i] = i;
  const std::vector<uint8_t> candidate = SlabForestEdges(edges.get(), m, n, execution, &up, &size);
  // The candidates' ends, gathered in order by chunks, for the last
  // Kruskal's tight loop (a third of the edges, or all without ranges).
  int64_t count = m;
  std::unique_ptr<std::array<int32_t, 2>[]> ends;
  if (!candidate.empty()) {
    BucketSlots slots(ChunksFor(m, 1 << 16), 1);
    const auto kept = [&](int64_t k) { return candidate[k] ? 0 : -1; };
    CountIntoBuckets(execution, m, slots, kept);
    count = slots.start[1];
    ends.reset(new std::array<int32_t, 2>[static_cast<std::size_t>(count)]);
    ScatterIntoBuckets(execution, m, slots, kept, [&](int64_t k, int64_t at) {
      ends[at] = {edges[k].u, edges[k].v};
    });
  } else {
    ends.reset(new std::array<int32_t, 2>[static_cast<std::size_t>(m)]);
    for (int64_t k = 0; k < m; ++k) ends[k] = {edges[k].u, edges[k].v};
  }
  edges.reset();
  // Tree adjacency as a compressed list: count, then fill.
  std::vector<int32_t> degree(n + 1, 0), chosen_u, chosen_v;
  chosen_u.reserve(n);
  chosen_v.reserve(n);
  for (int64_t k = 0; k < count; ++k) {
    const int32_t u = ends[k][0], v = ends[k][1];
    int32_t a = Find(up, u), b = Find(up, v);
    if (a == b) continue;
    if (size[a] < size[b]) std::swap(a, b);
    up[b] = a;
    size[a] += size[b];
    chosen_u.push_back(u);
    chosen_v.push_back(v);
    ++degree[u + 1];
    ++degree[v + 1];
  }
  ends.reset();
  // The length: the chosen edges' by chunks, added in chunk order.
  const int64_t chosen = static_cast<int64_t>(chosen_u.size());
  const int length_chunks = ChunksFor(chosen, 1 << 16);
  std::vector<double> length(length_chunks, 0.0);
  ForEachChunk(execution, chosen, length_chunks, [&](int c, int64_t begin, int64_t end) {
    double sum = 0;
    for (int64_t k = begin; k < end; ++k) {
      const double dx = points[chosen_u[k]].x - points[chosen_v[k]].x;
      const double dy = points[chosen_u[k]].y - points[chosen_v[k]].y;
      sum += std::sqrt(dx * dx + dy * dy);
    }
    length[c] = sum;
  });
  for (double l : length) tree.total_length += l;
  for (int32_t i = 0; i < n; ++i) degree[i + 1] += degree[i];
  std::vector<int32_t> adjacency(degree[n]), fill(degree.begin(), degree.end() - 1);
  for (std::size_t k = 0; k < chosen_u.size(); ++k) {
    adjacency[fill[chosen_u[k]]++] = chosen_v[k];
    adjacency[fill[chosen_v[k]]++] = chosen_u[k];
  }

  // Depth-first preorder from each root, in vertex order.
  tree.parent.assign(n, -1);
  tree.order.reserve(n);
  std::vector<char> seen(n, 0);
  std::vector<int32_t> stack;
  for (int32_t root = 0; root < n; ++root) {
    if (seen[root] || mesh.vertex_triangle[root] < 0) continue;
    seen[root] = 1;
    stack.push_back(root);
    while (!stack.empty()) {
      const int32_t v = stack.back();
      stack.pop_back();
      tree.order.push_back(v);
      for (int32_t k = degree[v]; k < degree[v + 1]; ++k) {
        const int32_t w = adjacency[k];
        if (seen[w]) continue;
        seen[w] = 1;
        tree.parent[w] = v;
        stack.push_back(w);
      }
    }
  }
  return tree;
}

}  // namespace surfreg
