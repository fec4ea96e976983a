#pragma once
// error_model variogram in a tiled measure (terrain/tiled_measure.h): the
// DoD of each tile (dz and node areas) goes to a temporary file as the tiles
// are done, then a second pass reads it back a window at a time: the model
// is fitted on the windows of terrain/dod_error.h (the whole grid up to 2²²
// cells, else 16 windows of 1024²) and the budget is propagated band by
// band (terrain/spatial_budget.h), as an untiled run does on its DoD held
// whole: the same numbers, to the rounding of the tiled measure's own sums.
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "terrain/change_uncertainty.h"
#include "terrain/tiled_measure.h"

namespace surfreg {

// The tiles' DoD on disk (a temporary file, removed when the store goes).
class TileDodStore {
 public:
  TileDodStore(int32_t columns, int32_t rows);
  // A tile's dz and node areas (TileDod): its window of the reference's samples.
  void Add(const TileDod& tile);
  // dz and node areas over `block`'s window (NaN and 0 where no tile gave one).
  void Read(DodBlock* block) const;

 private:
  struct Entry {
    SampleWindow window;
    long offset = 0;
  };
  int32_t columns_ = 0, rows_ = 0;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::vector<Entry> entries_;
};

struct TiledErrorInputs {
  GridLayout grid;  // the reference raster's cells, their sides in the frame's units
  // The reference's heights over a window {column, row, columns, rows}, NaN at nodata.
  std::function<std::vector<double>(int column, int row, int columns, int rows)> heights;
  double sigma_dod = std::nan("");  // the DoD's σ when given as numbers (NaN: estimate it)
  double confidence = 0, lod = 0;   // the threshold max(lod, t(confidence) σ)
  std::string error_model = "variogram";
  std::string where;  // starts the messages (the error_model key)
};

// The change uncertainty of the tiled run whose tiles `store` holds, with
// every reference cell stable terrain: the budget (σ and threshold medians
// over the model's windows) and its spatially correlated ±.
ChangeUncertainty TiledSpatialUncertainty(const TileDodStore& store, const TiledErrorInputs& inputs,
                                          const Execution& execution);

}  // namespace surfreg
