#pragma once
// A reference surface A and a moving surface B prepared for registration,
// and B's state at the current parameter value θ (docs/method.md, How a registration runs):
// - both in A's local frame, duplicates merged (heights averaged), in
//   Hilbert order;
// - A triangulated once; B triangulated once in its own frame (a raster at
//   full resolution on its own cells, measure/grid_mesh.h);
// - each surface is its data domain (measure/domain.h): the triangles of its
//   mesh that are data. The others (gap bridges, outline slivers: "junk")
//   stay in the mesh only so that walking and the overlay have a convex,
//   valid triangulation; nothing is integrated on them and no node located in
//   them is in the overlap;
// - at each new θ, B's points are moved, every B triangle's projection is
//   checked for folding (exact orientation), and both location sets are
//   updated by walking from where each point was found at the previous θ:
//   B's nodes in A's mesh and A's nodes in B's moved mesh.
//
// Folds: a triangle turns over in projection when a tilt carries it past
// vertical. Junk triangles (hull slivers nearly collinear in xy) turn over
// under tilts of a fraction of a degree; then B's mesh is re-triangulated at
// that pose around its active triangles, which are kept exactly (Delaunay,
// then the active triangles enforced by edge flips): the surface, and so
// every cost, does not change. When an active triangle folds:
// - after FixSurface (the volume solve), the step is infeasible: Update
//   fails. FixSurface leaves out, for the whole solve, the domain triangles
//   steeper than a given slope at the pose where it is called, so only a
//   tilt of several degrees from there can turn an active one over;
// - otherwise (the axial prealignment, which travels far), B is
//   re-triangulated at that pose and its domain found again by the rule (the
//   height field seen from above; a raster: its cells forced in again, the
//   folded ones and their neighbours left out), and the event is counted.
// When folded triangles carry more than `max_fold_fraction` of B's surface
// area, the surface itself overlaps in xy: Update fails.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "measure/delaunay.h"
#include "measure/domain.h"
#include "measure/locator.h"
#include "measure/spanning_tree.h"
#include "measure/surface.h"
#include "measure/tasks.h"
#include "registration/rigid_motion.h"

namespace surfreg {

struct ReferenceSide {
  std::vector<Point2> xy;  // A's local frame
  std::vector<double> z;
  // μ at each node (the surface's per-sample weights, merged duplicates
  // averaged), linear on `mesh`; empty = μ = 1. Fixed to the reference, so
  // μ does not move with θ. The costs weight by it whenever it is not empty.
  std::vector<double> weight;
  Triangulation mesh;
  SpanningTree tree;
  double hull_area = 0;
  std::vector<uint8_t> domain;         // per mesh triangle: 1 = data
  std::vector<uint8_t> domain_vertex;  // per node: 1 = a corner of a data triangle
};

struct MovingSide {
  std::vector<Eigen::Vector3d> points;  // at θ = 0, in A's local frame
  Triangulation mesh;                   // of the points' xy at θ = 0
  SpanningTree tree;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double hull_area = 0;
  DomainRule rule;              // how `domain` was found (again after a re-mesh)
  std::vector<uint8_t> domain;  // per triangle of `mesh`: 1 = data
  // With rule.grid: the raster's cells, six indices into `points` per cell
  // (measure/grid_mesh.h), forced in again by a free re-mesh.
  std::vector<int32_t> grid;
};

// Builds one side from a surface; `shift` is added to every point (moves it
// into the reference's local frame). Keeps a deterministic pseudo-random
// `keep_fraction` of the points (1 = all; at least 3): the coarse levels.
// The reference keeps the surface's weights (if any) of the points kept.
// `rule` decides each side's data domain.
// `execution`: the threads of the triangulation (results do not depend on it).
ReferenceSide PrepareReference(const Surface& surface, double keep_fraction = 1.0,
                               const DomainRule& rule = DomainRule(),
                               const Execution& execution = Execution());
MovingSide PrepareMoving(const Surface& surface, const std::array<double, 3>& shift,
                         double keep_fraction = 1.0, const DomainRule& rule = DomainRule(),
                         const Execution& execution = Execution());

// c + t of the motion θ about B's centroid: T(p) = R(ω)(p − c) + offset.
inline Eigen::Vector3d MotionOffset(const MovingSide& side, const std::array<double, 6>& theta) {
  return side.centroid + Eigen::Vector3d(theta[3], theta[4], theta[5]);
}

// The root-mean-square distance of the moving points from their centroid:
// the lever that turns a rotation into a length (rotations × it weigh
// alike with translations).
double RmsRadius(const MovingSide& side);

// Multiplies the reference's μ (1 where it has none) at every node by
// cos(slope)^exponent, the slope that of the node's normal: the sum of its
// triangles' 3D normals, each as long as twice the triangle's area. With
// exponent > 0 the volume cost weighs a vertical gap roughly as the gap
// along the normal (exponent 1) or as point-to-plane ICP does (2): steep
// flanks, where interpolation error inflates vertical gaps, stop dominating
// the fit. Exponent 0 leaves μ as it is. The mesh must be A's.
void ApplySlopeWeight(double exponent, ReferenceSide* reference);

struct UpdateStats {
  int64_t walk_steps = 0;  // triangles visited by all re-location walks
  int32_t folded = 0;      // B triangles whose moved projection is not counter-clockwise
  double folded_area_fraction = 0;  // their share of B's 3D surface area
  int32_t folded_active = 0;  // of them, active triangles (part of B's surface)
  bool remeshed = false;   // B was re-triangulated at this pose
  // Refused only because the surface is fixed (FixSurface): active triangles
  // folded, few enough that a free re-mesh would have gone on.
  bool remesh_refused = false;
};

class PairState {
 public:
  // Keeps references to both sides (they must outlive the state).
  PairState(const ReferenceSide& reference, const MovingSide& moving,
            double max_fold_fraction = 0.01);

  // Moves B to θ = (ω, t) and re-locates. The first call locates from
  // scratch (in spanning-tree order); later calls walk from the previous
  // locations. Returns false, with locations left untouched, if B folds
  // beyond max_fold_fraction.
  bool Update(const std::array<double, 6>& theta, UpdateStats* stats = nullptr);
  // Only moves B's points to θ: no fold test, nothing located. For
  // FixSurface at a new pose before the Update there, which then re-meshes
  // at most once (around the fixed surface), instead of a free re-mesh
  // first and the fixed surface's after it.
  void MoveTo(const std::array<double, 6>& theta);
  // Threads for locating A in B and B in A side by side (large clouds only).
  void set_execution(const Execution& execution) { execution_ = execution; }
  const Execution& execution() const { return execution_; }

  const ReferenceSide& reference() const { return reference_; }
  const MovingSide& moving() const { return moving_; }
  const std::array<double, 6>& theta() const { return theta_; }
  const MotionDerivative& derivative() const { return derivative_; }
  // B's moved points: xy, z, and q = R(ω)(p − c) (T(p) = q + c + t).
  const std::vector<Point2>& moved_xy() const { return moved_xy_; }
  const std::vector<double>& moved_z() const { return moved_z_; }
  const std::vector<Eigen::Vector3d>& moved_q() const { return moved_q_; }
  // MotionOffset at the current θ.
  Eigen::Vector3d motion_offset() const { return MotionOffset(moving_, theta_); }
  const std::vector<Location>& a_in_b() const { return a_in_b_; }
  const std::vector<Location>& b_in_a() const { return b_in_a_; }
  // Fixes B's surface for a solve: its active triangles become B's own
  // domain triangles (of its mesh at θ = 0, whatever re-meshes came before)
  // less those whose slope at the current pose exceeds `max_slope_deg`.
  // Until ReleaseSurface, a fold of an active triangle makes Update fail,
  // and re-meshes keep the active triangles exactly. Update (or MoveTo,
  // then Update) at the pose first. Returns the number of domain triangles
  // left out as too steep.
  int FixSurface(double max_slope_deg);
  void ReleaseSurface() { fixed_ = false; }
  // Which triangles FixSurface kept (a hash of their vertex triples): the
  // same value means the same surface.
  uint64_t surface_key() const { return surface_key_; }
  bool surface_fixed() const { return fixed_; }

  // B's current mesh: its own, or its re-triangulation after a fold.
  const Triangulation& moving_mesh() const { return mesh_; }
  // Per triangle of moving_mesh(): 1 if it is part of B's surface now.
  const std::vector<uint8_t>& active_b() const { return active_; }
  // Whether edge i (opposite corner i) of active B triangle t bounds B's
  // surface: no triangle, or an inactive one, across it.
  bool MovingBoundaryEdge(int32_t t, int i) const {
    const int32_t next = mesh_.neighbors[3 * t + i];
    return next < 0 || !active_[next];
  }
  // Whether a location in B's mesh / A's mesh is on that surface (on an edge
  // or a vertex: on any active triangle sharing it).
  bool OnMovingSurface(const Location& l) const;
  bool moving_node_active(std::size_t j) const { return active_vertex_[j] != 0; }
  bool OnReferenceSurface(const Location& l) const;
  // Per node: 1 if it is an inner vertex of the surface (InteriorVertices in
  // measure/domain.h), B's for its active triangles. The axial cost's taper.
  const std::vector<uint8_t>& moving_interior() const { return interior_vertex_; }
  const std::vector<uint8_t>& reference_interior() const { return reference_interior_; }
  // Per node: the cosine of A's slope (its unit vertex normal's z, the
  // normal averaged over its domain triangles by area), and B's unit vertex
  // normals at θ = 0 (over its own domain triangles; moved, R times them).
  // Interpolated linearly, the axial cost's normal_distance weight.
  const std::vector<double>& reference_cosine() const { return reference_cosine_; }
  const std::vector<Eigen::Vector3d>& moving_normal() const { return moving_normal_; }
  int32_t folded() const { return folded_; }
  int remeshes() const { return remeshes_; }
  // Changes whenever B's mesh or its active triangles change (re-meshes,
  // FixSurface): what a cache of the overlay must be rebuilt for.
  int surface_version() const { return surface_version_; }

 private:
  // B's Delaunay triangulation at the current pose, then LocateEverything:
  // keeping the active triangles (false if they cannot all be kept), or
  // (keep = false) with the domain found again by B's rule.
  bool RemeshAndLocate(bool keep, UpdateStats* stats);
  // Folds of mesh_ at the moved points (folded_, stats, how many of them
  // active); false beyond max_fold_fraction.
  bool CountFolds(UpdateStats* stats, int32_t* active_folded);
  // Runs both location passes, side by side if execution_ allows and large.
  template <typename AInB, typename BInA>
  void BothWays(AInB&& a_in_b, BInA&& b_in_a) const;
  void SetActiveFlags();  // active_ for mesh_ from the kept triangles
  void IndexKept();       // kept_begin_, kept_rest_ and surface_key_ from kept_triangles_
  // Both ways from scratch, in spanning-tree order.
  void LocateEverything(UpdateStats* stats);

  const ReferenceSide& reference_;
  const MovingSide& moving_;
  const double max_fold_fraction_;
  Triangulation mesh_;
  double area3d_ = 0;  // B's 3D surface area on mesh_
  int remeshes_ = 0;
  int surface_version_ = 0;
  std::array<double, 6> theta_{};
  MotionDerivative derivative_;
  std::vector<Point2> moved_xy_;
  std::vector<double> moved_z_;
  std::vector<Eigen::Vector3d> moved_q_;
  std::vector<Location> a_in_b_, b_in_a_;
  bool located_ = false;
  bool fixed_ = false;
  Execution execution_;
  int32_t folded_ = 0;
  std::vector<uint8_t> active_;           // per triangle of mesh_
  std::vector<uint8_t> active_vertex_;    // per B node: a corner of an active triangle
  std::vector<uint8_t> interior_vertex_;  // per B node: inner vertex of the active triangles
  std::vector<uint8_t> reference_interior_;  // per A node: inner vertex of A's domain
  std::vector<double> reference_cosine_;
  std::vector<Eigen::Vector3d> moving_normal_;
  // The fixed active triangles as sorted vertex triples, grouped by their
  // smallest vertex (CSR): to find them again in a new mesh.
  std::vector<int32_t> kept_begin_;
  std::vector<std::array<int32_t, 2>> kept_rest_;
  std::vector<int64_t> walk_steps_;  // Update's, per chunk of its walks
  std::vector<int32_t> kept_triangles_;  // 3 per active triangle, for EnforceTriangles
  uint64_t surface_key_ = 0;             // a hash of kept_triangles_
};

// The folds of B's own mesh (its domain triangles active) at θ, into
// `stats`: what Update on a new PairState counts there, without building
// one (nothing is located). False if they pass max_fold_fraction, as Update.
bool OwnMeshFolds(const MovingSide& moving, const std::array<double, 6>& theta, double max_fold_fraction,
                  UpdateStats* stats);

// The motion θ as a RigidMotion about B's centroid.
RigidMotion MotionOf(const MovingSide& moving, const std::array<double, 6>& theta);

}  // namespace surfreg
