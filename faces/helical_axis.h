#pragma once
// The finite helical axis (screw axis) of a rigid motion, and the path of a
// point under a sequence of poses (docs/faces.md, Jaw motion).
//
// Every rigid motion x ↦ R x + t is a screw: a rotation by an angle θ about
// an axis (unit direction n through a point p) and a slide s along it,
//   x ↦ R (x − p) + p + s n.
// With θ in [0°, 180°] and n's sign chosen so that the rotation is by +θ
// about n (right-hand rule): n is the unit rotation vector, s = n·t, and p,
// the axis' point closest to the origin (p ⊥ n), solves (I − R) p = t − s n:
//   p = ½ (t⊥ + cot(θ/2) · n × t),  t⊥ = t − s n.
// Between two poses J_a and J_b of the jaw (skull coordinates) the motion is
// M = J_b · J_a⁻¹ (it takes where a point of the jaw was in a to where it is
// in b).
//
// Degenerate motions: a rotation below min_angle_rad has no axis (p would
// lie ~|t|/θ away): a pure translation gives n = t/|t|, s = |t|, p = NaN
// (kind kTranslation); no translation either gives zeros (kind kNone). At
// exactly 180° n and −n describe the same rotation; the one Ceres' rotation
// vector gives is kept (s then follows its sign).
#include <Eigen/Core>

namespace surfreg {

enum class HelicalKind {
  kScrew,        // a rotation (≥ min_angle_rad) about a defined axis, and a slide along it
  kTranslation,  // no rotation: direction = t/|t|, point undefined (NaN)
  kNone,         // neither: all zeros
};

const char* HelicalKindName(HelicalKind kind);  // "screw", "translation", "none"

struct HelicalAxis {
  HelicalKind kind = HelicalKind::kNone;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // n, unit (zeros for kNone)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      // p, ⊥ n; NaN for kTranslation
  double angle_deg = 0;                                 // θ in [0, 180]
  double slide = 0;                                     // s = n·t, data units
};

struct HelicalTolerance {
  // Smaller rotations count as none: the axis is then undefined rather than
  // ~|t|/θ away and dominated by rounding.
  double min_angle_rad = 1e-9;
  // A smaller |t| (data units) counts as no translation.
  double min_translation = 1e-12;
};

// The screw of the rigid 4×4 motion `motion` (x ↦ R x + t).
HelicalAxis FiniteHelicalAxis(const Eigen::Matrix4d& motion,
                              const HelicalTolerance& tolerance = HelicalTolerance());

// The screw of M = pose_b · pose_a⁻¹. The translation tolerance is scaled
// by 1 + the larger of the poses' |t|: M of two equal poses is the identity
// only to rounding of their size.
HelicalAxis RelativeHelicalAxis(const Eigen::Matrix4d& pose_a, const Eigen::Matrix4d& pose_b,
                                const HelicalTolerance& tolerance = HelicalTolerance());

// Where `pose` takes the point p0: p_k = J_k · p0.
Eigen::Vector3d PathPoint(const Eigen::Matrix4d& pose, const Eigen::Vector3d& p0);

}  // namespace surfreg
