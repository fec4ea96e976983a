// The overlap graph of a series (registration/series.h): footprints on one
// occupancy grid, and the graph's connected pieces.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "registration/series.h"
#include "registration/series_internal.h"

namespace surfreg {
namespace {

struct Box {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -x0, y1 = -x0;
  void Add(double x, double y) {
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  }
  double Area() const { return std::max(0.0, x1 - x0) * std::max(0.0, y1 - y0); }
};

Box BoxOf(const Surface& s) {
  Box box;
  for (const Point2& p : s.xy) box.Add(p.x + s.origin[0], p.y + s.origin[1]);
  return box;
}

// Cells on a side at most: a footprint of 1024² bytes per epoch.
constexpr int kMaxCellsPerSide = 1024;
// The cell, in the sparsest epoch's mean sample spacings: enough samples per
// cell that a cloud covers its own footprint without holes.
constexpr double kCellSpacings = 3.0;

}  // namespace

namespace series_internal {

double Footprints::Count(std::initializer_list<int> epochs) const {
  double count = 0;
  const std::size_t cells = covered.empty() ? 0 : covered[0].size();
  for (std::size_t k = 0; k < cells; ++k) {
    bool all = true;
    for (int e : epochs) all = all && covered[e][k] != 0;
    count += all;
  }
  return count;
}

Footprints EpochFootprints(const std::vector<Surface>& epochs) {
  Box all;
  double spacing = 0;
  for (const Surface& s : epochs) {
    const Box box = BoxOf(s);
    all.Add(box.x0, box.y0);
    all.Add(box.x1, box.y1);
    if (!s.xy.empty())
      spacing = std::max(spacing, std::sqrt(box.Area() / static_cast<double>(s.size())));
  }
  const double width = all.x1 - all.x0, height = all.y1 - all.y0;
  double cell = kCellSpacings * spacing;
  cell = std::max({cell, width / kMaxCellsPerSide, height / kMaxCellsPerSide});
  if (!(cell > 0)) cell = 1;  // every sample at one point
  const int64_t columns = std::max<int64_t>(1, static_cast<int64_t>(width / cell) + 1);
  const int64_t rows = std::max<int64_t>(1, static_cast<int64_t>(height / cell) + 1);
  Footprints footprints;
  footprints.covered.assign(epochs.size(), std::vector<uint8_t>(columns * rows, 0));
  for (std::size_t e = 0; e < epochs.size(); ++e) {
    const Surface& s = epochs[e];
    for (const Point2& p : s.xy) {
      const int64_t c =
          std::min<int64_t>(columns - 1, static_cast<int64_t>((p.x + s.origin[0] - all.x0) / cell));
      const int64_t r =
          std::min<int64_t>(rows - 1, static_cast<int64_t>((p.y + s.origin[1] - all.y0) / cell));
      footprints.covered[e][r * columns + c] = 1;
    }
  }
  return footprints;
}

Eigen::MatrixXd Overlaps(const Footprints& footprints) {
  const int n = static_cast<int>(footprints.covered.size());
  std::vector<double> counts(n);
  for (int e = 0; e < n; ++e) counts[e] = footprints.Count({e});
  Eigen::MatrixXd overlap = Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double smaller = std::min(counts[i], counts[j]);
      overlap(i, j) = overlap(j, i) = smaller > 0 ? footprints.Count({i, j}) / smaller : 0;
    }
  }
  return overlap;
}

}  // namespace series_internal

Eigen::MatrixXd SeriesOverlaps(const std::vector<Surface>& epochs) {
  return series_internal::Overlaps(series_internal::EpochFootprints(epochs));
}

std::vector<std::vector<int>> GraphPieces(int n, const std::vector<std::pair<int, int>>& edges) {
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&parent](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto& [a, b] : edges) {
    const int ra = find(a), rb = find(b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  std::vector<std::vector<int>> pieces;
  std::vector<int> piece_of_root(n, -1);
  for (int v = 0; v < n; ++v) {
    const int root = find(v);
    if (piece_of_root[root] < 0) {
      piece_of_root[root] = static_cast<int>(pieces.size());
      pieces.emplace_back();
    }
    pieces[piece_of_root[root]].push_back(v);
  }
  return pieces;
}

}  // namespace surfreg
