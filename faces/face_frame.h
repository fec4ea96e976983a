#pragma once
// Faces in the standard frame of Dyshkant 2010, section 3.1: z along the line
// of sight towards the camera, y from chin to forehead, x across the face
// (right-handed); x and y centred (Σx = Σy = 0 over the kept nodes) and
// max z = 0. The face is then the height field z = F(x, y) of its visible
// side: for each xy, the surface nearest the camera.
//
// A face mesh or cloud may come in any orientation. It is turned into the
// frame either by a rotation the user gives or by its principal axes with
// two heuristics for the signs: the nose tip (the most prominent point)
// faces the camera and sits near the middle of the face, and the nose's
// ridge stands out more from its sides in the rows above the tip (the
// bridge between the eyes) than below it (the upper lip between the
// cheeks), a cue that a pitched frame does not bias. On a whole head the
// principal axes lean with the neck (the shipped mannequin's by ~15°).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "measure/mesh.h"
#include "measure/surface.h"

namespace surfreg {

enum class FaceOrientation {
  kAsIs,           // already in the frame's orientation: only centre and shift
  kGiven,          // FaceFrameOptions::rotation_deg, then centre and shift
  kPrincipalAxes,  // principal axes + nose-tip heuristics (default)
};

struct FaceFrameOptions {
  FaceOrientation orientation = FaceOrientation::kPrincipalAxes;
  // kGiven: rotation vector in degrees (axis × angle) taking input
  // coordinates to the frame's orientation.
  std::array<double, 3> rotation_deg = {0, 0, 0};
  // Keep only points at most this far behind the nose tip (frame z ≥
  // −depth_limit): drops ears and the sides of the head, which stand near
  // vertical in the height field. 0 = keep every visible point.
  double depth_limit = 0.0;
  // A vertex counts as hidden if some triangle above it is higher by more
  // than this (data units); 0 = 1e-9 × the mesh's bounding-box diagonal.
  double visibility_tolerance = 0.0;
};

struct FaceFrame {
  // frame point = rotation · input point + translation (rotation row-major).
  std::array<double, 9> rotation{};
  std::array<double, 3> translation{};
  // The visible height field in the frame, and the input vertex each point
  // came from (same order).
  std::vector<std::array<double, 3>> points;
  std::vector<int32_t> input_index;
  std::array<double, 3> nose_tip{};  // in the frame (its z is 0)
  int64_t hidden = 0;                // vertices dropped as not visible
  int64_t beyond_depth = 0;          // vertices dropped by depth_limit
};

// Brings `mesh` into the standard frame and keeps its visible side. A mesh
// with triangles keeps the vertices no triangle hides (seen along −z in the
// frame); a cloud keeps every point. Throws InputError naming mesh.source
// for fewer than 3 points, non-finite coordinates, a triangle index out of
// range, or a flat or degenerate point set whose axes are not defined.
FaceFrame NormalizeFace(const Mesh& mesh, const FaceFrameOptions& options = {});

// The indices of the vertices that no triangle hides when looking down the
// −z axis: vertex v is hidden if a triangle not using v covers v's xy
// (boundary included) with its plane above v.z + tolerance there.
std::vector<int32_t> VisibleVertices(const Mesh& mesh, double tolerance);

// The frame's points as a Surface (source = mesh.source).
Surface FaceSurface(const FaceFrame& frame, const std::string& source);

// Applies the frame's transform to input points: rotation · p + translation.
std::array<double, 3> ToFaceFrame(const FaceFrame& frame, const std::array<double, 3>& input);

}  // namespace surfreg
