#pragma once
// A held-out check that an alignment helped (pc_align users ask for it):
// the fit sees only part of the reference; the vertical differences on the
// rest, before and after the motion, show whether the motion improved data
// it did not use. The held-out part is whole tiles of the reference (not
// scattered samples, whose neighbours would still carry the fit there): the
// reference's bounding box cut into kHoldoutTiles × kHoldoutTiles tiles, a
// seeded random share of the tiles that hold samples.
#include <cstdint>
#include <vector>

#include "measure/dz_statistics.h"
#include "measure/surface.h"

namespace surfreg {

inline constexpr int kHoldoutTiles = 8;

// Per reference sample: 1 if it lies in a held-out tile. `fraction` in
// (0, 1): the share of the non-empty tiles held out (rounded, at least 1 and
// at most all but one); the same reference, fraction and seed always give
// the same tiles.
std::vector<uint8_t> HeldOutSamples(const Surface& reference, double fraction, uint64_t seed);

// `surface` without the samples flagged in `drop` (weights and raster cells
// kept for the others; the origin unchanged).
Surface WithoutSamples(const Surface& surface, const std::vector<uint8_t>& drop);

struct HoldoutCheck {
  bool done = false;
  double fraction = 0;
  int64_t samples = 0;      // reference samples held out
  // dz = moving − reference at the held-out samples inside Ω, before and
  // after the motion (the fitted motion measured on the whole reference).
  DzStatistics before, after;
  // √(median² + NMAD²) of dz: a robust RMSE, which sees a remaining offset
  // (the median) as well as a remaining spread (the NMAD).
  double robust_before = 0, robust_after = 0;
  bool improved = false;  // robust_after < robust_before
};

// √(median² + NMAD²) of `s`; NaN without values.
double RobustRmse(const DzStatistics& s);

}  // namespace surfreg
