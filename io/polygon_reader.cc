#include "io/polygon_reader.h"

#include <algorithm>
#include <cctype>

#include "measure/input_error.h"
#include "io/gdal_module.h"
#include "io/surface_reader_internal.h"

namespace surfreg {

std::vector<std::array<double, 2>> ReadPolygon(const std::string& path) {
  return ParsePolygon(io_internal::ReadFile(path), path);
}

std::vector<std::array<double, 2>> ParsePolygon(std::string_view data, const std::string& path) {
  std::vector<MaskRing> rings = ParseMaskText(data, path);
  if (rings.size() != 1) {
    io_internal::Fail(path, 0, "expected one polygon, found " + std::to_string(rings.size()) +
                                   " rings (separated by '>' lines)");
  }
  return std::move(rings[0]);
}

std::vector<MaskRing> ParseMaskText(std::string_view data, const std::string& path) {
  using io_internal::Fail;
  std::vector<MaskRing> rings(1);
  const auto close = [&](int line) {
    MaskRing& ring = rings.back();
    if (ring.size() > 3 && ring.front() == ring.back()) ring.pop_back();
    if (ring.size() < 3) {
      Fail(path, line,
           (rings.size() > 1 ? "ring " + std::to_string(rings.size()) + ": " : std::string()) +
               "a mask polygon needs at least 3 vertices, found " + std::to_string(ring.size()));
    }
  };
  io_internal::LineCursor cursor(data);
  std::string_view line;
  while (cursor.Next(&line)) {
    std::string_view rest = io_internal::StripComment(line);
    std::string_view token[3];
    int count = 0;
    while (count < 3 && io_internal::NextToken(&rest, &token[count])) ++count;
    if (count == 0) continue;
    if (count == 1 && token[0] == ">") {  // a new ring
      if (!rings.back().empty()) {
        close(cursor.line());
        rings.emplace_back();
      }
      continue;
    }
    if (count != 2) {
      Fail(path, cursor.line(),
           std::string("expected one vertex 'x y' (2 numbers) or '>', found ") +
               (count > 2 ? "more" : "1"));
    }
    std::array<double, 2> vertex;
    for (int k = 0; k < 2; ++k) {
      const io_internal::NumberStatus status = io_internal::ParseNumber(token[k], &vertex[k]);
      io_internal::CheckNumber(status, vertex[k], token[k], k == 0 ? "x" : "y", path,
                               cursor.line());
    }
    rings.back().push_back(vertex);
  }
  if (rings.size() > 1 && rings.back().empty()) rings.pop_back();  // a trailing '>'
  close(0);
  return rings;
}

bool IsVectorMaskPath(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return false;
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* known :
       {"gpkg", "shp", "geojson", "json", "kml", "gml", "fgb", "sqlite", "gmt", "tab", "mif"}) {
    if (ext == known) return true;
  }
  return false;
}

MaskFile ReadMask(const std::string& path, const std::string& layer) {
  MaskFile file;
  std::vector<std::string> names;
  if (IsVectorMaskPath(path)) {
    VectorRings read;
    std::string error;
    if (!Gdal(path).read_vector_rings(path, layer, &read, &error)) throw InputError(error);
    file.rings = std::move(read.rings);
    file.crs_wkt = std::move(read.crs_wkt);
    names = std::move(read.names);
  } else {
    if (!layer.empty()) {
      throw InputError(path + ": a layer ('" + layer +
                       "') applies to vector files only (.gpkg, .shp, .geojson, ...)");
    }
    file.rings = ParseMaskText(io_internal::ReadFile(path), path);
    for (std::size_t r = 0; r < file.rings.size(); ++r) {
      names.push_back(file.rings.size() == 1 ? "mask polygon" : "ring " + std::to_string(r + 1));
    }
  }
  std::string error;
  if (!ValidMaskRings(file.rings, [&names](std::size_t r) { return names[r]; }, &error)) {
    throw InputError(path + ": " + error);
  }
  return file;
}

}  // namespace surfreg
