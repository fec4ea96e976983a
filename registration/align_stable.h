#pragma once
// Align with AlignOptions::stable auto: the rounds of fit → classify → fit on
// the stable part (registration/stable_terrain.h), then the final solve.
#include "registration/align_result.h"

namespace surfreg {

// The solve alone (align.cc): the solved motion (rotation_vector,
// translation, matrix) and a verdict from the solver (converged or failed),
// whether or not the measure improved; no measures, no σ.
AlignResult AlignMotionOnly(const Surface& reference, const Surface& moving, const AlignOptions& options);

AlignResult AlignOnStableTerrain(const Surface& reference, const Surface& moving, const AlignOptions& options);

}  // namespace surfreg
