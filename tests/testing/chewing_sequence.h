#pragma once
// A synthetic chewing sequence with a known jaw motion (tests, benchmark and
// the shipped example configs/data/chewing/): the mannequin face
// (configs/data/mannequin_face_dense.xyz) scaled to millimetres and brought
// to the face frame (x, y centred on the mean, max z = 0), taken as the
// piecewise-linear surface over the Delaunay triangulation of its samples.
//
// Frame k (k = 0..N−1; frame 0 is the reference, jaw closed):
//   points = G_k( upper samples ∪ H_k(lower samples) )
// - the samples are fresh per frame: uniform in area over the surface, drawn
//   separately above (upper) and below (lower) the y level `boundary_y`;
// - H_k is the jaw: a rotation by the opening angle α_k about a hinge axis
//   parallel to x through `hinge` (the temporomandibular joints, behind and
//   above the mouth), then a small lateral swing about the vertical (y)
//   axis through the same point; α_k = max_opening_deg · (1 − cos(2πk/P))/2
//   (so α_0 = 0), lateral β_k = lateral_deg · sin(2πk/P), P = period_frames;
// - G_k is the head: a rotation of head_angle_deg · s_k about a fixed
//   oblique axis through the face centre, then a shift head_shift · s_k
//   along a fixed unit direction, s_k = sin(πk/N) (0 at k = 0).
// The truth for frame k is H_k (4×4, frame coordinates of the reference):
// the motion surfreg jaw should report, J_k = U_k · L_k⁻¹ = G_k⁻¹ · G_k H_k.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "measure/surface.h"

namespace surfreg {

struct ChewingOptions {
  int frames = 8;
  int upper_points = 5000;  // samples per frame with y ≥ boundary_y (before the motions)
  int lower_points = 5000;  // samples per frame with y < boundary_y
  double scale = 6.0;       // model units → millimetres (face ≈ 175 mm tall)
  double boundary_y = -35.0;                     // mm, the mouth line
  Eigen::Vector3d hinge = {0.0, 10.0, -90.0};    // mm, behind and above the mouth
  double max_opening_deg = 8.0;
  double lateral_deg = 1.0;
  double period_frames = 8.0;   // chewing cycle length, frames
  double head_angle_deg = 1.0;  // peak head rotation
  double head_shift = 1.0;      // peak head shift, mm
  uint64_t seed = 20240613;
};

struct ChewingFrame {
  std::vector<std::array<double, 3>> points;  // upper samples first, then lower
  int upper_count = 0;
  Eigen::Matrix4d jaw = Eigen::Matrix4d::Identity();   // H_k (the truth)
  Eigen::Matrix4d head = Eigen::Matrix4d::Identity();  // G_k
  double opening_deg = 0, lateral_deg = 0;
};

// The dense face points of `path` (x y z per line, '#' comments), in model
// units. Aborts the test program (CHECK-like) if the file cannot be read.
std::vector<std::array<double, 3>> ReadFacePoints(const std::string& path);

// The sequence from the dense face points (model units). Deterministic for
// a given seed.
std::vector<ChewingFrame> MakeChewingSequence(const std::vector<std::array<double, 3>>& face,
                                              const ChewingOptions& options);

// The path of the dense face file in the source tree (SURFREG_SOURCE_DIR).
std::string DenseFacePath();

// Writes frames/frame_000.xyz ... (creating frames/) and truth.csv (frame, rx_deg, ry_deg, rz_deg, tx,
// ty, tz of H_k, Euler R = Rz·Ry·Rx as surfreg reports) plus truth.json (the
// 4×4 matrices) into `directory`. Returns false on a write error.
bool WriteChewingSequence(const std::vector<ChewingFrame>& frames, const std::string& directory);

// The dense face (DenseFacePath), read once.
const std::vector<std::array<double, 3>>& DenseFace();

// The frames as surfaces, named "frame k".
std::vector<Surface> FrameSurfaces(const std::vector<ChewingFrame>& frames);

}  // namespace surfreg
