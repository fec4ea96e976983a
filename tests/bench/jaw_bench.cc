// Jaw tracking speed against full measures (issue 8): a 30-frame synthetic
// chewing sequence (tests/testing/chewing_sequence.h) of 2 × 20k-point
// halves, tracked by TrackJaw, against 60 Measure() calls of frame 0 vs
// frame 1 (40k vs 40k points), timed in the same process one after the
// other. Prints the ratio (target < 1) and the accuracy of every variant.
//
//   jaw_bench [--frames=30] [--points=20000] [--measures=60] [--variants]
//
// --variants adds rows for cost volume (10 L-BFGS steps after the axial solve),
// plain vertical gaps (normal_distance false) and no warm-start prediction.
// Frames are generated in memory before timing (no file reading is timed).
// Exit status 0, or 2 if the default variant misses the accuracy target.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "measure/measures.h"
#include "registration/jaw.h"
#include "tests/testing/chewing_sequence.h"

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

int Flag(int argc, char** argv, const char* name, int fallback) {
  const std::string prefix = std::string("--") + name + "=";
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], prefix.c_str(), prefix.size()) == 0) return std::atoi(argv[i] + prefix.size());
  }
  return fallback;
}

struct Row {
  const char* name;
  JawOptions options;
};

int Main(int argc, char** argv) {
  bool variants = false;
  for (int i = 1; i < argc; ++i) variants |= std::strcmp(argv[i], "--variants") == 0;
  ChewingOptions chewing;
  chewing.frames = Flag(argc, argv, "frames", 30);
  chewing.upper_points = chewing.lower_points = Flag(argc, argv, "points", 20000);
  chewing.period_frames = 24;  // a chewing cycle of 0.8 s at 30 frames per second
  const int measures = Flag(argc, argv, "measures", 60);
  std::fprintf(stderr, "generating %d frames of %d + %d points...\n", chewing.frames, chewing.upper_points,
               chewing.lower_points);
  const std::vector<ChewingFrame> frames = MakeChewingSequence(ReadFacePoints(DenseFacePath()), chewing);
  std::vector<Surface> surfaces;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    surfaces.push_back(MakeSurface(frames[k].points, {}, "frame " + std::to_string(k)));
  }

  Clock::time_point start = Clock::now();
  for (int i = 0; i < measures; ++i) Measure(surfaces[0], surfaces[1]);
  const double measure_seconds = Since(start);
  std::printf("%d x Measure(frame 0, frame 1), %zu vs %zu points: %.3f s (%.4f s each)\n\n", measures,
              surfaces[0].size(), surfaces[1].size(), measure_seconds, measure_seconds / measures);

  JawOptions base;
  base.boundary.y_level = chewing.boundary_y;
  base.boundary.margin = 2.0;
  std::vector<Row> rows = {{"axial (default)", base}};
  if (variants) {
    Row volume{"volume (+10 L-BFGS)", base};
    volume.options.cost = JawCost::kVolume;
    Row vertical{"axial, vertical gaps", base};
    vertical.options.normal_distance = false;
    Row still{"axial, no prediction", base};
    still.options.predict = false;
    rows.insert(rows.end(), {volume, vertical, still});
  }
  std::printf("| variant | jaw run (s) | per frame (s) | ratio to %d measures | solver iterations per part | max error (deg) | max error (mm) | failed frames |\n",
              measures);
  std::printf("|---|---|---|---|---|---|---|---|\n");
  int status = 0;
  for (const Row& row : rows) {
    start = Clock::now();
    const JawSummary summary = TrackJaw(surfaces, row.options);
    const double seconds = Since(start);
    double angle = 0, shift = 0, iterations = 0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      const std::array<double, 2> e = MotionDifference(summary.frames[k].jaw, frames[k].jaw);
      angle = std::max(angle, e[0]);
      shift = std::max(shift, e[1]);
      iterations += summary.frames[k].upper.iterations + summary.frames[k].lower.iterations;
    }
    iterations /= 2.0 * static_cast<double>(frames.size() - 1);
    std::printf("| %s | %.3f | %.4f | %.3f | %.1f | %.4f | %.4f | %d |\n", row.name, seconds,
                seconds / static_cast<double>(frames.size()), seconds / measure_seconds, iterations, angle,
                shift, summary.failed_frames);
    std::fflush(stdout);
    if (&row == &rows.front() && (angle > 0.1 || shift > 0.05 || seconds >= measure_seconds)) status = 2;
  }
  return status;
}

}  // namespace
}  // namespace surfreg

int main(int argc, char** argv) { return surfreg::Main(argc, argv); }
