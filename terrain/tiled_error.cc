#include "terrain/tiled_error.h"

#include <algorithm>
#include <cmath>

#include "measure/input_error.h"
#include "terrain/change_budget.h"

namespace surfreg {

TileDodStore::TileDodStore(int32_t columns, int32_t rows)
    : columns_(columns), rows_(rows), file_(std::tmpfile(), &std::fclose) {
  if (!file_)
    throw InputError("error_model variogram: cannot create a temporary file for the tiles' DoD");
}

void TileDodStore::Add(const TileDod& tile) {
  const std::size_t n = tile.dz.size();
  if (std::fseek(file_.get(), 0, SEEK_END) != 0)
    throw InputError("error_model variogram: the temporary file failed");
  Entry entry{tile.window, std::ftell(file_.get())};
  if (std::fwrite(tile.dz.data(), sizeof(double), n, file_.get()) != n ||
      std::fwrite(tile.node_area.data(), sizeof(double), n, file_.get()) != n) {
    throw InputError(
        "error_model variogram: cannot write the tiles' DoD to a temporary file (disk full?)");
  }
  entries_.push_back(entry);
}

void TileDodStore::Read(DodBlock* block) const {
  const std::size_t n =
      static_cast<std::size_t>(block->columns) * static_cast<std::size_t>(block->rows);
  block->dz.assign(n, std::nan(""));
  block->area.assign(n, 0.0);
  std::vector<double> values;
  for (const Entry& e : entries_) {
    const SampleWindow& w = e.window;
    const int x0 = std::max(w.column, block->column),
              x1 = std::min(w.column + w.columns, block->column + block->columns);
    const int y0 = std::max(w.row, block->row),
              y1 = std::min(w.row + w.rows, block->row + block->rows);
    if (x0 >= x1 || y0 >= y1) continue;
    const std::size_t cells =
        static_cast<std::size_t>(w.columns) * static_cast<std::size_t>(w.rows);
    values.resize(2 * cells);
    if (std::fseek(file_.get(), e.offset, SEEK_SET) != 0 ||
        std::fread(values.data(), sizeof(double), 2 * cells, file_.get()) != 2 * cells) {
      throw InputError(
          "error_model variogram: cannot read the tiles' DoD back from its temporary file");
    }
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        const std::size_t from = static_cast<std::size_t>(y - w.row) * w.columns +
                                 static_cast<std::size_t>(x - w.column);
        const std::size_t to = static_cast<std::size_t>(y - block->row) * block->columns +
                               static_cast<std::size_t>(x - block->column);
        block->dz[to] = values[from];
        block->area[to] = values[cells + from];
      }
    }
  }
}

ChangeUncertainty TiledSpatialUncertainty(const TileDodStore& store, const TiledErrorInputs& inputs,
                                          const Execution& execution) {
  const GridLayout& grid = inputs.grid;
  const DodBlockReader read = [&](DodBlock* block) {
    store.Read(block);
    block->height = inputs.heights(block->column, block->row, block->columns, block->rows);
    block->stable.assign(block->dz.size(), 1);
    if (std::isfinite(inputs.sigma_dod)) {
      block->sigma.assign(block->dz.size(), inputs.sigma_dod);
    } else {
      block->sigma.clear();
    }
    // As untiled: no σ and no area where there is no dz.
    for (std::size_t i = 0; i < block->dz.size(); ++i) {
      if (!std::isfinite(block->dz[i]) && !block->sigma.empty()) block->sigma[i] = std::nan("");
    }
  };
  ChangeUncertainty u;
  u.active = true;
  u.error_model = inputs.error_model;
  u.model = FitDodErrorModel(grid, read, execution, inputs.where);
  const double t = inputs.confidence > 0 ? TwoSidedNormalQuantile(inputs.confidence) : 0.0;
  ChangeBudgetSums sums;
  const SpatialSigma s = PropagateSpatialSigma(
      grid, DodBudgetRows(grid, read, u.model, t, inputs.lod, &sums), u.model.variogram, execution);
  const bool any = sums.nodes > 0;
  const double sigma_median = any ? u.model.sigma_median : std::nan("");
  u.budget = FinishChangeBudget(sums, t, sigma_median,
                                any ? std::max(inputs.lod, t * sigma_median) : std::nan(""));
  u.spatial = true;
  u.fill_sigma_spatial = s.fill, u.cut_sigma_spatial = s.cut, u.net_sigma_spatial = s.net;
  u.spatial_block = s.block;
  return u;
}

}  // namespace surfreg
