#pragma once
// Reading height-field samples z = F(x, y) from point files.
//
// Formats (chosen by file extension, case-insensitive):
//   .xyz .txt .csv  One point per line: "x y z" or "x y z weight", separated
//                   by whitespace and/or one ',' or ';'. '#' starts a comment
//                   (whole line or trailing); blank lines are skipped. The
//                   first non-comment line is skipped as a header if its
//                   first token is not a number (e.g. "x,y,z" or "X Y Z
//                   weight"). Every data line must have the same count (3 or
//                   4, or any with ReadOptions::columns, which picks x, y, z
//                   [, weight] by header name or position); the weight must
//                   be >= 0. Empty fields ("1,,2") are errors.
//   .las            LAS 1.0-1.4, point data record formats 0-10: x, y, z
//                   with the header's scale and offset; ReadOptions::classes
//                   filters by classification; the CRS comes from the OGC
//                   WKT VLR or the GeoTIFF keys' EPSG code. LAZ (.laz, or
//                   compressed points) is refused: decompress it first.
//   .ply            ascii or binary_little_endian 1.0 (binary_big_endian is
//                   rejected). Any elements and properties, including list
//                   properties and elements before "vertex", are skipped
//                   correctly. Vertex properties x, y, z are required; a
//                   property named exactly "weight" is read as the per-point
//                   weight (no other name, e.g. quality or confidence, is).
//   .off            OFF, COFF, NOFF or NCOFF (ascii): the first 3 numbers of
//                   each vertex line; faces are ignored.
//   .obj            "v x y z [w or colour...]" lines: the first 3 numbers;
//                   every other line type is ignored. OBJ has no weights.
//   .tif .tiff .vrt .asc .img .bil .hgt .dem .nc .gpkg .flt
//                   GDAL rasters: band 1, one sample at the centre of every
//                   valid cell (nodata, masked, NaN cells skipped); see
//                   io/raster_io.h for bands, windows and the pixel
//                   convention. Messages are "<name>: <what is wrong>".
//
// Coordinates are kept in input units and stored relative to a local origin
// (see MakeSurface in measure/surface.h), so UTM-sized values keep their
// precision. The result has passed ValidateSurface.
//
// Error policy: every problem throws surfreg::InputError with a single-line
// message "<name>:<line>: <what is wrong>" when a line is to blame (text
// formats, PLY header and ascii body) or "<name>: <what is wrong>" otherwise
// (e.g. "b.ply: file ends after 10 of 200 vertices"). Numbers must parse
// completely ("1.5m" is an error, not 1.5); NaN and infinite values are
// errors. Nothing is silently dropped. A file too large for the memory the
// run has is refused before it is read (see CheckPointCount).
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "measure/surface.h"

namespace surfreg {

struct ReadOptions {
  double origin_step = 1.0;  // passed to MakeSurface: origin rounded to this
  // The memory a run may use, bytes, against which the number of points is
  // checked (CheckPointCount); 0 = what the system has (AvailableMemoryBytes).
  uint64_t memory_limit_bytes = 0;
  // LAS: keep only the points of these classifications (0-255); empty = all.
  // Any other format with a non-empty list is an InputError (no classes).
  std::vector<int> classes;
  // Text clouds: the columns of x, y, z and optionally the weight, each a
  // 1-based position ("3") or a name in the header line (case-insensitive);
  // other columns are ignored. Empty = 3 columns (x y z) or 4 (x y z weight).
  // Any other format with a non-empty list is an InputError.
  std::vector<std::string> columns;
  // Text clouds are parsed in chunks of lines on this many threads (0 = every
  // core); the points and any error are the same on any number.
  int threads = 1;
};

// Peak memory of a whole run per input point, bytes, with margin: reading,
// triangulation, location, overlay and the registration pyramid (measured:
// 465 MiB for `measure` on two 1e6-point clouds).
constexpr uint64_t kBytesPerPoint = 500;

// The memory this process may use, bytes: the least of MemAvailable
// (/proc/meminfo, or the physical memory if that is missing), the cgroup's
// memory limit and RLIMIT_AS, each when set.
uint64_t AvailableMemoryBytes();

// Refuses a file whose `points` (counted, or declared by a PLY/OFF header)
// would need more memory than the run has (options.memory_limit_bytes, or
// AvailableMemoryBytes() if 0), before anything is allocated for them:
// throws InputError "<name>: N points need about X GiB, more than the Y GiB
// available". The readers call it; exposed for the raster and mesh readers.
void CheckPointCount(uint64_t points, const std::string& name, const ReadOptions& options);

// Reads `path`, choosing the format by its extension (see above). `path` is
// used as the name in messages and as Surface::source. A non-null `crs` is
// set to the file's CRS as text ParseCrs (terrain/geo_frame.h) reads: a LAS
// file's WKT or "EPSG:n", a raster's WKT; "" when the file has none (the
// other point formats never have one). A raster is read on
// options.threads threads (io/raster_io.h); a non-null `grid` then receives
// its size, geotransform and CRS (values empty: the samples are the valid
// cells, Surface::raster_cell), and is left untouched for other formats.
struct Raster;
Surface ReadSurface(const std::string& path, const ReadOptions& options = {},
                    std::string* crs = nullptr, Raster* grid = nullptr);

// One reader per format, reading `in` to its end. `name` is used in messages
// and as Surface::source. Binary PLY needs a stream opened in binary mode.
Surface ReadXyz(std::istream& in, const std::string& name, const ReadOptions& options = {});
Surface ReadPly(std::istream& in, const std::string& name, const ReadOptions& options = {});
Surface ReadOff(std::istream& in, const std::string& name, const ReadOptions& options = {});
Surface ReadObj(std::istream& in, const std::string& name, const ReadOptions& options = {});
Surface ReadLas(std::istream& in, const std::string& name, const ReadOptions& options = {},
                std::string* crs = nullptr);

}  // namespace surfreg
