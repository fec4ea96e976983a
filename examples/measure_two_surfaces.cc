// measure_two_surfaces A B: the volume between surfaces A and B (ρd), the
// mean vertical gap (ρ'd), the similarity ρs and the overlap, as they lie
// (no alignment).
#include <cstdio>

#include <surfreg/io/surface_reader.h>
#include <surfreg/measure/input_error.h>
#include <surfreg/measure/measures.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: measure_two_surfaces A B\n");
    return 2;
  }
  try {
    const surfreg::Surface a = surfreg::ReadSurface(argv[1]);
    const surfreg::Surface b = surfreg::ReadSurface(argv[2]);
    const surfreg::MeasureSummary measures = surfreg::Measure(a, b);
    std::printf("rho_d %.9g\n", measures.rho_d);               // units³
    std::printf("rho_d_axial %.9g\n", measures.rho_d_axial);   // units
    std::printf("rho_s %.9g\n", measures.rho_s);               // 1 / rho_d
    std::printf("overlap_area %.9g\n", measures.overlap_area); // units²
    std::printf("mean_abs_dz %.9g\n", measures.mean_abs_dz);   // units
    return 0;
  } catch (const surfreg::InputError& error) {
    // Bad input (unreadable file, too few points, no overlap): one line, exit 2.
    std::fprintf(stderr, "measure_two_surfaces: error: %s\n", error.what());
    return 2;
  }
}
