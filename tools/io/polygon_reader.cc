#include "tools/io/polygon_reader.h"

#include "tools/io/surface_reader_internal.h"

namespace surfreg {

std::vector<std::array<double, 2>> ReadPolygon(const std::string& path) {
  return ParsePolygon(io_internal::ReadFile(path), path);
}

std::vector<std::array<double, 2>> ParsePolygon(std::string_view data, const std::string& path) {
  using io_internal::Fail;
  std::vector<std::array<double, 2>> polygon;
  io_internal::LineCursor cursor(data);
  std::string_view line;
  while (cursor.Next(&line)) {
    std::string_view rest = io_internal::StripComment(line);
    std::string_view token[3];
    int count = 0;
    while (count < 3 && io_internal::NextToken(&rest, &token[count])) ++count;
    if (count == 0) continue;
    if (count != 2) {
      Fail(path, cursor.line(),
           std::string("expected one vertex 'x y' (2 numbers), found ") +
               (count > 2 ? "more" : "1"));
    }
    std::array<double, 2> vertex;
    for (int k = 0; k < 2; ++k) {
      const io_internal::NumberStatus status = io_internal::ParseNumber(token[k], &vertex[k]);
      io_internal::CheckNumber(status, vertex[k], token[k], k == 0 ? "x" : "y", path,
                               cursor.line());
    }
    polygon.push_back(vertex);
  }
  if (polygon.size() > 3 && polygon.front() == polygon.back()) polygon.pop_back();
  if (polygon.size() < 3) {
    Fail(path, 0,
         "a mask polygon needs at least 3 vertices, found " + std::to_string(polygon.size()));
  }
  return polygon;
}

}  // namespace surfreg
