// Memory limits of the surface readers (issue 7): a file or a declared point
// count that needs more memory than the run has is refused with one clear
// InputError line before anything is allocated for it, instead of the
// process being killed for running out of memory.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <sstream>
#include <string>

#include "tests/testing/file_checks.h"
#include "io/surface_reader.h"

namespace surfreg {
namespace {

using testing::Contains;
using testing::ErrorOf;

constexpr uint64_t kMiB = uint64_t{1} << 20;

Surface Parse(Surface (*reader)(std::istream&, const std::string&, const ReadOptions&),
              const std::string& text, const std::string& name, const ReadOptions& options = {}) {
  std::istringstream in(text, std::ios::in | std::ios::binary);
  return reader(in, name, options);
}

// n points on a 100-column grid, "x y z" lines.
std::string GridText(int n) {
  std::string text;
  for (int i = 0; i < n; ++i) {
    text += std::to_string(i % 100) + " " + std::to_string(i / 100) + " " + std::to_string(i % 7) +
            "\n";
  }
  return text;
}

TEST(ReaderLimitsTest, PlyHeaderDeclaringATrillionVerticesIsRefusedBeforeReading) {
  // The machine's real limit: 1e12 points x 500 B is far beyond any memory.
  for (const char* format : {"ascii", "binary_little_endian"}) {
    const std::string ply = std::string("ply\nformat ") + format +
                            " 1.0\nelement vertex 1000000000000\nproperty float x\n"
                            "property float y\nproperty float z\nend_header\n0 0 0\n";
    const std::string message = ErrorOf([&] { Parse(ReadPly, ply, "big.ply"); });
    EXPECT_TRUE(Contains(message, "big.ply: 1000000000000 points need about 465661.3 GiB, more "
                                  "than the "))
        << format;
    EXPECT_TRUE(Contains(message, " available")) << format;
  }
}

TEST(ReaderLimitsTest, OffHeaderDeclaringATrillionVerticesIsRefusedBeforeReading) {
  const std::string message =
      ErrorOf([] { Parse(ReadOff, "OFF\n1000000000000 0 0\n0 0 0\n", "big.off"); });
  EXPECT_TRUE(Contains(message, "big.off: 1000000000000 points need about 465661.3 GiB"));
}

TEST(ReaderLimitsTest, CountedPointsAgainstAnInjectedLimit) {
  // 3000 points x 500 B = 1.5e6 B: refused under 1 MiB, read at exactly that.
  ReadOptions small;
  small.memory_limit_bytes = kMiB;
  EXPECT_EQ(ErrorOf([&] { Parse(ReadXyz, GridText(3000), "grid.xyz", small); }),
            "grid.xyz: 3000 points need about 1.4 MiB, more than the 1.0 MiB available");
  ReadOptions exact;
  exact.memory_limit_bytes = 3000 * kBytesPerPoint;
  EXPECT_EQ(Parse(ReadXyz, GridText(3000), "grid.xyz", exact).size(), 3000u);
  EXPECT_EQ(ErrorOf([&] { Parse(ReadObj, "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "a.obj", [] {
                      ReadOptions tiny;
                      tiny.memory_limit_bytes = 2 * kBytesPerPoint;
                      return tiny;
                    }()); }),
            "a.obj: 3 points need about 1500 bytes, more than the 1000 bytes available");
}

TEST(ReaderLimitsTest, CheckPointCountBoundaryAndHugeCounts) {
  ReadOptions options;
  options.memory_limit_bytes = 10 * kBytesPerPoint;
  EXPECT_NO_THROW(CheckPointCount(10, "a", options));
  EXPECT_TRUE(Contains(ErrorOf([&] { CheckPointCount(11, "a", options); }), "a: 11 points"));
  // No overflow of count x bytes per point.
  EXPECT_TRUE(Contains(ErrorOf([&] { CheckPointCount(UINT64_MAX, "a", options); }),
                       "a: 18446744073709551615 points need about"));
}

TEST(ReaderLimitsTest, ReadSurfaceRefusesAFileLargerThanTheLimitBeforeReadingIt) {
  testing::TempDir dir;
  const std::string path = dir.File("big.xyz", std::string(2 * kMiB, '#'));
  ReadOptions options;
  options.memory_limit_bytes = kMiB;
  EXPECT_EQ(ErrorOf([&] { ReadSurface(path, options); }),
            path + ": the file is 2.0 MiB, more than the 1.0 MiB available");
}

TEST(ReaderLimitsTest, AvailableMemoryIsPositiveAndAtMostThePhysicalMemory) {
  const uint64_t physical = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
  const uint64_t available = AvailableMemoryBytes();
  EXPECT_GT(available, 0u);
  EXPECT_LE(available, physical);
}

}  // namespace
}  // namespace surfreg
