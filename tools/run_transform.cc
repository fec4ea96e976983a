// surfreg transform INPUT --transform=T --output=OUT [--inverse] [--grid=REF]
// [--classes=C,...] [--columns=X,Y,Z] [--threads=N|all]:
// applies a rigid transform file (tools/transform_file.h) to every point of
// a cloud or raster and writes the result as a cloud (.xyz .txt .ply) or,
// resampled onto a grid (the input raster's own, or REF's), as a GeoTIFF
// (io/raster_resample.h), on every core unless --threads says otherwise
// (the same bytes on any number).
#include <gflags/gflags.h>

#include <Eigen/LU>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "measure/input_error.h"
#include "measure/tasks.h"
#include "registration/align.h"
#include "tools/align_config.h"
#include "io/atomic_file.h"
#include "tools/commands.h"
#include "io/las_writer.h"
#include "io/raster_io.h"
#include "io/raster_resample.h"
#include "io/surface_reader.h"
#include "io/surface_writer.h"
#include "tools/progress_lines.h"
#include "tools/transform_file.h"
#include "tools/key_flags.h"

DEFINE_string(transform, "",
              "transform: the rigid transform file: surfreg's align JSON or a 4x4 text matrix "
              "(moving -> reference)");
DEFINE_bool(inverse, false, "transform: apply the inverse of the transform");
DEFINE_string(grid, "",
              "transform: a raster whose grid (size, geotransform, CRS) a .tif output is "
              "resampled onto (default: the input raster's own)");
DECLARE_bool(quiet);  // tools/run_measure.cc

namespace surfreg {
namespace {

// The flags, checked before anything is read.
void CheckFlags(const std::string& input, bool raster_out, bool raster_in) {
  // Missing flags are bad input (one line), not usage: the flag is named.
  if (FLAGS_transform.empty()) {
    throw InputError("flag '--transform' is required: the transform file (align JSON or 4x4 text)");
  }
  if (KeyFlag("output").empty()) throw InputError("flag '--output' is required: the file to write");
  if (!raster_out && !IsWritableSurfacePath(KeyFlag("output"))) {
    throw InputError("flag '--output': cannot write '" + KeyFlag("output") +
                     "' (expected a name ending in .xyz, .txt, .ply, .las or .tif)");
  }
  if (raster_out && !raster_in && FLAGS_grid.empty()) {
    throw InputError("flag '--output': a cloud written as GeoTIFF needs a grid: give --grid=REF.tif");
  }
  if (!FLAGS_grid.empty() && !raster_out) {
    throw InputError("flag '--grid': a grid is only for a .tif output, not '" + KeyFlag("output") + "'");
  }
  CheckOutputPath(KeyFlag("output"), "flag '--output'");
  for (const std::string& other : {input, FLAGS_transform, FLAGS_grid}) {
    if (!other.empty() && SameFile(KeyFlag("output"), other)) {
      throw InputError("flag '--output': '" + KeyFlag("output") + "' is also an input");
    }
  }
}

// --classes and --columns as align reads them (same values and messages).
ReadOptions CloudReadOptions(bool raster_in) {
  AlignConfig settings;
  for (const auto& [key, value] : {std::pair<const char*, const std::string&>{"classes", KeyFlag("classes")},
                                   {"columns", KeyFlag("columns")}}) {
    if (value.empty()) continue;
    if (raster_in) throw InputError(std::string("flag '--") + key + "': INPUT is a raster, not a cloud");
    ApplyAlignFlag(key, value, &settings);
  }
  ReadOptions options;
  options.classes = settings.classes;
  options.columns = settings.columns;
  return options;
}

// --band and --window as align reads them, for a raster INPUT.
RasterReadOptions RasterOptions(bool raster_in) {
  AlignConfig settings;
  for (const auto& [key, value] : {std::pair<const char*, const std::string&>{"band", KeyFlag("band")},
                                   {"window", KeyFlag("window")}}) {
    if (value.empty()) continue;
    if (!raster_in) throw InputError(std::string("flag '--") + key + "': INPUT is a cloud, not a raster");
    ApplyAlignFlag(key, value, &settings);
  }
  RasterReadOptions options;
  options.band = settings.terrain.band;
  const auto& w = settings.terrain.window;
  options.window = {w[0], w[1], w[2], w[3]};
  return options;
}

}  // namespace

int RunTransform(const std::vector<std::string>& args) {
  if (args.empty()) throw UsageError("transform: missing INPUT");
  if (args.size() > 1) throw UsageError("transform: too many arguments");
  const std::string& input = args[0];
  const bool raster_in = IsRasterPath(input);
  const bool raster_out = IsGeoTiffPath(KeyFlag("output"));
  CheckFlags(input, raster_out, raster_in);
  const Execution execution = ExecutionFor(ThreadsFlag());
  ReadOptions read_options = CloudReadOptions(raster_in);
  read_options.threads = execution.threads;
  RasterReadOptions raster_options = RasterOptions(raster_in);
  raster_options.threads = execution.threads;
  Eigen::Matrix4d m = ReadTransformFile(FLAGS_transform, "flag '--transform'");
  if (FLAGS_inverse) m = m.inverse().eval();

  // Stage lines for inputs large enough to take seconds (progress_lines.h).
  const bool loud = !FLAGS_quiet && LargeInputs({input});
  if (loud) PrintReadingLine("transform", {input});
  Raster grid;  // the input raster's: its grid is the default output grid
  Surface surface;
  if (raster_in) {
    grid = ReadRaster(input, raster_options);
    surface = RasterToSurface(grid, nullptr, 1.0, execution.threads);
  } else {
    surface = ReadSurface(input, read_options);
  }
  if (!FLAGS_grid.empty()) grid = ReadRaster(FLAGS_grid);
  const Surface moved = TransformSurface(surface, m, execution.threads);
  if (loud) {
    std::fprintf(stderr, "transform: writing %s%s\n", KeyFlag("output").c_str(),
                 raster_out ? " (resampled onto the grid)" : "");
  }
  if (raster_out) {
    WriteGeoTiff(KeyFlag("output"), ResampleOntoGrid(moved, grid, execution), "flag '--output'", execution.threads);
  } else if (IsLasPath(input) && IsLasPath(KeyFlag("output"))) {
    // The file's own records moved: every class and attribute kept.
    WriteMovedLas(input, RowMajor(m), KeyFlag("output"), "flag '--output'");
  } else {
    std::vector<std::string> comments = {
        input + " moved by " + (FLAGS_inverse ? "the inverse of " : "") + FLAGS_transform +
            " (surfreg transform); matrix applied, row-major:"};
    for (int i = 0; i < 4; ++i) {
      char row[160];
      std::snprintf(row, sizeof(row), "  %.17g %.17g %.17g %.17g", m(i, 0), m(i, 1), m(i, 2),
                    m(i, 3));
      comments.push_back(row);
    }
    WriteSurface(KeyFlag("output"), moved, "flag '--output'", comments);
  }
  std::printf("%s: %zu points moved by %s%s -> %s\n", input.c_str(), surface.size(),
              FLAGS_inverse ? "the inverse of " : "", FLAGS_transform.c_str(),
              KeyFlag("output").c_str());
  return 0;
}

}  // namespace surfreg
