#pragma once
// Reading triangle meshes (measure/mesh.h; for faces, faces/face_frame.h), and the text
// form of the face orientation shared by the face commands.
//
// Formats (by file extension, case-insensitive):
//   .off  OFF, COFF, NOFF, NCOFF (ascii): the vertex lines' first 3 numbers,
//         then one face per line "n i1 ... in [colour...]"; '#' comments.
//   .ply  ascii or binary_little_endian 1.0: vertex properties x, y, z, and
//         the "face" element's list property vertex_indices (or
//         vertex_index); other elements and properties are skipped.
//   .obj  "v x y z" and "f a b c ..." lines; face corners may be v, v/vt,
//         v//vn or v/vt/vn, indices 1-based or negative (relative to the
//         vertices read so far); other lines are ignored.
//   any other format ReadSurface knows (.xyz .txt .csv, GDAL rasters): a
//         point cloud (a Mesh without triangles).
// Polygons with more than 3 corners are split into a fan of triangles from
// their first corner. Coordinates are kept as in the file (no local origin).
//
// Errors: InputError "<file>:<line>: <what>" where a line is to blame (a face
// index out of range, a face with fewer than 3 corners, a number that does
// not parse) and "<file>: <what>" otherwise (e.g. the file ends after 10 of
// 200 faces; a face of a binary PLY names its face number).
#include <string>
#include <string_view>

#include "measure/mesh.h"

namespace surfreg {

// Reads the mesh at `path` (see above); Mesh::source = path.
Mesh ReadMesh(const std::string& path);

// True for the extensions ReadMesh reads with triangles (.off .ply .obj).
bool IsMeshPath(const std::string& path);

// A whole .off, .ply or .obj file already in memory, the format chosen by
// `name`'s extension (also used in messages); the errors of ReadMesh.
Mesh ParseMesh(std::string_view data, const std::string& name);

}  // namespace surfreg
