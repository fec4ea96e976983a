// PLY (ascii and binary_little_endian 1.0): the vertex element's x, y, z and
// optional weight; every other element and property is parsed only to be
// skipped, so that elements before "vertex" and list properties work.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "tools/io/surface_reader_internal.h"

namespace surfreg::io_internal {
namespace {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

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

std::size_t TypeSize(PlyType type) {
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

bool IsFloatType(PlyType type) { return type == PlyType::kFloat32 || type == PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;  // of the value, or of a list's items
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;  // of a list's length
  std::size_t line = 0;                  // header line, for messages
};

struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0;
};

struct PlyHeader {
  bool has_format = false;
  bool binary = false;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;  // first byte after the end_header line
  std::size_t body_line = 0;    // number of the first body line
};

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

PlyHeader ParseHeader(std::string_view data, const std::string& name) {
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
std::vector<int> VertexRoles(const PlyElement& vertex, const std::string& name) {
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
void CheckVertex(const double* value, bool has_weight, unsigned long long index,
                 const std::string& name, std::size_t line) {
  static const char* const kRoleName[] = {"x", "y", "z", "weight"};
  const std::string prefix = "vertex " + std::to_string(index) + ": ";
  for (int role = 0; role < (has_weight ? 4 : 3); ++role) {
    CheckNumber(NumberStatus::kOk, value[role], "", (prefix + kRoleName[role]).c_str(), name, line);
  }
  if (has_weight && value[3] < 0.0) Fail(name, line, prefix + "weight is negative");
}

std::string TruncatedMessage(unsigned long long done, unsigned long long count) {
  return "file ends after " + std::to_string(done) + " of " + std::to_string(count) + " vertices";
}

std::string TruncatedBeforeVertex(const PlyElement& element, unsigned long long done) {
  return "file ends in element '" + element.name + "' after " + std::to_string(done) + " of " +
         std::to_string(element.count) + ", before the vertices";
}

// --- binary_little_endian ---------------------------------------------------

class ByteReader {
 public:
  explicit ByteReader(std::string_view data)
      : p_(reinterpret_cast<const unsigned char*>(data.data())), end_(p_ + data.size()) {}

  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }

  bool Skip(unsigned long long n) {
    if (n > remaining()) return false;
    p_ += n;
    return true;
  }

  // Decodes byte by byte so the host's byte order does not matter.
  bool Read(PlyType type, double* value) {
    const std::size_t size = TypeSize(type);
    if (size > remaining()) return false;
    uint64_t bits = 0;
    for (std::size_t i = 0; i < size; ++i) bits |= static_cast<uint64_t>(p_[i]) << (8 * i);
    p_ += size;
    *value = Decode(type, bits);
    return true;
  }

 private:
  static double Decode(PlyType type, uint64_t bits) {
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

  const unsigned char* p_;
  const unsigned char* end_;
};

// Skips (or reads, into value[roles[k]]) one element instance. False if the
// data ends inside it.
bool ReadBinaryInstance(const PlyElement& element, const std::vector<int>* roles,
                        ByteReader* reader, double* value, const std::string& name) {
  for (std::size_t k = 0; k < element.properties.size(); ++k) {
    const PlyProperty& property = element.properties[k];
    double scalar = 0.0;
    if (!property.is_list) {
      if (roles == nullptr || (*roles)[k] < 0) {
        if (!reader->Skip(TypeSize(property.type))) return false;
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
    if (!reader->Skip(static_cast<unsigned long long>(scalar) * TypeSize(property.type))) {
      return false;
    }
  }
  return true;
}

PointList ReadBinaryBody(std::string_view body, const PlyHeader& header, std::size_t vertex,
                         const std::vector<int>& roles, const std::string& name) {
  ByteReader reader(body);
  double value[4] = {0.0, 0.0, 0.0, 0.0};
  for (std::size_t e = 0; e < vertex; ++e) {
    const PlyElement& element = header.elements[e];
    for (unsigned long long i = 0; i < element.count; ++i) {
      if (!ReadBinaryInstance(element, nullptr, &reader, value, name)) {
        Fail(name, 0, TruncatedBeforeVertex(element, i));
      }
    }
  }
  const PlyElement& element = header.elements[vertex];
  const bool has_weight = std::find(roles.begin(), roles.end(), 3) != roles.end();
  PointList list;
  list.points.reserve(std::min<unsigned long long>(element.count, reader.remaining() / 3));
  for (unsigned long long i = 0; i < element.count; ++i) {
    if (!ReadBinaryInstance(element, &roles, &reader, value, name)) {
      Fail(name, 0, TruncatedMessage(i, element.count));
    }
    CheckVertex(value, has_weight, i, name, 0);
    list.points.push_back({value[0], value[1], value[2]});
    if (has_weight) list.weight.push_back(value[3]);
  }
  return list;
}

// --- ascii ------------------------------------------------------------------

bool NextDataLine(LineCursor* cursor, std::string_view* line) {
  while (cursor->Next(line)) {
    if (!TrimCr(*line).empty()) return true;
  }
  return false;
}

// Parses one vertex line into value[roles[k]].
void ParseAsciiVertex(std::string_view line, const PlyElement& element,
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

PointList ReadAsciiBody(std::string_view body, const PlyHeader& header, std::size_t vertex,
                        const std::vector<int>& roles, const std::string& name) {
  LineCursor cursor(body, header.body_line);
  std::string_view line;
  for (std::size_t e = 0; e < vertex; ++e) {
    const PlyElement& element = header.elements[e];
    for (unsigned long long i = 0; i < element.count; ++i) {
      if (!NextDataLine(&cursor, &line)) Fail(name, 0, TruncatedBeforeVertex(element, i));
    }
  }
  const PlyElement& element = header.elements[vertex];
  const bool has_weight = std::find(roles.begin(), roles.end(), 3) != roles.end();
  PointList list;
  list.points.reserve(std::min<unsigned long long>(element.count, body.size() / 6));
  double value[4] = {0.0, 0.0, 0.0, 0.0};
  for (unsigned long long i = 0; i < element.count; ++i) {
    if (!NextDataLine(&cursor, &line)) Fail(name, 0, TruncatedMessage(i, element.count));
    ParseAsciiVertex(line, element, roles, i, value, name, cursor.line());
    if (has_weight && value[3] < 0.0) {
      Fail(name, cursor.line(), "vertex " + std::to_string(i) + ": weight is negative");
    }
    list.points.push_back({value[0], value[1], value[2]});
    if (has_weight) list.weight.push_back(value[3]);
  }
  return list;
}

}  // namespace

Surface ParsePly(std::string_view data, const std::string& name, const ReadOptions& options) {
  const PlyHeader header = ParseHeader(data, name);
  std::size_t vertex = 0;
  while (vertex < header.elements.size() && header.elements[vertex].name != "vertex") ++vertex;
  if (vertex == header.elements.size()) Fail(name, 0, "no 'vertex' element in the PLY header");
  const std::vector<int> roles = VertexRoles(header.elements[vertex], name);
  const std::string_view body = data.substr(header.body_offset);
  PointList list = header.binary ? ReadBinaryBody(body, header, vertex, roles, name)
                                 : ReadAsciiBody(body, header, vertex, roles, name);
  return Finish(std::move(list), name, options);
}

}  // namespace surfreg::io_internal
