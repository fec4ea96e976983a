#pragma once
// Mask polygons for the weight μ (WeightMode::kMask): `surfreg measure
// --weights=mask:FILE` and the `mask` key of `surfreg align`.
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace surfreg {

// Reads a polygon file: one "x y" vertex per line (blank-separated, input
// coordinates), '#' comments (whole line or trailing), blank lines skipped.
// A last vertex equal to the first (an explicitly closed ring) is dropped.
// Throws InputError "<path>:<line>: ..." for a bad line, "<path>: ..." for an
// unreadable file or fewer than 3 vertices.
std::vector<std::array<double, 2>> ReadPolygon(const std::string& path);

// The same on the file's contents `data`; `name` is used in messages.
std::vector<std::array<double, 2>> ParsePolygon(std::string_view data, const std::string& name);

}  // namespace surfreg
