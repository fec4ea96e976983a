// Surface readers: text (.xyz/.txt/.csv), OFF, OBJ and the by-extension
// ReadSurface (PLY is in surface_reader_ply_test.cc). Every valid form must
// read the exact values; every invalid one must fail with "<file>:<line>:".
#include "io/surface_reader.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "tests/surface_reader_test_util.h"

namespace surfreg {
namespace {

using reader_test::Contains;
using reader_test::ExpectPoint;
using reader_test::InputPoint;

Surface Xyz(const std::string& text, const ReadOptions& options = {}) {
  return reader_test::Read(ReadXyz, text, "data/a.xyz", options);
}
std::string XyzError(const std::string& text) {
  return reader_test::ErrorOf(ReadXyz, text, "data/a.xyz");
}

// The three points every valid-form test below encodes.
void ExpectTriangle(const Surface& s) {
  ASSERT_EQ(s.size(), 3u);
  ExpectPoint(s, 0, 1.0, 2.0, 3.0);
  ExpectPoint(s, 1, 4.5, -5.0, 6.0);
  ExpectPoint(s, 2, 7.0, 8.25, -9.0);
  EXPECT_TRUE(s.weight.empty());
}

// --- text: valid forms ------------------------------------------------------

TEST(ReadXyzTest, Whitespace) { ExpectTriangle(Xyz("1 2 3\n4.5\t-5\t6\n  7   8.25 -9  \n")); }

TEST(ReadXyzTest, Commas) { ExpectTriangle(Xyz("1,2,3\n4.5,-5,6\n7,8.25,-9\n")); }

TEST(ReadXyzTest, MixedSeparators) {
  ExpectTriangle(Xyz("1, 2 ,3\n4.5 ,-5,\t6\n 7\t, 8.25, -9\n"));
}

TEST(ReadXyzTest, CommentsAndBlankLines) {
  ExpectTriangle(Xyz("# survey\n\n1 2 3 # first\n   \n#4 4 4\n4.5 -5 6#no space\n\t\n7 8.25 -9\n"));
}

TEST(ReadXyzTest, HeaderLine) {
  ExpectTriangle(Xyz("x,y,z\n1,2,3\n4.5,-5,6\n7,8.25,-9\n"));
  ExpectTriangle(Xyz("# exported\n\nEasting Northing Height\n1 2 3\n4.5 -5 6\n7 8.25 -9\n"));
}

TEST(ReadXyzTest, WeightsColumn) {
  const Surface s = Xyz("X Y Z weight\n1 2 3 0.5\n4.5 -5 6 0\n7 8.25 -9 2e3\n");
  ASSERT_EQ(s.size(), 3u);
  ExpectPoint(s, 2, 7.0, 8.25, -9.0);
  EXPECT_EQ(s.weight, (std::vector<double>{0.5, 0.0, 2000.0}));
}

TEST(ReadXyzTest, CrlfLineEndings) { ExpectTriangle(Xyz("1 2 3\r\n4.5 -5 6\r\n7 8.25 -9\r\n")); }

TEST(ReadXyzTest, NoTrailingNewline) { ExpectTriangle(Xyz("1 2 3\n4.5 -5 6\n7 8.25 -9")); }

TEST(ReadXyzTest, Utf8ByteOrderMark) {
  ExpectTriangle(Xyz("\xEF\xBB\xBFx,y,z\n1,2,3\n4.5,-5,6\n7,8.25,-9"));
}

TEST(ReadXyzTest, NumberSpellings) {
  ExpectTriangle(Xyz("+1 2.0 3e0\n4.50 -5. +6\n.7e1 825e-2 -0009\n"));
}

TEST(ReadXyzTest, UnderflowReadsAsTinyValue) {
  const Surface s = Xyz("0 0 1e-400\n1 0 0\n0 1 0\n");
  EXPECT_EQ(InputPoint(s, 0)[2], 0.0);
}

TEST(ReadXyzTest, SourceIsTheName) { EXPECT_EQ(Xyz("0 0 0\n1 0 0\n0 1 0\n").source, "data/a.xyz"); }

TEST(ReadXyzTest, UtmCoordinatesRoundTripThroughOrigin) {
  const Surface s =
      Xyz("500000.125 4500000.25 101.5\n500010.5 4500000.75 99\n"
          "500003.375 4500020.0 100.125\n");
  EXPECT_EQ(s.origin[0], std::round(s.origin[0]));  // origin_step 1: whole metres
  EXPECT_LT(std::fabs(s.xy[0].x), 20.0);            // stored small
  ExpectPoint(s, 0, 500000.125, 4500000.25, 101.5);
  ExpectPoint(s, 1, 500010.5, 4500000.75, 99.0);
  ExpectPoint(s, 2, 500003.375, 4500020.0, 100.125);
}

TEST(ReadXyzTest, OriginStepOption) {
  ReadOptions options;
  options.origin_step = 100.0;
  const Surface s = Xyz("500000 4500000 10\n500010 4500000 10\n500000 4500160 10\n", options);
  EXPECT_EQ(s.origin[0], 500000.0);
  EXPECT_EQ(s.origin[1], 4500100.0);
  ExpectPoint(s, 2, 500000.0, 4500160.0, 10.0);
}

// Points around northing 4.5e6 / easting 6.0e5 with millimetre offsets: the
// local coordinates must keep the offsets to 1e-9 m.
TEST(ReadXyzTest, UtmSizePrecision) {
  std::string text;
  std::vector<std::array<double, 3>> expected;
  char line[96];
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      const long long x_mm = 4500000000LL + 1 * i + 7 * j;  // millimetres
      const long long y_mm = 600000000LL + 3 * i - 1 * j;
      std::snprintf(line, sizeof(line), "%lld.%03lld %lld.%03lld %d.%03d\n", x_mm / 1000,
                    x_mm % 1000, y_mm / 1000, y_mm % 1000, 12 + i, j);
      text += line;
      expected.push_back({x_mm * 1e-3, y_mm * 1e-3, 12 + i + j * 1e-3});
    }
  }
  const Surface s = Xyz(text);
  ASSERT_EQ(s.size(), expected.size());
  for (std::size_t k = 0; k < s.size(); ++k) {
    const std::array<double, 3> p = InputPoint(s, k);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], expected[k][c], 1e-9) << k << " " << c;
    // Differences between points come from the local coordinates alone.
    EXPECT_NEAR(s.xy[k].x - s.xy[0].x, expected[k][0] - expected[0][0], 1e-9);
    EXPECT_NEAR(s.xy[k].y - s.xy[0].y, expected[k][1] - expected[0][1], 1e-9);
  }
}

TEST(ReadXyzTest, ManyLines) {
  std::string text;
  for (int i = 0; i < 100000; ++i) {
    text +=
        std::to_string(i % 317) + "," + std::to_string(i / 317) + "," + std::to_string(i) + "\n";
  }
  const Surface s = Xyz(text);
  ASSERT_EQ(s.size(), 100000u);
  ExpectPoint(s, 99999, 99999 % 317, 99999 / 317, 99999);
}

// --- text: errors ---------------------------------------------------------------

TEST(ReadXyzErrorTest, TooFewNumbers) {
  EXPECT_EQ(XyzError("1 2 3\n4 5 6\n# c\n7 8\n"),
            "data/a.xyz:4: expected 3 numbers (x y z), found 2");
}

TEST(ReadXyzErrorTest, TooManyNumbers) {
  EXPECT_TRUE(Contains(XyzError("1 2 3 4 5\n"), "data/a.xyz:1: expected 3 numbers"));
  EXPECT_TRUE(Contains(XyzError("1 2 3 4 5\n"), "found 5"));
}

TEST(ReadXyzErrorTest, ColumnCountChanges) {
  const std::string message = XyzError("x y z\n1 2 3\n4 5 6 1\n");
  EXPECT_TRUE(Contains(message, "data/a.xyz:3: expected 3 numbers (x y z) like line 2, found 4"));
  EXPECT_TRUE(Contains(XyzError("1 2 3 1\n4 5 6\n"), "data/a.xyz:2: expected 4 numbers"));
}

TEST(ReadXyzErrorTest, BadToken) {
  EXPECT_EQ(XyzError("1 2 3\n1 2.5m 3\n"), "data/a.xyz:2: y is not a number: '2.5m'");
  EXPECT_TRUE(Contains(XyzError("1 2 3\n1 2 3\n0x10 1 1\n"), "data/a.xyz:3: x is not a number"));
  EXPECT_TRUE(Contains(XyzError("1 2 3\n1 2 3\n1 1 --1\n"), "data/a.xyz:3: z is not a number"));
  EXPECT_TRUE(Contains(XyzError("1 2 3 1\n1 2 3 abc\n"), "data/a.xyz:2: weight is not a number"));
}

TEST(ReadXyzErrorTest, OnlyTheFirstLineCanBeAHeader) {
  EXPECT_TRUE(Contains(XyzError("x y z\nX Y Z\n1 2 3\n"), "data/a.xyz:2: x is not a number: 'X'"));
  EXPECT_TRUE(Contains(XyzError("1 2 3\nx y z\n"), "data/a.xyz:2: x is not a number"));
}

TEST(ReadXyzErrorTest, NaNAndInfinity) {
  std::string text;
  for (int i = 0; i < 8; ++i) text += std::to_string(i) + " " + std::to_string(i * i) + " 1\n";
  EXPECT_EQ(XyzError(text + "1 2 nan\n"), "data/a.xyz:9: z is NaN");
  EXPECT_EQ(XyzError(text + "-inf 2 3\n"), "data/a.xyz:9: x is infinite");
  EXPECT_EQ(XyzError(text + "1 Infinity 3\n"), "data/a.xyz:9: y is infinite");
  EXPECT_TRUE(Contains(XyzError(text + "1 2 1e999\n"), "data/a.xyz:9: z is out of the range"));
  EXPECT_EQ(XyzError("1 2 3 1\n1 2 3 NaN\n"), "data/a.xyz:2: weight is NaN");
}

TEST(ReadXyzErrorTest, NegativeWeight) {
  EXPECT_EQ(XyzError("1 2 3 1\n\n4 5 6 -0.5\n"), "data/a.xyz:3: weight is negative: '-0.5'");
}

TEST(ReadXyzErrorTest, EmptyFields) {
  EXPECT_TRUE(Contains(XyzError("1,2,3\n1,,2\n"), "data/a.xyz:2: empty field"));
  EXPECT_TRUE(Contains(XyzError(",1,2,3\n"), "data/a.xyz:1: empty field"));
  EXPECT_TRUE(Contains(XyzError("1,2,3,\n"), "data/a.xyz:1: empty field"));
}

TEST(ReadXyzErrorTest, NoPoints) {
  EXPECT_TRUE(Contains(XyzError(""), "data/a.xyz: no points"));
  EXPECT_TRUE(Contains(XyzError("# only a comment\n\n"), "data/a.xyz: no points"));
  EXPECT_TRUE(Contains(XyzError("x,y,z\n"), "data/a.xyz: no points"));
}

TEST(ReadXyzErrorTest, TooFewOrCollinearPoints) {
  EXPECT_TRUE(Contains(XyzError("1 2 3\n4 5 6\n"), "data/a.xyz: 2 points"));
  EXPECT_TRUE(Contains(XyzError("0 0 1\n1 1 2\n2 2 3\n5 5 0\n"), "data/a.xyz: all points lie on"));
}

TEST(ReadXyzErrorTest, LineNumbersCountEveryLine) {
  EXPECT_TRUE(Contains(XyzError("# a\r\n\r\n1 2 3\r\n# b\r\n4 5\r\n"), "data/a.xyz:5:"));
}

TEST(ReadXyzErrorTest, BinaryGarbageGivesOneShortLine) {
  std::string garbage;
  for (int i = 0; i < 3000; ++i) garbage += static_cast<char>((i * 7919 + 13) % 256);
  const std::string message = XyzError(garbage);
  EXPECT_TRUE(Contains(message, "data/a.xyz"));
  EXPECT_EQ(message.find('\n'), std::string::npos);
  EXPECT_LT(message.size(), 200u);
  EXPECT_TRUE(Contains(XyzError(std::string("1 2 3\n1 2\0 3\n", 12)), "data/a.xyz:2:"));
}

// --- OFF ------------------------------------------------------------------------

Surface Off(const std::string& text) { return reader_test::Read(ReadOff, text, "c.off"); }
std::string OffError(const std::string& text) {
  return reader_test::ErrorOf(ReadOff, text, "c.off");
}

TEST(ReadOffTest, PlainWithFacesAndComments) {
  ExpectTriangle(Off("OFF\n# a mesh\n3 1 0\n\n1 2 3\n4.5 -5 6 # v1\n7 8.25 -9\n3 0 1 2\n"));
}

TEST(ReadOffTest, Variants) {
  ExpectTriangle(
      Off("COFF\n3 1 3\n1 2 3 255 0 0 255\n4.5 -5 6 0 255 0 255\n7 8.25 -9 0 0 0 1\n"
          "3 0 1 2\n"));
  ExpectTriangle(Off("NOFF\n3 0 0\n1 2 3 0 0 1\n4.5 -5 6 0 0 1\n7 8.25 -9 0 0 1\n"));
  ExpectTriangle(
      Off("NCOFF\r\n3 0\r\n1 2 3 0 0 1 1 1 1 1\r\n4.5 -5 6 0 0 1 1 1 1 1\r\n"
          "7 8.25 -9 0 0 1 1 1 1 1"));
}

TEST(ReadOffTest, CountsOnTheKeywordLine) {
  ExpectTriangle(Off("OFF 3 1 0\n1 2 3\n4.5 -5 6\n7 8.25 -9\n"));
}

TEST(ReadOffErrorTest, Errors) {
  EXPECT_EQ(OffError("OFF\n200 10 0\n0 0 0\n1 0 0\n"), "c.off: file ends after 2 of 200 vertices");
  EXPECT_TRUE(Contains(OffError("PLY\n3 1 0\n"), "c.off:1: not an OFF file"));
  EXPECT_TRUE(Contains(OffError("# x\n4OFF\n3 1 0\n"), "c.off:2: unsupported OFF variant '4OFF'"));
  EXPECT_TRUE(Contains(OffError("OFF BINARY\n"), "c.off:1: binary OFF is not supported"));
  EXPECT_TRUE(Contains(OffError("OFF\n3 x 0\n"), "c.off:2: expected the counts"));
  EXPECT_TRUE(Contains(OffError("OFF\n3\n"), "c.off:2: expected the counts"));
  EXPECT_TRUE(Contains(OffError("OFF\n"), "c.off: file ends before the counts"));
  EXPECT_EQ(OffError("OFF\n3 1 0\n1 2 3\n4 5\n"),
            "c.off:4: vertex 1: expected 3 numbers (x y z), found 2");
  EXPECT_EQ(OffError("OFF\n3 1 0\n1 2 3\n4 5 6\n7 nan 9\n"), "c.off:5: vertex 2: y is NaN");
  EXPECT_TRUE(Contains(OffError("OFF\n3 1 0\n1 2 3\n4 5 6\n7 8 9z\n"),
                       "c.off:5: vertex 2: z is not a number"));
  EXPECT_TRUE(Contains(OffError(""), "c.off: no points"));
  EXPECT_TRUE(Contains(OffError("OFF\n0 0 0\n"), "c.off: no points"));
}

// --- OBJ ------------------------------------------------------------------------

Surface Obj(const std::string& text) { return reader_test::Read(ReadObj, text, "m.obj"); }
std::string ObjError(const std::string& text) {
  return reader_test::ErrorOf(ReadObj, text, "m.obj");
}

TEST(ReadObjTest, VertexLinesAmongOthers) {
  ExpectTriangle(
      Obj("# made by hand\nmtllib a.mtl\no thing\nv 1 2 3\nvt 0.5 0.5\nvn 0 0 1\n"
          "v 4.5 -5 6 1.0\ng group\nvp 0.1 0.2\nv 7 8.25 -9 0.1 0.2 0.3 # colour\n"
          "usemtl m\ns off\nf 1/1/1 2/1/1 3/1/1\n"));
}

TEST(ReadObjTest, FourthNumberIsNotAWeight) {
  const Surface s = Obj("v 0 0 0 5\nv 1 0 0 5\nv 0 1 0 5\r\n");
  EXPECT_EQ(s.size(), 3u);
  EXPECT_TRUE(s.weight.empty());
}

TEST(ReadObjErrorTest, Errors) {
  EXPECT_EQ(ObjError("v 1 2 3\nvt 1\nv 1 2\n"), "m.obj:3: expected 3 numbers (x y z), found 2");
  EXPECT_EQ(ObjError("v 1 2 3\nv 1 x 3\n"), "m.obj:2: y is not a number: 'x'");
  EXPECT_EQ(ObjError("\n\nv 1 2 -inf\n"), "m.obj:3: z is infinite");
  EXPECT_TRUE(Contains(ObjError("vt 1 2\nf 1 2 3\n"), "m.obj: no points"));
}

// --- ReadSurface: by extension --------------------------------------------------

class ReadSurfaceTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& file_name, const std::string& content) {
    const std::string path = ::testing::TempDir() + "surface_reader_test_" + file_name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  static std::string ErrorOf(const std::string& path) {
    try {
      ReadSurface(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(ReadSurfaceTest, ChoosesTheFormatByExtension) {
  ExpectTriangle(ReadSurface(Write("a.XYZ", "1 2 3\n4.5 -5 6\n7 8.25 -9\n")));
  ExpectTriangle(ReadSurface(Write("a.txt", "1 2 3\n4.5 -5 6\n7 8.25 -9\n")));
  ExpectTriangle(ReadSurface(Write("a.Csv", "x,y,z\n1,2,3\n4.5,-5,6\n7,8.25,-9\n")));
  ExpectTriangle(ReadSurface(Write("a.off", "OFF\n3 0 0\n1 2 3\n4.5 -5 6\n7 8.25 -9\n")));
  ExpectTriangle(ReadSurface(Write("a.obj", "v 1 2 3\nv 4.5 -5 6\nv 7 8.25 -9\n")));
  ExpectTriangle(ReadSurface(Write("a.PLY",
                                   "ply\nformat ascii 1.0\nelement vertex 3\n"
                                   "property float x\nproperty float y\n"
                                   "property float z\nend_header\n"
                                   "1 2 3\n4.5 -5 6\n7 8.25 -9\n")));
  const std::string path = Write("b.xyz", "0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_EQ(ReadSurface(path).source, path);
}

TEST_F(ReadSurfaceTest, FileErrors) {
  EXPECT_EQ(ErrorOf("c.stl"),
            "c.stl: unknown surface format '.stl' (expected .xyz .txt .csv "
            ".ply .off .obj .las, or a GDAL raster: .tif .tiff .vrt .asc .img .bil .hgt .dem "
            ".nc .gpkg .flt)");
  EXPECT_TRUE(Contains(ErrorOf("dir.d/noext"), "dir.d/noext: no file extension"));
  const std::string missing = ::testing::TempDir() + "surface_reader_test_missing.xyz";
  EXPECT_EQ(ErrorOf(missing), missing + ": cannot open: No such file or directory");
  const std::string dir = ::testing::TempDir() + "surface_reader_test_dir.xyz";
  ::mkdir(dir.c_str(), 0755);
  EXPECT_TRUE(Contains(ErrorOf(dir), dir + ": cannot read"));
  const std::string bad = Write("bad.csv", "x,y,z\n1,2,3\n4,5,6\n7,8,nan\n");
  EXPECT_EQ(ErrorOf(bad), bad + ":4: z is NaN");
}

}  // namespace
}  // namespace surfreg
