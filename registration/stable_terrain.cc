#include "registration/stable_terrain.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "measure/delaunay.h"
#include "registration/gap_weight.h"

namespace surfreg {

const char* StableModeName(StableOptions::Mode mode) {
  return mode == StableOptions::Mode::kAuto ? "auto" : "all";
}

namespace {

// The middle value (the upper one of an even count), by selection; 0 for none.
double MedianOf(std::vector<double>* values) {
  if (values->empty()) return 0;
  std::nth_element(values->begin(), values->begin() + values->size() / 2, values->end());
  return (*values)[values->size() / 2];
}

// Per input sample: the local area per sample over its median, where the
// sampling's density is uneven by design; 1 everywhere otherwise. The area
// per sample is a third of the xy area of the triangles around a vertex, on
// vertices whose ring closes (on the hull part of the share is missing),
// then kDensityPasses times the mean over the sample and its neighbours that
// have one (a hull sample takes its neighbours'). Uneven by design: after
// the first pass, its 90th percentile at least kUnevenSpread times its 10th
// (the face mesh's vertices 140; a uniform random sampling 2.3, a jittered
// grid 1.2, a grid 1.1; gap_weight.h's DensitySpread is alike). Below it,
// the local area is one sampling's scatter about one density, which says
// nothing of the other surface's spacing there: used anyway, it moved the
// changed benchmark's pairs at random, 8% / 5% worse on the whole
// (docs/registration.md). The second pass narrows a random sampling's
// scatter (2.3x to 1.9x) and keeps a mesh's spread (140x to 110x).
constexpr int kDensityPasses = 2;
constexpr double kUnevenSpread = 5;

std::vector<double> LocalSpacingFactor(const Surface& reference, const Triangulation& mesh,
                                       const SampleAdjacency& adjacency) {
  const std::size_t n = reference.size();
  std::vector<double> area(n, 0.0);
  std::vector<uint8_t> open(n, 0);
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int32_t* v = &mesh.triangles[3 * static_cast<std::size_t>(t)];
    const Point2 p = reference.xy[v[0]], q = reference.xy[v[1]], r = reference.xy[v[2]];
    const double third = std::fabs((q.x - p.x) * (r.y - p.y) - (r.x - p.x) * (q.y - p.y)) / 6.0;
    for (int k = 0; k < 3; ++k) {
      area[v[k]] += third;
      if (mesh.neighbors[3 * static_cast<std::size_t>(t) + k] < 0) open[v[(k + 1) % 3]] = open[v[(k + 2) % 3]] = 1;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (open[i] || mesh.vertex_triangle[i] < 0 || !(area[i] > 0)) area[i] = -1;
  }
  std::vector<double> next(n);
  for (int pass = 0; pass < kDensityPasses; ++pass) {
    for (std::size_t i = 0; i < n; ++i) {
      double sum = area[i] > 0 ? area[i] : 0.0;
      int count = area[i] > 0 ? 1 : 0;
      for (int32_t k = adjacency.offset[i]; k < adjacency.offset[i + 1]; ++k) {
        const double a = area[adjacency.neighbour[k]];
        if (a > 0) sum += a, ++count;
      }
      next[i] = count > 0 ? sum / count : -1.0;
    }
    area.swap(next);
    if (pass == 0) {
      const double p10 = PositiveQuantile(area, 0.1);
      if (!(p10 > 0 && PositiveQuantile(area, 0.9) >= kUnevenSpread * p10)) return std::vector<double>(n, 1.0);
    }
  }
  const double median = PositiveQuantile(area, 0.5);
  std::vector<double> factor(n, 1.0);
  if (!(median > 0)) return factor;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = area[mesh.vertex_of_input[i]];
    if (a > 0) factor[i] = a / median;
  }
  return factor;
}

}  // namespace

SampleAdjacency MakeSampleAdjacency(const Surface& reference, const Execution& execution) {
  DelaunayOptions delaunay;
  delaunay.execution = execution;
  const Triangulation mesh = Triangulate(reference.xy, delaunay);
  const int32_t n = static_cast<int32_t>(reference.size());
  // Each sample's neighbours, sorted and without repeats: its Delaunay
  // edges (from both triangles of an edge) and, for a merged duplicate, its
  // vertex (so it shares its class). Counted, scattered, then each list
  // sorted on its own (in chunks of samples): what sorting all the directed
  // edges would give, without that sort.
  SampleAdjacency adjacency;
  std::vector<int32_t> start(static_cast<std::size_t>(n) + 1, 0);
  const auto each_edge = [&](const auto& add) {
    for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
      for (int k = 0; k < 3; ++k) {
        const int32_t a = mesh.triangles[t + k], b = mesh.triangles[t + (k + 1) % 3];
        add(a, b), add(b, a);
      }
    }
    for (int32_t i = 0; i < n; ++i) {
      const int32_t v = mesh.vertex_of_input[i];
      if (v != i) add(i, v), add(v, i);
    }
  };
  each_edge([&](int32_t a, int32_t) { ++start[a + 1]; });
  for (int32_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<int32_t> all(static_cast<std::size_t>(start[n]));
  {
    std::vector<int32_t> next(start.begin(), start.end() - 1);
    each_edge([&](int32_t a, int32_t b) { all[next[a]++] = b; });
  }
  std::vector<int32_t> kept(static_cast<std::size_t>(n), 0);  // each list's length without repeats
  const int chunks = ChunksFor(n, 8192);
  ForEachChunk(execution, n, chunks, [&](int, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      int32_t* first = all.data() + start[i];
      int32_t* last = all.data() + start[i + 1];
      std::sort(first, last);
      kept[i] = static_cast<int32_t>(std::unique(first, last) - first);
    }
  });
  adjacency.offset.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int32_t i = 0; i < n; ++i) adjacency.offset[i + 1] = adjacency.offset[i] + kept[i];
  adjacency.neighbour.resize(static_cast<std::size_t>(adjacency.offset[n]));
  ForEachChunk(execution, n, chunks, [&](int, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      std::copy(all.data() + start[i], all.data() + start[i] + kept[i],
                adjacency.neighbour.data() + adjacency.offset[i]);
    }
  });

  std::vector<Eigen::Vector3d> points(reference.size());
  for (std::size_t i = 0; i < reference.size(); ++i) {
    points[i] = Eigen::Vector3d(reference.xy[i].x, reference.xy[i].y, reference.z[i]);
  }
  const std::vector<double> by_vertex = CurvatureGaps(points, mesh, execution);
  std::vector<double> defined;
  for (double g : by_vertex) {
    if (g >= 0) defined.push_back(g);
  }
  const double median = MedianOf(&defined);
  // CurvatureGaps scales every vertex by the surface's median ring spacing
  // ℓ²; the interpolation gap at a place follows the sampling's spacing
  // there. So each g is scaled by the local area per sample over its median
  // (ℓ² ∝ area per sample): a mesh's vertices, a hundred times sparser on a
  // face's cheeks than on its nose, otherwise get gaps far too small where
  // sparse (their interpolation gaps then look like change) and far too
  // large where dense.
  const std::vector<double> density = LocalSpacingFactor(reference, mesh, adjacency);
  adjacency.curvature_gap.resize(reference.size());
  for (int32_t i = 0; i < n; ++i) {
    const double g = by_vertex[mesh.vertex_of_input[i]];
    adjacency.curvature_gap[i] = (g >= 0 ? g : median) * density[i];
  }
  adjacency.gradient.assign(reference.size(), {0.0, 0.0});
  ForEachChunk(execution, n, chunks, [&](int, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      double sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0;
      for (int32_t k = adjacency.offset[i]; k < adjacency.offset[i + 1]; ++k) {
        const int32_t j = adjacency.neighbour[k];
        const double dx = reference.xy[j].x - reference.xy[i].x, dy = reference.xy[j].y - reference.xy[i].y;
        const double dz = reference.z[j] - reference.z[i];
        sxx += dx * dx, sxy += dx * dy, syy += dy * dy, sxz += dx * dz, syz += dy * dz;
      }
      const double det = sxx * syy - sxy * sxy;
      if (det > 1e-12 * (sxx + syy) * (sxx + syy)) {
        adjacency.gradient[i] = {(syy * sxz - sxy * syz) / det, (sxx * syz - sxy * sxz) / det};
      }
    }
  });
  return adjacency;
}

namespace {

// A region is change only if the mean of the moving surface's own gaps
// there is within a factor of the reference's (stable_terrain.h). At the
// spots where two samplings of an unchanged face or DEM disagree, the ratio
// scatters over -1.2 to 0.7 (one at 1.47), and those spots are small: at
// most 19 samples over the 36 unchanged pairs of the benchmark. Change on
// curved ground is seen a little lower from the moving side: the
// interpolation gap has opposite signs at the two surfaces' nodes, and on
// the LIDAR blobs (3-12 m on ground whose curvature gap is 3-6 m) it puts
// the ratio at 0.4-0.7. So a region of at least kLargeRegionFactor x
// min_region_samples samples is change down to kPartnerLowLarge.
constexpr double kPartnerLow = 0.75, kPartnerHigh = 1 / 0.75, kPartnerLowLarge = 0.3;
constexpr int kLargeRegionFactor = 2;

// The median of `values` (reordered); 0 for none.
double Median(std::vector<double>* values) {
  if (values->empty()) return 0;
  const std::size_t half = values->size() / 2;
  std::nth_element(values->begin(), values->begin() + half, values->end());
  double m = (*values)[half];
  if (values->size() % 2 == 0) m = 0.5 * (m + *std::max_element(values->begin(), values->begin() + half));
  return m;
}

}  // namespace

StableTerrain ClassifyStable(const SampleAdjacency& adjacency, const GapField& gaps,
                             const std::vector<uint8_t>& eligible, const std::vector<uint8_t>& stable,
                             const StableOptions& options) {
  const std::vector<double>& dz = gaps.dz;
  const std::vector<double>& area = gaps.area;
  const std::size_t n = dz.size();
  const bool partners = !gaps.partner_count.empty();
  StableTerrain out;
  out.done = true;
  out.flag.assign(n, kOutsideOverlap);
  auto in_overlap = [&](std::size_t i) { return std::isfinite(dz[i]) && (eligible.empty() || eligible[i] != 0); };

  // The samples m and the scales are measured on: the current stable set,
  // or all of the overlap if that set left it.
  bool any_stable = false;
  for (std::size_t i = 0; i < n && !stable.empty(); ++i) any_stable |= in_overlap(i) && stable[i] == kStableSample;
  auto measured = [&](std::size_t i) {
    return in_overlap(i) && (!any_stable || stable[i] == kStableSample);
  };
  std::vector<double> values;
  values.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (measured(i)) values.push_back(dz[i]);
  }
  const double m = Median(&values);
  // The noise n: the gaps' robust scale where the reference is flatter than
  // its median curvature gap (there the gaps are noise, not curvature).
  const std::vector<double>& g = adjacency.curvature_gap;
  std::vector<double> flat_g;
  for (std::size_t i = 0; i < n; ++i) {
    if (measured(i)) flat_g.push_back(g[i]);
  }
  const double g_median = Median(&flat_g);
  values.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (measured(i) && g[i] <= g_median) {
      values.push_back(std::abs(dz[i] - m));
    }
  }
  const double noise = 1.4826 * Median(&values);
  auto unit = [&](std::size_t i) { return std::sqrt(noise * noise + g[i] * g[i]); };
  values.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (measured(i) && unit(i) > 0) {
      values.push_back(std::abs(dz[i] - m) / unit(i));
    }
  }
  const double sigma = 1.4826 * Median(&values);
  out.centre = m;
  out.noise_sigma = sigma * noise;
  // z_i: the gap from m in sample i's own scale σ √(n² + g_i²).
  auto z = [&](std::size_t i) {
    const double s = sigma * unit(i);
    return s > 0 ? (dz[i] - m) / s : 0.0;
  };

  // side[i]: +1 / −1 beyond the grow level above / below m, 0 within it.
  std::vector<int8_t> side(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!in_overlap(i)) continue;
    out.flag[i] = kStableSample;
    const double r = z(i);
    if (std::abs(r) > options.grow_sigmas) side[i] = r > 0 ? 1 : -1;
  }
  // Regions: connected samples on one side beyond the grow level that hold
  // at least one seed; each kept if large enough.
  std::vector<int32_t> region(n, -1);
  std::vector<int32_t> members;
  std::vector<uint8_t> changed(n, 0);
  int32_t next_region = 0;
  for (std::size_t start = 0; start < n; ++start) {
    if (side[start] == 0 || region[start] >= 0) continue;
    members.clear();
    members.push_back(static_cast<int32_t>(start));
    region[start] = next_region;
    bool seeded = false;
    for (std::size_t head = 0; head < members.size(); ++head) {
      const int32_t i = members[head];
      seeded |= std::abs(z(i)) > options.seed_sigmas;
      for (int32_t k = adjacency.offset[i]; k < adjacency.offset[i + 1]; ++k) {
        const int32_t j = adjacency.neighbour[k];
        if (region[j] < 0 && side[j] == side[start]) {
          region[j] = next_region;
          members.push_back(j);
        }
      }
    }
    ++next_region;
    if (!seeded || static_cast<int>(members.size()) < options.min_region_samples) continue;
    if (partners) {
      double sum_a = 0, sum_b = 0;
      int64_t count_b = 0;
      for (int32_t i : members) {
        sum_a += dz[i] - m;
        sum_b += gaps.partner_sum[i] - m * gaps.partner_count[i];
        count_b += gaps.partner_count[i];
      }
      // Too few of the moving surface's samples to confirm it: not change.
      if (count_b < 3) continue;
      const double mean_a = sum_a / static_cast<double>(members.size());
      const double mean_b = sum_b / static_cast<double>(count_b);
      // Change is seen alike from both surfaces' samples.
      const double ratio = mean_a != 0 ? mean_b / mean_a : 0.0;
      const bool large = static_cast<int64_t>(members.size()) >=
                         static_cast<int64_t>(kLargeRegionFactor) * options.min_region_samples;
      if (!(ratio >= (large ? kPartnerLowLarge : kPartnerLow) && ratio <= kPartnerHigh)) continue;
    }
    ++out.regions;
    for (int32_t i : members) changed[i] = 1;
  }
  // The rim: margin_rings rings of neighbours, within the overlap.
  std::vector<int32_t> frontier, next;
  for (std::size_t i = 0; i < n; ++i) {
    if (changed[i]) frontier.push_back(static_cast<int32_t>(i));
  }
  for (int ring = 0; ring < options.margin_rings; ++ring) {
    next.clear();
    for (int32_t i : frontier) {
      for (int32_t k = adjacency.offset[i]; k < adjacency.offset[i + 1]; ++k) {
        const int32_t j = adjacency.neighbour[k];
        if (!changed[j] && in_overlap(j)) {
          changed[j] = 1;
          next.push_back(j);
        }
      }
    }
    frontier.swap(next);
  }
  double stable_weight = 0, total_weight = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (out.flag[i] == kOutsideOverlap) continue;
    const double w = area.empty() ? 1.0 : area[i];
    total_weight += w;
    if (changed[i]) {
      out.flag[i] = kChangedSample;
      ++out.changed_samples;
    } else {
      stable_weight += w;
      ++out.stable_samples;
    }
  }
  out.stable_share = total_weight > 0 ? stable_weight / total_weight : 1.0;
  return out;
}

StableTerrain ClassifyStable(const Surface& reference, const std::vector<double>& dz,
                             const std::vector<uint8_t>& eligible, const std::vector<uint8_t>& stable,
                             const std::vector<double>& area, const StableOptions& options) {
  GapField gaps;
  gaps.dz = dz;
  gaps.area = area;
  return ClassifyStable(MakeSampleAdjacency(reference), gaps, eligible, stable, options);
}

}  // namespace surfreg
