#pragma once
// The error model of a DoD estimated from its stable terrain
// (`error_model: variogram`, docs/terrain.md "Spatially correlated
// errors"), after Hugonnet et al. (2022): dz on stable terrain is noise;
// its spread grows with slope and curvature (σ binned against each,
// robustly), and dz / σ is correlated in space (a variogram with a short
// and a long range, terrain/variogram.h). terrain/spatial_budget.h carries
// the model to the volumes.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "measure/tasks.h"
#include "terrain/variogram.h"

namespace surfreg {

// A window of a DoD on the reference raster's grid: columns [column,
// column + columns) and rows [row, row + rows), one value per cell,
// row-major.
struct DodBlock {
  int column = 0, row = 0, columns = 0, rows = 0;
  std::vector<double> dz;      // NaN where there is none
  std::vector<double> height;  // the reference's heights (slope, curvature); NaN where none
  std::vector<double> area;    // each node's area in the budget (0 where none)
  std::vector<double> sigma;   // the DoD's σ when given (e.g. sigma_reference); empty: estimate it
  std::vector<uint8_t> stable;  // 1: stable terrain, where dz is noise
};
// Fills the window `block` names (column, row, columns, rows set): from
// memory (DodGridReader), or from disk in a tiled run.
using DodBlockReader = std::function<void(DodBlock* block)>;

// A DoD held whole: the grid and its one block.
struct DodGrid {
  GridLayout layout;
  DodBlock cells;  // the whole grid
};
DodBlockReader DodGridReader(const DodGrid& dod);

// The windows a model is fitted on, {column, row, columns, rows}: the whole
// grid up to 2²² cells, else 16 windows of 1024 x 1024 cells spread evenly
// (a function of the grid's size alone: tiled and untiled runs fit the same).
std::vector<std::array<int, 4>> ErrorModelWindows(const GridLayout& grid);

// Slope (|∇z|, rise over run) and curvature (|∂²z/∂x² + ∂²z/∂y²|, per
// length) of `height` by central differences (one-sided at an edge or
// beside a hole; NaN where a cell has no neighbour).
void SlopeAndCurvature(const GridLayout& grid, const std::vector<double>& height,
                       std::vector<double>* slope, std::vector<double>* curvature);

// σ of dz against slope and curvature: the NMAD of dz in quantile bins of
// slope, then a factor from the NMAD of dz / σ(slope) in bins of
// curvature; linear between the bins' medians, constant beyond.
struct SigmaModel {
  std::vector<double> slope, sigma;                 // bins' median slope and σ
  std::vector<double> curvature, factor;            // bins' median curvature and factor
  double At(double slope, double curvature) const;  // NaN slope or curvature: the middle bin's
};

struct DodErrorModel {
  int64_t stable_cells = 0;  // stable cells used (dz within 4 NMAD of the median)
  double stable_median = 0, stable_nmad = 0;
  bool sigma_estimated = false;  // σ from slope and curvature (else the σ given)
  SigmaModel sigma_model;
  EmpiricalVariogram empirical;  // of (dz − median) / σ on the stable cells
  Variogram variogram;           // its fit; ranges in length units
  double sigma_median = 0;       // of σ over the windows' cells with a dz and an area
};

// The stable cells a model needs at least.
inline constexpr int64_t kMinStableCells = 1000;

// Fits the model on the stable cells of the windows ErrorModelWindows
// gives, read through `read` (with a cell around them for the slope). Too
// few stable cells: InputError starting with `where`.
DodErrorModel FitDodErrorModel(const GridLayout& grid, const DodBlockReader& read,
                               const Execution& execution, const std::string& where);

// Whether a cell's dz is taken as noise by `model`: stable terrain, and
// within 4 NMAD of the stable median (the cells the model was fitted on).
bool StableInlier(const DodErrorModel& model, bool stable, double dz);

// Reads the window of `block` (through `read`, with a cell around it for
// the slope) and sets `sigma` to each cell's σ: the one given, or the
// model's (NaN where there is no dz).
void ReadWithSigma(const GridLayout& grid, const DodBlockReader& read, const DodErrorModel& model,
                   DodBlock* block, std::vector<double>* sigma);

}  // namespace surfreg
