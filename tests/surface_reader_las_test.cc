// The LAS reader (io/surface_reader_las.cc): files written by
// las_test_writer.h for LAS 1.2 and 1.4 headers and point formats 0, 1, 3, 6
// (and extra bytes per record) read back to exactly X * scale + offset; the
// classification filter; the CRS from the WKT and GeoTIFF-key VLRs; and one
// message, naming the file and field, for each malformed file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "tests/las_test_writer.h"
#include "tests/surface_reader_test_util.h"
#include "io/surface_reader.h"

namespace surfreg {
namespace {

using las_test::LasFile;
using las_test::LasPoint;
using las_test::Sheet;
using las_test::WriteLas;
using reader_test::Contains;
using reader_test::InputPoint;

Surface Las(const std::string& bytes, const ReadOptions& options = {}, std::string* crs = nullptr) {
  std::istringstream in(bytes, std::ios::in | std::ios::binary);
  return ReadLas(in, "data/a.las", options, crs);
}

std::string LasError(const std::string& bytes, const ReadOptions& options = {}) {
  try {
    Las(bytes, options);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
  }
  return "";
}

// Every point of `f` (of the classes kept) read back exactly, in file order.
void ExpectPoints(const LasFile& f, const Surface& s, const std::vector<int>& classes = {}) {
  std::size_t j = 0;
  for (const LasPoint& p : f.points) {
    if (!classes.empty() &&
        std::find(classes.begin(), classes.end(), p.classification) == classes.end()) {
      continue;
    }
    ASSERT_LT(j, s.size());
    const std::array<double, 3> q = InputPoint(s, j);
    EXPECT_EQ(q[0], p.x * f.scale[0] + f.offset[0]) << "point " << j;
    EXPECT_EQ(q[1], p.y * f.scale[1] + f.offset[1]) << "point " << j;
    EXPECT_EQ(q[2], p.z * f.scale[2] + f.offset[2]) << "point " << j;
    ++j;
  }
  EXPECT_EQ(j, s.size());
  EXPECT_TRUE(s.weight.empty());
}

struct Variant {
  int minor, format, extra_bytes;
};

class LasFormats : public ::testing::TestWithParam<Variant> {};

TEST_P(LasFormats, ReadBackExactly) {
  LasFile f;
  f.minor = GetParam().minor;
  f.format = GetParam().format;
  if (GetParam().extra_bytes > 0) {
    f.record_length = las_test::kMinRecordLength[f.format] + GetParam().extra_bytes;
  }
  f.points = Sheet(40, {1, 2, 9});
  const Surface s = Las(WriteLas(f));
  EXPECT_EQ(s.source, "data/a.las");
  ExpectPoints(f, s);
}

INSTANTIATE_TEST_SUITE_P(
    Las, LasFormats,
    ::testing::Values(Variant{2, 0, 0}, Variant{2, 1, 0}, Variant{2, 3, 0}, Variant{4, 6, 0},
                      Variant{2, 1, 7}, Variant{4, 6, 13}, Variant{4, 1, 0}, Variant{0, 1, 0},
                      Variant{3, 3, 0}, Variant{4, 10, 0}),
    [](const ::testing::TestParamInfo<Variant>& v) {
      return "las1" + std::to_string(v.param.minor) + "_format" + std::to_string(v.param.format) +
             (v.param.extra_bytes ? "_extra" + std::to_string(v.param.extra_bytes) : "");
    });

TEST(LasReader, UtmScaleAndOffsetKeepFullPrecision) {
  LasFile f;
  f.scale = {0.001, 0.001, 0.0001};
  f.offset = {612345.678, 5812345.5, -12.25};
  f.points = Sheet(30);
  ExpectPoints(f, Las(WriteLas(f)));
  // The extremes of the integer range (scale 1: exact whatever the origin).
  f.scale = {1, 1, 1};
  f.offset = {0, 0, 0};
  f.points[3].x = std::numeric_limits<int32_t>::max();
  f.points[4].y = std::numeric_limits<int32_t>::min();
  f.points[5].z = std::numeric_limits<int32_t>::min();
  ExpectPoints(f, Las(WriteLas(f)));
}

TEST(LasReader, Las14CountFromThe64BitField) {
  LasFile f;
  f.minor = 4;
  f.format = 1;
  f.legacy_count = false;  // 0 in the legacy field: the 64-bit count is the count
  f.points = Sheet(25);
  ExpectPoints(f, Las(WriteLas(f)));
}

TEST(LasReader, ClassesFilter) {
  LasFile f;  // format 1: the low 5 bits, whatever the flag bits above them say
  f.points = Sheet(60, {1, 2, 2, 9, 6});
  ReadOptions ground;
  ground.classes = {2};
  ExpectPoints(f, Las(WriteLas(f), ground), {2});
  EXPECT_EQ(Las(WriteLas(f), ground).size(), 24u);
  ReadOptions two;
  two.classes = {2, 9};
  ExpectPoints(f, Las(WriteLas(f), two), {2, 9});
  // Format 6: the whole byte (classes above 31 exist).
  LasFile wide;
  wide.minor = 4;
  wide.format = 6;
  wide.points = Sheet(40, {2, 40, 200});
  ReadOptions high;
  high.classes = {40, 200};
  ExpectPoints(wide, Las(WriteLas(wide), high), {40, 200});
  ReadOptions none;
  none.classes = {7};
  EXPECT_EQ(LasError(WriteLas(f), none),
            "data/a.las: none of its 60 points has classification 7 (key 'classes')");
}

TEST(LasReader, CrsFromVlrs) {
  const std::string wkt =
      "PROJCS[\"WGS 84 / UTM zone 33N\",GEOGCS[\"WGS 84\"],AUTHORITY[\"EPSG\",\"32633\"]]";
  LasFile f;
  f.points = Sheet(20);
  std::string crs = "stale";
  Las(WriteLas(f), {}, &crs);
  EXPECT_EQ(crs, "");
  f.wkt = wkt;
  Las(WriteLas(f), {}, &crs);
  EXPECT_EQ(crs, wkt);
  f.projected_epsg = 2193;  // the WKT wins over the keys
  Las(WriteLas(f), {}, &crs);
  EXPECT_EQ(crs, wkt);
  f.wkt.clear();
  f.geographic_epsg = 4326;  // projected wins over geographic
  Las(WriteLas(f), {}, &crs);
  EXPECT_EQ(crs, "EPSG:2193");
  f.projected_epsg = 0;
  Las(WriteLas(f), {}, &crs);
  EXPECT_EQ(crs, "EPSG:4326");
  f.minor = 4;
  f.format = 6;
  f.wkt = wkt;
  Las(WriteLas(f), {}, &crs);
  EXPECT_EQ(crs, wkt);
}

// --- malformed files: one message naming the file and the field -------------

std::string Valid(int minor = 2, int format = 1) {
  LasFile f;
  f.minor = minor;
  f.format = format;
  f.points = Sheet(10);
  return WriteLas(f);
}

void PutDouble(std::string* bytes, std::size_t at, double value) {
  las_test::PutDouble(bytes, at, value);
}

TEST(LasReaderErrors, TruncatedHeader) {
  EXPECT_EQ(LasError(Valid().substr(0, 100)),
            "data/a.las: truncated LAS header: the file has 100 bytes, the header alone needs 227");
  EXPECT_EQ(LasError(Valid(4, 6).substr(0, 300)),
            "data/a.las: truncated LAS header: the header size (byte 94) is 375 bytes, the file "
            "has 300");
  EXPECT_EQ(LasError("LAS"), "data/a.las: not a LAS file (it does not start with 'LASF')");
  EXPECT_EQ(LasError("PK\x03\x04 and more"),
            "data/a.las: not a LAS file (it does not start with 'LASF')");
}

TEST(LasReaderErrors, PointCountBeyondTheFile) {
  const std::string bytes = Valid();
  EXPECT_EQ(LasError(bytes.substr(0, bytes.size() - 5)),
            "data/a.las: the header declares 10 points of 28 bytes from byte 227, but the file "
            "has 502 bytes: room for 9 (truncated file, or a wrong count)");
  std::string huge = Valid(4, 6);
  las_test::Put(&huge, 247, uint64_t{1} << 60, 8);  // no allocation of that size is tried
  EXPECT_TRUE(Contains(LasError(huge), "declares 1152921504606846976 points of 30 bytes"));
}

TEST(LasReaderErrors, RecordLengthAndFormat) {
  std::string short_record = Valid();
  las_test::Put(&short_record, 105, 20, 2);
  EXPECT_EQ(LasError(short_record),
            "data/a.las: point data record length 20 (byte 105) is less than the 28 bytes point "
            "format 1 needs");
  std::string unknown = Valid();
  unknown[104] = 11;
  EXPECT_EQ(LasError(unknown),
            "data/a.las: unknown point data record format 11 (byte 104; LAS has formats 0 to 10)");
  std::string compressed = Valid();
  compressed[104] = static_cast<char>(0x80 | 1);
  EXPECT_TRUE(Contains(LasError(compressed), "the points are LAZ-compressed; decompress"));
  std::string version = Valid();
  version[24] = 2;
  EXPECT_EQ(LasError(version), "data/a.las: LAS version 2.2 (byte 24) is not supported (1.0 to 1.4)");
  std::string header = Valid();
  las_test::Put(&header, 94, 200, 2);
  EXPECT_EQ(LasError(header),
            "data/a.las: header size 200 (byte 94) is less than the 227 bytes of a LAS 1.2 header");
}

TEST(LasReaderErrors, ScaleAndOffset) {
  std::string zero = Valid();
  PutDouble(&zero, 139, 0.0);
  EXPECT_EQ(LasError(zero), "data/a.las: y scale factor (byte 139) is 0");
  std::string nan = Valid();
  PutDouble(&nan, 147, std::nan(""));
  EXPECT_EQ(LasError(nan), "data/a.las: z scale factor (byte 147) is not a finite number");
  std::string offset = Valid();
  PutDouble(&offset, 155, HUGE_VAL);
  EXPECT_EQ(LasError(offset), "data/a.las: x offset (byte 155) is not a finite number");
  std::string overflow = Valid();
  PutDouble(&overflow, 131, 1e306);  // finite, but times the integers it overflows
  EXPECT_TRUE(Contains(LasError(overflow), "data/a.las: point 1 (byte 227): x is not finite"));
}

TEST(LasReaderErrors, OffsetsAndRecords) {
  std::string inside = Valid();
  las_test::Put(&inside, 96, 100, 4);
  EXPECT_EQ(LasError(inside),
            "data/a.las: offset to point data 100 (byte 96) is inside the 227-byte header");
  std::string past = Valid();
  las_test::Put(&past, 96, 100000, 4);
  EXPECT_EQ(LasError(past),
            "data/a.las: offset to point data 100000 (byte 96) is past the end of the file (507 "
            "bytes)");
  std::string vlr = Valid();
  las_test::Put(&vlr, 100, 1, 4);  // a VLR where the points start
  EXPECT_EQ(LasError(vlr),
            "data/a.las: variable length record 1 of 1 (byte 227) runs past the start of the "
            "point data (byte 227)");
  std::string evlr = Valid(4, 6);
  las_test::Put(&evlr, 243, 2, 4);
  las_test::Put(&evlr, 235, 670, 8);  // 5 bytes before the end: no room for its header
  EXPECT_TRUE(Contains(LasError(evlr), "extended variable length record"));
}

TEST(LasReaderErrors, FewerThanThreePoints) {
  LasFile f;
  f.points = Sheet(2);
  EXPECT_TRUE(Contains(LasError(WriteLas(f)), "data/a.las: 2 points"));
}

// --- by extension ------------------------------------------------------------

class LasFiles : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& bytes) {
    const std::string path = ::testing::TempDir() + "surface_reader_las_test_" + name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  static std::string ErrorOf(const std::string& path, const ReadOptions& options = {}) {
    try {
      ReadSurface(path, options);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(LasFiles, ByExtensionAnyCase) {
  LasFile f;
  f.points = Sheet(15);
  f.projected_epsg = 32760;
  for (const char* name : {"a.las", "b.LAS", "c.Las"}) {
    std::string crs;
    const Surface s = ReadSurface(Write(name, WriteLas(f)), {}, &crs);
    ExpectPoints(f, s);
    EXPECT_EQ(crs, "EPSG:32760");
  }
}

TEST_F(LasFiles, LazIsRefused) {
  const std::string path = Write("x.laz", "LASF compressed");
  EXPECT_EQ(ErrorOf(path),
            path + ": LAZ (compressed LAS) is not supported: decompress it first, e.g. `laszip -i "
                   "x.laz -o x.las` or `pdal translate x.laz x.las`");
  EXPECT_TRUE(Contains(ErrorOf("missing.LAZ"), "LAZ (compressed LAS) is not supported"));
}

TEST_F(LasFiles, ClassesAndColumnsOnlyWhereTheFormatHasThem) {
  ReadOptions classes;
  classes.classes = {2};
  const std::string xyz = Write("a.xyz", "0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_EQ(ErrorOf(xyz, classes),
            xyz + ": `classes` keeps LAS classifications, but a .xyz file has no classes");
  ReadOptions columns;
  columns.columns = {"1", "2", "3"};
  LasFile f;
  f.points = Sheet(5);
  const std::string las = Write("d.las", WriteLas(f));
  EXPECT_EQ(ErrorOf(las, columns),
            las + ": `columns` picks the columns of a text cloud (.xyz .txt .csv), but a .las "
                  "file has no columns");
}

// The fuzz seeds of tests/fuzz/corpus/las/ are these recipes' bytes (so they
// stay valid files of every kind the reader takes). To rewrite them after a
// change of the writer: SURFREG_WRITE_LAS_SEEDS=1 from the project root.
TEST(LasFuzzSeeds, AreTheWritersFiles) {
  struct Seed {
    const char* name;
    LasFile file;
  };
  std::vector<Seed> seeds;
  LasFile f;
  f.points = Sheet(12, {2, 1});
  f.minor = 2, f.format = 0;
  seeds.push_back({"las12_format0.las", f});
  f.format = 1, f.projected_epsg = 32633;
  seeds.push_back({"las12_format1_geokeys.las", f});
  f.format = 3, f.projected_epsg = 0, f.record_length = 40;
  seeds.push_back({"las12_format3_extra_bytes.las", f});
  f.minor = 4, f.format = 6, f.record_length = 0, f.wkt = "GEOGCS[\"WGS 84\"]";
  seeds.push_back({"las14_format6_wkt.las", f});
  const bool write = std::getenv("SURFREG_WRITE_LAS_SEEDS") != nullptr;
  for (const Seed& seed : seeds) {
    const std::string path = std::string("tests/fuzz/corpus/las/") + seed.name;
    const std::string bytes = WriteLas(seed.file);
    if (write) std::ofstream(path, std::ios::binary) << bytes;
    std::ifstream in(path, std::ios::binary);
    ASSERT_TRUE(in) << path << " (run from the project root)";
    const std::string stored((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(stored, bytes) << path;
    EXPECT_EQ(Las(stored).size(), 12u) << path;
  }
}

}  // namespace
}  // namespace surfreg
