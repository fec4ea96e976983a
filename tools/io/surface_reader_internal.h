#pragma once
// Shared pieces of the surface readers (not part of the public API): the
// per-format parsers work on the whole file as one buffer, so that reading
// a million lines costs no per-line allocation.
#include <array>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "tools/io/surface_reader.h"

namespace surfreg::io_internal {

// Throws InputError "<name>:<line>: <what>", or "<name>: <what>" if line == 0.
[[noreturn]] void Fail(const std::string& name, std::size_t line, const std::string& what);

// `token` in single quotes for a message: shortened, non-printables escaped,
// so that a binary file never produces a multi-line or huge message.
std::string Quote(std::string_view token);

enum class NumberStatus { kOk, kNotANumber, kOutOfRange };

// Parses the whole of `token` as a double (an optional leading '+' is
// allowed). "nan" and "inf" parse (kOk): callers check finiteness so they can
// say which value is bad.
NumberStatus ParseNumber(std::string_view token, double* value);

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

// The lower-case extension of the file name in `path`, with its dot; empty if none.
std::string Extension(const std::string& path);

}  // namespace surfreg::io_internal
