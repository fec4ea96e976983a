#pragma once
// Internal to the overlay (measure/overlay.cc) and the overlay kept as
// combinatorics (registration/overlay_topology.h): THE clip of a B triangle
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
  // Plain arrays: Point2's member initializers would zero them on every call.
  double next_x[8], next_y[8];
  int origin[8], next_origin[8];  // B corner index 0..2, or -1 for a computed point
  uint8_t labels[8], next_label[8];
  int support[8], next_support[8];  // of the edge from corner k to corner k + 1
  const bool labelled = label != nullptr;
  int n = 3;
  for (int k = 0; k < 3; ++k) {
    x[k] = b[k].x;
    y[k] = b[k].y;
    origin[k] = k;
    if (labelled) {
      labels[k] = CornerB(k);
      support[k] = (k + 2) % 3;  // the edge from corner k to k + 1 is opposite corner k + 2
    }
  }
  for (int i = 0; i < 3 && n > 0; ++i) {
    const Point2& e0 = a[(i + 1) % 3];
    const Point2& e1 = a[(i + 2) % 3];
    const double ex = e1.x - e0.x, ey = e1.y - e0.y;
    double value[8];
    int side[8];
    bool all_inside = true;
    for (int k = 0; k < n; ++k) {
      value[k] = ex * (y[k] - e0.y) - ey * (x[k] - e0.x);
      side[k] = origin[k] >= 0 ? s[origin[k]][i] : SignOf(value[k]);
      all_inside = all_inside && side[k] >= 0;
    }
    if (all_inside) continue;  // the common case: nothing to cut on this edge
    int m = 0;
    for (int k = 0; k < n && m < 8; ++k) {
      const int l = k + 1 == n ? 0 : k + 1;
      if (side[k] >= 0) {
        next_x[m] = x[k];
        next_y[m] = y[k];
        next_origin[m] = origin[k];
        if (labelled) {
          next_label[m] = labels[k];
          // On edge i's line and the next corner outside: the edge runs along edge i.
          next_support[m] = side[k] == 0 && side[l] < 0 ? 3 + i : support[k];
        }
        ++m;
      }
      if (m < 8 && ((side[k] > 0 && side[l] < 0) || (side[k] < 0 && side[l] > 0))) {
        const double denominator = value[k] - value[l];
        double t = denominator != 0.0 ? value[k] / denominator : 0.5;
        t = std::min(1.0, std::max(0.0, t));
        next_x[m] = x[k] + t * (x[l] - x[k]);
        next_y[m] = y[k] + t * (y[l] - y[k]);
        next_origin[m] = -1;
        if (labelled) {
          next_label[m] =
              support[k] < 3 ? CornerCross(i, support[k]) : CornerA(3 - i - (support[k] - 3));
          next_support[m] = side[k] > 0 ? 3 + i : support[k];  // leaving: along edge i
        }
        ++m;
      }
    }
    n = m;
    std::copy(next_x, next_x + m, x);
    std::copy(next_y, next_y + m, y);
    std::copy(next_origin, next_origin + m, origin);
    if (labelled) {
      std::copy(next_label, next_label + m, labels);
      std::copy(next_support, next_support + m, support);
    }
  }
  if (n < 3) return 0;
  double twice = 0.0;
  for (int k = 1; k + 1 < n; ++k) {
    twice += (x[k] - x[0]) * (y[k + 1] - y[0]) - (y[k] - y[0]) * (x[k + 1] - x[0]);
  }
  if (!(twice > 0.0)) return 0;
  *twice_area = twice;
  if (labelled) std::copy(labels, labels + n, label);
  return n;
}

}  // namespace overlay_internal
}  // namespace surfreg
