#pragma once
// Writing height-field samples back to files, in input coordinates (each
// stored sample plus the surface's origin), so that a written file reads
// back (io/surface_reader.h) as the same points.
//
//   .xyz .txt  "x y z" per line (or "x y z weight" when the surface has
//              weights), shortest decimal text that reads back as the same
//              double; '#' comment lines first.
//   .ply       binary_little_endian 1.0, element vertex with properties
//              double x, y, z (and double weight when present); comments
//              in the header.
//   .las       LAS 1.2, point format 0 (io/las_writer.h): no comments,
//              no weights.
#include <string>
#include <vector>

#include "measure/surface.h"

namespace surfreg {

// True if WriteSurface knows the extension of `path` (case-insensitive).
bool IsWritableSurfacePath(const std::string& path);

// The file contents. `comments` are single lines without the leading '#'
// (line breaks in them are replaced by blanks).
std::string SurfaceToXyz(const Surface& surface, const std::vector<std::string>& comments = {});
std::string SurfaceToPly(const Surface& surface, const std::vector<std::string>& comments = {});

// Writes `surface` to `path` atomically (io/atomic_file.h), the format
// chosen by the extension. Throws InputError starting with `label` for an
// unknown extension or a file that cannot be written.
void WriteSurface(const std::string& path, const Surface& surface, const std::string& label,
                  const std::vector<std::string>& comments = {});

}  // namespace surfreg
