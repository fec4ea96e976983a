#pragma once
// Internal to the overlay (measure/overlay.cc) and the overlay kept as
// combinatorics (registration/volume_cost/overlay_topology.h): THE clip of a B triangle
// by an A triangle, so that both keep exactly the same cells with exactly
// the same corners. Not a public interface.
#include <algorithm>
#include <cstdint>

#include "measure/surface.h"

namespace surfreg {
namespace overlay_internal {

// Corner labels: kind in bits 0-1, then the local indices.
enum : uint8_t { kCornerA = 0, kCornerB = 1, kCornerCross = 2 };
inline uint8_t CornerA(int i) { return static_cast<uint8_t>(kCornerA | (i << 2)); }
inline uint8_t CornerB(int j) { return static_cast<uint8_t>(kCornerB | (j << 2)); }
// T_A's edge i (opposite its vertex i) with T_B's edge j (opposite vertex j).
inline uint8_t CornerCross(int i, int j) {
  return static_cast<uint8_t>(kCornerCross | (i << 2) | (j << 4));
}

inline int SignOf(double v) { return (v > 0.0) - (v < 0.0); }

// The polygon while it is clipped. No member initializers: zeroing it on
// every clip would cost more than the clip's common case.
struct ClipPolygon {
  struct Corner {
    double x, y;
  };
  Corner corner[8];
  int8_t origin[8];   // T_B's corner 0..2, or -1 for a computed point
  uint8_t label[8];   // kLabelled only
  int8_t support[8];  // kLabelled only: of the edge from corner k to corner k + 1
};

// One Sutherland-Hodgman pass: `in` (n corners) clipped by T_A's edge line
// i into `out`. Returns the new corner count, or -1 when nothing is cut
// (`out` untouched). T_B's corners are classified by their exact signs
// s[.][i], computed points by their floating-point side.
template <bool kLabelled, int i>
inline int ClipPass(const Point2 a[3], const int8_t* const s[3], const ClipPolygon& in, int n,
                    ClipPolygon& out) {
  const Point2& e0 = a[(i + 1) % 3];
  const Point2& e1 = a[(i + 2) % 3];
  const double ex = e1.x - e0.x, ey = e1.y - e0.y;
  const auto value_of = [&](const ClipPolygon::Corner& p) {
    return ex * (p.y - e0.y) - ey * (p.x - e0.x);
  };
  const int corner_side[3] = {s[0][i], s[1][i], s[2][i]};
  double value[8];
  int side[8];
  int outside = 0;
  for (int k = 0; k < n; ++k) {
    if (in.origin[k] >= 0) {
      side[k] = corner_side[in.origin[k]];
    } else {
      value[k] = value_of(in.corner[k]);
      side[k] = SignOf(value[k]);
    }
    outside |= side[k] < 0;
  }
  if (!outside) return -1;  // the common case: nothing to cut on this edge
  // T_B's corners' values only now: only a cut interpolates.
  for (int k = 0; k < n; ++k) {
    if (in.origin[k] >= 0) value[k] = value_of(in.corner[k]);
  }
  int m = 0;
  for (int k = 0; k < n && m < 8; ++k) {
    const int l = k + 1 == n ? 0 : k + 1;
    // Written unconditionally, kept when inside or on: fewer branches.
    out.corner[m] = in.corner[k];
    out.origin[m] = in.origin[k];
    if (kLabelled) {
      out.label[m] = in.label[k];
      // On edge i's line and the next corner outside: the edge runs along edge i.
      out.support[m] = static_cast<int8_t>(side[k] == 0 && side[l] < 0 ? 3 + i : in.support[k]);
    }
    m += side[k] >= 0;
    if (m < 8 && side[k] * side[l] < 0) {  // a strict crossing
      const double denominator = value[k] - value[l];
      double t = denominator != 0.0 ? value[k] / denominator : 0.5;
      t = std::min(1.0, std::max(0.0, t));
      const ClipPolygon::Corner& p = in.corner[k];
      const ClipPolygon::Corner& q = in.corner[l];
      out.corner[m] = {p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
      out.origin[m] = -1;
      if (kLabelled) {
        const int support = in.support[k];
        out.label[m] = support < 3 ? CornerCross(i, support) : CornerA(3 - i - (support - 3));
        out.support[m] = static_cast<int8_t>(side[k] > 0 ? 3 + i : support);  // leaving: along edge i
      }
      ++m;
    }
  }
  return m;
}

// The clip into two scratch polygons (each pass writes the other one).
// Returns the corner count (0 for an empty or zero-area result) and in
// *result the polygon that holds the corners.
template <bool kLabelled>
inline int ClipTriangleInto(const Point2 a[3], const Point2 b[3], const int8_t* const s[3],
                            ClipPolygon scratch[2], const ClipPolygon** result, double* twice_area) {
  ClipPolygon* current = &scratch[0];
  ClipPolygon* other = &scratch[1];
  for (int k = 0; k < 3; ++k) {
    current->corner[k] = {b[k].x, b[k].y};
    current->origin[k] = static_cast<int8_t>(k);
    if (kLabelled) {
      current->label[k] = CornerB(k);
      current->support[k] = static_cast<int8_t>(k == 0 ? 2 : k - 1);  // opposite corner k + 2
    }
  }
  int n = 3;
  const auto pass = [&](int m) {
    if (m < 0) return;
    n = m;
    std::swap(current, other);
  };
  pass(ClipPass<kLabelled, 0>(a, s, *current, n, *other));
  if (n > 0) pass(ClipPass<kLabelled, 1>(a, s, *current, n, *other));
  if (n > 0) pass(ClipPass<kLabelled, 2>(a, s, *current, n, *other));
  if (n < 3) return 0;
  const ClipPolygon::Corner* p = current->corner;
  double twice = 0.0;
  for (int k = 1; k + 1 < n; ++k) {
    twice += (p[k].x - p[0].x) * (p[k + 1].y - p[0].y) - (p[k].y - p[0].y) * (p[k + 1].x - p[0].x);
  }
  if (!(twice > 0.0)) return 0;
  *twice_area = twice;
  *result = current;
  return n;
}

// T_B (corners b) clipped by T_A's three half-planes (corners a,
// counter-clockwise), Sutherland-Hodgman. T_B's own corners are classified
// exactly: s[k][i] is the sign of its corner k against T_A's edge line i
// (opposite corner i; +1 inside); computed points by their floating-point
// side. Writes the corners to x, y (room for 8) and returns their number,
// 0 for an empty or zero-area result; *twice_area is twice the area.
//
// With `label` non-null, also each corner's label: every polygon edge lies
// on an edge of T_B (support 0..2) or of T_A (3..5); a cut of a T_B edge by
// T_A's edge i is their crossing, a cut of T_A's edge i' by its edge i is
// their shared vertex. The labels never change the arithmetic.
inline int ClipTriangle(const Point2 a[3], const Point2 b[3], const int8_t* const s[3], double* x,
                        double* y, double* twice_area, uint8_t* label) {
  ClipPolygon scratch[2];
  const ClipPolygon* result = nullptr;
  const int n = label != nullptr ? ClipTriangleInto<true>(a, b, s, scratch, &result, twice_area)
                                 : ClipTriangleInto<false>(a, b, s, scratch, &result, twice_area);
  for (int k = 0; k < n; ++k) {
    x[k] = result->corner[k].x;
    y[k] = result->corner[k].y;
    if (label != nullptr) label[k] = result->label[k];
  }
  return n;
}

}  // namespace overlay_internal
}  // namespace surfreg
