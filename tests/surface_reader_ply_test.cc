// PLY reader: ascii and binary_little_endian bodies (built byte by byte
// here), every scalar type, list properties, elements before "vertex", the
// optional weight, and the errors with their file, line or vertex number.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>

#include "tests/surface_reader_test_util.h"
#include "io/surface_reader.h"

namespace surfreg {
namespace {

using reader_test::ByteWriter;
using reader_test::Contains;
using reader_test::ExpectPoint;

Surface Ply(const std::string& bytes) { return reader_test::Read(ReadPly, bytes, "b.ply"); }
std::string PlyError(const std::string& bytes) {
  return reader_test::ErrorOf(ReadPly, bytes, "b.ply");
}

// "ply", the format line (line 2), a comment (line 3), then `elements`.
std::string Header(const std::string& format, const std::string& elements) {
  return "ply\nformat " + format + " 1.0\ncomment written by a test\n" + elements + "end_header\n";
}

const char kVertexFloat[] =
    "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
const char kTriangleAscii[] = "1 2 3\n4.5 -5 6\n7 8.25 -9\n";

void ExpectTriangle(const Surface& s) {
  ASSERT_EQ(s.size(), 3u);
  ExpectPoint(s, 0, 1.0, 2.0, 3.0);
  ExpectPoint(s, 1, 4.5, -5.0, 6.0);
  ExpectPoint(s, 2, 7.0, 8.25, -9.0);
}

const float kTriangle[3][3] = {{1.0f, 2.0f, 3.0f}, {4.5f, -5.0f, 6.0f}, {7.0f, 8.25f, -9.0f}};

// --- ascii ----------------------------------------------------------------

TEST(ReadPlyTest, Ascii) {
  const Surface s = Ply("ply\nformat ascii 1.0\ncomment c\nobj_info scanner 1\n" +
                        std::string(kVertexFloat) + "end_header\n" + kTriangleAscii);
  ExpectTriangle(s);
  EXPECT_TRUE(s.weight.empty());
  EXPECT_EQ(s.source, "b.ply");
}

TEST(ReadPlyTest, AsciiExtraPropertyAndFacesAfter) {
  ExpectTriangle(Ply(Header("ascii",
                            "element vertex 3\nproperty float x\nproperty float y\n"
                            "property uchar red\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\n") +
                     "1 2 255 3\n4.5 -5 0 6\n7 8.25 17 -9\n3 0 1 2\n"));
}

TEST(ReadPlyTest, AsciiFacesBeforeVertices) {
  ExpectTriangle(Ply(Header("ascii",
                            "element face 2\nproperty list uchar int vertex_indices\n"
                            "property uchar flags\n" +
                                std::string(kVertexFloat)) +
                     "3 0 1 2 1\n4 0 1 2 0 0\n" + kTriangleAscii));
}

TEST(ReadPlyTest, AsciiListPropertyInVertex) {
  ExpectTriangle(
      Ply(Header("ascii",
                 "element vertex 3\nproperty float x\nproperty list uint8 float32 extra\n"
                 "property float y\nproperty float z\n") +
          "1 2 0.5 0.25 2 3\n4.5 0 -5 6\n7 1 1e3 8.25 -9\n"));
}

TEST(ReadPlyTest, AsciiWeightAndAliases) {
  const Surface s = Ply(Header("ascii",
                               "element vertex 3\nproperty float64 x\nproperty float32 y\n"
                               "property int16 z\nproperty double weight\n") +
                        "1 2 3 0.5\n4.5 -5 6 0\n7 8.25 -9 3\n");
  ExpectTriangle(s);
  EXPECT_EQ(s.weight, (std::vector<double>{0.5, 0.0, 3.0}));
}

TEST(ReadPlyTest, AsciiCrlfAndBlankLines) {
  ExpectTriangle(
      Ply("ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n"
          "property float y\r\nproperty float z\r\nend_header\r\n"
          "1 2 3\r\n\r\n4.5 -5 6\r\n7 8.25 -9"));
}

// --- binary_little_endian -------------------------------------------------

TEST(ReadPlyTest, BinaryFloat) {
  ByteWriter body;
  for (const auto& p : kTriangle) body.Put(p[0]).Put(p[1]).Put(p[2]);
  ExpectTriangle(Ply(Header("binary_little_endian", kVertexFloat) + body.bytes()));
}

TEST(ReadPlyTest, BinaryDoubleKeepsUtmValuesExact) {
  ByteWriter body;
  body.Put(500000.125).Put(4500000.25).Put(101.5);
  body.Put(500010.5).Put(4500000.75).Put(99.0);
  body.Put(500003.375).Put(4500020.0).Put(100.125);
  const Surface s = Ply(Header("binary_little_endian",
                               "element vertex 3\nproperty double x\nproperty double y\n"
                               "property double z\n") +
                        body.bytes());
  ExpectPoint(s, 0, 500000.125, 4500000.25, 101.5);
  ExpectPoint(s, 2, 500003.375, 4500020.0, 100.125);
}

TEST(ReadPlyTest, BinaryEveryScalarTypeAndWeight) {
  const std::string header =
      Header("binary_little_endian",
             "element vertex 3\nproperty char a\nproperty uchar b\nproperty short c\n"
             "property ushort d\nproperty double x\nproperty int e\nproperty uint f\n"
             "property float y\nproperty int32 z\nproperty float weight\nproperty uint16 g\n");
  ByteWriter body;
  const int32_t z[3] = {3, 6, -9};
  for (int i = 0; i < 3; ++i) {
    body.Put<int8_t>(-1).Put<uint8_t>(200).Put<int16_t>(-300).Put<uint16_t>(60000);
    body.Put<double>(kTriangle[i][0]).Put<int32_t>(-70000).Put<uint32_t>(4000000000u);
    body.Put<float>(kTriangle[i][1]).Put<int32_t>(z[i]).Put<float>(0.5f * i).Put<uint16_t>(7);
  }
  const Surface s = Ply(header + body.bytes());
  ExpectTriangle(s);
  EXPECT_EQ(s.weight, (std::vector<double>{0.0, 0.5, 1.0}));
}

TEST(ReadPlyTest, BinaryIntegerCoordinates) {
  ByteWriter body;
  body.Put<int32_t>(-100000).Put<int16_t>(-5).Put<uint8_t>(0);
  body.Put<int32_t>(100000).Put<int16_t>(-5).Put<uint8_t>(255);
  body.Put<int32_t>(0).Put<int16_t>(32767).Put<uint8_t>(1);
  const Surface s = Ply(Header("binary_little_endian",
                               "element vertex 3\nproperty int x\nproperty short y\n"
                               "property uchar z\n") +
                        body.bytes());
  ExpectPoint(s, 0, -100000.0, -5.0, 0.0);
  ExpectPoint(s, 1, 100000.0, -5.0, 255.0);
  ExpectPoint(s, 2, 0.0, 32767.0, 1.0);
}

TEST(ReadPlyTest, BinaryElementsWithListsBeforeVertices) {
  const std::string header =
      Header("binary_little_endian",
             "element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
             "element edge 1\nproperty int v1\nproperty int v2\n"
             "element range 2\nproperty list ushort double values\n" +
                 std::string(kVertexFloat) + "element tail 1\nproperty list uchar int items\n");
  ByteWriter body;
  body.Put<uint8_t>(3).Put<int32_t>(0).Put<int32_t>(1).Put<int32_t>(2).Put<uint8_t>(9);
  body.Put<uint8_t>(4).Put<int32_t>(0).Put<int32_t>(1).Put<int32_t>(2).Put<int32_t>(0);
  body.Put<uint8_t>(1);
  body.Put<int32_t>(0).Put<int32_t>(1);
  body.Put<uint16_t>(0);
  body.Put<uint16_t>(2).Put(1.5).Put(2.5);
  for (const auto& p : kTriangle) body.Put(p[0]).Put(p[1]).Put(p[2]);
  body.Put<uint8_t>(1).Put<int32_t>(5);
  ExpectTriangle(Ply(header + body.bytes()));
}

TEST(ReadPlyTest, BinaryListPropertyInVertexAndCrlfHeader) {
  ByteWriter body;
  for (int i = 0; i < 3; ++i) {
    body.Put(kTriangle[i][0]).Put<uint8_t>(static_cast<uint8_t>(i));
    for (int k = 0; k < i; ++k) body.Put<int16_t>(-1);
    body.Put(kTriangle[i][1]).Put(kTriangle[i][2]);
  }
  ExpectTriangle(
      Ply("ply\r\nformat binary_little_endian 1.0\r\nelement vertex 3\r\n"
          "property float x\r\nproperty list uchar short extra\r\n"
          "property float y\r\nproperty float z\r\nend_header\r\n" +
          body.bytes()));
}

// --- errors ---------------------------------------------------------------

TEST(ReadPlyErrorTest, HeaderErrors) {
  EXPECT_EQ(PlyError(Header("binary_big_endian", kVertexFloat)),
            "b.ply:2: binary_big_endian PLY is not supported (use ascii or binary_little_endian)");
  EXPECT_TRUE(Contains(PlyError("PLY\n"), "b.ply:1: not a PLY file"));
  EXPECT_TRUE(Contains(PlyError(""), "b.ply:1: not a PLY file"));
  EXPECT_TRUE(
      Contains(PlyError(Header("utf8", kVertexFloat)), "b.ply:2: unknown PLY format 'utf8'"));
  EXPECT_TRUE(Contains(PlyError("ply\nformat ascii 2.0\n"), "b.ply:2: unsupported PLY version"));
  EXPECT_TRUE(Contains(PlyError("ply\n" + std::string(kVertexFloat) + "end_header\n"),
                       "b.ply:6: no 'format' line"));
  EXPECT_TRUE(Contains(PlyError("ply\nformat ascii 1.0\n" + std::string(kVertexFloat)),
                       "b.ply: the header has no end_header"));
  EXPECT_TRUE(Contains(PlyError(Header("ascii", "property float x\n")),
                       "b.ply:4: property before any element"));
  EXPECT_TRUE(Contains(PlyError(Header("ascii", "element vertex 3\nproperty float16 x\n")),
                       "b.ply:5: unknown PLY property type 'float16'"));
  EXPECT_TRUE(Contains(PlyError(Header("ascii", "element vertex -3\n")),
                       "b.ply:4: element count is not a non-negative integer: '-3'"));
  EXPECT_TRUE(Contains(PlyError(Header("ascii", "element face 1\nproperty list float int i\n")),
                       "b.ply:5: list length type must be an integer"));
  EXPECT_TRUE(Contains(PlyError(Header("ascii", "elements vertex 3\n")),
                       "b.ply:4: unknown PLY header line"));
}

TEST(ReadPlyErrorTest, VertexElementErrors) {
  EXPECT_EQ(
      PlyError(Header("ascii", "element vertex 3\nproperty float x\nproperty float y\n") + "1 2\n"),
      "b.ply:4: the vertex element has no property 'z'");
  EXPECT_TRUE(Contains(PlyError(Header("ascii", "element face 1\nproperty int a\n") + "1\n"),
                       "b.ply: no 'vertex' element"));
  EXPECT_TRUE(Contains(PlyError(Header("ascii",
                                       "element vertex 1\nproperty list uchar float x\n"
                                       "property float y\nproperty float z\n")),
                       "b.ply:5: vertex property 'x' must not be a list"));
  EXPECT_TRUE(Contains(
      PlyError(Header("ascii", "element vertex 0\n" + std::string(kVertexFloat).substr(17))),
      "b.ply: no points"));
}

TEST(ReadPlyErrorTest, TruncatedBinary) {
  ByteWriter body;
  for (int i = 0; i < 10; ++i) body.Put(1.0f * i).Put(2.0f * i * i).Put(3.0f);
  body.Put(1.0f);  // half a vertex
  EXPECT_EQ(PlyError(Header("binary_little_endian",
                            "element vertex 200\nproperty float x\nproperty float y\n"
                            "property float z\n") +
                     body.bytes()),
            "b.ply: file ends after 10 of 200 vertices");
  ByteWriter faces;
  faces.Put<uint8_t>(3).Put<int32_t>(0).Put<int32_t>(1).Put<int32_t>(2).Put<uint8_t>(3);
  EXPECT_EQ(PlyError(Header("binary_little_endian",
                            "element face 5\nproperty list uchar int vertex_indices\n" +
                                std::string(kVertexFloat)) +
                     faces.bytes()),
            "b.ply: file ends in element 'face' after 1 of 5, before the vertices");
  ByteWriter negative;
  negative.Put<int8_t>(-1);
  EXPECT_TRUE(Contains(
      PlyError(Header("binary_little_endian",
                      "element face 1\nproperty list char int i\n" + std::string(kVertexFloat)) +
               negative.bytes()),
      "negative length of list 'i'"));
}

TEST(ReadPlyErrorTest, TruncatedAscii) {
  EXPECT_EQ(PlyError(Header("ascii",
                            "element vertex 5\nproperty float x\nproperty float y\n"
                            "property float z\n") +
                     kTriangleAscii),
            "b.ply: file ends after 3 of 5 vertices");
  EXPECT_EQ(PlyError(Header("ascii", "element face 3\nproperty list uchar int vertex_indices\n" +
                                         std::string(kVertexFloat)) +
                     "3 0 1 2\n"),
            "b.ply: file ends in element 'face' after 1 of 3, before the vertices");
}

TEST(ReadPlyErrorTest, NonFiniteValues) {
  // The header is lines 1-8, so vertex 1 is on line 10.
  EXPECT_EQ(PlyError(Header("ascii", kVertexFloat) + "1 2 3\n4 5 nan\n7 8 9\n"),
            "b.ply:10: vertex 1: z is NaN");
  ByteWriter body;
  body.Put(1.0f).Put(2.0f).Put(3.0f).Put(4.0f).Put(5.0f).Put(6.0f);
  body.Put(std::numeric_limits<float>::quiet_NaN()).Put(8.0f).Put(9.0f);
  EXPECT_EQ(PlyError(Header("binary_little_endian", kVertexFloat) + body.bytes()),
            "b.ply: vertex 2: x is NaN");
  ByteWriter inf;
  inf.Put(1.0).Put(std::numeric_limits<double>::infinity()).Put(3.0);
  EXPECT_EQ(PlyError(Header("binary_little_endian",
                            "element vertex 1\nproperty double x\nproperty double y\n"
                            "property double z\n") +
                     inf.bytes()),
            "b.ply: vertex 0: y is infinite");
}

TEST(ReadPlyErrorTest, AsciiValueErrors) {
  const std::string header = Header("ascii", kVertexFloat);
  EXPECT_EQ(PlyError(header + "1 2 3\n4 5\n"),
            "b.ply:10: vertex 1: the line ends before property 'z'");
  EXPECT_EQ(PlyError(header + "1 2 3 4\n"),
            "b.ply:9: vertex 0: more values than the header's properties: '4'");
  EXPECT_EQ(PlyError(header + "1 2 3\n4 5 6\n7 8 9x\n"),
            "b.ply:11: vertex 2: z is not a number: '9x'");
  const std::string with_list = Header("ascii",
                                       "element vertex 1\nproperty list uchar int l\n"
                                       "property float x\nproperty float y\n"
                                       "property float z\n");
  EXPECT_TRUE(
      Contains(PlyError(with_list + "-1 1 2 3\n"), "b.ply:10: vertex 0: bad length of list 'l'"));
  EXPECT_TRUE(Contains(PlyError(with_list + "9 1 2 3\n"),
                       "b.ply:10: vertex 0: the line ends inside list 'l'"));
  const std::string weighted =
      Header("ascii", std::string(kVertexFloat) + "property float weight\n");
  EXPECT_EQ(PlyError(weighted + "1 2 3 1\n4 5 6 -2\n"), "b.ply:11: vertex 1: weight is negative");
}

}  // namespace
}  // namespace surfreg
