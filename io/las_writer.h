#pragma once
// Writing LAS point clouds (ASPRS LAS 1.2 and later; io/surface_reader.h
// reads them).
//
// - SurfaceToLas: a new LAS 1.2 file, point data record format 0, from a
//   surface's samples in input coordinates. Per axis the offset is the
//   smallest coordinate and the scale the power of ten that spans the
//   extent in at most 2^30 steps (each coordinate within 5e-9 of the
//   extent of its input value); return 1 of 1, classification 0 ("never classified"); no CRS
//   record and no weights (LAS has no field for them).
// - MovedLas: an existing LAS file with every point record moved by a rigid
//   motion: all its points (every class, also those a `classes` filter left
//   out of the surface), every other byte as it was (attributes, GPS time,
//   colours, extra bytes, VLRs and EVLRs, so the CRS record too); the
//   header's bounds follow the points, its offsets are the moved bounds'
//   minima, and a scale is made coarser (by powers of ten) only on an axis
//   whose moved extent no longer fits 32-bit integers at it.
#include <array>
#include <string>
#include <string_view>

#include "measure/surface.h"

namespace surfreg {

// True if `path` ends in .las (any case).
bool IsLasPath(const std::string& path);

// The file's bytes. Throws InputError (starting with `label`) for more
// points than LAS 1.2 can count (2^32 - 1).
std::string SurfaceToLas(const Surface& surface, const std::string& label);

// A 4 x 4 rigid motion, row-major, in the file's coordinates.
using LasMotion = std::array<double, 16>;

// `las`: the bytes of a LAS file named `name` (for messages). Throws
// InputError for a file whose header or point records do not fit its size.
std::string MovedLas(std::string_view las, const LasMotion& matrix, const std::string& name);

// MovedLas of the file `input`, written atomically to `output`.
void WriteMovedLas(const std::string& input, const LasMotion& matrix, const std::string& output,
                   const std::string& label);

}  // namespace surfreg
