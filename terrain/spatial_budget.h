#pragma once
// The standard error of volumes summed over a DoD whose errors are
// spatially correlated (docs/terrain.md, "Spatially correlated errors"):
// the error at cell i is σ_i Z_i, Z a unit Gaussian field with the
// correlation ρ(d) of a fitted variogram (terrain/variogram.h), and a volume
// is Σ a_i g(dz_i) for fill, cut or net beyond a threshold L_i.
//
// Without a threshold the net is linear and Var = Σ_ij a_i a_j σ_i σ_j ρ_ij
// exactly. A threshold makes g jump at ±L; then each cell's g is expanded in
// Hermite polynomials of Z_i (Mehler's formula: Cov(g_i, g_j) = Σ_k c_ik
// c_jk ρ^k / k!), kept to k = 2 and bounded beyond by √(R_i R_j) ρ³, R_i
// the variance left: exact for ρ = 0 and ρ = 1, an upper bound between.
// c and R are taken at the cell's detected change (dz beyond L, 0 within):
// cells below the threshold carry the chance of a false detection.
#include <cstdint>
#include <functional>
#include <vector>

#include "measure/tasks.h"
#include "terrain/variogram.h"

namespace surfreg {

// Σ_ij w_i w_j K(d_ij) over the cells of `grid` (w: one weight per cell,
// 0 where none), K radial and 0 beyond `support` (length units; infinite
// = the whole grid). Exact when the grid is small enough that every pair
// within the support is at most `budget` multiply-adds; otherwise the
// weights are summed over blocks of b x b cells (b the smallest that fits
// the budget) and the blocks' sums paired at their centres' distance: an
// approximation linear in the cells, whose error is that of K varying over
// a block. `block` (optional) gets b.
double KernelQuadraticForm(const GridLayout& grid, const std::vector<double>& w,
                           double (*kernel)(double, const void*), const void* kernel_data,
                           double support, const Execution& execution, double budget = 1e8,
                           int* block = nullptr);

// One cell's contribution g to fill (X > L: X), cut (X < −L: −X) and net
// (their difference) for X = μ + σ Z, μ the detected change (dz if |dz| >
// L, else 0; L = 0: no threshold; 0 on known stable terrain, `noise`), in Hermite terms: c₁ = E[g
// Z], c₂ = E[g (Z² − 1)] and the variance left beyond them, Var g − c₁² − c₂²/2.
struct HermiteTerms {
  enum Budget { kFill = 0, kCut = 1, kNet = 2 };
  double c1[3] = {0, 0, 0}, c2[3] = {0, 0, 0}, rest[3] = {0, 0, 0};
};
HermiteTerms CellHermiteTerms(double dz, double sigma, double threshold, bool noise = false);

struct SpatialSigma {
  double fill = 0, cut = 0, net = 0;  // ± one standard error
  int block = 1;                      // the largest block of the approximation (1: exact)
};

// Rows [row0, row1) of a DoD's cells, the full width of the grid, row-major:
// dz, σ, the threshold L and the node area (NaN, NaN, 0, 0 where none).
struct BudgetRows {
  std::vector<double> dz, sigma, threshold, area;
  // 1 where the cell is known stable terrain (its dz is noise: no change,
  // detected or not); empty: none known.
  std::vector<uint8_t> noise;
};
// Fills `rows` with rows [row0, row1) of the grid; the first `core` of them
// are met here for the first time (the rest come again in the next band).
using BudgetRowReader = std::function<void(int row0, int row1, int core, BudgetRows* rows)>;

// How many rows the propagation takes at a time (its memory: about 80 bytes
// a cell of them): a function of the grid's width alone, so that a tiled
// and an untiled run add the same numbers in the same order.
int PropagationBandRows(const GridLayout& grid);

// The standard errors of fill, cut and net over the cells with a finite
// dz, σ and area, the correlation that of `variogram`, the rows read band
// by band (PropagationBandRows, plus the rows within the correlation's
// reach below it).
SpatialSigma PropagateSpatialSigma(const GridLayout& grid, const BudgetRowReader& read,
                                   const Variogram& variogram, const Execution& execution,
                                   double budget = 1e8);

// The same for a DoD held whole (`dz`, `sigma`, `threshold`, `area`: one
// per cell of `grid`).
SpatialSigma PropagateSpatialSigma(const GridLayout& grid, const std::vector<double>& dz,
                                   const std::vector<double>& sigma,
                                   const std::vector<double>& threshold,
                                   const std::vector<double>& area, const Variogram& variogram,
                                   const Execution& execution, double budget = 1e8);

}  // namespace surfreg
