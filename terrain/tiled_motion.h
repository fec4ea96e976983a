#pragma once
// Two rasters too large to hold, aligned (issue 24): the rigid motion is
// solved on a bounded sample of both (SampleRasterPatches), then the moving
// raster is measured moved, tile by tile (MovedRasterSource into
// MeasureTiled), so memory is bounded by the sample and by a tile.
//
// The sample is a set of square patches of the reference at full
// resolution, one per cell of a grid of strata over the raster (its place
// in the stratum seeded), and for each the moving raster's window that
// covers it (under the initial motion) plus a margin. Full resolution, not
// a thinned raster: the motion's accuracy is that of the data, and the
// patches' data domains are their own complete cells, so the gaps between
// patches are no surface (nothing bridges them). Spread over the whole
// raster, the patches keep the lever arm a rotation needs.
#include <array>
#include <cstdint>
#include <vector>

#include "measure/surface.h"
#include "terrain/tiled_measure.h"

namespace surfreg {

// A rigid motion of input coordinates, the 4 × 4 matrix row-major
// (moving -> reference, as align reports it).
using RowMajorMatrix4 = std::array<double, 16>;
inline constexpr RowMajorMatrix4 kIdentityMatrix4 = {1, 0, 0, 0, 0, 1, 0, 0,
                                                     0, 0, 1, 0, 0, 0, 0, 1};

struct PatchSampleOptions {
  int64_t max_reference_samples = 250000;  // reference samples taken at most (> 0)
  int32_t patch = 128;                     // side of a reference patch in samples (>= 8)
  int32_t margin = 16;                     // samples added on each side of a moving window (>= 0)
  uint64_t seed = 1;                       // where each patch lies in its stratum
  // Where the moving raster's data over a patch is looked for: the motion
  // the solve starts from, and the range of the moving raster's heights
  // (input coordinates) that a tilted motion needs (ExtentOfSamples).
  RowMajorMatrix4 initial = kIdentityMatrix4;
  double moving_z_min = 0, moving_z_max = 0;
};

struct PatchSample {
  // Each side's samples from every patch, once each (overlapping moving
  // windows merged), in row-major order of their raster cells (whole-raster
  // numbering); origin = the sources' origin.
  Surface reference, moving;
  std::vector<SampleWindow> patches;  // the reference's windows
  bool whole = false;  // the reference fitted whole: one patch, the moving raster whole
};

// The sample above. When the reference has no more samples than
// max_reference_samples, it is read whole and the moving raster whole: the
// sample is the pair. Throws InputError for invalid options, and when the
// patches hold fewer than 3 reference samples (e.g. all nodata).
PatchSample SampleRasterPatches(const TiledRasterSource& reference, const TiledRasterSource& moving,
                                const PatchSampleOptions& options);

// What one pass over a raster's valid samples finds: their box and the
// lowest and highest height (input coordinates), read in bands of
// `band_rows` rows (a memory bound). count 0 (and zeros) if all nodata.
struct SampleExtent {
  XyBox box;
  double z_min = 0, z_max = 0;
  int64_t count = 0;
};
SampleExtent ExtentOfSamples(const TiledRasterSource& raster, int32_t band_rows);

// `moving` after `motion` (input coordinates): `read` gives a window's
// samples moved (their raster cells kept: still meshed on their own cells,
// grid_mesh.h), `cover` the window of samples whose moved cells may meet a
// box: the preimage of the box's prism over the heights [z_min, z_max] of
// the raster (ExtentOfSamples), which is exact for any rigid motion whose
// rotation keeps the vertical within 90°. Throws InputError when it does not.
TiledRasterSource MovedRasterSource(TiledRasterSource moving, const RowMajorMatrix4& motion,
                                    double z_min, double z_max);

}  // namespace surfreg
