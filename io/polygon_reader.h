#pragma once
// Polygon files: the mask of the weight μ (WeightMode::kMask: `surfreg
// measure --weights=mask:FILE` and the `mask` key of `surfreg align`), and
// single polygons (the jaw's boundary).
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "measure/mask_region.h"

namespace surfreg {

// Reads a polygon file: one "x y" vertex per line (blank-separated, input
// coordinates), '#' comments (whole line or trailing), blank lines skipped.
// A last vertex equal to the first (an explicitly closed ring) is dropped.
// Throws InputError "<path>:<line>: ..." for a bad line, "<path>: ..." for an
// unreadable file, fewer than 3 vertices or more than one ring.
std::vector<std::array<double, 2>> ReadPolygon(const std::string& path);

// The same on the file's contents `data`; `name` is used in messages.
std::vector<std::array<double, 2>> ParsePolygon(std::string_view data, const std::string& name);

// A text mask: rings as ReadPolygon's, separated by a line holding only '>'
// (GMT's multi-segment mark); combined by the even–odd rule (a ring inside
// another is a hole). Not checked beyond each ring's 3 vertices.
std::vector<MaskRing> ParseMaskText(std::string_view data, const std::string& name);

// Whether `path` names a vector file read through OGR (by extension: .gpkg,
// .shp, .geojson, .json, .kml, .gml, .fgb, .sqlite, .gmt, .tab, .mif).
bool IsVectorMaskPath(const std::string& path);

struct MaskFile {
  std::vector<MaskRing> rings;  // in the file's coordinates
  std::string crs_wkt;          // the file's CRS; "" for text or none (= the reference's)
};

// Reads a mask: a vector file (IsVectorMaskPath: every ring of the Polygon
// and MultiPolygon features of layer `layer`, the first layer when "") or a
// text mask (ParseMaskText; `layer` must be ""). Checks the rings
// (ValidMaskRings): InputError "<path>: ..." naming the feature and ring of
// a vector file ("feature 7 ring 2"), or the ring of a text file.
MaskFile ReadMask(const std::string& path, const std::string& layer = "");

}  // namespace surfreg
