#pragma once
// The error model of a DoD estimated from its stable terrain
// (`error_model: variogram`, docs/terrain.md "Spatially correlated
// errors"), after Hugonnet et al. (2022): dz on stable terrain is noise;
// its spread grows with slope and curvature (σ binned against each,
// robustly), and dz / σ is correlated in space (a variogram with a short
// and a long range, terrain/variogram.h). terrain/spatial_budget.h carries
// the model to the volumes.
#include <cstdint>
#include <string>
#include <vector>

#include "measure/tasks.h"
#include "terrain/variogram.h"

namespace surfreg {

// A DoD on the reference raster's grid, one value per cell (row-major).
struct DodGrid {
  GridLayout layout;
  std::vector<double> dz;       // NaN where there is none
  std::vector<double> height;   // the reference's heights (slope, curvature); NaN where none
  std::vector<double> area;     // each node's area in the budget (0 where none)
  std::vector<uint8_t> stable;  // 1: stable terrain, where dz is noise
};

// Slope (|∇z|, rise over run) and curvature (|∂²z/∂x² + ∂²z/∂y²|, per
// length) of `height` by central differences (one-sided at an edge or
// beside a hole; NaN where a cell has no neighbour).
void SlopeAndCurvature(const GridLayout& grid, const std::vector<double>& height, std::vector<double>* slope,
                       std::vector<double>* curvature);

// σ of dz against slope and curvature: the NMAD of dz in quantile bins of
// slope, then a factor from the NMAD of dz / σ(slope) in bins of
// curvature; linear between the bins' medians, constant beyond.
struct SigmaModel {
  std::vector<double> slope, sigma;         // bins' median slope and σ
  std::vector<double> curvature, factor;    // bins' median curvature and factor
  double At(double slope, double curvature) const;  // NaN slope or curvature: the middle bin's
};

struct DodErrorModel {
  int64_t stable_cells = 0;       // stable cells used (dz within 4 NMAD of the median)
  double stable_median = 0, stable_nmad = 0;
  bool sigma_estimated = false;   // σ from slope and curvature (else the σ given)
  SigmaModel sigma_model;
  EmpiricalVariogram empirical;   // of (dz − median) / σ on the stable cells
  Variogram variogram;            // its fit; ranges in length units
};

// The stable cells a model needs at least.
inline constexpr int64_t kMinStableCells = 1000;

// Fits the model on the stable cells of `dod`. `sigma` (one per cell):
// the DoD's σ when given (then only the variogram is fitted), empty to
// estimate it from slope and curvature; on return σ at every cell with a
// dz (NaN elsewhere). Too few stable cells: InputError starting with
// `where`.
DodErrorModel FitDodErrorModel(const DodGrid& dod, std::vector<double>* sigma, const Execution& execution,
                               const std::string& where);

}  // namespace surfreg
