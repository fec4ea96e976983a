#pragma once
// A wider search for the start of an alignment (issue 20): the axial
// prealignment's basin is about 10° and 20 sample spacings wide; starts
// farther away end in another minimum. WideSearch tries many starts on a
// coarse subsample of both surfaces and returns the one whose axial solve
// ends with the smallest mean squared gap over a substantial overlap.
// Internal to align.cc.
#include <array>

#include "registration/align_options.h"
#include "registration/pair_state.h"

namespace surfreg {

struct WideSearchResult {
  std::array<double, 6> theta{};  // the best start found (θ about the full cloud's centroid)
  int candidates = 0;             // starts solved
  double mean_square_gap = 0;     // of the best, on the coarse subsample
};

// `reference` and `moving` are the coarse sides (moving.centroid set to the
// full cloud's, so θ means the same motion as on the finest level);
// `theta0` the user's start; `rotation_scale` B's RMS radius.
WideSearchResult WideSearch(const ReferenceSide& reference, const MovingSide& moving,
                            const std::array<double, 6>& theta0, const AlignOptions& options,
                            double rotation_scale);

}  // namespace surfreg
