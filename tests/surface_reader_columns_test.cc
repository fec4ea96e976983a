// Text clouds with ReadOptions::columns (x, y, z [, weight] by header name
// or 1-based position, other columns ignored), ';' as a separator, and the
// message for more than 4 columns without `columns`.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/surface_reader_test_util.h"
#include "io/surface_reader.h"

namespace surfreg {
namespace {

using reader_test::Contains;
using reader_test::ExpectPoint;

ReadOptions Columns(std::vector<std::string> columns) {
  ReadOptions options;
  options.columns = std::move(columns);
  return options;
}

Surface Xyz(const std::string& text, const ReadOptions& options = {}) {
  return reader_test::Read(ReadXyz, text, "data/a.xyz", options);
}

std::string XyzError(const std::string& text, const ReadOptions& options) {
  try {
    Xyz(text, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// x y z intensity r g b, as many LIDAR exports write them.
const char* const kSeven =
    "X Y Z Intensity R G B\n"
    "1 2 3 100 255 0 0\n"
    "4.5 -5 6 120 0 255 0\n"
    "7 8.25 -9 90 0 0 255\n";

void ExpectTriangle(const Surface& s) {
  ASSERT_EQ(s.size(), 3u);
  ExpectPoint(s, 0, 1.0, 2.0, 3.0);
  ExpectPoint(s, 1, 4.5, -5.0, 6.0);
  ExpectPoint(s, 2, 7.0, 8.25, -9.0);
}

TEST(XyzColumns, SevenColumnsNeedColumns) {
  EXPECT_EQ(XyzError(kSeven, {}),
            "data/a.xyz:2: expected 3 numbers (x y z) or 4 (x y z weight), found 7 columns; give "
            "`columns` (e.g. columns: 1,2,3) to pick x, y, z");
}

TEST(XyzColumns, ByName) {
  ExpectTriangle(Xyz(kSeven, Columns({"X", "Y", "Z"})));
  ExpectTriangle(Xyz(kSeven, Columns({"x", "y", "z"})));  // names match in any case
  const Surface s = Xyz(kSeven, Columns({"x", "y", "z", "intensity"}));
  EXPECT_EQ(s.weight, (std::vector<double>{100, 120, 90}));
}

TEST(XyzColumns, ByPosition) {
  ExpectTriangle(Xyz(kSeven, Columns({"1", "2", "3"})));
  const Surface s = Xyz(kSeven, Columns({"1", "2", "3", "5"}));
  EXPECT_EQ(s.weight, (std::vector<double>{255, 0, 0}));
  // Reordered columns, no header; the unpicked column may hold anything.
  ExpectTriangle(
      Xyz("class h e n\nground 3 1 2\nground 6 4.5 -5\nwater -9 7 8.25\n", Columns({"3", "4", "2"})));
  // 3 columns picked from 4: the 4th is not read as a weight.
  EXPECT_TRUE(Xyz("1 2 3 7\n4.5 -5 6 7\n7 8.25 -9 7\n", Columns({"1", "2", "3"})).weight.empty());
}

TEST(XyzColumns, FieldsBeyondThePositionLimitAreCountedNotKept) {
  std::string tail;
  for (int i = 0; i < 150000; ++i) tail += " 0";
  const Surface s =
      Xyz("1 2 3" + tail + "\n4.5 -5 6" + tail + "\n7 8.25 -9" + tail + "\n", Columns({"1", "2", "3"}));
  ExpectTriangle(s);
  EXPECT_EQ(XyzError("1 2 3" + tail + "\n4 5 6\n", Columns({"1", "2", "3"})),
            "data/a.xyz:2: found 3 columns, line 1 has 150003");
  EXPECT_EQ(XyzError("1 2 3\n", Columns({"1", "2", "100001"})),
            "data/a.xyz: columns: position '100001' is not 1 to 100000 (1-based)");
}

TEST(XyzColumns, SemicolonSeparator) {
  ExpectTriangle(Xyz("x;y;z\n1;2;3\n4.5;-5;6\n7;8.25;-9\n"));
  ExpectTriangle(Xyz("1 ; 2; 3\n4.5 ;-5 ;6\n7;\t8.25;-9\n"));
  ExpectTriangle(Xyz("id;X;Y;Z\n1;1;2;3\n2;4.5;-5;6\n3;7;8.25;-9\n", Columns({"X", "Y", "Z"})));
  EXPECT_TRUE(Contains(XyzError("1;2;3\n1;;2;3\n", {}), "data/a.xyz:2: empty field"));
}

TEST(XyzColumns, Errors) {
  EXPECT_EQ(XyzError(kSeven, Columns({"X", "Y", "H"})),
            "data/a.xyz:1: columns: no column 'H' in the header line ('X, Y, Z, Intensity, R, G, "
            "B')");
  EXPECT_EQ(XyzError("1 2 3\n4 5 6\n7 8 0\n", Columns({"X", "Y", "Z"})),
            "data/a.xyz:1: columns names a column ('X') but the file has no header line (its "
            "first line is numbers); give positions, e.g. columns: 1,2,3");
  EXPECT_EQ(XyzError("1 2 3\n4 5 6\n7 8 0\n", Columns({"1", "2", "4"})),
            "data/a.xyz:1: columns picks column 4, but the line has 3");
  EXPECT_EQ(XyzError("a b c d\n1 2 3 4\n4 5 6\n", Columns({"a", "b", "c"})),
            "data/a.xyz:3: found 3 columns, the header line 1 names 4");
  EXPECT_EQ(XyzError("1 2 3 4\n4 5 6\n", Columns({"1", "2", "3"})),
            "data/a.xyz:2: found 3 columns, line 1 has 4");
  EXPECT_EQ(XyzError("1 2 3 x\n", Columns({"1", "2", "4"})), "data/a.xyz:1: z is not a number: 'x'");
  EXPECT_EQ(XyzError("1 2 3 -1\n", Columns({"1", "2", "3", "4"})),
            "data/a.xyz:1: weight is negative: '-1'");
  EXPECT_EQ(XyzError("1 2 3\n", Columns({"1", "2"})),
            "data/a.xyz: columns: expected 3 or 4 columns (x, y, z and optionally weight), got 2");
  EXPECT_EQ(XyzError("1 2 3\n", Columns({"0", "1", "2"})),
            "data/a.xyz: columns: position '0' is not 1 to 100000 (1-based)");
}

// Files of more than 4 MB are parsed in chunks of lines: the same points on
// any number of threads, and an error in a late chunk names its own line.
std::string LargeText(int lines, const std::string& header, const std::string& columns_after) {
  std::string text = header;
  for (int i = 0; i < lines; ++i) {
    text += std::to_string(i % 997) + "." + std::to_string(i % 7) + " " + std::to_string(i / 997) + " " +
            std::to_string((i * 37LL) % 1000) + columns_after + "\n";
  }
  return text;
}

TEST(XyzChunks, SamePointsOnAnyNumberOfThreads) {
  for (const std::string& header : {std::string(""), std::string("# comment\nx y z w\n")}) {
    const std::string text = LargeText(1000000, header, header.empty() ? "" : " 2.5");
    ASSERT_GT(text.size(), 12u << 20);  // three chunks
    ReadOptions one;
    const Surface a = Xyz(text, one);
    ASSERT_EQ(a.size(), 1000000u);
    ReadOptions many;
    many.threads = 4;
    const Surface b = Xyz(text, many);
    ASSERT_EQ(b.size(), a.size());
    for (std::size_t i = 0; i < a.size(); i += 1013) {
      EXPECT_EQ(reader_test::InputPoint(a, i), reader_test::InputPoint(b, i)) << i;
    }
    EXPECT_EQ(a.weight, b.weight);
    ExpectPoint(a, 999999, 999999 % 997 + (999999 % 7) / 10.0, 999999 / 997, (999999LL * 37) % 1000);
  }
}

TEST(XyzChunks, ErrorsInLateChunksNameTheirLine) {
  std::string text = LargeText(1000000, "", "");
  // Line 800 001 (in the last chunk) gets a fourth number; line 900 001 a word.
  auto line_start = [&](int line) {
    std::size_t at = 0;
    for (int k = 1; k < line; ++k) at = text.find('\n', at) + 1;
    return at;
  };
  std::string four = text;
  four.insert(four.find('\n', line_start(800001)), " 7");
  ReadOptions many;
  many.threads = 4;
  EXPECT_EQ(XyzError(four, many), "data/a.xyz:800001: expected 3 numbers (x y z) like line 1, found 4");
  EXPECT_EQ(XyzError(four, ReadOptions()), XyzError(four, many));
  std::string word = four;
  word.replace(line_start(900001), 1, "q");
  EXPECT_EQ(XyzError(word, many), XyzError(four, many));  // the first one in the file
  std::string only_word = text;
  only_word.replace(line_start(900001), 1, "q");
  EXPECT_TRUE(Contains(XyzError(only_word, many), "data/a.xyz:900001:"));
  EXPECT_EQ(XyzError(only_word, ReadOptions()), XyzError(only_word, many));
}

}  // namespace
}  // namespace surfreg
