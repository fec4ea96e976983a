#pragma once
// A reference surface A and a moving surface B prepared for registration,
// and B's state at the current parameter value θ (DESIGN.md 4):
// - both in A's local frame, duplicates merged (heights averaged), in
//   Hilbert order;
// - A triangulated once; B triangulated once in its own frame and keeping
//   that mesh while it moves (a rigid motion moves the mesh);
// - at each new θ, B's points are moved, every B triangle's projection is
//   checked for folding (exact orientation), and both location sets are
//   updated by walking from where each point was found at the previous θ:
//   B's nodes in A's mesh and A's nodes in B's moved mesh.
//
// Folds: a triangle turns over in projection when a tilt carries it past
// vertical. Random samplings have slivers (nearly collinear in xy) that are
// nearly vertical in 3D, and a tilt of a degree or two turns some of them
// over: then B is re-triangulated at that pose (the height field seen from
// above) and the event is counted. When the folded triangles carry more than
// `max_fold_fraction` of B's surface area, the surface itself overlaps in xy
// (it is no longer a height field at that pose): Update fails and says so.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "measure/delaunay.h"
#include "measure/locator.h"
#include "measure/spanning_tree.h"
#include "measure/surface.h"
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
};

struct MovingSide {
  std::vector<Eigen::Vector3d> points;  // at θ = 0, in A's local frame
  Triangulation mesh;                   // of the points' xy at θ = 0
  SpanningTree tree;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double hull_area = 0;
};

// Builds one side from a surface; `shift` is added to every point (moves it
// into the reference's local frame). Keeps a deterministic pseudo-random
// `keep_fraction` of the points (1 = all; at least 3): the coarse levels.
// The reference keeps the surface's weights (if any) of the points kept.
ReferenceSide PrepareReference(const Surface& surface, double keep_fraction = 1.0);
MovingSide PrepareMoving(const Surface& surface, const std::array<double, 3>& shift,
                         double keep_fraction = 1.0);

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
  bool remeshed = false;   // B was re-triangulated at this pose
  // Refused only because re-meshing is off: slivers folded, few enough that
  // a re-mesh would have gone on (set_remesh_on_fold).
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

  const ReferenceSide& reference() const { return reference_; }
  const MovingSide& moving() const { return moving_; }
  const std::array<double, 6>& theta() const { return theta_; }
  const MotionDerivative& derivative() const { return derivative_; }
  // B's moved points: xy, z, and q = R(ω)(p − c) (T(p) = q + c + t).
  const std::vector<Point2>& moved_xy() const { return moved_xy_; }
  const std::vector<double>& moved_z() const { return moved_z_; }
  const std::vector<Eigen::Vector3d>& moved_q() const { return moved_q_; }
  const std::vector<Location>& a_in_b() const { return a_in_b_; }
  const std::vector<Location>& b_in_a() const { return b_in_a_; }
  // Whether a fold within max_fold_fraction re-triangulates B (the default)
  // or makes Update return false. A solver whose line search compares
  // values turns it off: a new mesh is a different surface B, so values
  // before and after it are not of one function.
  void set_remesh_on_fold(bool remesh) { remesh_on_fold_ = remesh; }
  // Re-triangulates B at the current pose (Delaunay of its moved xy) and
  // locates everything again; for a solver stopped at a fold, so that it can
  // go on with a surface that does not fold there. Update must have succeeded.
  void Retriangulate();

  // B's current mesh: its own, or its re-triangulation after a fold.
  const Triangulation& moving_mesh() const { return mesh_; }
  int32_t folded() const { return folded_; }
  int remeshes() const { return remeshes_; }

 private:
  // B's Delaunay triangulation at the current pose, then LocateEverything.
  void RemeshAndLocate(UpdateStats* stats);
  // Both ways from scratch, in spanning-tree order.
  void LocateEverything(UpdateStats* stats);

  const ReferenceSide& reference_;
  const MovingSide& moving_;
  const double max_fold_fraction_;
  Triangulation mesh_;
  double area3d_ = 0;  // B's 3D surface area on mesh_
  int remeshes_ = 0;
  std::array<double, 6> theta_{};
  MotionDerivative derivative_;
  std::vector<Point2> moved_xy_;
  std::vector<double> moved_z_;
  std::vector<Eigen::Vector3d> moved_q_;
  std::vector<Location> a_in_b_, b_in_a_;
  bool located_ = false;
  bool remesh_on_fold_ = true;
  int32_t folded_ = 0;
};

// The motion θ as a RigidMotion about B's centroid.
RigidMotion MotionOf(const MovingSide& moving, const std::array<double, 6>& theta);

}  // namespace surfreg
