#pragma once
// The spatial correlation of a DoD's errors (docs/terrain.md, "Spatially
// correlated errors"): an empirical variogram of values on a grid (the
// standardized dz of stable terrain, outliers cut), and its fit by a nugget plus a
// short- and a long-range spherical model, as Hugonnet et al. (2022) and
// xDEM do. The correlation it implies is what terrain/spatial_budget.h
// propagates to volumes.
#include <array>
#include <cstdint>
#include <vector>

#include "measure/tasks.h"

namespace surfreg {

// A row-major grid of `columns` x `rows` cells of dx x dy length units.
struct GridLayout {
  int columns = 0, rows = 0;
  double dx = 1, dy = 1;
  int64_t cells() const { return static_cast<int64_t>(columns) * rows; }
};

struct EmpiricalVariogram {
  std::vector<double> lag;     // mean distance of each bin's pairs (length units)
  std::vector<double> gamma;   // semivariance: Matheron's estimator, ½ mean(Δ²)
  std::vector<int64_t> pairs;  // pairs in the bin
};

// The empirical variogram of `values` (one per cell of `grid`, NaN = none)
// in lag bins from one cell to half the valid cells' bounding-box diagonal,
// each growing by 25%; up to `pairs_per_bin` pairs per bin drawn at random
// (a fixed seed: the same bins for any thread count). Bins without pairs
// are left out.
EmpiricalVariogram SampleVariogram(const GridLayout& grid, const std::vector<double>& values,
                                   const Execution& execution = Execution{1},
                                   int64_t pairs_per_bin = 20000);

// The same over several grids (windows of one DoD; each pair within one):
// cells drawn over all of them alike, lags up to half the largest valid
// bounding-box diagonal.
struct GridValues {
  GridLayout grid;
  const std::vector<double>* values = nullptr;
};
EmpiricalVariogram SampleVariogram(const std::vector<GridValues>& grids,
                                   const Execution& execution = Execution{1},
                                   int64_t pairs_per_bin = 20000);

// The spherical model's correlation at lag h for range r: 1 − 1.5 h/r +
// 0.5 (h/r)³ below r, 0 beyond; 1 everywhere for an infinite range.
double SphericalCorrelation(double h, double range);

// nugget + Σ sill_k · (1 − SphericalCorrelation(h, range_k)) for h > 0.
struct Variogram {
  double nugget = 0;
  std::array<double, 2> sill = {0, 0};   // short, long
  std::array<double, 2> range = {0, 0};  // length units, range[0] <= range[1]
  double Total() const { return nugget + sill[0] + sill[1]; }
  double Gamma(double h) const;        // 0 at h = 0
  double Correlation(double h) const;  // 1 − Gamma(h) / Total(); 1 at h = 0
};

// The weighted least-squares fit (weights pairs / γ², Cressie's) of a
// nugget plus none, one or two spherical models with non-negative sills,
// the ranges searched on a logarithmic grid in [min_range, max_range] and
// refined; a richer model only where an F test of the residuals finds it
// significant (a flat variogram is a pure nugget). One model is the long
// one (sill[1], range[1]); an unused one has sill and range 0. Fewer than
// 3 bins: the nugget alone.
Variogram FitVariogram(const EmpiricalVariogram& empirical, double min_range, double max_range);

}  // namespace surfreg
