// align_two_surfaces REFERENCE MOVING: aligns MOVING onto REFERENCE with the
// default options and prints the 4 x 4 matrix that maps moving points onto
// the reference (input coordinates), one row per line.
#include <cstdio>

#include <surfreg/io/surface_reader.h>
#include <surfreg/measure/input_error.h>
#include <surfreg/registration/align.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: align_two_surfaces REFERENCE MOVING\n");
    return 2;
  }
  try {
    // Any format the CLI reads: .xyz/.txt/.csv, .ply, .off, .obj, GDAL rasters.
    const surfreg::Surface reference = surfreg::ReadSurface(argv[1]);
    const surfreg::Surface moving = surfreg::ReadSurface(argv[2]);
    const surfreg::AlignResult result = surfreg::Align(reference, moving);
    // The verdict says whether the motion can be trusted; report it (with
    // the motion and the gap before and after), but the matrix is printed
    // either way (it is the initial motion if not improved).
    std::fprintf(stderr, "%s\n", result.BriefReport().c_str());
    const Eigen::Matrix4d matrix = result.reference_from_moving.ToMatrix();
    for (int row = 0; row < 4; ++row) {
      std::printf("%.12g %.12g %.12g %.12g\n", matrix(row, 0), matrix(row, 1), matrix(row, 2), matrix(row, 3));
    }
    return result.verdict == surfreg::Verdict::kFailed ? 1 : 0;
  } catch (const surfreg::InputError& error) {
    // Bad input (unreadable file, no overlap, ...): one line, exit 2.
    std::fprintf(stderr, "align_two_surfaces: error: %s\n", error.what());
    return 2;
  }
}
