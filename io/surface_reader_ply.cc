// PLY (ascii and binary_little_endian 1.0): the vertex element's x, y, z and
// optional weight; every other element and property is parsed only to be
// skipped, so that elements before "vertex" and list properties work.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/surface_reader_internal.h"

namespace surfreg::io_internal {
namespace {

bool ParsePlyType(std::string_view word, PlyType* type) {
  struct Entry {
    const char* name;
    const char* alias;
    PlyType type;
  };
  static const Entry kTypes[] = {
      {"char", "int8", PlyType::kInt8},        {"uchar", "uint8", PlyType::kUint8},
      {"short", "int16", PlyType::kInt16},     {"ushort", "uint16", PlyType::kUint16},
      {"int", "int32", PlyType::kInt32},       {"uint", "uint32", PlyType::kUint32},
      {"float", "float32", PlyType::kFloat32}, {"double", "float64", PlyType::kFloat64},
  };
  for (const Entry& entry : kTypes) {
    if (word == entry.name || word == entry.alias) {
      *type = entry.type;
      return true;
    }
  }
  return false;
}

}  // namespace

std::size_t PlyTypeSize(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

namespace {

bool IsFloatType(PlyType type) { return type == PlyType::kFloat32 || type == PlyType::kFloat64; }

std::string_view TrimCr(std::string_view line) {
  while (!line.empty() && IsBlank(line.back())) line.remove_suffix(1);
  return line;
}

void ParseFormat(std::string_view rest, const std::string& name, std::size_t line,
                 PlyHeader* header) {
  std::string_view format, version;
  if (!NextToken(&rest, &format) || !NextToken(&rest, &version)) {
    Fail(name, line, "expected 'format <encoding> 1.0'");
  }
  double number = 0.0;
  if (ParseNumber(version, &number) != NumberStatus::kOk || number != 1.0) {
    Fail(name, line, "unsupported PLY version " + Quote(version) + " (expected 1.0)");
  }
  if (format == "binary_big_endian") {
    Fail(name, line, "binary_big_endian PLY is not supported (use ascii or binary_little_endian)");
  }
  if (format != "ascii" && format != "binary_little_endian") {
    Fail(name, line, "unknown PLY format " + Quote(format));
  }
  header->has_format = true;
  header->binary = format == "binary_little_endian";
}

PlyElement ParseElement(std::string_view rest, const std::string& name, std::size_t line) {
  PlyElement element;
  element.line = line;
  std::string_view element_name, count;
  if (!NextToken(&rest, &element_name) || !NextToken(&rest, &count)) {
    Fail(name, line, "expected 'element <name> <count>'");
  }
  if (!ParseCount(count, &element.count)) {
    Fail(name, line, "element count is not a non-negative integer: " + Quote(count));
  }
  element.name = std::string(element_name);
  return element;
}

PlyProperty ParseProperty(std::string_view rest, const std::string& name, std::size_t line) {
  PlyProperty property;
  property.line = line;
  std::string_view word, property_name;
  if (!NextToken(&rest, &word)) Fail(name, line, "property has no type");
  if (word == "list") {
    property.is_list = true;
    std::string_view count_type;
    if (!NextToken(&rest, &count_type) || !ParsePlyType(count_type, &property.count_type) ||
        IsFloatType(property.count_type)) {
      Fail(name, line, "list length type must be an integer PLY type, found " + Quote(count_type));
    }
    if (!NextToken(&rest, &word)) Fail(name, line, "list property has no item type");
  }
  if (!ParsePlyType(word, &property.type)) {
    Fail(name, line, "unknown PLY property type " + Quote(word));
  }
  if (!NextToken(&rest, &property_name)) Fail(name, line, "property has no name");
  property.name = std::string(property_name);
  return property;
}

void ParseHeaderLine(std::string_view line, const std::string& name, std::size_t number,
                     PlyHeader* header) {
  std::string_view keyword;
  if (!NextToken(&line, &keyword)) return;  // a blank line: harmless
  if (keyword == "comment" || keyword == "obj_info") return;
  if (keyword == "format") {
    ParseFormat(line, name, number, header);
  } else if (keyword == "element") {
    header->elements.push_back(ParseElement(line, name, number));
  } else if (keyword == "property") {
    if (header->elements.empty()) Fail(name, number, "property before any element");
    header->elements.back().properties.push_back(ParseProperty(line, name, number));
  } else {
    Fail(name, number, "unknown PLY header line starting with " + Quote(keyword));
  }
}

}  // namespace

PlyHeader ParsePlyHeader(std::string_view data, const std::string& name) {
  LineCursor cursor(data);
  std::string_view line;
  if (!cursor.Next(&line) || TrimCr(line) != "ply") {
    Fail(name, 1, "not a PLY file (the first line must be 'ply')");
  }
  PlyHeader header;
  while (cursor.Next(&line)) {
    if (TrimCr(line) == "end_header") {
      if (!header.has_format) Fail(name, cursor.line(), "no 'format' line before end_header");
      header.body_offset = cursor.offset();
      header.body_line = cursor.line() + 1;
      return header;
    }
    ParseHeaderLine(line, name, cursor.line(), &header);
  }
  Fail(name, 0, "the header has no end_header line");
}

// What each vertex property is for: an index into {x, y, z, weight}, or -1.
std::vector<int> PlyVertexRoles(const PlyElement& vertex, const std::string& name) {
  static const char* const kRoleName[] = {"x", "y", "z", "weight"};
  std::vector<int> roles(vertex.properties.size(), -1);
  bool found[4] = {false, false, false, false};
  for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
    const PlyProperty& property = vertex.properties[k];
    for (int role = 0; role < 4; ++role) {
      if (property.name != kRoleName[role] || found[role]) continue;
      if (property.is_list) {
        Fail(name, property.line, "vertex property '" + property.name + "' must not be a list");
      }
      roles[k] = role;
      found[role] = true;
    }
  }
  for (int role = 0; role < 3; ++role) {
    if (!found[role]) {
      Fail(name, vertex.line,
           std::string("the vertex element has no property '") + kRoleName[role] + "'");
    }
  }
  return roles;
}

// Checks one vertex's values (value[3] is the weight if `has_weight`).
void CheckPlyVertex(const double* value, bool has_weight, unsigned long long index,
                    const std::string& name, std::size_t line) {
  static const char* const kRoleName[] = {"x", "y", "z", "weight"};
  const std::string prefix = "vertex " + std::to_string(index) + ": ";
  for (int role = 0; role < (has_weight ? 4 : 3); ++role) {
    CheckNumber(NumberStatus::kOk, value[role], "", (prefix + kRoleName[role]).c_str(), name, line);
  }
  if (has_weight && value[3] < 0.0) Fail(name, line, prefix + "weight is negative");
}

namespace {

std::string TruncatedMessage(unsigned long long done, unsigned long long count) {
  return "file ends after " + std::to_string(done) + " of " + std::to_string(count) + " vertices";
}

std::string TruncatedBeforeVertex(const PlyElement& element, unsigned long long done) {
  return "file ends in element '" + element.name + "' after " + std::to_string(done) + " of " +
         std::to_string(element.count) + ", before the vertices";
}

}  // namespace

std::string TruncatedAfterVertex(const PlyElement& element, unsigned long long done) {
  return "file ends in element '" + element.name + "' after " + std::to_string(done) + " of " +
         std::to_string(element.count);
}

std::string TrailingDataMessage(const std::string& what, unsigned long long vertices) {
  return what + " data after the " + std::to_string(vertices) +
         " vertices and the other elements the header declares (are its counts wrong?)";
}

// --- binary_little_endian ---------------------------------------------------

double PlyByteReader::Decode(PlyType type, uint64_t bits) {
  switch (type) {
    case PlyType::kInt8:
      return static_cast<int8_t>(static_cast<uint8_t>(bits));
    case PlyType::kUint8:
      return static_cast<uint8_t>(bits);
    case PlyType::kInt16:
      return static_cast<int16_t>(static_cast<uint16_t>(bits));
    case PlyType::kUint16:
      return static_cast<uint16_t>(bits);
    case PlyType::kInt32:
      return static_cast<int32_t>(static_cast<uint32_t>(bits));
    case PlyType::kUint32:
      return static_cast<uint32_t>(bits);
    case PlyType::kFloat32: {
      const auto word = static_cast<uint32_t>(bits);
      float f;
      std::memcpy(&f, &word, sizeof(f));
      return f;
    }
    case PlyType::kFloat64: {
      double d;
      std::memcpy(&d, &bits, sizeof(d));
      return d;
    }
  }
  return 0.0;
}

// Skips (or reads, into value[roles[k]]) one element instance. False if the
// data ends inside it.
bool ReadPlyBinaryInstance(const PlyElement& element, const std::vector<int>* roles,
                           PlyByteReader* reader, double* value, const std::string& name) {
  for (std::size_t k = 0; k < element.properties.size(); ++k) {
    const PlyProperty& property = element.properties[k];
    double scalar = 0.0;
    if (!property.is_list) {
      if (roles == nullptr || (*roles)[k] < 0) {
        if (!reader->Skip(PlyTypeSize(property.type))) return false;
      } else if (!reader->Read(property.type, &value[(*roles)[k]])) {
        return false;
      }
      continue;
    }
    if (!reader->Read(property.count_type, &scalar)) return false;
    if (scalar < 0.0) {
      Fail(name, 0,
           "element '" + element.name + "': negative length of list '" + property.name + "'");
    }
    if (!reader->Skip(static_cast<unsigned long long>(scalar) * PlyTypeSize(property.type))) {
      return false;
    }
  }
  return true;
}

namespace {

PointList ReadBinaryBody(std::string_view body, const PlyHeader& header, std::size_t vertex,
                         const std::vector<int>& roles, const std::string& name) {
  PlyByteReader reader(body);
  double value[4] = {0.0, 0.0, 0.0, 0.0};
  for (std::size_t e = 0; e < vertex; ++e) {
    const PlyElement& element = header.elements[e];
    // An element without properties takes no bytes: skipping its (maybe
    // 1e18) instances one by one would never end (found by fuzz_ply).
    if (element.properties.empty()) continue;
    for (unsigned long long i = 0; i < element.count; ++i) {
      if (!ReadPlyBinaryInstance(element, nullptr, &reader, value, name)) {
        Fail(name, 0, TruncatedBeforeVertex(element, i));
      }
    }
  }
  const PlyElement& element = header.elements[vertex];
  const bool has_weight = std::find(roles.begin(), roles.end(), 3) != roles.end();
  PointList list;
  list.points.reserve(std::min<unsigned long long>(element.count, reader.remaining() / 3));
  for (unsigned long long i = 0; i < element.count; ++i) {
    if (!ReadPlyBinaryInstance(element, &roles, &reader, value, name)) {
      Fail(name, 0, TruncatedMessage(i, element.count));
    }
    CheckPlyVertex(value, has_weight, i, name, 0);
    list.points.push_back({value[0], value[1], value[2]});
    if (has_weight) list.weight.push_back(value[3]);
  }
  // The elements after the vertices (faces, ...) must be complete, and
  // nothing but whitespace may follow them: a header whose counts are too
  // small would otherwise silently drop points.
  for (std::size_t e = vertex + 1; e < header.elements.size(); ++e) {
    const PlyElement& after = header.elements[e];
    if (after.properties.empty()) continue;  // no bytes (see above)
    for (unsigned long long i = 0; i < after.count; ++i) {
      if (!ReadPlyBinaryInstance(after, nullptr, &reader, value, name)) {
        Fail(name, 0, TruncatedAfterVertex(after, i));
      }
    }
  }
  const std::string_view rest = body.substr(body.size() - reader.remaining());
  if (rest.find_first_not_of(" \t\r\n") != std::string_view::npos) {
    Fail(name, 0, TrailingDataMessage(std::to_string(rest.size()) + " bytes of", element.count));
  }
  return list;
}

// --- ascii ------------------------------------------------------------------

}  // namespace

bool NextPlyDataLine(LineCursor* cursor, std::string_view* line) {
  while (cursor->Next(line)) {
    if (!TrimCr(*line).empty()) return true;
  }
  return false;
}

// Parses one vertex line into value[roles[k]].
void ParsePlyAsciiVertex(std::string_view line, const PlyElement& element,
                         const std::vector<int>& roles, unsigned long long index, double* value,
                         const std::string& name, std::size_t number) {
  static const char* const kRoleName[] = {"x", "y", "z", "weight"};
  const std::string prefix = "vertex " + std::to_string(index) + ": ";
  std::string_view token;
  for (std::size_t k = 0; k < element.properties.size(); ++k) {
    const PlyProperty& property = element.properties[k];
    if (!NextToken(&line, &token)) {
      Fail(name, number, prefix + "the line ends before property '" + property.name + "'");
    }
    if (property.is_list) {
      unsigned long long n = 0;
      if (!ParseCount(token, &n)) {
        Fail(name, number, prefix + "bad length of list '" + property.name + "': " + Quote(token));
      }
      for (unsigned long long j = 0; j < n; ++j) {
        if (!NextToken(&line, &token)) {
          Fail(name, number, prefix + "the line ends inside list '" + property.name + "'");
        }
      }
      continue;
    }
    double scalar = 0.0;
    const NumberStatus status = ParseNumber(token, &scalar);
    const int role = roles[k];
    if (role >= 0) {
      CheckNumber(status, scalar, token, (prefix + kRoleName[role]).c_str(), name, number);
      value[role] = scalar;
    } else if (status == NumberStatus::kNotANumber) {
      Fail(name, number, prefix + property.name + " is not a number: " + Quote(token));
    }
  }
  if (NextToken(&line, &token)) {
    Fail(name, number, prefix + "more values than the header's properties: " + Quote(token));
  }
}

namespace {

PointList ReadAsciiBody(std::string_view body, const PlyHeader& header, std::size_t vertex,
                        const std::vector<int>& roles, const std::string& name) {
  LineCursor cursor(body, header.body_line);
  std::string_view line;
  for (std::size_t e = 0; e < vertex; ++e) {
    const PlyElement& element = header.elements[e];
    for (unsigned long long i = 0; i < element.count; ++i) {
      if (!NextPlyDataLine(&cursor, &line)) Fail(name, 0, TruncatedBeforeVertex(element, i));
    }
  }
  const PlyElement& element = header.elements[vertex];
  const bool has_weight = std::find(roles.begin(), roles.end(), 3) != roles.end();
  PointList list;
  list.points.reserve(std::min<unsigned long long>(element.count, body.size() / 6));
  double value[4] = {0.0, 0.0, 0.0, 0.0};
  for (unsigned long long i = 0; i < element.count; ++i) {
    if (!NextPlyDataLine(&cursor, &line)) Fail(name, 0, TruncatedMessage(i, element.count));
    ParsePlyAsciiVertex(line, element, roles, i, value, name, cursor.line());
    if (has_weight && value[3] < 0.0) {
      Fail(name, cursor.line(), "vertex " + std::to_string(i) + ": weight is negative");
    }
    list.points.push_back({value[0], value[1], value[2]});
    if (has_weight) list.weight.push_back(value[3]);
  }
  for (std::size_t e = vertex + 1; e < header.elements.size(); ++e) {
    const PlyElement& after = header.elements[e];
    for (unsigned long long i = 0; i < after.count; ++i) {
      if (!NextPlyDataLine(&cursor, &line)) Fail(name, 0, TruncatedAfterVertex(after, i));
    }
  }
  if (NextPlyDataLine(&cursor, &line)) {
    Fail(name, cursor.line(), TrailingDataMessage("a line of", element.count));
  }
  return list;
}

}  // namespace

Surface ParsePly(std::string_view data, const std::string& name, const ReadOptions& options) {
  const PlyHeader header = ParsePlyHeader(data, name);
  std::size_t vertex = 0;
  while (vertex < header.elements.size() && header.elements[vertex].name != "vertex") ++vertex;
  if (vertex == header.elements.size()) Fail(name, 0, "no 'vertex' element in the PLY header");
  const std::vector<int> roles = PlyVertexRoles(header.elements[vertex], name);
  // Before a count the header declares allocates anything.
  CheckPointCount(header.elements[vertex].count, name, options);
  const std::string_view body = data.substr(header.body_offset);
  PointList list = header.binary ? ReadBinaryBody(body, header, vertex, roles, name)
                                 : ReadAsciiBody(body, header, vertex, roles, name);
  return Finish(std::move(list), name, options);
}

}  // namespace surfreg::io_internal
