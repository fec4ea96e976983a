// Transform files (tools/transform_file.h): surfreg's align JSON and 4 x 4
// text matrices read to the same doubles, MatrixText reads back exactly,
// and every bad file is one InputError naming the file (and line) and why.
#include "tools/transform_file.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "tests/testing/file_checks.h"

namespace surfreg {
namespace {

using testing::Contains;
using testing::ErrorOf;
using testing::TempDir;

// A rotation about a skew axis and a UTM-sized shift: no entry is round.
Eigen::Matrix4d Motion() {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(512345.678, -4.25, 1e-3);
  return m;
}

std::string Read(const std::string& path) {
  return ErrorOf([&] { ReadTransformFile(path, "flag '--transform'"); });
}

TEST(TransformFileTest, MatrixTextReadsBackExactly) {
  TempDir dir;
  const Eigen::Matrix4d m = Motion();
  const std::string text = MatrixText(m);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 4);
  const Eigen::Matrix4d back = ReadTransformFile(dir.File("m.txt", text), "x");
  EXPECT_EQ(back, m);  // %.17g: the same doubles
}

TEST(TransformFileTest, OneLineIsSixteenNumbersRowMajor) {
  Eigen::Matrix4d m = Motion();
  const std::string line = MatrixOneLine(m);
  EXPECT_EQ(std::count(line.begin(), line.end(), ' '), 15);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_EQ(std::stod(line.substr(line.rfind(' '))), 1.0);  // m(3, 3) last
  TempDir dir;
  EXPECT_EQ(ReadTransformFile(dir.File("m.txt", line), "x"), m);
}

TEST(TransformFileTest, ReadsAlignJson) {
  TempDir dir;
  const std::string json =
      "{\"matrix\": [[0, -1, 0, 10.5], [1, 0, 0, -2], [0, 0, 1, 0.25], [0, 0, 0, 1]], "
      "\"rotation_vector\": [0, 0, 1.5707963267948966], \"verdict\": \"converged_improved\"}\n";
  const Eigen::Matrix4d m = ReadTransformFile(dir.File("t.json", json), "x");
  Eigen::Matrix4d expected;
  expected << 0, -1, 0, 10.5, 1, 0, 0, -2, 0, 0, 1, 0.25, 0, 0, 0, 1;
  EXPECT_EQ(m, expected);
}

TEST(TransformFileTest, ReadsCommasCommentsAndBlankLines) {
  TempDir dir;
  const std::string text =
      "# from CloudCompare\n\n"
      "0,-1,0,10.5\n"
      "1, 0, 0, -2   # trailing comment\n"
      "\t0\t0\t1\t0.25\n"
      "0 0 0 1\n";
  Eigen::Matrix4d expected;
  expected << 0, -1, 0, 10.5, 1, 0, 0, -2, 0, 0, 1, 0.25, 0, 0, 0, 1;
  EXPECT_EQ(ReadTransformFile(dir.File("t.txt", text), "x"), expected);
}

TEST(TransformFileTest, FifteenOrSeventeenNumbers) {
  TempDir dir;
  const std::string fifteen = dir.File("t.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0\n");
  const std::string message = Read(fifteen);
  EXPECT_TRUE(Contains(message, "flag '--transform': " + fifteen + ": 15 numbers"));
  const std::string seventeen = dir.File("u.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n\n5\n");
  EXPECT_TRUE(Contains(Read(seventeen), seventeen + ":6: 17 numbers"));
}

TEST(TransformFileTest, NanAndWordsNameTheLine) {
  TempDir dir;
  const std::string nan = dir.File("t.txt", "1 0 0 0\n0 1 0 nan\n0 0 1 0\n0 0 0 1\n");
  EXPECT_TRUE(Contains(Read(nan), nan + ":2: 'nan' is not a finite number"));
  const std::string word = dir.File("u.txt", "1 0 0 0\n0 1 0 0\n0 0 1 1.5m\n0 0 0 1\n");
  EXPECT_TRUE(Contains(Read(word), word + ":3: '1.5m' is not a number"));
}

TEST(TransformFileTest, ShearScaleReflectionAndLastRow) {
  TempDir dir;
  const std::string shear = dir.File("s.txt", "1 0.1 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_TRUE(Contains(Read(shear), "not a rigid motion: the 3 x 3 part is not a rotation"));
  const std::string scale = dir.File("k.txt", "2 0 0 0\n0 2 0 0\n0 0 2 0\n0 0 0 1\n");
  EXPECT_TRUE(Contains(Read(scale), "not a rigid motion"));
  const std::string mirror = dir.File("m.txt", "1 0 0 0\n0 1 0 0\n0 0 -1 0\n0 0 0 1\n");
  EXPECT_TRUE(Contains(Read(mirror), mirror + ": not a rigid motion: the 3 x 3 part is a reflection"));
  const std::string row = dir.File("r.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0.5 1\n");
  EXPECT_TRUE(Contains(Read(row), "the last row is 0 0 0.5 1, not 0 0 0 1"));
}

TEST(TransformFileTest, SevenDigitsAreRigidEnough) {
  TempDir dir;
  char text[512];
  const Eigen::Matrix4d m = Motion();
  std::string all;
  for (int i = 0; i < 4; ++i) {
    std::snprintf(text, sizeof(text), "%.7g %.7g %.7g %.10g\n", m(i, 0), m(i, 1), m(i, 2), m(i, 3));
    all += text;
  }
  const Eigen::Matrix4d back = ReadTransformFile(dir.File("m.txt", all), "x");
  EXPECT_LT((back - m).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(TransformFileTest, MissingFileAndBadJson) {
  TempDir dir;
  const std::string missing = dir.path() + "/none.txt";
  EXPECT_TRUE(Contains(Read(missing), "flag '--transform': " + missing + ": cannot open"));
  const std::string no_matrix = dir.File("a.json", "{\"rotation_vector\": [0, 0, 0]}\n");
  EXPECT_TRUE(Contains(Read(no_matrix), no_matrix + ": a JSON transform needs a \"matrix\" member"));
  const std::string ragged =
      dir.File("b.json", "{\n\"matrix\": [[1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}\n");
  EXPECT_TRUE(Contains(Read(ragged), ragged + ":2: \"matrix\" must be 4 lists of 4 numbers"));
  const std::string broken = dir.File("c.json", "{\"matrix\": [[1, 0, 0, 0]\n");
  EXPECT_TRUE(Contains(Read(broken), "not valid JSON"));
  const std::string empty = dir.File("d.txt", "# nothing\n");
  EXPECT_TRUE(Contains(Read(empty), empty + ": 0 numbers"));
}

}  // namespace
}  // namespace surfreg
