// The writers of aligned surfaces (io/surface_writer.h), read back by
// the readers, and atomic output files (io/atomic_file.h).
#include <dirent.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "tests/testing/file_checks.h"
#include "io/atomic_file.h"
#include "io/las_writer.h"
#include "io/surface_reader.h"
#include "io/surface_writer.h"

namespace surfreg {
namespace {

using testing::Contains;
using testing::Contents;
using testing::ErrorOf;
using testing::TempDir;

Surface SampleSurface(bool weights) {
  std::vector<std::array<double, 3>> points = {{500000.125, 4100000.5, 123.25},
                                               {500010.0, 4100000.0, -0.1},
                                               {500000.0, 4100012.75, 1e-7},
                                               {500007.3, 4100007.1, 3.0 / 7}};
  std::vector<double> w;
  if (weights) w = {1, 0.5, 0, 2.0 / 3};
  return MakeSurface(points, w, "sample");
}

void ExpectSamePoints(const Surface& a, const Surface& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.weight.size(), b.weight.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.xy[i].x + a.origin[0], b.xy[i].x + b.origin[0]) << i;
    EXPECT_EQ(a.xy[i].y + a.origin[1], b.xy[i].y + b.origin[1]) << i;
    EXPECT_EQ(a.z[i] + a.origin[2], b.z[i] + b.origin[2]) << i;
    if (!a.weight.empty()) {
      EXPECT_EQ(a.weight[i], b.weight[i]) << i;
    }
  }
}

TEST(SurfaceWriter, RoundTripsThroughTheReaders) {
  TempDir dir;
  for (const bool weights : {false, true}) {
    const Surface surface = SampleSurface(weights);
    for (const char* name : {"s.xyz", "s.txt", "S.PLY"}) {
      const std::string path = dir.path() + "/" + name;
      WriteSurface(path, surface, "test", {"a comment", "two\nlines"});
      ExpectSamePoints(surface, ReadSurface(path));
    }
  }
  EXPECT_TRUE(Contains(Contents(dir.path() + "/S.PLY"),
                       "format binary_little_endian 1.0\ncomment a comment\n"
                       "comment two lines\nelement vertex 4\nproperty double x\n"));
  EXPECT_EQ(dir.Files().size(), 3u);  // no temporary files left
}

TEST(SurfaceWriter, XyzText) {
  const std::string text = SurfaceToXyz(SampleSurface(false), {"c"});
  EXPECT_EQ(text.substr(0, text.find('\n', 4) + 1), "# c\n500000.125 4100000.5 123.25\n");
  // Heights pass through the local frame (z - 62): the last bits may change.
  const std::string weighted = SurfaceToXyz(SampleSurface(true));
  EXPECT_TRUE(Contains(weighted, "\n500010 4100000 -0.1"));
  EXPECT_TRUE(Contains(weighted, " 0.5\n500000 4100012.75 1.00000001"));  // not 5e+05
}

// LAS: steps of the power of ten that spans each axis' extent in at most
// 2^30 (the sample's x, y extents ~10: 1e-8; z 123.35: 1e-6), half a step
// at most from the input.
TEST(SurfaceWriter, LasRoundTripsToTheQuantization) {
  TempDir dir;
  const Surface surface = SampleSurface(true);
  const std::string path = dir.path() + "/s.LAS";
  WriteSurface(path, surface, "test");
  const Surface back = ReadSurface(path);
  ASSERT_EQ(back.size(), surface.size());
  EXPECT_TRUE(back.weight.empty());  // LAS has no field for weights
  for (std::size_t i = 0; i < surface.size(); ++i) {
    EXPECT_NEAR(back.xy[i].x + back.origin[0], surface.xy[i].x + surface.origin[0], 0.5e-8 + 1e-12) << i;
    EXPECT_NEAR(back.xy[i].y + back.origin[1], surface.xy[i].y + surface.origin[1], 0.5e-8 + 1e-12) << i;
    EXPECT_NEAR(back.z[i] + back.origin[2], surface.z[i] + surface.origin[2], 0.5e-6 + 1e-12) << i;
  }
}

// Every record moved, the other bytes kept; then back with the inverse.
TEST(SurfaceWriter, MovedLasKeepsAttributesAndInverts) {
  const Surface surface = SampleSurface(false);
  std::string las = SurfaceToLas(surface, "test");
  for (std::size_t i = 0; i < surface.size(); ++i) las[227 + 20 * i + 15] = static_cast<char>(2 + i);  // classes
  const double c = std::cos(0.3), s = std::sin(0.3);
  // A turn of 0.3 rad and a shift of 2e7 (the offsets follow the points).
  const LasMotion turn = {c, -s, 0, 2e7, s, c, 0, -5, 0, 0, 1, 0.5, 0, 0, 0, 1};
  const LasMotion inverse = {c, s, 0, -c * 2e7 + 5 * s, -s, c, 0, s * 2e7 + 5 * c, 0, 0, 1, -0.5, 0, 0, 0, 1};
  const std::string moved = MovedLas(las, turn, "s.las");
  ASSERT_EQ(moved.size(), las.size());
  for (std::size_t i = 0; i < surface.size(); ++i) {
    EXPECT_EQ(moved.substr(227 + 20 * i + 12, 8), las.substr(227 + 20 * i + 12, 8)) << i;
  }
  TempDir dir;
  WriteFileAtomically(dir.path() + "/m.las", moved, "test");
  const Surface m = ReadSurface(dir.path() + "/m.las");
  WriteFileAtomically(dir.path() + "/b.las", MovedLas(moved, inverse, "m.las"), "test");
  const Surface b = ReadSurface(dir.path() + "/b.las");
  for (std::size_t i = 0; i < surface.size(); ++i) {
    const double x = surface.xy[i].x + surface.origin[0], y = surface.xy[i].y + surface.origin[1];
    EXPECT_NEAR(m.xy[i].x + m.origin[0], c * x - s * y + 2e7, 1e-7) << i;
    EXPECT_NEAR(m.xy[i].y + m.origin[1], s * x + c * y - 5, 1e-7) << i;
    EXPECT_NEAR(b.xy[i].x + b.origin[0], x, 1e-7) << i;
    EXPECT_NEAR(b.xy[i].y + b.origin[1], y, 1e-7) << i;
    EXPECT_NEAR(b.z[i] + b.origin[2], surface.z[i] + surface.origin[2], 1e-6) << i;
  }
}

TEST(SurfaceWriter, MovedLasRejectsARecordsOverrun) {
  const std::string las = SurfaceToLas(SampleSurface(false), "test");
  const LasMotion identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_TRUE(Contains(ErrorOf([&] { MovedLas(las.substr(0, las.size() - 5), identity, "cut.las"); }),
                       "cut.las: 4 point records of 20 bytes from byte 227 do not fit the file's"));
  EXPECT_TRUE(Contains(ErrorOf([&] { MovedLas("LASF", identity, "tiny.las"); }), "tiny.las: not a LAS file"));
}

TEST(SurfaceWriter, UnknownExtension) {
  TempDir dir;
  EXPECT_TRUE(Contains(
      ErrorOf([&] { WriteSurface(dir.path() + "/s.obj", SampleSurface(false), "key 'aligned'"); }),
      "key 'aligned': cannot write a surface as"));
  EXPECT_TRUE(dir.Files().empty());
}

TEST(AtomicFile, WritesAndReplaces) {
  TempDir dir;
  const std::string path = dir.path() + "/out.json";
  WriteFileAtomically(path, "first", "test");
  WriteFileAtomically(path, "second", "test");
  EXPECT_EQ(Contents(path), "second");
  EXPECT_EQ(dir.Files(), std::vector<std::string>{"out.json"});
  struct stat info;
  ASSERT_EQ(::stat(path.c_str(), &info), 0);
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(info.st_mode & 0777, 0666 & ~mask);  // like any new file, not mkstemp's 0600
}

TEST(AtomicFile, BadPathsNameTheLabelAndCreateNothing) {
  TempDir dir;
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteFileAtomically(dir.path() + "/missing/o", "d", "k"); }),
                       "k: cannot write '" + dir.path() + "/missing/o': directory '" + dir.path() +
                           "/missing' does not exist"));
  const std::string file = dir.File("file", "x");
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteFileAtomically(file + "/o", "d", "k"); }),
                       "'" + file + "' is not a directory"));
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteFileAtomically(dir.path(), "d", "key 'log'"); }),
                       "key 'log': cannot write '" + dir.path() + "': it is a directory"));
  EXPECT_EQ(dir.Files(), std::vector<std::string>{"file"});
}

// A write that fails half-way (file size limit: EFBIG) removes the temporary
// file and leaves the previous file untouched.
TEST(AtomicFile, FailedWriteLeavesNoTemporaryFile) {
  TempDir dir;
  const std::string path = dir.File("out.json", "old");
  struct rlimit saved;
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
  void (*saved_handler)(int) = std::signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = saved;
  small.rlim_cur = 64;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const std::string error =
      ErrorOf([&] { WriteFileAtomically(path, std::string(4096, 'x'), "key 'output'"); });
  setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, saved_handler);
  EXPECT_TRUE(Contains(error, "key 'output': cannot write '" + path + "': File too large"));
  EXPECT_EQ(dir.Files(), std::vector<std::string>{"out.json"});
  EXPECT_EQ(Contents(path), "old");
}

}  // namespace
}  // namespace surfreg
