#include "registration/pair_state.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "measure/bucket_scatter.h"
#include "measure/grid_mesh.h"
#include "measure/input_error.h"
#include "measure/predicates.h"
#include "measure/tasks.h"
#include "measure/spatial_sort.h"
#include "registration/kept_remesh.h"

namespace surfreg {
namespace {

uint64_t Mix(uint64_t x) {  // splitmix64 finalizer: a fixed pseudo-random key per index
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

struct Cloud {
  std::vector<Point2> xy;
  std::vector<double> z;
  std::vector<double> weight;    // empty when the surface has none
  std::vector<int32_t> grid;     // a raster's cells (measure/grid_mesh.h), indices into xy
  std::vector<uint8_t> in_grid;  // per mesh triangle: one of the grid's
};

// Subsampled, Hilbert-sorted, duplicates merged (mean height), triangulated;
// with `grid` (a raster at full resolution: a subsampled lattice is not
// one) on its own cells.
Cloud PrepareCloud(const Surface& surface, const std::array<double, 3>& shift,
                   double keep_fraction, bool grid, const Execution& execution, Triangulation* mesh) {
  Cloud all;
  const std::size_t n = surface.size();
  const bool weighted = !surface.weight.empty();
  const double threshold = keep_fraction * 18446744073709551616.0;  // 2^64
  std::vector<int32_t> sample;  // the surface index of each point of `all`
  for (std::size_t i = 0; i < n; ++i) {
    if (keep_fraction < 1.0 && static_cast<double>(Mix(i)) >= threshold) continue;
    all.xy.push_back({surface.xy[i].x + shift[0], surface.xy[i].y + shift[1]});
    all.z.push_back(surface.z[i] + shift[2]);
    if (weighted) all.weight.push_back(surface.weight[i]);
    sample.push_back(static_cast<int32_t>(i));
  }
  if (all.xy.size() < 3) {
    throw InputError(surface.source + ": too few points left after subsampling by " +
                     std::to_string(keep_fraction));
  }
  const std::vector<int32_t> order = SpatialOrder(all.xy, /*brio=*/false, 0, execution);
  Cloud sorted;
  sorted.xy.reserve(order.size());
  sorted.z.reserve(order.size());
  std::vector<int32_t> index_of(grid ? n : 0, -1);  // surface index -> cloud index
  for (int32_t k : order) {
    if (grid) index_of[sample[k]] = static_cast<int32_t>(sorted.xy.size());
    sorted.xy.push_back(all.xy[k]);
    sorted.z.push_back(all.z[k]);
    if (weighted) sorted.weight.push_back(all.weight[k]);
  }
  DelaunayOptions delaunay;
  delaunay.execution = execution;
  *mesh = Triangulate(sorted.xy, delaunay);
  Cloud* result = &sorted;
  Cloud unique;
  if (mesh->num_duplicates > 0) {
    // Keep one point per xy with the mean height (and weight, as Measure
    // does), then triangulate the rest: a moving surface must not carry
    // unreferenced points.
    std::vector<double> sum(sorted.xy.size(), 0.0), weight_sum(weighted ? sorted.xy.size() : 0, 0.0);
    std::vector<int32_t> count(sorted.xy.size(), 0), unique_of(sorted.xy.size(), -1);
    for (std::size_t i = 0; i < sorted.xy.size(); ++i) {
      sum[mesh->vertex_of_input[i]] += sorted.z[i];
      ++count[mesh->vertex_of_input[i]];
      if (weighted) weight_sum[mesh->vertex_of_input[i]] += sorted.weight[i];
    }
    for (std::size_t i = 0; i < sorted.xy.size(); ++i) {
      if (mesh->vertex_of_input[i] != static_cast<int32_t>(i)) continue;
      unique_of[i] = static_cast<int32_t>(unique.xy.size());
      unique.xy.push_back(sorted.xy[i]);
      unique.z.push_back(sum[i] / count[i]);
      if (weighted) unique.weight.push_back(weight_sum[i] / count[i]);
    }
    // A raster cell with a merged corner is degenerate: it goes.
    for (int32_t& k : index_of) k = k < 0 ? -1 : unique_of[k];
    *mesh = Triangulate(unique.xy, delaunay);
    result = &unique;
  }
  if (grid) {
    result->grid = GridCellTriangles(surface.raster_cell, surface.source, execution);
    RemapGridTriangles(index_of, &result->grid);
    result->in_grid = EnforceGrid(result->xy, result->grid, mesh);
  }
  return std::move(*result);
}

}  // namespace

ReferenceSide PrepareReference(const Surface& surface, double keep_fraction, const DomainRule& rule,
                               const Execution& execution) {
  ValidateSurface(surface);
  ReferenceSide side;
  // A subsampled lattice is no longer a lattice (the coarse levels).
  DomainRule own = rule;
  own.grid = surface.raster_grid() && keep_fraction >= 1.0;
  Cloud cloud = PrepareCloud(surface, {0, 0, 0}, keep_fraction, own.grid, execution, &side.mesh);
  side.xy = std::move(cloud.xy);
  side.z = std::move(cloud.z);
  side.weight = std::move(cloud.weight);
  side.tree = EuclideanMst(side.xy, side.mesh, execution);
  side.hull_area = MeshArea(side.xy, side.mesh);
  side.domain = DataDomain(side.xy, side.mesh, own, &cloud.in_grid);
  side.domain_vertex = DomainVertices(side.mesh, side.xy.size(), side.domain);
  return side;
}

namespace {

// The corners of the triangles t of `mesh` with keep(t), in mesh order,
// found and copied by chunks.
template <typename Keep>
std::vector<int32_t> TrianglesWhere(const Triangulation& mesh, const Execution& execution, const Keep& keep) {
  const int64_t n = mesh.num_triangles();
  BucketSlots slots(ChunksFor(n, kItemChunk), 1);
  const auto bucket = [&keep](int64_t t) { return keep(t) ? 0 : -1; };
  CountIntoBuckets(execution, n, slots, bucket);
  std::vector<int32_t> corners(static_cast<std::size_t>(3 * slots.start[1]));
  ScatterIntoBuckets(execution, n, slots, bucket, [&](int64_t t, int64_t at) {
    std::copy(&mesh.triangles[3 * t], &mesh.triangles[3 * t + 3], corners.begin() + 3 * at);
  });
  return corners;
}

// Per vertex: the unit sum of its domain triangles' normals, each as long as
// twice the triangle's area (upward: both meshes are counter-clockwise in xy).
std::vector<Eigen::Vector3d> VertexNormals(const std::vector<Eigen::Vector3d>& p, const Triangulation& mesh,
                                           const std::vector<uint8_t>& in_domain) {
  std::vector<Eigen::Vector3d> normal(p.size(), Eigen::Vector3d::Zero());
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (!in_domain[t]) continue;
    const int32_t* v = &mesh.triangles[3 * t];
    const Eigen::Vector3d n = (p[v[1]] - p[v[0]]).cross(p[v[2]] - p[v[0]]);
    for (int i = 0; i < 3; ++i) normal[v[i]] += n;
  }
  for (Eigen::Vector3d& n : normal) {
    const double length = n.norm();
    n = length > 0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::UnitZ();
  }
  return normal;
}

}  // namespace

void ApplySlopeWeight(double exponent, ReferenceSide* reference) {
  if (exponent == 0) return;
  ReferenceSide& a = *reference;
  std::vector<Eigen::Vector3d> points(a.xy.size());
  for (std::size_t v = 0; v < a.xy.size(); ++v) points[v] = {a.xy[v].x, a.xy[v].y, a.z[v]};
  // Over every triangle of the mesh; a node on none keeps its μ (cos = 1).
  const std::vector<Eigen::Vector3d> normal =
      VertexNormals(points, a.mesh, std::vector<uint8_t>(a.mesh.num_triangles(), 1));
  if (a.weight.empty()) a.weight.assign(a.xy.size(), 1.0);
  for (std::size_t v = 0; v < a.xy.size(); ++v) a.weight[v] *= std::pow(normal[v].z(), exponent);
}


double RmsRadius(const MovingSide& side) {
  double sum = 0;
  for (const Eigen::Vector3d& p : side.points) sum += (p - side.centroid).squaredNorm();
  return std::sqrt(sum / static_cast<double>(side.points.size()));
}

MovingSide PrepareMoving(const Surface& surface, const std::array<double, 3>& shift,
                         double keep_fraction, const DomainRule& rule, const Execution& execution) {
  ValidateSurface(surface);
  MovingSide side;
  side.rule = rule;
  side.rule.grid = surface.raster_grid() && keep_fraction >= 1.0;
  Cloud cloud = PrepareCloud(surface, shift, keep_fraction, side.rule.grid, execution, &side.mesh);
  side.tree = EuclideanMst(cloud.xy, side.mesh, execution);
  side.hull_area = MeshArea(cloud.xy, side.mesh);
  side.domain = DataDomain(cloud.xy, side.mesh, side.rule, &cloud.in_grid);
  side.grid = std::move(cloud.grid);
  side.points.resize(cloud.xy.size());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < cloud.xy.size(); ++i) {
    side.points[i] = Eigen::Vector3d(cloud.xy[i].x, cloud.xy[i].y, cloud.z[i]);
    sum += side.points[i];
  }
  side.centroid = sum / static_cast<double>(cloud.xy.size());
  return side;
}

RigidMotion MotionOf(const MovingSide& moving, const std::array<double, 6>& theta) {
  RigidMotion motion;
  motion.rotation_vector = {theta[0], theta[1], theta[2]};
  motion.translation = {theta[3], theta[4], theta[5]};
  motion.centre = {moving.centroid.x(), moving.centroid.y(), moving.centroid.z()};
  return motion;
}

namespace {

double TriangleArea3d(const std::vector<Eigen::Vector3d>& p, const int32_t* v) {
  return 0.5 * (p[v[1]] - p[v[0]]).cross(p[v[2]] - p[v[0]]).norm();
}

double SurfaceArea(const std::vector<Eigen::Vector3d>& p, const Triangulation& mesh) {
  double area = 0;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) area += TriangleArea3d(p, &mesh.triangles[3 * t]);
  return area;
}

}  // namespace

PairState::PairState(const ReferenceSide& reference, const MovingSide& moving,
                     double max_fold_fraction)
    : reference_(reference), moving_(moving), max_fold_fraction_(max_fold_fraction),
      mesh_(moving.mesh) {
  const std::size_t n = moving.points.size();
  moved_xy_.resize(n);
  moved_z_.resize(n);
  moved_q_.resize(n);
  area3d_ = SurfaceArea(moving.points, mesh_);
  active_ = moving.domain;
  active_vertex_ = DomainVertices(mesh_, n, active_);
  interior_vertex_ = InteriorVertices(mesh_, n, active_);
  reference_interior_ = InteriorVertices(reference.mesh, reference.xy.size(), reference.domain);
  moving_normal_ = VertexNormals(moving.points, moving.mesh, moving.domain);
  {
    std::vector<Eigen::Vector3d> a3(reference.xy.size());
    for (std::size_t i = 0; i < a3.size(); ++i) a3[i] = {reference.xy[i].x, reference.xy[i].y, reference.z[i]};
    const std::vector<Eigen::Vector3d> normal = VertexNormals(a3, reference.mesh, reference.domain);
    reference_cosine_.resize(normal.size());
    for (std::size_t i = 0; i < normal.size(); ++i) reference_cosine_[i] = normal[i].z();
  }
  kept_triangles_ = TrianglesWhere(mesh_, execution_, [this](int64_t t) { return active_[t] != 0; });
  IndexKept();
}

namespace {

// B's points moved by θ (q = R(ω)(p − c), xy and z of q + c + t); z and q
// only where wanted.
void MovePoints(const MovingSide& moving, const Eigen::Matrix3d& rotation, const std::array<double, 6>& theta,
                const Execution& execution, Point2* xy, double* z, Eigen::Vector3d* q) {
  const Eigen::Vector3d offset = MotionOffset(moving, theta);
  const int64_t n = static_cast<int64_t>(moving.points.size());
  ForEachChunk(execution, n, ChunksFor(n, kItemChunk), [&](int, int64_t begin, int64_t end) {
    for (int64_t j = begin; j < end; ++j) {
      const Eigen::Vector3d moved = rotation * (moving.points[j] - moving.centroid);
      if (q != nullptr) q[j] = moved;
      xy[j] = {moved.x() + offset.x(), moved.y() + offset.y()};
      if (z != nullptr) z[j] = moved.z() + offset.z();
    }
  });
}

struct MeshFolds {
  int32_t folded = 0, folded_active = 0;
  double area = 0;  // their 3-D area
};

// By fixed chunks of triangles, summed in chunk order: the same on any
// thread count.
MeshFolds CountMeshFolds(const Triangulation& mesh, const std::vector<Point2>& xy, const std::vector<uint8_t>& active,
                         const std::vector<Eigen::Vector3d>& points, const Execution& execution) {
  const int chunks = ChunksFor(mesh.num_triangles(), kItemChunk);
  std::vector<MeshFolds> parts(chunks);
  ForEachChunk(execution, mesh.num_triangles(), chunks, [&](int c, int64_t begin, int64_t end) {
    MeshFolds part;
    for (int64_t t = begin; t < end; ++t) {
      const int32_t* v = &mesh.triangles[3 * t];
      if (Orient2D(xy[v[0]], xy[v[1]], xy[v[2]]) <= 0.0) {
        ++part.folded;
        part.folded_active += active[t];
        part.area += TriangleArea3d(points, v);
      }
    }
    parts[c] = part;
  });
  MeshFolds folds;
  for (const MeshFolds& part : parts) {
    folds.folded += part.folded, folds.folded_active += part.folded_active, folds.area += part.area;
  }
  return folds;
}

// Into `stats` (if given); true if within max_fold_fraction of `area3d`.
bool ReportFolds(const MeshFolds& folds, double area3d, double max_fold_fraction, UpdateStats* stats) {
  const double fraction = area3d > 0 ? folds.area / area3d : 0.0;
  if (stats != nullptr) {
    stats->folded = folds.folded;
    stats->folded_active = folds.folded_active;
    stats->folded_area_fraction = fraction;
  }
  return folds.folded == 0 || fraction <= max_fold_fraction;
}

}  // namespace

void PairState::MoveTo(const std::array<double, 6>& theta) {
  theta_ = theta;
  derivative_ = DifferentiateMotion({theta[0], theta[1], theta[2]});
  MovePoints(moving_, derivative_.rotation, theta, execution_, moved_xy_.data(), moved_z_.data(), moved_q_.data());
}

bool PairState::CountFolds(UpdateStats* stats, int32_t* active_folded) {
  const MeshFolds folds = CountMeshFolds(mesh_, moved_xy_, active_, moving_.points, execution_);
  folded_ = folds.folded;
  if (active_folded != nullptr) *active_folded = folds.folded_active;
  return ReportFolds(folds, area3d_, max_fold_fraction_, stats);
}

bool OwnMeshFolds(const MovingSide& moving, const std::array<double, 6>& theta, double max_fold_fraction,
                  UpdateStats* stats) {
  std::vector<Point2> xy(moving.points.size());
  MovePoints(moving, DifferentiateMotion({theta[0], theta[1], theta[2]}).rotation, theta, Execution{1}, xy.data(),
             nullptr, nullptr);
  const MeshFolds folds = CountMeshFolds(moving.mesh, xy, moving.domain, moving.points, Execution{1});
  return ReportFolds(folds, SurfaceArea(moving.points, moving.mesh), max_fold_fraction, stats);
}

bool PairState::Update(const std::array<double, 6>& theta, UpdateStats* stats) {
  MoveTo(theta);
  const std::size_t n = moving_.points.size();
  // A fold turns a triangle's projection over; walking and the overlay
  // assume a valid planar mesh, so nothing is located then.
  int32_t folded_active = 0;
  if (!CountFolds(stats, &folded_active)) return false;
  const int32_t folded = folded_;
  if (folded > 0 && folded_active == 0) {
    // Only junk turned over: re-mesh around the active triangles, which
    // stay as they are, so the surface does not change.
    if (RemeshAndLocate(true, stats)) return true;
  }
  if (folded > 0 && fixed_) {
    if (stats != nullptr) stats->remesh_refused = true;
    return false;
  }
  if (folded > 0) {
    // Data turned over: the height field seen from above at this pose is
    // B's Delaunay triangulation there.
    RemeshAndLocate(false, stats);
    return true;
  }
  if (!located_) {
    LocateEverything(stats);
    return true;
  }
  // Steps of a solver are small: most walks end within a triangle or two.
  // A's points in B, then B's in A, as one range cut into chunks (each
  // walk starts where its point was: the same locations for any cut).
  const Triangulation& mesh_b = mesh_;
  const int64_t num_a = static_cast<int64_t>(reference_.xy.size());
  const int64_t total = num_a + static_cast<int64_t>(n);
  const int chunks = ChunksFor(total, 4096);
  walk_steps_.assign(static_cast<std::size_t>(chunks), 0);
  ForEachChunk(execution_, total, chunks, [&](int c, int64_t begin, int64_t end) {
    int64_t sum = 0;
    for (int64_t i = begin; i < std::min(end, num_a); ++i) {
      int steps = 0;
      a_in_b_[i] = LocatePoint(moved_xy_, mesh_b, reference_.xy[i], a_in_b_[i].triangle, &steps);
      sum += steps;
    }
    for (int64_t j = std::max(begin, num_a) - num_a; j < end - num_a; ++j) {
      int steps = 0;
      b_in_a_[j] = LocatePoint(reference_.xy, reference_.mesh, moved_xy_[j], b_in_a_[j].triangle, &steps);
      sum += steps;
    }
    walk_steps_[c] = sum;
  });
  if (stats != nullptr) {
    stats->walk_steps = 0;
    for (int64_t steps : walk_steps_) stats->walk_steps += steps;
  }
  return true;
}

template <typename AInB, typename BInA>
void PairState::BothWays(AInB&& a_in_b, BInA&& b_in_a) const {
  // A thread costs tens of microseconds: worth it on large clouds only.
  constexpr std::size_t kParallelPoints = 20000;
    const bool large = reference_.xy.size() + moved_xy_.size() >= kParallelPoints;
  RunBoth(large ? execution_ : Execution{1}, std::forward<AInB>(a_in_b), std::forward<BInA>(b_in_a));
}

bool PairState::RemeshAndLocate(bool keep, UpdateStats* stats) {
  Triangulation mesh;
  if (keep) {
    // Only the active triangles' corners: the others are not part of the
    // surface, and under a tilt a vertex whose triangles are all left out
    // (too steep) can swing over an active triangle.
    if (kept_triangles_.empty()) return false;
    // Locally, around R's boundary, where the current mesh holds every kept
    // triangle (the usual case: junk folded); else Delaunay of all of them.
    int32_t active = 0;
    for (uint8_t a : active_) active += a;
    const bool local = static_cast<std::size_t>(active) == kept_triangles_.size() / 3 &&
                       RemeshAroundKept(moved_xy_, mesh_, active_, &mesh);
    if (!local) {
      if (!TriangulateKept(moved_xy_, kept_triangles_, &mesh)) return false;
    }
    mesh_ = std::move(mesh);
    SetActiveFlags();
  } else {
    DelaunayOptions delaunay;
    delaunay.execution = execution_;
    mesh_ = Triangulate(moved_xy_, delaunay);
    std::vector<uint8_t> in_grid;  // a raster: its cells at this pose (folds left out)
    if (moving_.rule.grid) in_grid = EnforceGrid(moved_xy_, moving_.grid, &mesh_);
    active_ = DataDomain(moved_xy_, mesh_, moving_.rule, &in_grid, execution_);
    active_vertex_ = DomainVertices(mesh_, moved_xy_.size(), active_);
    interior_vertex_ = InteriorVertices(mesh_, moved_xy_.size(), active_);
    kept_triangles_.clear();
    for (int32_t t = 0; t < mesh_.num_triangles(); ++t) {
      if (!active_[t]) continue;
      kept_triangles_.insert(kept_triangles_.end(), &mesh_.triangles[3 * t], &mesh_.triangles[3 * t + 3]);
    }
    IndexKept();
  }
  area3d_ = SurfaceArea(moving_.points, mesh_);
  ++remeshes_;
  ++surface_version_;
  if (stats != nullptr) stats->remeshed = true;
  LocateEverything(stats);
  return true;
}

void PairState::IndexKept() {
  const int32_t n = static_cast<int32_t>(moved_xy_.size());
  const int64_t count = static_cast<int64_t>(kept_triangles_.size() / 3);
  // Each triangle's corners sorted, and the key (per chunk's hash, chained
  // in chunk order), by chunks; then indexed by the least corner.
  std::vector<std::array<int32_t, 3>> sorted(static_cast<std::size_t>(count));
  const int chunks = ChunksFor(count, kItemChunk);
  std::vector<uint64_t> part_key(chunks);
  ForEachChunk(execution_, count, chunks, [&](int c, int64_t begin, int64_t end) {
    uint64_t key = static_cast<uint64_t>(end - begin);
    for (int64_t k = begin; k < end; ++k) {
      std::array<int32_t, 3> v = {kept_triangles_[3 * k], kept_triangles_[3 * k + 1], kept_triangles_[3 * k + 2]};
      for (int32_t corner : v) key = Mix(key ^ static_cast<uint64_t>(corner));
      std::sort(v.begin(), v.end());
      sorted[k] = v;
    }
    part_key[c] = key;
  });
  surface_key_ = static_cast<uint64_t>(count);
  for (uint64_t key : part_key) surface_key_ = Mix(surface_key_ ^ key);
  kept_begin_.assign(n + 1, 0);
  for (const auto& v : sorted) ++kept_begin_[v[0] + 1];
  for (int32_t v = 0; v < n; ++v) kept_begin_[v + 1] += kept_begin_[v];
  kept_rest_.resize(static_cast<std::size_t>(count));
  std::vector<int32_t> fill(kept_begin_.begin(), kept_begin_.end() - 1);
  for (const auto& v : sorted) kept_rest_[fill[v[0]]++] = {v[1], v[2]};
}

void PairState::SetActiveFlags() {
  const int32_t count = mesh_.num_triangles();
  active_.resize(static_cast<std::size_t>(count));
  ForEachChunk(execution_, count, ChunksFor(count, kItemChunk), [&](int, int64_t begin, int64_t end) {
    for (int64_t t = begin; t < end; ++t) {
      std::array<int32_t, 3> v = {mesh_.triangles[3 * t], mesh_.triangles[3 * t + 1],
                                  mesh_.triangles[3 * t + 2]};
      std::sort(v.begin(), v.end());
      uint8_t kept = 0;
      for (int32_t k = kept_begin_[v[0]]; k < kept_begin_[v[0] + 1]; ++k) {
        if (kept_rest_[k][0] == v[1] && kept_rest_[k][1] == v[2]) kept = 1;
      }
      active_[t] = kept;
    }
  });
  active_vertex_ = DomainVertices(mesh_, moved_xy_.size(), active_);
  interior_vertex_ = InteriorVertices(mesh_, moved_xy_.size(), active_);
}

int PairState::FixSurface(double max_slope_deg) {
  // B's own domain triangles, found in the current mesh (which holds them all
  // unless a free re-mesh replaced some) and enforced into it. Left out: the
  // steep ones, and every triangle sharing a corner with one. A steep
  // triangle that turns over carries its corner across the opposite edge,
  // into the triangle beyond it: with both out, the active surface still
  // does not overlap itself in xy (measured on a face: without the ring,
  // 1 in 6 of the prealignment's trial steps was refused for that).
  const double min_cos = std::cos(max_slope_deg * M_PI / 180.0);
  const Triangulation& own = moving_.mesh;
  std::vector<uint8_t> near_steep(moved_xy_.size(), 0);
  std::vector<uint8_t> steep(own.num_triangles(), 0);
  ForEachChunk(execution_, own.num_triangles(), ChunksFor(own.num_triangles(), kItemChunk),
               [&](int, int64_t begin, int64_t end) {
                 for (int64_t t = begin; t < end; ++t) {
                   if (!moving_.domain[t]) continue;
                   const int32_t* v = &own.triangles[3 * t];
                   const Eigen::Vector3d p0(moved_xy_[v[0]].x, moved_xy_[v[0]].y, moved_z_[v[0]]);
                   const Eigen::Vector3d p1(moved_xy_[v[1]].x, moved_xy_[v[1]].y, moved_z_[v[1]]);
                   const Eigen::Vector3d p2(moved_xy_[v[2]].x, moved_xy_[v[2]].y, moved_z_[v[2]]);
                   const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0);
                   steep[t] = !(normal.z() > min_cos * normal.norm());
                 }
               });
  int num_steep = 0;
  for (int32_t t = 0; t < own.num_triangles(); ++t) {
    if (!steep[t]) continue;
    ++num_steep;
    for (int k = 0; k < 3; ++k) near_steep[own.triangles[3 * t + k]] = 1;
  }
  std::vector<int32_t> previous;
  previous.swap(kept_triangles_);
  kept_triangles_ = TrianglesWhere(own, execution_, [&](int64_t t) {
    const int32_t* v = &own.triangles[3 * t];
    return moving_.domain[t] && !near_steep[v[0]] && !near_steep[v[1]] && !near_steep[v[2]];
  });
  const int steep_count = num_steep;
  // Fixed again on the same triangles, all active in the current mesh: the
  // same surface (an overlay cache of it stays valid).
  if (fixed_ && previous == kept_triangles_) {
    int32_t active = 0;
    for (uint8_t a : active_) active += a;
    if (static_cast<std::size_t>(active) == kept_triangles_.size() / 3) return steep_count;
  }
  IndexKept();
  fixed_ = true;
  ++surface_version_;
  SetActiveFlags();
  int32_t found = 0;
  for (uint8_t a : active_) found += a;
  if (static_cast<std::size_t>(found) != kept_triangles_.size() / 3) {
    // Some were replaced by an earlier free re-mesh: put them back.
    if (RemeshAndLocate(true, nullptr)) return steep_count;
    // Cannot be (they fold here): keep the current mesh's domain instead.
    kept_triangles_.clear();
    for (int32_t t = 0; t < mesh_.num_triangles(); ++t) {
      if (active_[t]) kept_triangles_.insert(kept_triangles_.end(), &mesh_.triangles[3 * t], &mesh_.triangles[3 * t + 3]);
    }
    IndexKept();
    SetActiveFlags();
  }
  return steep_count;
}

bool PairState::OnMovingSurface(const Location& l) const {
  if (!l.found()) return false;
  if (active_[l.triangle]) return true;
  if (l.where == Where::kOnEdge) {
    const int32_t next = mesh_.neighbors[3 * l.triangle + l.index];
    return next >= 0 && active_[next];
  }
  if (l.where == Where::kOnVertex) return active_vertex_[mesh_.triangles[3 * l.triangle + l.index]] != 0;
  return false;
}

bool PairState::OnReferenceSurface(const Location& l) const {
  if (!l.found()) return false;
  const ReferenceSide& a = reference_;
  if (a.domain[l.triangle]) return true;
  if (l.where == Where::kOnEdge) {
    const int32_t next = a.mesh.neighbors[3 * l.triangle + l.index];
    return next >= 0 && a.domain[next];
  }
  if (l.where == Where::kOnVertex) return a.domain_vertex[a.mesh.triangles[3 * l.triangle + l.index]] != 0;
  return false;
}

void PairState::LocateEverything(UpdateStats* stats) {
  LocateAllStats all_a, all_b;
  BothWays([&] {
    a_in_b_ = LocateAll(moved_xy_, mesh_, reference_.xy, reference_.mesh, reference_.tree, &all_a, execution_);
  }, [&] { b_in_a_ = LocateAll(reference_.xy, reference_.mesh, moved_xy_, mesh_, moving_.tree, &all_b, execution_); });
  located_ = true;
  if (stats != nullptr) stats->walk_steps = all_a.steps + all_b.steps;
}

}  // namespace surfreg
