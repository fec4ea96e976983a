// Raster reading and GeoTIFF writing (see raster_io.h): the GDAL calls are
// in the GDAL module (gdal_module.h); here the checks, the conversion to a
// surface and the atomic replacement of the output.
#include "io/raster_io.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glog/logging.h>

#include "measure/input_error.h"
#include "measure/tasks.h"
#include "measure/uninitialized_vector.h"
#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "io/gdal_module.h"
#include "io/surface_reader_internal.h"

namespace surfreg {
namespace {

[[noreturn]] void Fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

}  // namespace

Point2 Raster::CellCentre(int column, int row) const {
  const double c = column + 0.5, r = row + 0.5;
  const auto& gt = geotransform;
  return {gt[0] + c * gt[1] + r * gt[2], gt[3] + c * gt[4] + r * gt[5]};
}

Raster ReadRaster(const std::string& path, const RasterReadOptions& options) {
  const GdalModule& gdal = Gdal(path);
  Raster raster;
  std::string error;
  // Bands of rows of about a million cells (their number a function of the
  // size only), each read on a handle of its own; a small window at once
  // (a window given whole needs no look at the file first).
  const auto chunks_for = [](int64_t columns, int64_t rows) {
    return ChunksFor(rows, std::max<int64_t>(1, (int64_t{1} << 20) / std::max<int64_t>(columns, 1)));
  };
  const RasterWindow& w = options.window;
  const bool small_window = w.columns > 0 && w.rows > 0 && chunks_for(w.columns, w.rows) == 1;
  if (!small_window && !gdal.read_raster_header(path, options, &raster, &error)) throw InputError(error);
  const int chunks = small_window ? 1 : chunks_for(raster.columns, raster.rows);
  if (chunks == 1) {
    if (!gdal.read_raster(path, options, &raster, &error)) throw InputError(error);
  } else {
    const Execution execution = ExecutionFor(options.threads);
    raster.values.resize(static_cast<std::size_t>(raster.columns) * static_cast<std::size_t>(raster.rows));
    std::vector<int64_t> non_finite(chunks, 0);
    std::vector<std::string> errors(chunks);
    std::string crs_error;
    // The CRS beside the rows: its export loads PROJ's database (~20 ms).
    RunBoth(
        execution,
        [&] {
          if (!gdal.read_raster_crs(path, &raster.crs_wkt, &crs_error) && crs_error.empty()) {
            crs_error = path + ": cannot read the CRS";
          }
        },
        [&] {
          ForEachChunk(execution, raster.rows, chunks, [&](int c, int64_t first, int64_t last) {
            double* values = raster.values.data() + first * raster.columns;
            if (!gdal.read_raster_rows(path, options, static_cast<int>(first), static_cast<int>(last - first),
                                       values, &non_finite[c], &errors[c]) &&
                errors[c].empty()) {
              errors[c] = path + ": cannot read rows " + std::to_string(first) + " to " + std::to_string(last);
            }
          });
        });
    if (!crs_error.empty()) throw InputError(crs_error);
    for (int c = 0; c < chunks; ++c) {
      if (!errors[c].empty()) throw InputError(errors[c]);
      raster.non_finite_cells += non_finite[c];
    }
  }
  if (raster.non_finite_cells > 0) {
    LOG(WARNING) << path << ": " << raster.non_finite_cells << " of "
                 << static_cast<int64_t>(raster.columns) * raster.rows
                 << " cells are NaN or infinite (not the band's nodata value): read as nodata";
  }
  return raster;
}

Surface GridCellsToSurface(const std::array<double, 6>& gt, int column0, int row0, int columns, int rows,
                           const double* values, const std::array<double, 3>* origin, double origin_step,
                           std::vector<int64_t>* cell_of_sample, int threads) {
  const Execution execution = ExecutionFor(threads);
  const int64_t width = std::max(columns, 0), height = std::max(rows, 0);
  // Bands of rows of about 2^16 cells (their number a function of the size only).
  const int chunks = ChunksFor(height, std::max<int64_t>(1, (int64_t{1} << 16) / std::max<int64_t>(width, 1)));
  // The centre exactly as Raster::CellCentre (the same doubles as one pass).
  const auto centre = [&gt](int column, int row) {
    const double c = column + 0.5, r = row + 0.5;
    return Point2{gt[0] + c * gt[1] + r * gt[2], gt[3] + c * gt[4] + r * gt[5]};
  };
  struct Counted {
    int64_t valid = 0;
    std::array<double, 3> lo, hi;  // of the finite coordinates, for the origin
  };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<Counted> counted(chunks, Counted{0, {kInf, kInf, kInf}, {-kInf, -kInf, -kInf}});
  ForEachChunk(execution, height, chunks, [&](int c, int64_t first, int64_t last) {
    Counted n = counted[c];
    for (int64_t row = first; row < last; ++row) {
      const double* z = values + row * width;
      for (int64_t column = 0; column < width; ++column) {
        if (!std::isfinite(z[column])) continue;
        ++n.valid;
        if (origin != nullptr) continue;
        const Point2 p = centre(column0 + static_cast<int>(column), row0 + static_cast<int>(row));
        const double xyz[3] = {p.x, p.y, z[column]};
        for (int k = 0; k < 3; ++k) {
          if (!std::isfinite(xyz[k])) continue;
          n.lo[k] = std::min(n.lo[k], xyz[k]), n.hi[k] = std::max(n.hi[k], xyz[k]);
        }
      }
    }
    counted[c] = n;
  });
  std::vector<int64_t> offset(static_cast<std::size_t>(chunks) + 1, 0);
  std::array<double, 3> lo = counted[0].lo, hi = counted[0].hi;
  for (int c = 0; c < chunks; ++c) {
    offset[c + 1] = offset[c] + counted[c].valid;
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], counted[c].lo[k]), hi[k] = std::max(hi[k], counted[c].hi[k]);
  }
  Surface surface;
  surface.origin = origin != nullptr ? *origin : SurfaceOrigin(lo, hi, origin_step);
  const std::size_t total = static_cast<std::size_t>(offset[chunks]);
  surface.xy.resize(total);
  surface.z.resize(total);
  surface.raster_cell.resize(total);
  if (cell_of_sample != nullptr) cell_of_sample->assign(total, 0);
  const std::array<double, 3> o = surface.origin;
  ForEachChunk(execution, height, chunks, [&](int c, int64_t first, int64_t last) {
    std::size_t i = static_cast<std::size_t>(offset[c]);
    for (int64_t row = first; row < last; ++row) {
      const double* z = values + row * width;
      for (int64_t column = 0; column < width; ++column) {
        if (!std::isfinite(z[column])) continue;
        const int grid_column = column0 + static_cast<int>(column), grid_row = row0 + static_cast<int>(row);
        const Point2 p = centre(grid_column, grid_row);
        surface.xy[i] = {p.x - o[0], p.y - o[1]};
        surface.z[i] = z[column] - o[2];
        surface.raster_cell[i] = {grid_column, grid_row};
        if (cell_of_sample != nullptr) (*cell_of_sample)[i] = row * width + column;
        ++i;
      }
    }
  });
  return surface;
}

Surface RasterToSurface(const Raster& raster, std::vector<int64_t>* cell_of_sample, double origin_step,
                        int threads) {
  if (raster.values.size() != static_cast<std::size_t>(std::max(raster.columns, 0)) * std::max(raster.rows, 0)) {
    Fail(raster.source, std::to_string(raster.values.size()) + " values for " + std::to_string(raster.columns) +
                            " x " + std::to_string(raster.rows) + " cells");
  }
  Surface surface = GridCellsToSurface(raster.geotransform, 0, 0, raster.columns, raster.rows, raster.values.data(),
                                       nullptr, origin_step, cell_of_sample, threads);
  if (surface.xy.empty()) Fail(raster.source, "every cell is nodata");
  surface.source = raster.source;  // meshed on its own cells (measure/grid_mesh.h)
  ValidateSurface(surface, ExecutionFor(threads));
  return surface;
}

namespace {

std::string TemporaryName(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp-" + std::to_string(getpid()) + "-" + std::to_string(counter++);
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

// The nodata value (raster_io.h) for a raster's values as Float32, after
// checking that every finite one fits: a scan by chunks.
float ChooseFloat32Nodata(const Raster& raster, const std::string& where, const Execution& execution) {
  const float preferred[] = {-9999.0f, -99999.0f, -32768.0f, std::numeric_limits<float>::lowest()};
  constexpr int kPreferred = 4;
  constexpr double kMax = std::numeric_limits<float>::max();
  const int64_t n = static_cast<int64_t>(raster.values.size());
  const int chunks = ChunksFor(n, int64_t{1} << 16);
  struct ChunkScan {
    int64_t too_large = -1;  // the chunk's first value outside Float32
    bool used[kPreferred] = {false, false, false, false};
  };
  std::vector<ChunkScan> scans(chunks);
  ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
    ChunkScan& scan = scans[c];
    for (int64_t i = begin; i < end; ++i) {
      const double v = raster.values[i];
      if (!(std::fabs(v) <= kMax)) {  // NaN, infinite or too large
        if (std::isfinite(v) && scan.too_large < 0) scan.too_large = i;
        continue;
      }
      const float f = static_cast<float>(v);
      for (int k = 0; k < kPreferred; ++k) scan.used[k] = scan.used[k] || f == preferred[k];
    }
  });
  for (const ChunkScan& scan : scans) {  // the first in row-major order
    if (scan.too_large < 0) continue;
    const int64_t i = scan.too_large;
    Fail(where, "value " + Number(raster.values[i]) + " at column " + std::to_string(i % raster.columns) +
                    ", row " + std::to_string(i / raster.columns) + " does not fit Float32");
  }
  for (int k = 0; k < kPreferred; ++k) {
    if (std::none_of(scans.begin(), scans.end(), [&](const ChunkScan& s) { return s.used[k]; })) {
      return preferred[k];
    }
  }
  // Every usual value is data: step down from -9999 (at most size + 1 tries).
  for (float candidate = -10000.0f;; candidate -= 1.0f) {
    const bool used = std::any_of(raster.values.begin(), raster.values.end(), [&](double v) {
      return std::isfinite(v) && static_cast<float>(v) == candidate;
    });
    if (!used) return candidate;
  }
}

}  // namespace

void WriteGeoTiff(const std::string& path, const Raster& raster, const std::string& label, int threads) {
  const std::string where = label + ": '" + path + "'";
  const std::size_t cells =
      static_cast<std::size_t>(std::max(raster.columns, 0)) * std::max(raster.rows, 0);
  if (raster.columns <= 0 || raster.rows <= 0 || raster.values.size() != cells) {
    Fail(where, "raster of " + std::to_string(raster.columns) + " x " +
                    std::to_string(raster.rows) + " cells has " +
                    std::to_string(raster.values.size()) + " values");
  }
  CheckOutputPath(path, label);
  const GdalModule& gdal = Gdal(where);
  const Execution execution = ExecutionFor(threads);
  GeoTiffLayout layout;
  layout.nodata = ChooseFloat32Nodata(raster, where, execution);
  layout.tiled = raster.columns > 512 || raster.rows > 512;
  layout.threads = execution.threads;
  const std::string temporary = TemporaryName(path);
  const int slot = RegisterTemporary(temporary);  // an interrupted run removes it
  try {
    std::string error;
    void* writer = gdal.open_geotiff(temporary, raster.columns, raster.rows, raster.geotransform,
                                     raster.crs_wkt, layout, where, &error);
    if (writer == nullptr) throw InputError(error);
    // Bands of 256 rows (a row of blocks), converted by chunks: GDAL's cache
    // holds the blocks until closing, so no whole Float32 copy beside it.
    const int band_rows = std::min(raster.rows, 256);
    UninitializedVector<float> band(static_cast<std::size_t>(band_rows) * raster.columns);
    bool written = true;
    for (int row = 0; row < raster.rows && written; row += band_rows) {
      const int rows = std::min(band_rows, raster.rows - row);
      const int64_t n = static_cast<int64_t>(rows) * raster.columns;
      const double* in = raster.values.data() + static_cast<std::size_t>(row) * raster.columns;
      ForEachChunk(execution, n, ChunksFor(n, int64_t{1} << 16), [&](int, int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) {
          band[i] = std::isfinite(in[i]) ? static_cast<float>(in[i]) : layout.nodata;
        }
      });
      written = gdal.write_geotiff_floats(writer, 0, row, raster.columns, rows, band.data(), &error);
    }
    // Closing compresses the blocks on GDAL's threads: for the serial-fraction
    // measurement a region as wide as the tiles (one for a small striped file).
    const int64_t tiles =
        layout.tiled ? ((int64_t{raster.columns} + 255) / 256) * ((int64_t{raster.rows} + 255) / 256) : 1;
    bool closed = false;
    std::string close_error;
    RunSpreadByLibrary(static_cast<int>(std::min<int64_t>(tiles, kMaxChunks)),
                       [&] { closed = gdal.close_geotiff(writer, &close_error); });
    if (!written) throw InputError(error);
    if (!closed) throw InputError(close_error);
    if (std::rename(temporary.c_str(), path.c_str()) != 0) {
      Fail(where, std::string("cannot rename the temporary file: ") + std::strerror(errno));
    }
  } catch (...) {
    std::remove(temporary.c_str());
    UnregisterTemporary(slot);
    throw;
  }
  UnregisterTemporary(slot);
}

GeoTiffStreamWriter::GeoTiffStreamWriter(const std::string& path, int columns, int rows,
                                         const std::array<double, 6>& geotransform,
                                         const std::string& crs_wkt, const std::string& label)
    : path_(path), where_(label + ": '" + path + "'") {
  if (columns <= 0 || rows <= 0) {
    Fail(where_, "raster of " + std::to_string(columns) + " x " + std::to_string(rows) + " cells");
  }
  CheckOutputPath(path, label);
  const GdalModule& gdal = Gdal(where_);
  temporary_ = TemporaryName(path);
  slot_ = RegisterTemporary(temporary_);  // an interrupted run removes it
  std::string error;
  writer_ = gdal.open_geotiff(temporary_, columns, rows, geotransform, crs_wkt, GeoTiffLayout{}, where_, &error);
  if (writer_ == nullptr) {
    std::remove(temporary_.c_str());
    UnregisterTemporary(slot_);
    slot_ = -1;
    throw InputError(error);
  }
}

GeoTiffStreamWriter::~GeoTiffStreamWriter() {
  if (slot_ < 0) return;  // finished, or never opened
  std::string ignored;
  if (writer_ != nullptr) Gdal(where_).close_geotiff(writer_, &ignored);
  std::remove(temporary_.c_str());
  UnregisterTemporary(slot_);
}

void GeoTiffStreamWriter::Write(int column, int row, int columns, int rows, const double* values,
                                std::size_t count) {
  if (count != static_cast<std::size_t>(columns) * rows) {
    Fail(where_, "a window of " + std::to_string(columns) + " x " + std::to_string(rows) +
                     " cells has " + std::to_string(count) + " values");
  }
  std::string error;
  if (!Gdal(where_).write_geotiff_window(writer_, column, row, columns, rows, values, &error)) {
    throw InputError(error);
  }
}

void GeoTiffStreamWriter::Finish() {
  std::string error;
  void* writer = writer_;
  writer_ = nullptr;  // closed below whatever happens
  if (!Gdal(where_).close_geotiff(writer, &error)) throw InputError(error);
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    Fail(where_, std::string("cannot rename the temporary file: ") + std::strerror(errno));
  }
  UnregisterTemporary(slot_);
  slot_ = -1;
}

bool IsRasterPath(const std::string& path) {
  static const char* const kExtensions[] = {".tif", ".tiff", ".vrt", ".asc",  ".img", ".bil",
                                            ".hgt", ".dem",  ".nc",  ".gpkg", ".flt"};
  const std::string ext = io_internal::Extension(path);
  for (const char* known : kExtensions) {
    if (ext == known) return true;
  }
  return false;
}

}  // namespace surfreg
