#pragma once
// The rigid correction most of the overlap agrees on, from the gaps alone:
// the first step of finding the stable terrain (stable_terrain.h). A fit
// pulled by what changed (an L1 or least-squares fit tilts toward a raised
// block) leaves its error in the gaps as a smooth field, g_i ≈ J_i β with
// J_i the gap's derivative in a small rigid motion of the moving surface
// (its normal n_i = (−∂z/∂x, −∂z/∂y, 1) and lever r_i: J_i = [r_i × n_i,
// n_i]). β is found by consensus over tiles of the overlap, which change
// spoils whole or not at all: 8 × 8 tiles; 300 seeded trials of 4 tiles
// each, β their least-squares fit, scored tile by tile (MSAC: each tile's
// median residual in the scale of a median there, squares truncated at 3²,
// weighted by the tile's samples); the best refined on its inliers. Per
// tile, because rough stable terrain leaves each sample far within its own
// large scale under a fit to a flat changed part, but not the tiles' medians. The residuals dz − J β then show the change as regions
// on a flat background.
#include <cstdint>
#include <vector>

#include "measure/surface.h"
#include "measure/tasks.h"
#include "registration/stable_terrain.h"

namespace surfreg {

struct ConsensusFit {
  std::vector<double> residual;  // dz − J β per reference sample (NaN where dz is, or not eligible)
  std::vector<uint8_t> flag;     // StableFlag: the consensus' inliers stable, the others changed
  double noise = 0;              // the gaps' scale from neighbour differences, data units
  double inlier_share = 0;       // of the eligible samples in the overlap
};

// `dz`: the gaps at the reference's samples (NaN outside the overlap);
// `eligible[i] == 0` leaves sample i out (empty: all eligible). Tiles and
// trials run on `execution`'s threads: the same fit for any number.
ConsensusFit RigidConsensus(const Surface& reference, const SampleAdjacency& adjacency,
                            const std::vector<double>& dz, const std::vector<uint8_t>& eligible,
                            const Execution& execution = Execution{1});

}  // namespace surfreg
