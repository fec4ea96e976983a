// terrain_change A B [LOD]: two DEMs (GeoTIFF rasters or point clouds)
// differenced as they lie through the terrain library, as
// `surfreg measure A B --lod=LOD --json` does: both brought into one metric
// frame, the statistics of dz = B − A at A's nodes, and the cut/fill beyond
// the level of detection LOD (data units; default 0).
#include <cstdio>
#include <cstdlib>

#include <surfreg/measure/input_error.h>
#include <surfreg/terrain/terrain_measure.h>

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: terrain_change A B [LOD]\n");
    return 2;
  }
  surfreg::TerrainRequest request;
  request.reference = argv[1];
  request.moving = argv[2];
  if (argc == 4) request.terrain.lod = std::atof(argv[3]);
  surfreg::MeasureOptions options;
  options.detect_change = true;  // cut/fill beyond the level of detection
  try {
    const surfreg::TerrainMeasure m = surfreg::MeasureTerrain(request, options);
    const surfreg::DzStatistics& dz = m.dz;
    const surfreg::MeasureSummary& s = m.summary;
    std::printf("frame %s\n", m.frame.Describe().c_str());
    std::printf("dz count %lld mean %.17g median %.17g nmad %.17g stddev %.17g rmse %.17g\n",
                static_cast<long long>(dz.count), dz.mean, dz.median, dz.nmad, dz.stddev, dz.rmse);
    std::printf("change lod %.17g fill %.17g cut %.17g net %.17g fill_area %.17g cut_area %.17g\n",
                s.level_of_detection, s.fill_detected, s.cut_detected, s.fill_detected - s.cut_detected,
                s.fill_area, s.cut_area);
    return 0;
  } catch (const surfreg::InputError& error) {
    // Bad input (unreadable file, a CRS that does not fit, no overlap): one line, exit 2.
    std::fprintf(stderr, "terrain_change: error: %s\n", error.what());
    return 2;
  }
}
