// Triangle meshes from OFF, PLY and OBJ files (faces kept, polygons split
// into fans), every other surface format as a point cloud; and the text form
// of a face orientation.
#include "io/mesh_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "measure/input_error.h"
#include "io/surface_reader.h"
#include "io/surface_reader_internal.h"

namespace surfreg {
namespace {

using io_internal::Fail;
using io_internal::LineCursor;
using io_internal::NextToken;
using io_internal::Quote;

// Appends the fan (c0, c[i], c[i+1]) of one polygon to mesh->triangles after
// checking its corners (0-based) against the vertex count.
void AddPolygon(const std::vector<int64_t>& corners, std::size_t vertex_count,
                const std::string& name, std::size_t line, const std::string& what, Mesh* mesh) {
  if (corners.size() < 3) {
    Fail(name, line,
         what + "has " + std::to_string(corners.size()) + " vertices (a face needs at least 3)");
  }
  for (const int64_t c : corners) {
    if (c < 0 || static_cast<uint64_t>(c) >= vertex_count) {
      Fail(name, line,
           what + "vertex index " + std::to_string(c) + " is out of range (the mesh has " +
               std::to_string(vertex_count) + " vertices, 0-based)");
    }
  }
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
    mesh->triangles.push_back({static_cast<int32_t>(corners[0]), static_cast<int32_t>(corners[i]),
                               static_cast<int32_t>(corners[i + 1])});
  }
}

// A whole token as a (signed) integer.
bool ParseInteger(std::string_view token, int64_t* value) {
  double number = 0.0;
  if (io_internal::ParseNumber(token, &number) != io_internal::NumberStatus::kOk) return false;
  if (!(std::fabs(number) < 9.0e15) || number != std::floor(number)) return false;
  if (token.find_first_of(".eE") != std::string_view::npos) return false;
  *value = static_cast<int64_t>(number);
  return true;
}

// Parses x y z (the first 3 tokens) of `line`.
std::array<double, 3> ParsePoint(std::string_view line, const std::string& what,
                                 const std::string& name, std::size_t number) {
  static const char* const kAxis[] = {"x", "y", "z"};
  std::array<double, 3> p{};
  std::string_view token;
  for (int k = 0; k < 3; ++k) {
    if (!NextToken(&line, &token)) {
      Fail(name, number, what + "expected 3 numbers (x y z), found " + std::to_string(k));
    }
    const io_internal::NumberStatus status = io_internal::ParseNumber(token, &p[k]);
    io_internal::CheckNumber(status, p[k], token, (what + kAxis[k]).c_str(), name, number);
  }
  return p;
}

// --- OFF --------------------------------------------------------------------

bool NextContentLine(LineCursor* cursor, std::string_view* line) {
  while (cursor->Next(line)) {
    *line = io_internal::StripComment(*line);
    std::string_view rest = *line, token;
    if (NextToken(&rest, &token)) return true;
  }
  return false;
}

Mesh ParseOffMesh(std::string_view data, const std::string& name) {
  LineCursor cursor(data);
  std::string_view line, token;
  if (!NextContentLine(&cursor, &line)) Fail(name, 0, "empty file");
  NextToken(&line, &token);
  if (token != "OFF" && token != "COFF" && token != "NOFF" && token != "NCOFF") {
    Fail(name, cursor.line(),
         "expected the header OFF, COFF, NOFF or NCOFF, found " + Quote(token));
  }
  std::string_view rest = line;
  if (!NextToken(&rest, &token)) {
    if (!NextContentLine(&cursor, &line)) Fail(name, 0, "file ends before the counts line");
  }
  unsigned long long counts[2] = {0, 0};
  for (unsigned long long& count : counts) {
    if (!NextToken(&line, &token) || !io_internal::ParseCount(token, &count)) {
      Fail(name, cursor.line(), "expected the counts 'vertices faces edges'");
    }
  }
  Mesh mesh;
  mesh.source = name;
  mesh.vertices.reserve(std::min<unsigned long long>(counts[0], data.size() / 6));
  for (unsigned long long i = 0; i < counts[0]; ++i) {
    if (!NextContentLine(&cursor, &line)) {
      Fail(name, 0,
           "file ends after " + std::to_string(i) + " of " + std::to_string(counts[0]) +
               " vertices");
    }
    mesh.vertices.push_back(
        ParsePoint(line, "vertex " + std::to_string(i) + ": ", name, cursor.line()));
  }
  std::vector<int64_t> corners;
  for (unsigned long long f = 0; f < counts[1]; ++f) {
    if (!NextContentLine(&cursor, &line)) {
      Fail(name, 0,
           "file ends after " + std::to_string(f) + " of " + std::to_string(counts[1]) + " faces");
    }
    const std::string what = "face " + std::to_string(f) + ": ";
    unsigned long long n = 0;
    NextToken(&line, &token);
    if (!io_internal::ParseCount(token, &n)) {
      Fail(name, cursor.line(), what + "bad vertex count " + Quote(token));
    }
    corners.clear();
    for (unsigned long long j = 0; j < n; ++j) {
      int64_t index = 0;
      if (!NextToken(&line, &token)) {
        Fail(name, cursor.line(),
             what + "the line ends after " + std::to_string(j) + " of " + std::to_string(n) +
                 " vertex indices");
      }
      if (!ParseInteger(token, &index)) {
        Fail(name, cursor.line(), what + "vertex index is not an integer: " + Quote(token));
      }
      corners.push_back(index);
    }
    // Anything after the indices is a colour: ignored.
    AddPolygon(corners, mesh.vertices.size(), name, cursor.line(), what, &mesh);
  }
  return mesh;
}

// --- OBJ --------------------------------------------------------------------

// One face corner "v", "v/vt", "v//vn" or "v/vt/vn" → 0-based vertex index.
int64_t ObjCorner(std::string_view token, std::size_t vertex_count, const std::string& name,
                  std::size_t line) {
  const std::string_view head = token.substr(0, token.find('/'));
  int64_t index = 0;
  if (!ParseInteger(head, &index) || index == 0) {
    Fail(name, line, "bad face vertex " + Quote(token) + " (expected a non-zero integer index)");
  }
  // Negative indices count back from the last vertex read so far.
  return index > 0 ? index - 1 : static_cast<int64_t>(vertex_count) + index;
}

Mesh ParseObjMesh(std::string_view data, const std::string& name) {
  LineCursor cursor(data);
  std::string_view line, keyword, token;
  Mesh mesh;
  mesh.source = name;
  std::vector<int64_t> corners;
  std::size_t faces = 0;
  while (cursor.Next(&line)) {
    line = io_internal::StripComment(line);
    if (!NextToken(&line, &keyword)) continue;
    if (keyword == "v") {
      mesh.vertices.push_back(ParsePoint(line, "", name, cursor.line()));
    } else if (keyword == "f") {
      corners.clear();
      while (NextToken(&line, &token)) {
        corners.push_back(ObjCorner(token, mesh.vertices.size(), name, cursor.line()));
      }
      AddPolygon(corners, mesh.vertices.size(), name, cursor.line(),
                 "face " + std::to_string(faces++) + ": ", &mesh);
    }
  }
  return mesh;
}

// --- PLY --------------------------------------------------------------------

// The index of the face element's vertex list property (-1 if there is no
// face element); throws if a face element has no usable list.
int FaceListProperty(const io_internal::PlyElement& face, const std::string& name) {
  for (std::size_t k = 0; k < face.properties.size(); ++k) {
    const io_internal::PlyProperty& p = face.properties[k];
    if (p.name != "vertex_indices" && p.name != "vertex_index") continue;
    if (!p.is_list || p.type == io_internal::PlyType::kFloat32 ||
        p.type == io_internal::PlyType::kFloat64) {
      Fail(name, p.line, "face property '" + p.name + "' must be a list of integers");
    }
    return static_cast<int>(k);
  }
  Fail(name, face.line, "the face element has no list property vertex_indices or vertex_index");
}

// Reads one binary face instance; its vertex list goes to *corners.
bool ReadBinaryFace(const io_internal::PlyElement& face, int list, io_internal::PlyByteReader* in,
                    std::vector<int64_t>* corners) {
  corners->clear();
  for (std::size_t k = 0; k < face.properties.size(); ++k) {
    const io_internal::PlyProperty& p = face.properties[k];
    double value = 0.0;
    if (!p.is_list) {
      if (!in->Skip(io_internal::PlyTypeSize(p.type))) return false;
      continue;
    }
    if (!in->Read(p.count_type, &value)) return false;
    if (value < 0.0) value = 0.0;  // a negative length: a "face with 0 vertices" below
    const auto n = static_cast<unsigned long long>(value);
    if (static_cast<int>(k) != list) {
      if (!in->Skip(n * io_internal::PlyTypeSize(p.type))) return false;
      continue;
    }
    for (unsigned long long j = 0; j < n; ++j) {
      if (!in->Read(p.type, &value)) return false;
      corners->push_back(static_cast<int64_t>(value));
    }
  }
  return true;
}

// Parses one ascii face line; its vertex list goes to *corners.
void ParseAsciiFace(std::string_view line, const io_internal::PlyElement& face, int list,
                    const std::string& what, const std::string& name, std::size_t number,
                    std::vector<int64_t>* corners) {
  corners->clear();
  std::string_view token;
  for (std::size_t k = 0; k < face.properties.size(); ++k) {
    const io_internal::PlyProperty& p = face.properties[k];
    if (!NextToken(&line, &token)) {
      Fail(name, number, what + "the line ends before property '" + p.name + "'");
    }
    if (!p.is_list) continue;
    unsigned long long n = 0;
    if (!io_internal::ParseCount(token, &n)) {
      Fail(name, number, what + "bad length of list '" + p.name + "': " + Quote(token));
    }
    for (unsigned long long j = 0; j < n; ++j) {
      int64_t index = 0;
      if (!NextToken(&line, &token)) {
        Fail(name, number, what + "the line ends inside list '" + p.name + "'");
      }
      if (static_cast<int>(k) != list) continue;
      if (!ParseInteger(token, &index)) {
        Fail(name, number, what + "vertex index is not an integer: " + Quote(token));
      }
      corners->push_back(index);
    }
  }
}

std::string Truncated(const io_internal::PlyElement& element, unsigned long long done) {
  return "file ends in element '" + element.name + "' after " + std::to_string(done) + " of " +
         std::to_string(element.count);
}

// Walks every element in header order: vertices into mesh->vertices, faces
// (checked once all elements are read, since a face may come before the
// vertices) into polygons.
Mesh ParsePlyMesh(std::string_view data, const std::string& name) {
  const io_internal::PlyHeader header = io_internal::ParsePlyHeader(data, name);
  const auto& elements = header.elements;
  std::size_t vertex = 0;
  while (vertex < elements.size() && elements[vertex].name != "vertex") ++vertex;
  if (vertex == elements.size()) Fail(name, 0, "no 'vertex' element in the PLY header");
  const std::vector<int> roles = io_internal::PlyVertexRoles(elements[vertex], name);
  Mesh mesh;
  mesh.source = name;
  std::vector<std::vector<int64_t>> polygons;
  std::vector<std::size_t> polygon_line;  // 0 for binary
  const std::string_view body = data.substr(header.body_offset);
  io_internal::PlyByteReader reader(body);
  LineCursor cursor(body, header.body_line);
  std::string_view line;
  double value[4] = {0, 0, 0, 0};
  std::vector<int64_t> corners;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const io_internal::PlyElement& element = elements[e];
    const bool is_face = element.name == "face";
    const int list = is_face ? FaceListProperty(element, name) : -1;
    for (unsigned long long i = 0; i < element.count; ++i) {
      if (header.binary) {
        const bool ok =
            e == vertex ? io_internal::ReadPlyBinaryInstance(element, &roles, &reader, value, name)
            : is_face   ? ReadBinaryFace(element, list, &reader, &corners)
                      : io_internal::ReadPlyBinaryInstance(element, nullptr, &reader, value, name);
        if (!ok) Fail(name, 0, Truncated(element, i));
        if (e == vertex) io_internal::CheckPlyVertex(value, false, i, name, 0);
      } else {
        if (!io_internal::NextPlyDataLine(&cursor, &line)) Fail(name, 0, Truncated(element, i));
        if (e == vertex) {
          io_internal::ParsePlyAsciiVertex(line, element, roles, i, value, name, cursor.line());
        } else if (is_face) {
          ParseAsciiFace(line, element, list, "face " + std::to_string(i) + ": ", name,
                         cursor.line(), &corners);
        }
      }
      if (e == vertex) mesh.vertices.push_back({value[0], value[1], value[2]});
      if (is_face) {
        polygons.push_back(corners);
        polygon_line.push_back(header.binary ? 0 : cursor.line());
      }
    }
  }
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    AddPolygon(polygons[f], mesh.vertices.size(), name, polygon_line[f],
               "face " + std::to_string(f) + ": ", &mesh);
  }
  return mesh;
}

}  // namespace

bool IsMeshPath(const std::string& path) {
  const std::string ext = io_internal::Extension(path);
  return ext == ".off" || ext == ".ply" || ext == ".obj";
}

Mesh ParseMesh(std::string_view data, const std::string& name) {
  const std::string ext = io_internal::Extension(name);
  if (!IsMeshPath(name)) Fail(name, 0, "not a mesh format (expected .off, .ply or .obj)");
  Mesh mesh = ext == ".off"   ? ParseOffMesh(data, name)
              : ext == ".ply" ? ParsePlyMesh(data, name)
                              : ParseObjMesh(data, name);
  if (mesh.vertices.empty()) Fail(name, 0, "no vertices");
  if (mesh.vertices.size() > static_cast<std::size_t>(INT32_MAX)) {
    Fail(name, 0, "too many vertices for 32-bit triangle indices");
  }
  return mesh;
}

Mesh ReadMesh(const std::string& path) {
  if (IsMeshPath(path)) return ParseMesh(io_internal::ReadFile(path), path);
  Mesh mesh;
  // Clouds: ReadSurface keeps points relative to a local origin; the mesh
  // keeps input coordinates.
  const Surface surface = ReadSurface(path);
  mesh.source = path;
  mesh.vertices.reserve(surface.size());
  for (std::size_t i = 0; i < surface.size(); ++i) {
    mesh.vertices.push_back({surface.xy[i].x + surface.origin[0],
                             surface.xy[i].y + surface.origin[1],
                             surface.z[i] + surface.origin[2]});
  }
  return mesh;
}

}  // namespace surfreg
