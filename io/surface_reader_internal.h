#pragma once
// Shared pieces of the surface readers (not part of the public API): the
// per-format parsers work on the whole file as one buffer, so that reading
// a million lines costs no per-line allocation.
#include <array>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "io/surface_reader.h"
#include "measure/option_keys.h"

namespace surfreg::io_internal {

// Throws InputError "<name>:<line>: <what>", or "<name>: <what>" if line == 0.
[[noreturn]] void Fail(const std::string& name, std::size_t line, const std::string& what);

// Quote, NumberStatus and ParseNumber (measure/option_keys.h), as the
// readers have always named them.
using ::surfreg::NumberStatus;
using ::surfreg::ParseNumber;
using ::surfreg::Quote;

// Parses the whole of `token` as a non-negative integer.
bool ParseCount(std::string_view token, unsigned long long* value);

// Checks `value` (parsed from `token` with `status`) and throws a message
// naming `what` (e.g. "z", "vertex 3: x") if it is not a finite number.
void CheckNumber(NumberStatus status, double value, std::string_view token, const char* what,
                 const std::string& name, std::size_t line);

// Splits a buffer into lines ('\n'-terminated; a '\r' before it is left in
// the line, where tokenizers treat it as blank space).
class LineCursor {
 public:
  explicit LineCursor(std::string_view data, std::size_t first_line = 1)
      : data_(data), next_line_(first_line) {}
  // The next line, without its '\n'. False at the end of the buffer.
  bool Next(std::string_view* line);
  std::size_t line() const { return next_line_ - 1; }  // number of the last line returned
  std::size_t offset() const { return pos_; }          // where the next line starts

 private:
  std::string_view data_;
  std::size_t pos_ = 0;
  std::size_t next_line_;
};

inline bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// The next blank-separated token of `*rest` (which is advanced past it).
bool NextToken(std::string_view* rest, std::string_view* token);

// `line` up to its first '#'.
std::string_view StripComment(std::string_view line);

// Collected points in input coordinates.
struct PointList {
  std::vector<std::array<double, 3>> points;
  std::vector<double> weight;  // empty, or one per point
};

// Builds the Surface (MakeSurface + ValidateSurface); "no points" if empty.
Surface Finish(PointList&& list, const std::string& name, const ReadOptions& options);

// The whole stream as one buffer.
std::string ReadAll(std::istream& in, const std::string& name);

// The whole file at `path`; an unreadable file or a directory throws
// InputError naming it.
std::string ReadFile(const std::string& path);

Surface ParseXyz(std::string_view data, const std::string& name, const ReadOptions& options);
Surface ParsePly(std::string_view data, const std::string& name, const ReadOptions& options);
Surface ParseOff(std::string_view data, const std::string& name, const ReadOptions& options);
Surface ParseObj(std::string_view data, const std::string& name, const ReadOptions& options);
// LAS (surface_reader_las.cc); a non-null `crs` gets the file's CRS text or "".
Surface ParseLas(std::string_view data, const std::string& name, const ReadOptions& options,
                 std::string* crs);

// What a format can be asked for: ReadOptions::classes needs LAS,
// ReadOptions::columns a text cloud.
enum class OptionFit { kText, kLas, kOther };

// Throws InputError "<name>: ..." if `options` asks for classes or columns
// that a file of this kind (`format` names it, e.g. ".ply") does not have.
void CheckOptionsFit(const ReadOptions& options, OptionFit kind, const std::string& format,
                     const std::string& name);

// The lower-case extension of the file name in `path`, with its dot; empty if none.
std::string Extension(const std::string& path);

// --- PLY, shared by the surface reader and the mesh reader (mesh_reader.cc) --

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::size_t PlyTypeSize(PlyType type);

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

// Parses the header of the PLY file `data` (ascii or binary_little_endian 1.0).
PlyHeader ParsePlyHeader(std::string_view data, const std::string& name);

// What each vertex property is for: an index into {x, y, z, weight}, or -1;
// throws if x, y or z is missing or a list.
std::vector<int> PlyVertexRoles(const PlyElement& vertex, const std::string& name);

// Checks one vertex's values (value[3] is the weight if `has_weight`).
void CheckPlyVertex(const double* value, bool has_weight, unsigned long long index,
                    const std::string& name, std::size_t line);

// Little-endian values from a binary PLY body, decoded byte by byte so the
// host's byte order does not matter. Keeps a view of the bytes it was given.
class PlyByteReader {
 public:
  explicit PlyByteReader(std::string_view data)
      : p_(reinterpret_cast<const unsigned char*>(data.data())), end_(p_ + data.size()) {}

  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }

  bool Skip(unsigned long long n) {
    if (n > remaining()) return false;
    p_ += n;
    return true;
  }

  // False (nothing consumed) if the data ends before the value.
  bool Read(PlyType type, double* value) {
    const std::size_t size = PlyTypeSize(type);
    if (size > remaining()) return false;
    uint64_t bits = 0;
    for (std::size_t i = 0; i < size; ++i) bits |= static_cast<uint64_t>(p_[i]) << (8 * i);
    p_ += size;
    *value = Decode(type, bits);
    return true;
  }

 private:
  static double Decode(PlyType type, uint64_t bits);

  const unsigned char* p_;
  const unsigned char* end_;
};

// Skips (or reads, into value[roles[k]], when `roles` is given) one binary
// element instance. False if the data ends inside it.
bool ReadPlyBinaryInstance(const PlyElement& element, const std::vector<int>* roles,
                           PlyByteReader* reader, double* value, const std::string& name);

// The next non-blank line of an ascii body.
bool NextPlyDataLine(LineCursor* cursor, std::string_view* line);

// Parses one ascii vertex line into value[roles[k]] (list properties skipped).
void ParsePlyAsciiVertex(std::string_view line, const PlyElement& element,
                         const std::vector<int>& roles, unsigned long long index, double* value,
                         const std::string& name, std::size_t number);

}  // namespace surfreg::io_internal
