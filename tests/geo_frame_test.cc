// CRS parsing and the common metric frame. Truth comes from outside
// GeographicLib: PROJ (through GDAL's OGRCoordinateTransformation), closed-
// form ellipsoid formulas written here, and a published UTM example.
#include "terrain/geo_frame.h"

#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "tests/testing/file_checks.h"
#include "measure/measures.h"
#include "io/raster_io.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kA = 6378137.0, kF = 1 / 298.257223563;  // WGS 84
constexpr double kE2 = kF * (2 - kF);

// One-line InputError messages, with nothing on stderr (file_checks.h).
inline std::string ErrorOf(const std::function<void()>& f) { return testing::SilentErrorOf(f); }
using testing::Contains;

std::array<double, 3> At(const Surface& s, size_t i) {
  return {s.origin[0] + s.xy[i].x, s.origin[1] + s.xy[i].y, s.origin[2] + s.z[i]};
}

Surface Points(const std::vector<std::array<double, 3>>& p, const std::string& name) {
  return MakeSurface(p, {}, name, 1.0);
}

// PROJ: lon/lat in `source` to `target` (x = easting) for each point, in place.
void ProjTransform(const char* target, std::vector<std::array<double, 3>>* points,
                   const char* source = "EPSG:4326") {
  OGRSpatialReference from, to;
  from.SetFromUserInput(source);
  to.SetFromUserInput(target);
  from.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&from, &to));
  ASSERT_TRUE(t);
  for (auto& p : *points) ASSERT_TRUE(t->Transform(1, &p[0], &p[1]));
}

// Radii of curvature, meridian (M) and prime vertical (N), at latitude φ.
double MeridianRadius(double lat) {
  const double w = 1 - kE2 * std::sin(lat * kDeg) * std::sin(lat * kDeg);
  return kA * (1 - kE2) / (w * std::sqrt(w));
}
double NormalRadius(double lat) {
  return kA / std::sqrt(1 - kE2 * std::sin(lat * kDeg) * std::sin(lat * kDeg));
}

// East-north-up of (lat, lon, h) about (lat0, lon0, 0), by the textbook
// formulas: geocentric coordinates, then the rotation into the tangent plane.
std::array<double, 3> Enu(double lat0, double lon0, double lat, double lon, double h) {
  const auto ecef = [](double la, double lo, double hh) {
    const double n = NormalRadius(la);
    return std::array<double, 3>{(n + hh) * std::cos(la * kDeg) * std::cos(lo * kDeg),
                                 (n + hh) * std::cos(la * kDeg) * std::sin(lo * kDeg),
                                 (n * (1 - kE2) + hh) * std::sin(la * kDeg)};
  };
  const auto p = ecef(lat, lon, h), o = ecef(lat0, lon0, 0);
  const double d[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
  const double sf = std::sin(lat0 * kDeg), cf = std::cos(lat0 * kDeg);
  const double sl = std::sin(lon0 * kDeg), cl = std::cos(lon0 * kDeg);
  return {-sl * d[0] + cl * d[1], -sf * cl * d[0] - sf * sl * d[1] + cf * d[2],
          cf * cl * d[0] + cf * sl * d[1] + sf * d[2]};
}

const Crs& LonLat() {
  static const Crs crs = ParseCrs("lonlat", "test");
  return crs;
}

// --- ParseCrs --------------------------------------------------------------

TEST(ParseCrsTest, EpsgCodesWktProjStringsAndShorthands) {
  const Crs g = ParseCrs("EPSG:4326", "k");
  EXPECT_EQ(g.kind, CrsKind::kGeographic);
  EXPECT_EQ(g.name, "WGS 84");
  EXPECT_FALSE(g.wkt.empty());
  const Crs u = ParseCrs(" EPSG:32633 ", "k");
  EXPECT_EQ(u.kind, CrsKind::kProjected);
  EXPECT_EQ(u.name, "WGS 84 / UTM zone 33N");
  EXPECT_EQ(u.metres_per_unit, 1.0);
  const Crs feet = ParseCrs("EPSG:2227", "k");  // NAD83 / California zone 3 (ftUS)
  EXPECT_EQ(feet.kind, CrsKind::kProjected);
  EXPECT_NEAR(feet.metres_per_unit, 1200.0 / 3937.0, 1e-15);
  const Crs from_wkt = ParseCrs(u.wkt, "k");
  EXPECT_EQ(from_wkt.kind, CrsKind::kProjected);
  EXPECT_EQ(from_wkt.name, u.name);
  const Crs proj = ParseCrs("+proj=utm +zone=60 +south +datum=WGS84 +units=m +no_defs", "k");
  EXPECT_EQ(proj.kind, CrsKind::kProjected);
  for (const char* text : {"lonlat", "geographic", "LonLat"}) {
    const Crs s = ParseCrs(text, "k");
    EXPECT_EQ(s.kind, CrsKind::kGeographic) << text;
    EXPECT_EQ(s.name, "WGS 84") << text;
  }
  for (const char* text : {"none", "", "  NONE "}) {
    const Crs s = ParseCrs(text, "k");
    EXPECT_EQ(s.kind, CrsKind::kNone) << text;
    EXPECT_EQ(s.wkt, "") << text;
  }
}

TEST(ParseCrsTest, GarbageAndUnusableCrssAreInputErrors) {
  EXPECT_TRUE(Contains(ErrorOf([] { ParseCrs("not a crs", "t.yaml:3: key 'crs'"); }),
                       "t.yaml:3: key 'crs': unreadable CRS 'not a crs'"));
  EXPECT_TRUE(Contains(ErrorOf([] { ParseCrs("EPSG:999999", "flag --crs"); }),
                       "flag --crs: unreadable CRS 'EPSG:999999'"));
  EXPECT_TRUE(Contains(ErrorOf([] { ParseCrs("GEOGCS[\"x\",", "k"); }), "k: unreadable CRS"));
  // A file name is not read (config text stays text).
  const std::string file = ::testing::TempDir() + "geo_frame_test_crs.wkt";
  std::ofstream(file) << ParseCrs("EPSG:4326", "k").wkt;
  EXPECT_TRUE(Contains(ErrorOf([&] { ParseCrs(file, "k"); }), "k: unreadable CRS"));
  EXPECT_TRUE(Contains(ErrorOf([] { ParseCrs("EPSG:4978", "k"); }), "is geocentric"));
  EXPECT_TRUE(
      Contains(ErrorOf([] { ParseCrs("EPSG:5703", "k"); }), "is neither projected nor geographic"));
}

// --- UTM and ENU conversions -----------------------------------------------

TEST(ToCommonMetricFrameTest, UtmMatchesAPublishedExampleAndProj) {
  // Baghdad, lat 33.3, lon 44.4: UTM 38N 444140.54 3684706.36 (GeographicLib's
  // UTMUPS example, 1 cm).
  std::vector<std::array<double, 3>> ll = {
      {44.4, 33.3, 10.0}, {44.41, 33.31, 20.0}, {44.39, 33.32, -5.0}, {44.43, 33.28, 7.5}};
  Surface a = Points(ll, "a"), b = Points(ll, "b");
  const GeoFrame frame = ToCommonMetricFrame(&a, LonLat(), &b, LonLat(), FrameChoice::kAuto);
  EXPECT_EQ(frame.kind, GeoFrame::kUtm);
  EXPECT_EQ(frame.zone, 38);
  EXPECT_TRUE(frame.northp);
  EXPECT_EQ(frame.Describe(), "UTM zone 38N (WGS 84; EPSG:32638)");
  EXPECT_NEAR(At(a, 0)[0], 444140.54, 0.005);
  EXPECT_NEAR(At(a, 0)[1], 3684706.36, 0.005);
  ProjTransform("EPSG:32638", &ll);
  for (size_t i = 0; i < ll.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(At(a, i)[k], ll[i][k], 1e-6) << i << " " << k;  // heights unchanged
      EXPECT_NEAR(At(b, i)[k], ll[i][k], 1e-6) << i << " " << k;
    }
  }
  EXPECT_EQ(a.source, "a");
}

TEST(ToCommonMetricFrameTest, SouthernHemisphereUtmMatchesProjAndKeepsWeights) {
  std::vector<std::array<double, 3>> ll;
  for (int i = 0; i < 25; ++i)
    ll.push_back({174.7 + 0.013 * (i % 5), -36.9 + 0.011 * (i / 5), 1.0 * i});
  Surface a = MakeSurface(ll, std::vector<double>(25, 0.5), "a.tif");
  Surface b = Points(ll, "b.tif");
  const GeoFrame frame = ToCommonMetricFrame(&a, LonLat(), &b, LonLat(), FrameChoice::kUtm);
  EXPECT_EQ(frame.Describe(), "UTM zone 60S (WGS 84; EPSG:32760)");
  ProjTransform("EPSG:32760", &ll);
  for (size_t i = 0; i < ll.size(); ++i) {
    EXPECT_NEAR(At(a, i)[0], ll[i][0], 1e-6);
    EXPECT_NEAR(At(a, i)[1], ll[i][1], 1e-6);
    EXPECT_EQ(At(a, i)[2], ll[i][2]);
  }
  EXPECT_EQ(a.weight, std::vector<double>(25, 0.5));
  EXPECT_TRUE(b.weight.empty());
}

TEST(ToCommonMetricFrameTest, UtmUsesTheEllipsoidOfTheCrs) {
  // NAD27 (Clarke 1866) lon/lat to NAD27 / UTM zone 10N: a pure projection
  // on another ellipsoid (WGS 84's would be off by metres).
  std::vector<std::array<double, 3>> ll = {{-122.4, 37.7, 0}, {-122.3, 37.8, 1}, {-122.4, 37.8, 2}};
  const Crs nad27 = ParseCrs("EPSG:4267", "k");
  Surface a = Points(ll, "a"), b = Points(ll, "b");
  const GeoFrame frame = ToCommonMetricFrame(&a, nad27, &b, nad27, FrameChoice::kAuto);
  EXPECT_EQ(frame.Describe(), "UTM zone 10N (NAD27; EPSG:26710)");
  ProjTransform("EPSG:26710", &ll, "EPSG:4267");
  for (size_t i = 0; i < ll.size(); ++i) {
    EXPECT_NEAR(At(a, i)[0], ll[i][0], 1e-6);
    EXPECT_NEAR(At(a, i)[1], ll[i][1], 1e-6);
  }
}

TEST(ToCommonMetricFrameTest, EnuMatchesTheClosedFormAboutTheOverlapCentre) {
  // Boxes [7.00, 7.04] x [45.00, 45.02] and [7.02, 7.06] x [45.01, 45.03]:
  // the overlap [7.02, 7.04] x [45.01, 45.02] is centred at (7.03, 45.015).
  std::vector<std::array<double, 3>> pa = {
      {7.00, 45.00, 100}, {7.04, 45.00, 120}, {7.00, 45.02, 90}, {7.04, 45.02, 300}};
  std::vector<std::array<double, 3>> pb = {
      {7.02, 45.01, 100}, {7.06, 45.01, 120}, {7.02, 45.03, 90}, {7.06, 45.03, 300}};
  Surface a = Points(pa, "a"), b = Points(pb, "b");
  const GeoFrame frame = ToCommonMetricFrame(&a, LonLat(), &b, LonLat(), FrameChoice::kEnu);
  ASSERT_EQ(frame.kind, GeoFrame::kEnu);
  EXPECT_NEAR(frame.lat0, 45.015, 1e-12);
  EXPECT_NEAR(frame.lon0, 7.03, 1e-12);
  EXPECT_EQ(frame.h0, 0.0);
  // The origin to the last bit (7.03 is not the double nearest 7.03 here).
  EXPECT_EQ(frame.Describe(),
            "local ENU about 45.015N 7.029999999999999E, h 0 m (WGS 84; +proj=pipeline +step "
            "+proj=unitconvert +xy_in=deg +xy_out=rad +step +proj=cart +ellps=WGS84 +step "
            "+proj=topocentric +ellps=WGS84 +lat_0=45.015 +lon_0=7.029999999999999 +h_0=0)");
  for (size_t i = 0; i < 4; ++i) {
    const auto ea = Enu(frame.lat0, frame.lon0, pa[i][1], pa[i][0], pa[i][2]);
    const auto eb = Enu(frame.lat0, frame.lon0, pb[i][1], pb[i][0], pb[i][2]);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(At(a, i)[k], ea[k], 1e-6) << i << " " << k;
      EXPECT_NEAR(At(b, i)[k], eb[k], 1e-6) << i << " " << k;
    }
  }
}

// The frame's definition rebuilds it outside surfreg: the ENU pipeline run
// by PROJ gives our coordinates, and Describe() gives the origin exactly.
TEST(ToCommonMetricFrameTest, EnuDefinitionIsAProjPipelineOfTheFrame) {
  for (const char* text : {"EPSG:4326", "EPSG:4267"}) {  // WGS 84; NAD27 (Clarke 1866: +a +rf)
    const Crs crs = ParseCrs(text, "k");
    std::vector<std::array<double, 3>> p = {{-122.412345678901, 37.70123456789, 10},
                                            {-122.301, 37.8, 250},
                                            {-122.4, 37.8123456789, -20}};
    Surface a = Points(p, "a"), b = Points(p, "b");
    const GeoFrame frame = ToCommonMetricFrame(&a, crs, &b, crs, FrameChoice::kEnu);
    ASSERT_EQ(frame.kind, GeoFrame::kEnu);
    const std::string text_of_frame = frame.Describe();
    double lat = 0, lon = 0;
    char ns = 0, ew = 0;
    ASSERT_EQ(std::sscanf(text_of_frame.c_str(), "local ENU about %lf%c %lf%c", &lat, &ns, &lon, &ew),
              4)
        << text_of_frame;
    EXPECT_EQ(ns == 'S' ? -lat : lat, frame.lat0) << text_of_frame;
    EXPECT_EQ(ew == 'W' ? -lon : lon, frame.lon0) << text_of_frame;
    EXPECT_TRUE(Contains(text_of_frame, frame.definition));
    OGRCoordinateTransformationOptions options;
    ASSERT_TRUE(options.SetCoordinateOperation(frame.definition.c_str(), false));
    std::unique_ptr<OGRCoordinateTransformation> t(
        OGRCreateCoordinateTransformation(nullptr, nullptr, options));
    ASSERT_TRUE(t) << frame.definition;
    for (size_t i = 0; i < p.size(); ++i) {
      ASSERT_TRUE(t->Transform(1, &p[i][0], &p[i][1], &p[i][2]));
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(At(a, i)[k], p[i][k], 1e-6) << text << " " << i;
    }
  }
  EXPECT_EQ(DescribeCrs(ParseCrs("lonlat", "k")), "WGS 84 (EPSG:4326)");
  EXPECT_EQ(DescribeCrs(ParseCrs("EPSG:2193", "k")),
            "NZGD2000 / New Zealand Transverse Mercator 2000 (EPSG:2193)");
  EXPECT_EQ(DescribeCrs(ParseCrs("none", "k")), "none");
  // An ESRI .prj's WKT: the EPSG CRS it is, but for the names.
  const Crs esri = ParseCrs(
      "GEOGCS[\"GCS_WGS_1984\",DATUM[\"D_WGS_1984\",SPHEROID[\"WGS_1984\",6378137.0,"
      "298.257223563]],PRIMEM[\"Greenwich\",0.0],UNIT[\"Degree\",0.0174532925199433]]",
      "k");
  EXPECT_TRUE(Contains(DescribeCrs(esri), "(EPSG:4326)")) << DescribeCrs(esri);
  Surface a = Points({{174.7, -36.9, 0}, {174.71, -36.9, 0}, {174.7, -36.89, 1}}, "a");
  Surface b = a;
  EXPECT_EQ(ToCommonMetricFrame(&a, esri, &b, esri, FrameChoice::kAuto).definition, "EPSG:32760");
  // No EPSG code: the PROJ string.
  const Crs custom = ParseCrs("+proj=tmerc +lon_0=173.3 +k=0.9996 +x_0=1600000 +ellps=GRS80", "k");
  EXPECT_TRUE(Contains(DescribeCrs(custom), "(+proj=tmerc +lat_0=0 +lon_0=173.3 +k=0.9996"))
      << DescribeCrs(custom);
}

TEST(ToCommonMetricFrameTest, AutoChoosesEnuAcrossZonesAboutTheUnionOfDisjointBoxes) {
  // Zones 31 (lon 5.9) and 32 (lon 6.1); boxes disjoint: the union
  // [5.8, 6.2] x [45.0, 45.1] is centred at (6.0, 45.05).
  Surface a = Points({{5.8, 45.0, 0}, {5.9, 45.0, 0}, {5.8, 45.1, 1}}, "a");
  Surface b = Points({{6.1, 45.0, 0}, {6.2, 45.0, 0}, {6.2, 45.1, 1}}, "b");
  const GeoFrame frame = ToCommonMetricFrame(&a, LonLat(), &b, LonLat(), FrameChoice::kAuto);
  EXPECT_EQ(frame.kind, GeoFrame::kEnu);
  EXPECT_NEAR(frame.lat0, 45.05, 1e-12);
  EXPECT_NEAR(frame.lon0, 6.0, 1e-12);
  // Longitudes 360 degrees apart are the same place: 179.9 vs -179.95 overlap.
  Surface c = Points({{179.9, 0, 0}, {180.1, 0, 0}, {179.9, 0.1, 1}}, "c");
  Surface d = Points({{-179.95, 0, 0}, {-179.85, 0, 0}, {-179.95, 0.1, 1}}, "d");
  const GeoFrame wrap = ToCommonMetricFrame(&c, LonLat(), &d, LonLat(), FrameChoice::kEnu);
  EXPECT_NEAR(wrap.lon0, -179.925, 1e-9);  // centre of the overlap [180.05, 180.1]
  // East on the equator is N sin(lon - lon0): 180.1 and 180.15 (= -179.85) are 0.05 deg apart.
  EXPECT_NEAR(At(d, 1)[0] - At(c, 1)[0],
              NormalRadius(0) * (std::sin(0.075 * kDeg) - std::sin(0.025 * kDeg)), 1e-3);
}

TEST(ToCommonMetricFrameTest, PolarDataUseEnuOrFailForUtm) {
  auto polar = [](const char* name) {
    return Points({{10, 85.0, 0}, {11, 85.0, 0}, {10, 85.1, 1}}, name);
  };
  Surface a = polar("a"), b = polar("b");
  EXPECT_EQ(ToCommonMetricFrame(&a, LonLat(), &b, LonLat(), FrameChoice::kAuto).kind,
            GeoFrame::kEnu);
  Surface c = polar("c"), d = polar("d");
  EXPECT_EQ(ErrorOf([&] { ToCommonMetricFrame(&c, LonLat(), &d, LonLat(), FrameChoice::kUtm); }),
            "c and d: UTM is not defined at latitude 85.0500 (polar); use frame enu");
}

TEST(ToCommonMetricFrameTest, AsGivenForNoCrsAndForOneProjectedCrs) {
  const std::vector<std::array<double, 3>> p = {
      {500000, 6e6, 1}, {500010, 6e6, 2}, {500000, 6e6 + 10, 3}};
  for (const char* text : {"none", "EPSG:32760", "EPSG:2227"}) {
    const Crs crs = ParseCrs(text, "k");
    Surface a = Points(p, "a"), b = Points(p, "b");
    const GeoFrame frame = ToCommonMetricFrame(&a, crs, &b, ParseCrs(text, "k"), FrameChoice::kUtm);
    EXPECT_EQ(frame.kind, GeoFrame::kAsGiven) << text;
    for (size_t i = 0; i < 3; ++i) EXPECT_EQ(At(a, i), p[i]);
  }
  Surface a = Points(p, "a"), b = Points(p, "b");
  const Crs utm = ParseCrs("EPSG:32760", "k");
  EXPECT_EQ(ToCommonMetricFrame(&a, utm, &b, utm, FrameChoice::kAuto).Describe(),
            "coordinates as given (WGS 84 / UTM zone 60S; EPSG:32760)");
  EXPECT_EQ(GeoFrame().Describe(), "coordinates as given (no CRS)");
}

TEST(ToCommonMetricFrameTest, MismatchedCrssNameBothCrssAndFiles) {
  const std::vector<std::array<double, 3>> p = {{170, -40, 1}, {170.1, -40, 2}, {170, -39.9, 3}};
  const auto error = [&](const char* ref, const char* mov) {
    Surface a = Points(p, "ref.tif"), b = Points(p, "mov.xyz");
    return ErrorOf([&] {
      ToCommonMetricFrame(&a, ParseCrs(ref, "k"), &b, ParseCrs(mov, "k"), FrameChoice::kAuto);
    });
  };
  EXPECT_EQ(error("EPSG:32760", "lonlat"),
            "reference ref.tif (CRS WGS 84 / UTM zone 60S) and moving mov.xyz (CRS WGS 84): one "
            "is projected, the other geographic; give both the same CRS (reproject, or set it)");
  EXPECT_TRUE(Contains(error("EPSG:32760", "EPSG:32759"),
                       "(CRS WGS 84 / UTM zone 60S) and moving mov.xyz (CRS WGS 84 / UTM zone "
                       "59S): different projected CRSs; reproject"));
  EXPECT_TRUE(Contains(error("EPSG:32760", "EPSG:2227"), "(and not both in metres)"));
  EXPECT_TRUE(Contains(error("none", "lonlat"),
                       "reference ref.tif (CRS none) and moving mov.xyz (CRS WGS 84): the moving "
                       "surface has a CRS and the reference has none; give it with the key "
                       "'reference_crs' (flag --reference_crs)"));
  EXPECT_TRUE(Contains(error("EPSG:32760", "none"), "give it with the key 'moving_crs'"));
  EXPECT_TRUE(
      Contains(error("EPSG:4326", "EPSG:4267"), "(CRS NAD27): different geographic datums"));
  Surface a = Points({{500000, 6e6, 0}, {500001, 6e6, 0}, {500000, 6e6 + 1, 0}}, "utm.xyz");
  Surface b = Points(p, "b");
  EXPECT_TRUE(Contains(
      ErrorOf([&] { ToCommonMetricFrame(&a, LonLat(), &b, LonLat(), FrameChoice::kAuto); }),
      "utm.xyz: point 1 (500000, 6000000) is not a longitude, latitude in degrees"));
}

// ReprojectSurface: lon/lat samples brought into UTM 60S land where PROJ puts
// them, to the micrometre; weights and raster cells stay with their samples;
// SameCrs tells the two apart. A point PROJ cannot map names the surface.
TEST(ReprojectSurfaceTest, LonLatIntoUtmMatchesProjAndKeepsSamples) {
  std::vector<std::array<double, 3>> lonlat;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) lonlat.push_back({174.7 + 0.01 * i, -36.9 + 0.01 * j, 10.0 * i + j});
  }
  std::vector<std::array<double, 3>> utm = lonlat;
  ProjTransform("EPSG:32760", &utm);
  Surface s = MakeSurface(lonlat, std::vector<double>(lonlat.size(), 0.5), "ll.xyz", 1.0);
  for (int i = 0; i < static_cast<int>(s.size()); ++i) s.raster_cell.push_back({i % 4, i / 4});
  const Crs utm_crs = ParseCrs("EPSG:32760", "k");
  EXPECT_FALSE(SameCrs(LonLat(), utm_crs));
  EXPECT_TRUE(SameCrs(utm_crs, ParseCrs("EPSG:32760", "k")));
  EXPECT_TRUE(SameCrs(ParseCrs("none", "k"), ParseCrs("none", "k")));
  ReprojectSurface(&s, LonLat(), utm_crs);
  ASSERT_EQ(s.size(), utm.size());
  for (std::size_t i = 0; i < utm.size(); ++i) {
    const std::array<double, 3> p = At(s, i);
    EXPECT_NEAR(p[0], utm[i][0], 1e-6);
    EXPECT_NEAR(p[1], utm[i][1], 1e-6);
    EXPECT_EQ(p[2], lonlat[i][2]);  // no vertical datum: heights as they were
    EXPECT_EQ(s.weight[i], 0.5);
    EXPECT_EQ(s.raster_cell[i].column, static_cast<int>(i) % 4);
  }
  Surface far = Points({{0, 95, 0}, {1, 95, 0}, {0, 96, 0}}, "far.xyz");  // latitude 95
  EXPECT_TRUE(Contains(ErrorOf([&] { ReprojectSurface(&far, LonLat(), utm_crs); }),
                       "far.xyz: cannot reproject from CRS 'WGS 84' to 'WGS 84 / UTM zone 60S'"));
}

// --- the acceptance test: lon/lat pair vs its UTM reprojection by PROJ ------

double Height(double lon, double lat, bool moved) {
  const double u = (lon - 174.76) * 200, v = (lat + 36.87) * 200;
  double z = 40 + 15 * std::sin(u) * std::cos(0.7 * v) + 5 * u * v;
  if (moved) z += 2 + 3 * std::exp(-((u - 1) * (u - 1) + v * v));
  return z;
}

Raster LonLatDem(bool moved) {
  Raster r;
  r.columns = r.rows = 60;
  r.geotransform = {174.745, 0.0005, 0, -36.855, 0, -0.0005};
  r.crs_wkt = ParseCrs("EPSG:4326", "k").wkt;
  for (int row = 0; row < 60; ++row) {
    for (int c = 0; c < 60; ++c) {
      const Point2 p = r.CellCentre(c, row);
      r.values.push_back(Height(p.x, p.y, moved));
    }
  }
  return r;
}

TEST(ToCommonMetricFrameTest, LonLatRasterPairMeasuresLikeItsProjReprojection) {
  const std::string dir = ::testing::TempDir();
  WriteGeoTiff(dir + "geo_frame_a.tif", LonLatDem(false), "test");
  WriteGeoTiff(dir + "geo_frame_b.tif", LonLatDem(true), "test");
  const Raster ra = ReadRaster(dir + "geo_frame_a.tif"), rb = ReadRaster(dir + "geo_frame_b.tif");
  const Crs crs = ParseCrs(ra.crs_wkt, "a.tif");
  ASSERT_EQ(crs.kind, CrsKind::kGeographic);

  // (i) ours: UTM through GeographicLib.
  Surface a = RasterToSurface(ra, nullptr), b = RasterToSurface(rb, nullptr);
  const GeoFrame frame =
      ToCommonMetricFrame(&a, crs, &b, ParseCrs(rb.crs_wkt, "b"), FrameChoice::kAuto);
  EXPECT_EQ(frame.Describe(), "UTM zone 60S (WGS 84; EPSG:32760)");
  const double rho_utm = Measure(a, b).rho_d;

  // (ii) the same cell centres reprojected by PROJ, the same grid cells.
  std::vector<std::array<double, 3>> pa, pb;
  std::vector<RasterCell> cells;
  for (int row = 0; row < 60; ++row) {
    for (int c = 0; c < 60; ++c) {
      const Point2 p = ra.CellCentre(c, row);
      pa.push_back({p.x, p.y, ra.values[row * 60 + c]});
      pb.push_back({p.x, p.y, rb.values[row * 60 + c]});
      cells.push_back({c, row});
    }
  }
  ProjTransform("EPSG:32760", &pa);
  ProjTransform("EPSG:32760", &pb);
  Surface proj_a = Points(pa, "pa"), proj_b = Points(pb, "pb");
  proj_a.raster_cell = proj_b.raster_cell = cells;
  const double rho_proj = Measure(proj_a, proj_b).rho_d;
  std::printf("rho_d: UTM %.12g, PROJ %.12g (relative %.2e)\n", rho_utm, rho_proj,
              rho_utm / rho_proj - 1);
  EXPECT_GT(rho_proj, 1e6);  // a real volume (m³), not a degenerate zero
  // The same cells on both sides: the surfaces differ only as the projections do.
  EXPECT_LT(std::fabs(rho_utm - rho_proj) / rho_proj, 1e-9) << rho_utm << " vs " << rho_proj;

  // ENU: true distances, UTM's differ by its scale factor (~1e-4 here).
  Surface ea = RasterToSurface(ra, nullptr), eb = RasterToSurface(rb, nullptr);
  ToCommonMetricFrame(&ea, crs, &eb, crs, FrameChoice::kEnu);
  const double rho_enu = Measure(ea, eb).rho_d;
  std::printf("rho_d: ENU %.12g (relative to UTM %.2e)\n", rho_enu, rho_enu / rho_utm - 1);
  EXPECT_LT(std::fabs(rho_enu - rho_utm) / rho_utm, 1e-3) << rho_enu << " vs " << rho_utm;
  std::remove((dir + "geo_frame_a.tif").c_str());
  std::remove((dir + "geo_frame_b.tif").c_str());
}

// --- TranslationAsGeographic -------------------------------------------------

TEST(TranslationAsGeographicTest, EnuMetreNorthAndEastAt45North) {
  GeoFrame frame;
  frame.kind = GeoFrame::kEnu;
  frame.lat0 = 45, frame.lon0 = 7;
  const std::array<double, 3> p = {7, 45, 0};
  const GeographicOffset north = TranslationAsGeographic(frame, LonLat(), p, {0, 1, 0});
  EXPECT_NEAR(north.dlat_deg, 1 / (MeridianRadius(45) * kDeg), 1e-6 * north.dlat_deg);
  EXPECT_NEAR(north.dlat_deg * 111132.0, 1.0, 1e-4);  // the survey rule of thumb
  EXPECT_NEAR(north.dlon_deg, 0, 1e-15);
  EXPECT_NEAR(north.north_m, 1, 1e-9);
  EXPECT_NEAR(north.east_m, 0, 1e-9);
  EXPECT_NEAR(north.dh_m, 0, 1e-6);  // curvature: 1 / (2 R) m
  const GeographicOffset east = TranslationAsGeographic(frame, LonLat(), p, {1, 0, 0});
  EXPECT_NEAR(east.dlon_deg, 1 / (NormalRadius(45) * std::cos(45 * kDeg) * kDeg),
              1e-6 * east.dlon_deg);
  EXPECT_NEAR(east.east_m, 1, 1e-9);
  const GeographicOffset up = TranslationAsGeographic(frame, LonLat(), p, {0, 0, 2.5});
  EXPECT_NEAR(up.dh_m, 2.5, 1e-9);
  EXPECT_NEAR(up.up_m, 2.5, 1e-9);
  EXPECT_NEAR(up.dlat_deg, 0, 1e-13);  // ulp(45) = 7e-15
}

TEST(TranslationAsGeographicTest, UtmOnTheCentralMeridianAndAgainstProj) {
  GeoFrame frame;
  frame.kind = GeoFrame::kUtm;
  frame.zone = 60, frame.northp = false;
  const double lat = -36.87;
  // On the central meridian (177E) the scale is exactly 0.9996 and grid north is north;
  // at height h the same change of latitude spans (M + h) / M times the arc on the ellipsoid.
  const double h = 5, m = MeridianRadius(lat);
  const GeographicOffset o = TranslationAsGeographic(frame, LonLat(), {177, lat, h}, {0, 1, 0});
  EXPECT_NEAR(o.north_m, (m + h) / (0.9996 * m), 1e-9);
  EXPECT_NEAR(o.east_m, 0, 1e-9);
  EXPECT_NEAR(o.dlat_deg, 1 / (0.9996 * m * kDeg), 1e-6 * o.dlat_deg);
  EXPECT_EQ(o.dh_m, 0);
  // Off the meridian, against PROJ: p to UTM, add t, back to lon/lat.
  const std::array<double, 3> t = {3, -4, 1.5};
  std::vector<std::array<double, 3>> q = {{174.76, lat, 0}};
  ProjTransform("EPSG:32760", &q);
  q[0][0] += t[0], q[0][1] += t[1];
  OGRSpatialReference utm, ll;
  utm.SetFromUserInput("EPSG:32760");
  ll.SetFromUserInput("EPSG:4326");
  utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  ll.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> back(OGRCreateCoordinateTransformation(&utm, &ll));
  ASSERT_TRUE(back->Transform(1, &q[0][0], &q[0][1]));
  const GeographicOffset g = TranslationAsGeographic(frame, LonLat(), {174.76, lat, 0}, t);
  EXPECT_NEAR(g.dlat_deg, q[0][1] - lat, 1e-11);  // 1e-11 deg ~ 1 µm
  EXPECT_NEAR(g.dlon_deg, q[0][0] - 174.76, 1e-11);
  EXPECT_NEAR(g.dh_m, 1.5, 1e-12);
  // East/north are ground metres: |(e, n)| = |t| / k, with k > 0.9996 off the meridian.
  const double ground = std::hypot(g.east_m, g.north_m);
  EXPECT_LT(ground, 5.0 / 0.9996);
  EXPECT_GT(ground, 5.0 / 1.0004);
}

TEST(TranslationAsGeographicTest, AsGivenProjectedAndNoCrs) {
  GeoFrame frame;  // kAsGiven
  std::vector<std::array<double, 3>> p = {{177, -36.87, 0}};
  ProjTransform("EPSG:32760", &p);  // on the central meridian: x = 500000
  const double lat = -36.87, k0 = 0.9996;
  const GeographicOffset o = TranslationAsGeographic(frame, ParseCrs("EPSG:32760", "k"),
                                                     {p[0][0], p[0][1], 10}, {1, 2, 3});
  EXPECT_EQ(o.east_m, 1);
  EXPECT_EQ(o.north_m, 2);
  EXPECT_EQ(o.up_m, 3);
  EXPECT_EQ(o.dh_m, 3);
  EXPECT_NEAR(o.dlat_deg, 2 / (k0 * MeridianRadius(lat) * kDeg), 1e-5 * o.dlat_deg);
  EXPECT_NEAR(o.dlon_deg, 1 / (k0 * NormalRadius(lat) * std::cos(lat * kDeg) * kDeg),
              1e-5 * o.dlon_deg);
  const GeographicOffset feet =
      TranslationAsGeographic(frame, ParseCrs("EPSG:2227", "k"), {6e6, 2e6, 0}, {1, 1, 1});
  EXPECT_NEAR(feet.east_m, 1200.0 / 3937.0, 1e-15);
  EXPECT_TRUE(std::isfinite(feet.dlat_deg));
  const GeographicOffset none = TranslationAsGeographic(frame, Crs(), {1, 2, 3}, {4, 5, 6});
  EXPECT_TRUE(std::isnan(none.dlat_deg));
  EXPECT_TRUE(std::isnan(none.dlon_deg));
  EXPECT_EQ(none.east_m, 4);
  EXPECT_EQ(none.north_m, 5);
  EXPECT_EQ(none.up_m, 6);
}

}  // namespace
}  // namespace surfreg
