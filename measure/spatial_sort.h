#pragma once
// Insertion orders that keep incremental construction local: Hilbert-curve
// order, optionally in biased randomized insertion order (BRIO) rounds
// (Amenta, Choi, Rote 2003): a small random sample first, then rounds that
// double in size, each sorted along the curve.
#include <cstdint>
#include <vector>

#include "measure/surface.h"
#include "measure/tasks.h"

namespace surfreg {

// Hilbert index of (x, y) on a 2^order x 2^order grid, 1 <= order <= 16.
uint32_t HilbertIndex(uint32_t x, uint32_t y, int order);

// Indices 0..n-1 of `points` in Hilbert order over their bounding box. With
// `brio`, in BRIO rounds drawn with `seed`. Deterministic for a given input:
// the same order on any number of `execution`'s threads.
std::vector<int32_t> SpatialOrder(const std::vector<Point2>& points, bool brio, uint64_t seed,
                                  const Execution& execution = Execution{1});

}  // namespace surfreg
