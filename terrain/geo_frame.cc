// CRS parsing (GDAL/PROJ, through the GDAL module) and the common metric
// frame (GeographicLib); see geo_frame.h.
#include "terrain/geo_frame.h"

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/TransverseMercator.hpp>
#include <GeographicLib/UTMUPS.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <vector>

#include "measure/input_error.h"
#include "io/gdal_module.h"

namespace surfreg {
namespace {

using GeographicLib::Math;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kUtmScale = 0.9996;
constexpr double kUtmFalseEasting = 500000.0;
constexpr double kUtmFalseNorthingSouth = 10000000.0;

std::string Trim(const std::string& text) {
  std::size_t b = 0, e = text.size();
  while (b < e && std::isspace(static_cast<unsigned char>(text[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(text[e - 1]))) --e;
  return text.substr(b, e - b);
}

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// The shortest text that reads back as `value`: full precision, no noise digits.
std::string Exact(double value) {
  char text[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

// The ellipsoid and prime meridian of a geographic (or projected) CRS;
// WGS 84 and Greenwich when unknown.
struct Datum {
  double a = GeographicLib::Constants::WGS84_a();
  double f = GeographicLib::Constants::WGS84_f();
  double prime_meridian_deg = 0;
  std::string name = "WGS 84";
};

Datum DatumOf(const Crs& crs) {
  Datum datum;
  CrsDatum known;
  if (!Gdal("CRS '" + crs.name + "'").datum_of(crs.wkt, &known)) return datum;
  datum.a = known.a;
  datum.f = known.f;
  datum.prime_meridian_deg = known.prime_meridian_deg;
  if (!known.name.empty()) datum.name = known.name;
  return datum;
}

struct Box {
  double lon_lo = HUGE_VAL, lon_hi = -HUGE_VAL, lat_lo = HUGE_VAL, lat_hi = -HUGE_VAL;
  double lon_centre() const { return 0.5 * (lon_lo + lon_hi); }
  double lat_centre() const { return 0.5 * (lat_lo + lat_hi); }
};

// Bounding box of a geographic surface (Greenwich longitudes); checks that
// the coordinates can be degrees.
Box LonLatBox(const Surface& s, double prime_meridian_deg) {
  Box box;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double lon = s.origin[0] + s.xy[i].x + prime_meridian_deg;
    const double lat = s.origin[1] + s.xy[i].y;
    if (!(std::fabs(lat) <= 90.0) || !(std::fabs(lon) <= 540.0)) {
      char what[160];
      std::snprintf(what, sizeof(what),
                    ": point %zu (%.9g, %.9g) is not a longitude, latitude in degrees", i + 1,
                    s.origin[0] + s.xy[i].x, lat);
      throw InputError(s.source + what + " (is the CRS really geographic?)");
    }
    box.lon_lo = std::min(box.lon_lo, lon), box.lon_hi = std::max(box.lon_hi, lon);
    box.lat_lo = std::min(box.lat_lo, lat), box.lat_hi = std::max(box.lat_hi, lat);
  }
  return box;
}

// Centre of the part all boxes share, or of their union if they share none.
void CentreOf(const std::vector<Box>& boxes, double* lat, double* lon) {
  Box common, all;
  common.lon_lo = common.lat_lo = -HUGE_VAL;
  common.lon_hi = common.lat_hi = HUGE_VAL;
  for (const Box& b : boxes) {
    common = {std::max(common.lon_lo, b.lon_lo), std::min(common.lon_hi, b.lon_hi),
              std::max(common.lat_lo, b.lat_lo), std::min(common.lat_hi, b.lat_hi)};
    all = {std::min(all.lon_lo, b.lon_lo), std::max(all.lon_hi, b.lon_hi),
           std::min(all.lat_lo, b.lat_lo), std::max(all.lat_hi, b.lat_hi)};
  }
  const Box& centred = common.lon_lo > common.lon_hi || common.lat_lo > common.lat_hi ? all : common;
  *lat = centred.lat_centre();
  *lon = Math::AngNormalize(centred.lon_centre());
}

int Zone(double lat, double lon) {
  return GeographicLib::UTMUPS::StandardZone(lat, Math::AngNormalize(lon));
}

double CentralMeridian(int zone) { return 6.0 * zone - 183.0; }

// The ENU frame as a PROJ pipeline: lon, lat (degrees, the CRS's prime
// meridian), ellipsoidal height -> geocentric -> east, north, up about the
// origin (lat0, lon0 Greenwich, h0), on the datum's ellipsoid.
std::string EnuDefinition(const GeoFrame& frame, const Datum& datum) {
  const bool wgs84 = datum.a == GeographicLib::Constants::WGS84_a() &&
                     datum.f == GeographicLib::Constants::WGS84_f();
  const std::string ellipsoid = wgs84          ? "+ellps=WGS84"
                                : datum.f == 0 ? "+R=" + Exact(datum.a)
                                               : "+a=" + Exact(datum.a) + " +rf=" + Exact(1 / datum.f);
  const std::string pm =
      datum.prime_meridian_deg != 0 ? " +pm=" + Exact(datum.prime_meridian_deg) : "";
  return "+proj=pipeline +step +proj=unitconvert +xy_in=deg +xy_out=rad +step +proj=cart " +
         ellipsoid + pm + " +step +proj=topocentric " + ellipsoid + " +lat_0=" +
         Exact(frame.lat0) + " +lon_0=" + Exact(frame.lon0) + " +h_0=" + Exact(frame.h0);
}

// Forward and inverse maps between (lat, lon, h) and the frame's x, y, z.
class FrameMap {
 public:
  FrameMap(const GeoFrame& frame, const Datum& datum)
      : frame_(frame),
        tm_(datum.a, datum.f, kUtmScale),
        enu_(frame.lat0, frame.lon0, frame.h0, GeographicLib::Geocentric(datum.a, datum.f)) {}

  void Forward(double lat, double lon, double h, double* x, double* y, double* z) const {
    if (frame_.kind == GeoFrame::kUtm) {
      tm_.Forward(CentralMeridian(frame_.zone), lat, lon, *x, *y);
      *x += kUtmFalseEasting;
      *y += frame_.northp ? 0.0 : kUtmFalseNorthingSouth;
      *z = h;
    } else {
      enu_.Forward(lat, lon, h, *x, *y, *z);
    }
  }
  void Reverse(double x, double y, double z, double* lat, double* lon, double* h) const {
    if (frame_.kind == GeoFrame::kUtm) {
      tm_.Reverse(CentralMeridian(frame_.zone), x - kUtmFalseEasting,
                  y - (frame_.northp ? 0.0 : kUtmFalseNorthingSouth), *lat, *lon);
      *h = z;
    } else {
      enu_.Reverse(x, y, z, *lat, *lon, *h);
    }
  }

 private:
  const GeoFrame& frame_;
  GeographicLib::TransverseMercator tm_;
  GeographicLib::LocalCartesian enu_;
};

void Convert(const FrameMap& map, double prime_meridian_deg, Surface* s) {
  std::vector<std::array<double, 3>> points(s->size());
  for (std::size_t i = 0; i < s->size(); ++i) {
    const double lon = s->origin[0] + s->xy[i].x + prime_meridian_deg;
    const double lat = s->origin[1] + s->xy[i].y;
    const double h = s->origin[2] + s->z[i];
    map.Forward(lat, lon, h, &points[i][0], &points[i][1], &points[i][2]);
  }
  std::vector<RasterCell> cells = std::move(s->raster_cell);  // a converted raster keeps its cells
  *s = MakeSurface(points, std::move(s->weight), std::move(s->source), 1.0);
  s->raster_cell = std::move(cells);
}

const char* KindName(CrsKind kind) {
  switch (kind) {
    case CrsKind::kNone:
      return "no CRS";
    case CrsKind::kProjected:
      return "projected";
    case CrsKind::kGeographic:
      return "geographic";
  }
  return "?";
}

// The frame of surfaces[0] and the others (all geographic on `datum`),
// each converted into it.
GeoFrame GeographicFrame(const std::vector<Surface*>& surfaces, const Datum& datum, FrameChoice choice) {
  std::vector<Box> boxes;
  for (const Surface* s : surfaces) {
    boxes.push_back(LonLatBox(*s, datum.prime_meridian_deg));
    // The same place may be written 360 degrees apart (0..360 vs -180..180).
    Box& box = boxes.back();
    const double shift = 360.0 * std::round((box.lon_centre() - boxes[0].lon_centre()) / 360.0);
    box.lon_lo -= shift, box.lon_hi -= shift;
  }
  GeoFrame frame;
  frame.datum = datum.name;
  double lat = 0, lon = 0;
  CentreOf(boxes, &lat, &lon);
  const int first_zone = Zone(boxes[0].lat_centre(), boxes[0].lon_centre());
  const int centre_zone = Zone(lat, lon);
  if (choice == FrameChoice::kUtm && centre_zone == GeographicLib::UTMUPS::UPS) {
    char what[128];
    std::snprintf(what, sizeof(what), "UTM is not defined at latitude %.4f (polar); use frame enu",
                  lat);
    std::string names;
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
      names += (k == 0 ? "" : k + 1 == surfaces.size() ? " and " : ", ") + surfaces[k]->source;
    }
    throw InputError(names + ": " + what);
  }
  const bool same_zone =
      first_zone != GeographicLib::UTMUPS::UPS &&
      std::all_of(boxes.begin(), boxes.end(),
                  [&](const Box& b) { return Zone(b.lat_centre(), b.lon_centre()) == first_zone; });
  if (choice == FrameChoice::kUtm || (choice == FrameChoice::kAuto && same_zone)) {
    frame.kind = GeoFrame::kUtm;
    frame.zone = choice == FrameChoice::kUtm ? centre_zone : first_zone;
    frame.northp = lat >= 0;
  } else {
    frame.kind = GeoFrame::kEnu;
    frame.lat0 = lat, frame.lon0 = lon, frame.h0 = 0.0;
    frame.definition = EnuDefinition(frame, datum);
  }
  const FrameMap map(frame, datum);
  for (Surface* s : surfaces) Convert(map, datum.prime_meridian_deg, s);
  return frame;
}

}  // namespace

FrameChoice FrameChoiceOf(const std::string& frame) {
  return frame == "enu" ? FrameChoice::kEnu : frame == "utm" ? FrameChoice::kUtm : FrameChoice::kAuto;
}

Crs ParseCrs(const std::string& text, const std::string& label) {
  const std::string trimmed = Trim(text);
  const std::string lower = Lower(trimmed);
  Crs crs;
  crs.name = "none";
  if (trimmed.empty() || lower == "none") return crs;
  const bool shorthand = lower == "lonlat" || lower == "geographic";
  CrsFacts facts;
  std::string error;
  if (!Gdal(label).parse_crs(shorthand ? "EPSG:4326" : trimmed, &facts, &error)) {
    throw InputError(label + ": " + error);
  }
  crs.kind = facts.kind == CrsFacts::kGeographic ? CrsKind::kGeographic : CrsKind::kProjected;
  crs.name = facts.name;
  crs.wkt = facts.wkt;
  crs.metres_per_unit = facts.metres_per_unit;
  return crs;
}

std::string GeoFrame::Describe() const {
  const std::string defined = definition.empty() ? "" : "; " + definition;
  switch (kind) {
    case kUtm:
      return "UTM zone " + std::to_string(zone) + (northp ? "N" : "S") + " (" + datum + defined +
             ")";
    case kEnu:
      return "local ENU about " + Exact(std::fabs(lat0)) + (lat0 < 0 ? "S " : "N ") +
             Exact(std::fabs(lon0)) + (lon0 < 0 ? "W" : "E") + ", h " + Exact(h0) + " m (" +
             datum + defined + ")";
    case kAsGiven:
      break;
  }
  return "coordinates as given (" + (datum.empty() ? std::string("no CRS") : datum) + defined +
         ")";
}

std::string DescribeCrs(const Crs& crs) {
  if (crs.kind == CrsKind::kNone) return "none";
  const std::string id = Gdal("CRS '" + crs.name + "'").identify_crs(crs.wkt);
  return id.empty() ? crs.name : crs.name + " (" + id + ")";
}

bool SameCrs(const Crs& a, const Crs& b) {
  if (a.kind == CrsKind::kNone || b.kind == CrsKind::kNone) return a.kind == b.kind;
  if (a.kind != b.kind) return false;
  return Gdal("CRS '" + a.name + "'").same_crs(a.wkt, b.wkt, false) == 1;
}

void ReprojectSurface(Surface* surface, const Crs& from, const Crs& to) {
  std::vector<std::array<double, 3>> points(surface->size());
  for (std::size_t i = 0; i < surface->size(); ++i) {
    points[i] = {surface->origin[0] + surface->xy[i].x, surface->origin[1] + surface->xy[i].y,
                 surface->origin[2] + surface->z[i]};
  }
  std::string error;
  if (!Gdal(surface->source).transform_points(from.wkt, to.wkt, &points, &error)) {
    throw InputError(surface->source + ": cannot reproject from CRS '" + from.name + "' to '" +
                     to.name + "': " + error);
  }
  std::vector<RasterCell> cells = std::move(surface->raster_cell);  // a raster keeps its cells
  *surface = MakeSurface(points, std::move(surface->weight), std::move(surface->source), 1.0);
  surface->raster_cell = std::move(cells);
}

GeoFrame ToCommonMetricFrame(Surface* reference, const Crs& reference_crs, Surface* moving,
                             const Crs& moving_crs, FrameChoice choice) {
  const auto mismatch = [&](const std::string& why) {
    throw InputError("reference " + reference->source + " (CRS " + reference_crs.name +
                     ") and moving " + moving->source + " (CRS " + moving_crs.name + "): " + why);
  };
  const CrsKind kind = reference_crs.kind;
  if ((kind == CrsKind::kNone) != (moving_crs.kind == CrsKind::kNone)) {
    const bool reference_has = kind != CrsKind::kNone;
    mismatch(std::string("the ") + (reference_has ? "reference" : "moving") +
             " surface has a CRS and the " + (reference_has ? "moving" : "reference") +
             " has none; give it with the key '" + (reference_has ? "moving_crs" : "reference_crs") +
             "' (flag --" + (reference_has ? "moving_crs" : "reference_crs") + ")");
  }
  if (kind != moving_crs.kind) {
    mismatch(std::string("one is ") + KindName(kind) + ", the other " + KindName(moving_crs.kind) +
             "; give both the same CRS (reproject, or set it)");
  }
  GeoFrame frame;
  if (kind == CrsKind::kNone) {
    frame.datum = "no CRS";
    return frame;
  }
  const GdalModule& gdal = Gdal("reference " + reference->source);
  const int same = gdal.same_crs(reference_crs.wkt, moving_crs.wkt, kind == CrsKind::kGeographic);
  if (same < 0) mismatch("a CRS is unreadable");
  if (kind == CrsKind::kProjected) {
    if (same == 0) {
      const bool metres = reference_crs.metres_per_unit == 1 && moving_crs.metres_per_unit == 1;
      mismatch(std::string("different projected CRSs") +
               (metres ? "" : " (and not both in metres)") + "; reproject one onto the other");
    }
    frame.datum = reference_crs.name;
    frame.definition = gdal.identify_crs(reference_crs.wkt);
    return frame;
  }
  if (same == 0) {
    mismatch("different geographic datums; transform one onto the other's datum");
  }
  frame = GeographicFrame({reference, moving}, DatumOf(reference_crs), choice);
  if (frame.kind == GeoFrame::kUtm) {
    frame.definition = gdal.identify_utm(reference_crs.wkt, frame.zone, frame.northp);
  }
  return frame;
}

GeoFrame ToSeriesMetricFrame(const std::vector<Surface*>& surfaces, const std::vector<Crs>& crs,
                             const std::vector<std::string>& labels, FrameChoice choice) {
  int first = -1, geographic = -1;  // the first epoch with a CRS, the first geographic one
  for (std::size_t k = 0; k < crs.size(); ++k) {
    if (crs[k].kind != CrsKind::kNone && first < 0) first = static_cast<int>(k);
    if (crs[k].kind == CrsKind::kGeographic && geographic < 0) geographic = static_cast<int>(k);
  }
  GeoFrame frame;
  if (first < 0) {
    frame.datum = "no CRS";
    return frame;
  }
  const GdalModule& gdal = Gdal(labels[first]);
  for (std::size_t k = 0; k < crs.size(); ++k) {
    const auto refuse = [&](const std::string& why) {
      const int other = geographic >= 0 ? geographic : first;
      throw InputError(labels[k] + " (CRS " + crs[k].name + ") and " + labels[other] + " (CRS " +
                       crs[other].name + "): " + why);
    };
    if (geographic >= 0 && crs[k].kind == CrsKind::kNone) {
      refuse("one has no CRS and the other is in longitude and latitude; give the epochs' CRS (key "
             "'crs')");
    }
    if (geographic >= 0 && crs[k].kind == CrsKind::kProjected) {
      refuse("one is projected, the other geographic; give every epoch in one CRS (reproject)");
    }
    if (crs[k].kind == CrsKind::kNone || static_cast<int>(k) == first) continue;
    const int same = gdal.same_crs(crs[first].wkt, crs[k].wkt, geographic >= 0);
    if (same < 0) refuse("a CRS is unreadable");
    if (same == 0) {
      refuse(geographic >= 0 ? "different geographic datums; transform them onto one datum"
                             : "different CRSs; give every epoch in one CRS (reproject)");
    }
  }
  if (geographic < 0) {
    frame.datum = crs[first].name;
    frame.definition = gdal.identify_crs(crs[first].wkt);
    return frame;
  }
  frame = GeographicFrame(surfaces, DatumOf(crs[0]), choice);
  if (frame.kind == GeoFrame::kUtm) frame.definition = gdal.identify_utm(crs[0].wkt, frame.zone, frame.northp);
  return frame;
}

void PointsToFrame(const GeoFrame& frame, const Crs& crs,
                   std::vector<std::array<double, 3>>* points) {
  if (frame.kind == GeoFrame::kAsGiven) return;
  const Datum datum = DatumOf(crs);
  const FrameMap map(frame, datum);
  for (std::array<double, 3>& p : *points) {
    const double lon = p[0] + datum.prime_meridian_deg, lat = p[1], h = p[2];
    map.Forward(lat, lon, h, &p[0], &p[1], &p[2]);
  }
}

void PointsFromFrame(const GeoFrame& frame, const Crs& crs, std::vector<std::array<double, 3>>* points) {
  if (frame.kind == GeoFrame::kAsGiven) return;
  const Datum datum = DatumOf(crs);
  const FrameMap map(frame, datum);
  for (std::array<double, 3>& p : *points) {
    double lat = 0, lon = 0, h = 0;
    map.Reverse(p[0], p[1], p[2], &lat, &lon, &h);
    p = {lon - datum.prime_meridian_deg, lat, h};
  }
}

namespace {

// Latitude/longitude of a projected point through PROJ; false if unknown.
bool ProjectedToLonLat(const Crs& crs, double x, double y, double* lat, double* lon) {
  return Gdal("CRS '" + crs.name + "'").projected_to_lonlat(crs.wkt, x, y, lat, lon);
}

}  // namespace

GeographicOffset TranslationAsGeographic(const GeoFrame& frame, const Crs& crs,
                                         const std::array<double, 3>& p_input,
                                         const std::array<double, 3>& translation) {
  GeographicOffset offset;
  const auto& t = translation;
  if (frame.kind == GeoFrame::kAsGiven) {
    const double unit = crs.kind == CrsKind::kProjected ? crs.metres_per_unit : 1.0;
    offset.east_m = t[0] * unit, offset.north_m = t[1] * unit, offset.up_m = t[2];
    offset.dh_m = t[2];
    offset.dlat_deg = offset.dlon_deg = kNaN;
    double lat0, lon0, lat1, lon1;
    if (crs.kind == CrsKind::kProjected &&
        ProjectedToLonLat(crs, p_input[0], p_input[1], &lat0, &lon0) &&
        ProjectedToLonLat(crs, p_input[0] + t[0], p_input[1] + t[1], &lat1, &lon1)) {
      offset.dlat_deg = lat1 - lat0;
      offset.dlon_deg = Math::AngDiff(lon0, lon1);
    }
    return offset;
  }
  const Datum datum = DatumOf(crs);
  const FrameMap map(frame, datum);
  const double lat = p_input[1], lon = p_input[0] + datum.prime_meridian_deg, h = p_input[2];
  double x, y, z, lat1, lon1, h1;
  map.Forward(lat, lon, h, &x, &y, &z);
  map.Reverse(x + t[0], y + t[1], z + t[2], &lat1, &lon1, &h1);
  offset.dlat_deg = lat1 - lat;
  offset.dlon_deg = Math::AngDiff(lon, lon1);
  offset.dh_m = h1 - h;
  const GeographicLib::LocalCartesian at_p(lat, lon, h,
                                           GeographicLib::Geocentric(datum.a, datum.f));
  at_p.Forward(lat1, lon1, h1, offset.east_m, offset.north_m, offset.up_m);
  return offset;
}

}  // namespace surfreg
