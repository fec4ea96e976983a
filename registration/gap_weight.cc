#include "registration/gap_weight.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "registration/ring_fit.h"

namespace surfreg {

std::vector<double> PlaneGaps(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh,
                              std::size_t stride) {
  std::vector<double> gap(points.size(), -1.0);
  std::array<Eigen::Vector3d, kMaxRing> ring;
  for (std::size_t v = 0; v < points.size(); v += std::max<std::size_t>(stride, 1)) {
    const int neighbours = RingOffsets(points, mesh, v, &ring);
    if (neighbours < 3) continue;
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();  // of z = c0 + c1 dx + c2 dy
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (int k = 0; k < neighbours; ++k) {
      const Eigen::Vector3d row(1.0, ring[k].x(), ring[k].y());
      normal += row * row.transpose();
      rhs += row * ring[k].z();
    }
    const Eigen::Vector3d plane = normal.ldlt().solve(rhs);
    if (std::isfinite(plane[0])) gap[v] = std::fabs(plane[0]);
  }
  return gap;
}

std::vector<double> CurvatureGaps(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh,
                                  const Execution& execution) {
  std::vector<double> gap(points.size(), -1.0);  // first |λ₁| + |λ₂| of H
  // Each vertex's fit is its own: in chunks, the rings' ℓ² gathered per
  // chunk (their median does not depend on the order).
  const int64_t n = static_cast<int64_t>(points.size());
  const int chunks = ChunksFor(n, 4096);
  std::vector<std::vector<double>> spacing2_of(chunks);
  ForEachChunk(execution, n, chunks, [&](int chunk, int64_t begin, int64_t end) {
    RingQuadratic fit;
    for (int64_t v = begin; v < end; ++v) {
      if (!FitRingQuadratic(points, mesh, static_cast<std::size_t>(v), 0.0, &fit)) continue;
      // |λ₁| + |λ₂| of [[H_xx, H_xy], [H_xy, H_yy]] in closed form.
      const Eigen::Vector3d& h = fit.hessian;
      const double mean = 0.5 * (h[0] + h[2]), radius = std::hypot(0.5 * (h[0] - h[2]), h[1]);
      const double curvature = std::fabs(mean + radius) + std::fabs(mean - radius);
      if (!std::isfinite(curvature)) continue;
      gap[v] = curvature;
      spacing2_of[chunk].push_back(fit.spacing2);
    }
  });
  std::vector<double> spacing2;  // the rings' ℓ²
  for (const std::vector<double>& part : spacing2_of) spacing2.insert(spacing2.end(), part.begin(), part.end());
  if (spacing2.empty()) return gap;
  std::nth_element(spacing2.begin(), spacing2.begin() + spacing2.size() / 2, spacing2.end());
  const double l2 = spacing2[spacing2.size() / 2];
  for (double& g : gap)
    if (g >= 0) g *= 0.25 * l2;
  return gap;
}

void ApplyGapWeight(double floor_fraction, ReferenceSide* reference, const Execution& execution) {
  if (floor_fraction == 0) return;
  ReferenceSide& a = *reference;
  std::vector<Eigen::Vector3d> points(a.xy.size());
  for (std::size_t v = 0; v < a.xy.size(); ++v) points[v] = {a.xy[v].x, a.xy[v].y, a.z[v]};
  const std::vector<double> own = CurvatureGaps(points, a.mesh, execution);
  // The node's local gap: the mean, over the triangles around it, of their
  // corners' own gaps. An average, not the largest: on a noisy surface the
  // largest of a ring picks the noise's extremes, and weights correlated
  // with the noise draw cost accuracy there (measured: docs/registration.md).
  std::vector<double> sum(points.size(), 0.0);
  std::vector<int32_t> count(points.size(), 0);
  for (int32_t t = 0; t < a.mesh.num_triangles(); ++t) {
    const int32_t* v = &a.mesh.triangles[3 * t];
    for (int j = 0; j < 3; ++j) {
      if (own[v[j]] < 0) continue;
      for (int i = 0; i < 3; ++i) {
        sum[v[i]] += own[v[j]];
        ++count[v[i]];
      }
    }
  }
  std::vector<double> local(points.size(), -1.0);
  for (std::size_t v = 0; v < points.size(); ++v)
    if (count[v] > 0) local[v] = sum[v] / count[v];
  std::vector<double> known;
  for (double g : local)
    if (g >= 0) known.push_back(g);
  if (known.empty()) return;  // no node with a closed ring: nothing to go by
  std::nth_element(known.begin(), known.begin() + known.size() / 2, known.end());
  const double median = known[known.size() / 2];
  // Gaps at rounding level (a plane, a flat region) carry no scale: the
  // floor is at least 1e-9 of the data's extent.
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : points) box.extend(p);
  const double floor = std::max(floor_fraction * median, 1e-9 * box.diagonal().norm());
  if (a.weight.empty()) a.weight.assign(points.size(), 1.0);
  for (std::size_t v = 0; v < points.size(); ++v)
    a.weight[v] *= floor / (floor + (local[v] >= 0 ? local[v] : median));
}

double PositiveQuantile(const std::vector<double>& values, double q) {
  std::vector<double> known;
  for (double a : values)
    if (a > 0) known.push_back(a);
  if (known.size() < 10) return 0;
  const auto k = known.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(known.size() - 1));
  std::nth_element(known.begin(), k, known.end());
  return *k;
}

namespace {

// Each node's local area per sample: a third of its data triangles' xy area
// (all triangles when `domain` is empty), averaged over the corners of the
// triangles around it (one sample's share scatters, a Poisson sampling's by
// ±50%, a ring's much less); −1 on no data triangle.
template <typename XY>
std::vector<double> LocalAreaPerSample(std::size_t n, const Triangulation& mesh, const std::vector<uint8_t>& domain,
                                       const XY& xy) {
  const int32_t triangles = mesh.num_triangles();
  std::vector<double> own(n, 0.0), sum(n, 0.0), local(n, -1.0);
  std::vector<int32_t> count(n, 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (int32_t t = 0; t < triangles; ++t) {
      if (!domain.empty() && !domain[t]) continue;
      const int32_t* v = &mesh.triangles[3 * t];
      if (pass == 0) {
        const Point2 p = xy(v[0]), q = xy(v[1]), r = xy(v[2]);
        const double third = std::fabs((q.x - p.x) * (r.y - p.y) - (r.x - p.x) * (q.y - p.y)) / 6.0;
        for (int i = 0; i < 3; ++i) own[v[i]] += third;
        continue;
      }
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
          sum[v[i]] += own[v[j]];
          ++count[v[i]];
        }
      }
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (count[v] > 0 && sum[v] > 0) local[v] = sum[v] / count[v];
  return local;
}

double Spread(const std::vector<double>& local) {
  const double p10 = PositiveQuantile(local, 0.1), p90 = PositiveQuantile(local, 0.9);
  return p10 > 0 ? p90 / p10 : 0.0;
}

std::vector<double> LocalArea(const ReferenceSide& a) {
  return LocalAreaPerSample(a.xy.size(), a.mesh, a.domain, [&](int32_t v) { return a.xy[v]; });
}

}  // namespace

double DensitySpread(const ReferenceSide& reference) { return Spread(LocalArea(reference)); }

double DensitySpread(const MovingSide& moving) {
  return Spread(LocalAreaPerSample(moving.points.size(), moving.mesh, moving.domain, [&](int32_t v) {
    return Point2{moving.points[v].x(), moving.points[v].y()};
  }));
}

bool ApplyDensityWeight(double uneven_ratio, ReferenceSide* reference) {
  if (uneven_ratio == 0) return false;
  ReferenceSide& a = *reference;
  const std::vector<double> local = LocalArea(a);
  if (!(Spread(local) >= uneven_ratio)) return false;
  const double median = PositiveQuantile(local, 0.5);
  if (a.weight.empty()) a.weight.assign(local.size(), 1.0);
  // A node on no data triangle is integrated nowhere: its μ is left.
  for (std::size_t v = 0; v < local.size(); ++v)
    if (local[v] > 0) a.weight[v] *= median / local[v];
  return true;
}

}  // namespace surfreg
