#pragma once
// Coordinate reference systems of input surfaces, and the one metric frame
// in which two surfaces are compared. Measure() and Align() treat x, y, z as
// one Cartesian space, so longitude/latitude in degrees must be turned into
// metres first, and two surfaces in different CRSs must not be mixed. This
// is the only GeographicLib user; CRS text is parsed with GDAL/PROJ.
//
// Geographic surfaces: x = longitude, y = latitude (degrees, Greenwich or
// the CRS's prime meridian), z = ellipsoidal height (metres), whatever the
// axis order the CRS's authority defines. Longitudes must be continuous
// within a file (a surface crossing the antimeridian uses e.g. 179..181).
#include <array>
#include <string>
#include <vector>

#include "measure/surface.h"

namespace surfreg {

enum class CrsKind {
  kNone,        // no CRS known: coordinates are used as they are
  kProjected,   // planar x, y in a linear unit (also engineering/local CRSs)
  kGeographic,  // longitude, latitude in degrees on an ellipsoid
};

struct Crs {
  CrsKind kind = CrsKind::kNone;
  std::string wkt;             // WKT2 of the CRS; "" for kNone
  std::string name = "none";   // e.g. "WGS 84 / UTM zone 60S"; "none" for kNone
  double metres_per_unit = 1;  // linear unit of a projected CRS (0.3048 for ft); 1 otherwise
};

// Parses a raster's WKT or a config value: "EPSG:4326", "EPSG:32633", WKT,
// a PROJ string, or the shorthands "lonlat"/"geographic" (WGS 84 longitude,
// latitude in degrees, ellipsoidal height) and "none" or "" (kNone); no
// file or network look-ups. Throws InputError "<label>: unreadable CRS
// '<text>' (...)" for text that does not parse, and "<label>: ..." for
// CRSs that cannot describe a height field here (geocentric, vertical only,
// geographic in units other than degrees).
Crs ParseCrs(const std::string& text, const std::string& label);

enum class FrameChoice {
  kAuto,  // geographic pairs: UTM if both lie in one UTM zone, else ENU
  kEnu,   // geographic pairs: local east-north-up (tangent plane)
  kUtm,   // geographic pairs: UTM zone of the centre of the data
};

// The choice a `frame` key's value names: "enu", "utm", else kAuto.
FrameChoice FrameChoiceOf(const std::string& frame);

struct GeoFrame {
  enum Kind {
    kAsGiven,  // input coordinates kept (no CRS, or one projected CRS)
    kEnu,      // GeographicLib::LocalCartesian about (lat0, lon0, h0)
    kUtm,      // transverse Mercator, UTM zone `zone`, scale 0.9996, false easting 500 km
  } kind = kAsGiven;
  double lat0 = 0, lon0 = 0, h0 = 0;  // ENU origin: degrees (Greenwich), metres
  int zone = 0;                       // UTM zone 1..60
  bool northp = true;                 // UTM hemisphere (false northing 10000 km if false)
  std::string datum;  // name of the geographic CRS for kEnu/kUtm ("WGS 84"), else the CRS name
  // The frame as others can rebuild it: an EPSG code ("EPSG:32760" for UTM
  // or a projected CRS that has one), else a PROJ string (ENU: the
  // geodetic-to-topocentric pipeline from lon, lat in degrees and
  // ellipsoidal height); "" without a CRS. Set by ToCommonMetricFrame.
  std::string definition;

  // One line, e.g. "UTM zone 60S (WGS 84; EPSG:32760)" or "local ENU about
  // 36.85S 174.76E, h 0 m (WGS 84; +proj=pipeline ...)", numbers in the
  // shortest text that reads back as the same double.
  std::string Describe() const;
};

// "WGS 84 (EPSG:4326)": the CRS's name and its EPSG code (or PROJ string)
// when known; "none" for kNone.
std::string DescribeCrs(const Crs& crs);

// Whether two CRSs are the same (both none counts as the same).
bool SameCrs(const Crs& a, const Crs& b);

// Moves every sample of `surface` from CRS `from` into CRS `to` (GDAL/PROJ;
// heights unchanged unless the CRSs carry vertical datums), keeping a
// raster's cells and the weights. Throws InputError naming the surface and
// both CRSs if a point cannot be transformed.
void ReprojectSurface(Surface* surface, const Crs& from, const Crs& to);

// Brings both surfaces into one metric frame, in place (rebuilt with
// MakeSurface, origin rounded to 1 m; weights and source kept), and returns
// that frame:
//   both kNone                            -> kAsGiven
//   both projected and the same CRS       -> kAsGiven (in that CRS's unit)
//   both geographic on the same datum     -> kUtm if `choice` is kUtm, or kAuto and
//       both bounding-box centres are in the same UTM zone; otherwise kEnu about the
//       centre of the overlap of the two lon/lat bounding boxes (of their union if
//       they do not overlap), h0 = 0. UTM heights stay ellipsoidal heights; ENU z is
//       the height above the tangent plane at the origin.
//   anything else -> InputError naming both CRSs and both files (reference first).
// The ellipsoid of the geographic CRS is used (not always WGS 84). Latitudes
// outside [-90, 90] are an InputError (projected coordinates labelled
// geographic). kUtm near the poles (where UTM is undefined) is an error.
GeoFrame ToCommonMetricFrame(Surface* reference, const Crs& reference_crs, Surface* moving,
                             const Crs& moving_crs, FrameChoice choice);

// The same for the epochs of a series, in place, surfaces[k] in crs[k]
// (labels[k] names it in errors, e.g. "epoch 2 (c.tif)"); surfaces[0] takes
// the reference's part above:
//   no CRS or projected -> kAsGiven: every projected epoch in one CRS (epochs
//       without a CRS are taken as in it);
//   geographic -> every epoch geographic on one datum: kUtm if `choice` is
//       kUtm, or kAuto and every bounding-box centre is in one UTM zone, else
//       kEnu about the centre of the part all bounding boxes share (of their
//       union if they share none), h0 = 0.
// An epoch without a CRS among geographic ones, or projected beside them, is
// an InputError naming both epochs.
GeoFrame ToSeriesMetricFrame(const std::vector<Surface*>& surfaces, const std::vector<Crs>& crs,
                             const std::vector<std::string>& labels, FrameChoice choice);

// Points of `crs` (input coordinates: lon, lat, h for geographic) into
// `frame`, in place, as ToCommonMetricFrame moves surfaces; kAsGiven
// leaves them as they are. E.g. a mask polygon drawn in input coordinates.
void PointsToFrame(const GeoFrame& frame, const Crs& crs,
                   std::vector<std::array<double, 3>>* points);

// The inverse: points of `frame` back into `crs` (lon, lat, h for
// geographic), in place; kAsGiven leaves them as they are.
void PointsFromFrame(const GeoFrame& frame, const Crs& crs, std::vector<std::array<double, 3>>* points);

// A translation as seen on the ground.
struct GeographicOffset {
  double dlat_deg = 0, dlon_deg = 0;         // change of latitude/longitude (NaN if unknown)
  double dh_m = 0;                           // change of ellipsoidal height (z units for kAsGiven)
  double east_m = 0, north_m = 0, up_m = 0;  // the displacement in the local ENU frame at p
};

// The translation `translation` (in the frame's units) applied to the point
// `p_input` (input coordinates of `crs`: lon, lat, h for geographic), as a
// change of latitude/longitude/height of that point plus its east/north/up
// components in metres, measured in the tangent plane at p (so UTM's scale
// factor and meridian convergence are taken out). For kAsGiven frames:
// east, north = t.x, t.y times metres_per_unit; up = dh = t.z (vertical
// units are not known); lat/lon offsets through PROJ (to WGS 84) when the
// CRS is projected, else NaN.
GeographicOffset TranslationAsGeographic(const GeoFrame& frame, const Crs& crs,
                                         const std::array<double, 3>& p_input,
                                         const std::array<double, 3>& translation);

}  // namespace surfreg
