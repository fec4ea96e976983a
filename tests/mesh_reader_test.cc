// Tests of io/mesh_reader.h: each format's vertices and (fan-split)
// triangles written out by hand, each error's one-line message, and the
// orientation text.
#include "tools/face_orientation.h"
#include "io/mesh_reader.h"

#include <gtest/gtest.h>

#include <cstring>

#include "tests/testing/file_checks.h"

namespace surfreg {
namespace {

using testing::Contains;
using testing::ErrorOf;
using testing::TempDir;
using Triangles = std::vector<std::array<int32_t, 3>>;
using Vertices = std::vector<std::array<double, 3>>;

const Vertices kSquare = {{0, 0, 0}, {1, 0, 0.5}, {1, 1, 1}, {0, 1, 1.5}};

TEST(MeshReaderTest, OffWithCommentsQuadAndColour) {
  TempDir dir;
  const std::string file = dir.File("m.OFF",
                                    "# made by hand\nOFF\n4 2 0\n0 0 0\n1 0 0.5 # a comment\n"
                                    "1 1 1\n0 1 1.5\n4 0 1 2 3 255 0 0\n3 3 2 1\n");
  const Mesh m = ReadMesh(file);
  EXPECT_EQ(m.vertices, kSquare);
  EXPECT_EQ(m.triangles, (Triangles{{0, 1, 2}, {0, 2, 3}, {3, 2, 1}}));
  EXPECT_EQ(m.source, file);
  // Counts on the keyword's line.
  EXPECT_EQ(ReadMesh(dir.File("n.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")).triangles,
            (Triangles{{0, 1, 2}}));
}

TEST(MeshReaderTest, ObjCornerFormsAndNegativeIndices) {
  TempDir dir;
  const std::string file = dir.File("m.obj",
                                    "# square\nv 0 0 0\nv 1 0 0.5\nvt 0 0\nvn 0 0 1\n"
                                    "v 1 1 1 1.0\nv 0 1 1.5\nf 1 2/1 3//1 4/1/1\n"
                                    "f -1 -2 -3\ng group\nusemtl x\n");
  const Mesh m = ReadMesh(file);
  EXPECT_EQ(m.vertices, kSquare);
  EXPECT_EQ(m.triangles, (Triangles{{0, 1, 2}, {0, 2, 3}, {3, 2, 1}}));
}

TEST(MeshReaderTest, PlyAscii) {
  TempDir dir;
  const std::string file = dir.File(
      "m.ply",
      "ply\nformat ascii 1.0\ncomment hi\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nelement face 2\nproperty uchar flags\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0 1\n1 0 0.5 2\n1 1 1 3\n"
      "0 1 1.5 4\n7 4 0 1 2 3\n0 3 3 2 1\n");
  const Mesh m = ReadMesh(file);
  EXPECT_EQ(m.vertices, kSquare);
  EXPECT_EQ(m.triangles, (Triangles{{0, 1, 2}, {0, 2, 3}, {3, 2, 1}}));
}

template <typename T>
void Put(std::string* out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // the test host is little-endian (x86, arm)
  out->append(bytes, sizeof(T));
}

TEST(MeshReaderTest, PlyBinaryLittleEndianFacesBeforeVertices) {
  std::string text =
      "ply\nformat binary_little_endian 1.0\nelement face 2\n"
      "property list uchar uint vertex_index\nproperty float quality\n"
      "element vertex 4\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  Put<uint8_t>(&text, 4);
  for (uint32_t i : {0u, 1u, 2u, 3u}) Put(&text, i);
  Put<float>(&text, 0.5f);
  Put<uint8_t>(&text, 3);
  for (uint32_t i : {3u, 2u, 1u}) Put(&text, i);
  Put<float>(&text, 0.5f);
  for (const auto& p : kSquare) {
    for (double c : p) Put(&text, c);
  }
  TempDir dir;
  const std::string file = dir.File("b.ply", text);
  const Mesh m = ReadMesh(file);
  EXPECT_EQ(m.vertices, kSquare);
  EXPECT_EQ(m.triangles, (Triangles{{0, 1, 2}, {0, 2, 3}, {3, 2, 1}}));
  // Cut inside the vertices.
  const std::string cut = dir.File("c.ply", text.substr(0, text.size() - 5));
  EXPECT_TRUE(Contains(ErrorOf([&] { ReadMesh(cut); }), "element 'vertex' after 3 of 4"));
}

TEST(MeshReaderTest, CloudsKeepInputCoordinates) {
  TempDir dir;
  const std::string file = dir.File("c.xyz",
                                    "500000.25 4000000.5 10\n500001 4000000 11\n"
                                    "500000 4000001 12.5\n");
  const Mesh m = ReadMesh(file);
  EXPECT_EQ(m.vertices,
            (Vertices{{500000.25, 4000000.5, 10}, {500001, 4000000, 11}, {500000, 4000001, 12.5}}));
  EXPECT_TRUE(m.triangles.empty());
  // The shipped head reads as 12977 vertices and 25888 triangles.
  const Mesh head = ReadMesh("configs/data/mannequin_head.off");
  EXPECT_EQ(head.vertices.size(), 12977u);
  EXPECT_EQ(head.triangles.size(), 25888u);
}

TEST(MeshReaderTest, Errors) {
  TempDir dir;
  auto error = [&](const std::string& name, const std::string& text) {
    const std::string file = dir.File(name, text);
    return ErrorOf([&] { ReadMesh(file); });
  };
  const std::string tri = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_TRUE(Contains(error("a.off", tri + "3 0 1 3\n"),
                       "a.off:6: face 0: vertex index 3 is out of range"));
  EXPECT_TRUE(Contains(error("b.off", tri + "2 0 1\n"), "b.off:6: face 0: has 2 vertices"));
  EXPECT_TRUE(Contains(error("c.off", tri), "c.off: file ends after 0 of 1 faces"));
  EXPECT_TRUE(Contains(error("d.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"),
                       "d.off: file ends after 2 of 3 vertices"));
  EXPECT_TRUE(Contains(error("e.off", tri + "3 0 1\n"), "e.off:6: face 0: the line ends after 2"));
  EXPECT_TRUE(Contains(error("f.off", tri + "3 0 1 x\n"), "f.off:6: face 0: vertex index is not"));
  EXPECT_TRUE(Contains(error("g.off", "PFF\n"), "g.off:1: expected the header OFF"));
  EXPECT_TRUE(Contains(error("h.off", "OFF\n1 0 0\n0 0 nan\n"), "h.off:3: vertex 0: z is NaN"));
  EXPECT_TRUE(Contains(error("i.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n"),
                       "i.obj:3: face 0: vertex index 2 is out of range"));
  EXPECT_TRUE(Contains(error("j.obj", "v 0 0 0\nf 1 0 1\n"), "j.obj:2: bad face vertex '0'"));
  EXPECT_TRUE(Contains(error("k.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n"),
                       "k.obj:4: face 0: vertex index -1 is out of range"));
  EXPECT_TRUE(Contains(error("l.obj", "v 0 0\n"), "l.obj:1: expected 3 numbers"));
  EXPECT_TRUE(Contains(error("m.obj", "# nothing\n"), "m.obj: no vertices"));
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_TRUE(Contains(error("n.ply", ply + "3 0 1 5\n"),
                       "n.ply:13: face 0: vertex index 5 is out of range"));
  EXPECT_TRUE(Contains(error("o.ply", ply), "o.ply: file ends in element 'face' after 0 of 1"));
  EXPECT_TRUE(Contains(error("p.ply", ply + "3 0 1\n"), "p.ply:13: face 0: the line ends inside"));
  EXPECT_TRUE(Contains(error("q.ply",
                             "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 0\n"
                             "property float area\nend_header\n"),
                       "q.ply:7: the face element has no list property vertex_indices"));
  EXPECT_TRUE(Contains(ErrorOf([&] { ReadMesh(dir.path() + "/missing.off"); }), "cannot open"));
  EXPECT_TRUE(Contains(error("r.png", "x"), "unknown surface format"));
}

TEST(FaceOrientationFromStringTest, ParsesAndRejects) {
  FaceFrameOptions options;
  options.depth_limit = 3.0;
  FaceOrientationFromString("as_is", "--orientation", &options);
  EXPECT_EQ(options.orientation, FaceOrientation::kAsIs);
  FaceOrientationFromString("auto", "--orientation", &options);
  EXPECT_EQ(options.orientation, FaceOrientation::kPrincipalAxes);
  FaceOrientationFromString("-90, 0,1.5", "--orientation", &options);
  EXPECT_EQ(options.orientation, FaceOrientation::kGiven);
  EXPECT_EQ(options.rotation_deg, (std::array<double, 3>{-90, 0, 1.5}));
  EXPECT_EQ(options.depth_limit, 3.0);  // untouched
  EXPECT_EQ(FaceOrientationToString(options), "-90,0,1.5");
  FaceOrientationFromString("[1,2,3]", "--orientation", &options);
  EXPECT_EQ(options.rotation_deg, (std::array<double, 3>{1, 2, 3}));
  for (const char* bad : {"", "Auto", "1,2", "1,2,3,4", "1,,3", "1,x,3", "1,nan,3", "1,2,3,"}) {
    EXPECT_TRUE(Contains(
        ErrorOf([&] { FaceOrientationFromString(bad, "f.yaml:3: key 'orientation'", &options); }),
        "f.yaml:3: key 'orientation': expected auto, as_is or a rotation vector"))
        << bad;
  }
}

}  // namespace
}  // namespace surfreg
