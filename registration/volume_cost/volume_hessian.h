#pragma once
// The curvature of the volume cost inside Ω, in closed form. With
// d = F̂_B' − F_A and g = ∂_θd = n·u (volume_cost.h), ∇∫μ|d| = ∫μ sign(d) g
// (plus Ω's moving boundary), and
//   ∇²∫_Ω μ|d| = 2 ∮_{d=0} μ g gᵀ / |∇ₓd| ds          (sign(d) jumps by 2)
//              + Σ_{B edges} κ ∫_edge μ sign(d) w wᵀ ds   (g jumps at a kink)
//              + the terms of Ω's moving boundary and of ∂_θ within a triangle,
// where κ is the jump of ∇F̂_B'·ν across a moved B edge (normal ν) and
// w = ν·u_xy its speed. d is linear on each overlay cell and g affine on each
// moved B triangle, so both line integrals are exact (Simpson). The terms
// left out are small where Ω's outline is short: against central
// differences of the exact gradient at peer pairs' solutions, diagonals
// within 0.2% on noisy terrain, 36% on a face (whose long open outline
// moves); the σ calibration is that of the differences
// (docs/registration.md). The sandwich σ's bread (registration/sandwich.h)
// and the metric the volume solve is whitened by (registration/solvers.h).
#include <Eigen/Core>

#include "measure/mask_region.h"
#include "measure/tasks.h"
#include "registration/pair_state.h"

namespace surfreg {

// The two line terms over Ω (∩ mask) at the state's θ (state.Update must
// have succeeded), of ∫μ|d| (divide by ∫_Ω μ for the per-area cost's, at
// its minimum where ∇f = 0 and Ω's area is stationary). Zero without a zero set
// or kinks; cells where d ≡ 0 add no zero line. In chunks on the threads
// `execution` allows (the same bits on any number).
Eigen::Matrix<double, 6, 6> InteriorVolumeHessian(const PairState& state, const Execution& execution,
                                            const MaskRegion* mask = nullptr);

}  // namespace surfreg
