// Mesh formats read as point sets: OFF (and its COFF/NOFF/NCOFF variants)
// and Wavefront OBJ. Faces are ignored: the surface is re-triangulated.
#include <algorithm>
#include <array>
#include <string>

#include "io/surface_reader_internal.h"

namespace surfreg::io_internal {
namespace {

// The next line that has a token once its '#' comment is removed.
bool NextContentLine(LineCursor* cursor, std::string_view* line) {
  while (cursor->Next(line)) {
    *line = StripComment(*line);
    std::string_view rest = *line, token;
    if (NextToken(&rest, &token)) return true;
  }
  return false;
}

// Parses the first 3 tokens of `line` as x y z into `point`; `what` prefixes
// messages ("vertex 3: " or "").
void ParseXyzTokens(std::string_view line, const std::string& what, const std::string& name,
                    std::size_t number, std::array<double, 3>* point) {
  static const char* const kAxis[] = {"x", "y", "z"};
  std::string_view token[3];
  int found = 0;
  while (found < 3 && NextToken(&line, &token[found])) ++found;
  if (found < 3) {
    Fail(name, number, what + "expected 3 numbers (x y z), found " + std::to_string(found));
  }
  for (int k = 0; k < 3; ++k) {
    const NumberStatus status = ParseNumber(token[k], &(*point)[k]);
    CheckNumber(status, (*point)[k], token[k], (what + kAxis[k]).c_str(), name, number);
  }
}

void CheckOffKeyword(std::string_view keyword, const std::string& name, std::size_t number) {
  if (keyword == "OFF" || keyword == "COFF" || keyword == "NOFF" || keyword == "NCOFF") return;
  if (keyword.size() > 3 && keyword.substr(keyword.size() - 3) == "OFF") {
    Fail(name, number,
         "unsupported OFF variant " + Quote(keyword) + " (expected OFF, COFF, NOFF or NCOFF)");
  }
  Fail(name, number, "not an OFF file: expected the header 'OFF', found " + Quote(keyword));
}

// Reads "nv nf [ne]" from `line` and returns nv.
unsigned long long ParseOffCounts(std::string_view line, const std::string& name,
                                  std::size_t number) {
  std::string_view token;
  unsigned long long counts[3] = {0, 0, 0};
  int found = 0;
  while (NextToken(&line, &token)) {
    if (found == 3 || !ParseCount(token, &counts[found])) {
      Fail(name, number, "expected the counts 'vertices faces edges', found " + Quote(token));
    }
    ++found;
  }
  if (found < 2) Fail(name, number, "expected the counts 'vertices faces edges'");
  return counts[0];
}

}  // namespace

Surface ParseOff(std::string_view data, const std::string& name, const ReadOptions& options) {
  LineCursor cursor(data);
  std::string_view line, keyword;
  if (!NextContentLine(&cursor, &line)) Fail(name, 0, "no points (empty file)");
  NextToken(&line, &keyword);
  CheckOffKeyword(keyword, name, cursor.line());
  // The counts usually have their own line but may follow the keyword.
  std::string_view rest = line, token;
  const bool counts_follow = NextToken(&rest, &token);
  if (counts_follow && token == "BINARY") Fail(name, cursor.line(), "binary OFF is not supported");
  if (!counts_follow && !NextContentLine(&cursor, &line)) {
    Fail(name, 0, "file ends before the counts line 'vertices faces edges'");
  }
  const unsigned long long count = ParseOffCounts(line, name, cursor.line());
  CheckPointCount(count, name, options);  // before a header's count allocates anything
  PointList list;
  list.points.reserve(std::min<unsigned long long>(count, data.size() / 6));
  for (unsigned long long i = 0; i < count; ++i) {
    if (!NextContentLine(&cursor, &line)) {
      Fail(name, 0,
           "file ends after " + std::to_string(i) + " of " + std::to_string(count) + " vertices");
    }
    std::array<double, 3> point;
    ParseXyzTokens(line, "vertex " + std::to_string(i) + ": ", name, cursor.line(), &point);
    list.points.push_back(point);
  }
  return Finish(std::move(list), name, options);
}

Surface ParseObj(std::string_view data, const std::string& name, const ReadOptions& options) {
  LineCursor cursor(data);
  std::string_view line, keyword;
  PointList list;
  while (cursor.Next(&line)) {
    line = StripComment(line);
    if (!NextToken(&line, &keyword) || keyword != "v") continue;  // vt, vn, f, ...: not points
    std::array<double, 3> point;
    // A 4th number is the homogeneous w or a colour, never a weight: ignored.
    ParseXyzTokens(line, "", name, cursor.line(), &point);
    list.points.push_back(point);
  }
  return Finish(std::move(list), name, options);
}

}  // namespace surfreg::io_internal
