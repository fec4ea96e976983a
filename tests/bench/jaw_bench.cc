// Jaw tracking speed against full measures (issue 8), as Google Benchmark
// rows in one run: a synthetic chewing sequence (tests/testing/
// chewing_sequence.h, 30 frames of 2 × 20k-point halves by default) tracked
// by TrackJaw, against Measure() of frame 0 vs frame 1 (40k vs 40k points).
//
// Rows (wall time):
//   BM_MeasureFramePair: one Measure(frame 0, frame 1);
//   BM_TrackJaw/<variant>: the whole sequence, one TrackJaw per iteration;
//     counters: per_frame_s, measures (the run in units of one
//     BM_MeasureFramePair, measured in this process just before; the target
//     is < 1 per 2 frames, i.e. < 60 for 30 frames: ratio_to_target = the
//     run / (2 × frames) measures, target < 1), iterations_per_part, and
//     the worst frame's error against the generated truth (max_error_deg,
//     max_error_mm), failed_frames.
// <variant>: axial (the default); with --variants also volume (10 L-BFGS
// steps after the axial solve), vertical (normal_distance false) and
// no_prediction.
//
//   jaw_bench [--frames=30] [--points=20000] [--variants] [--accuracy_only]
//             [benchmark flags]
//
// Frames are generated before timing (no file reading is timed). Exit
// status 2 (with an ERROR line) when the default variant misses its
// accuracy target (0.1°, 0.05 mm) or, unless --accuracy_only, takes as long
// as 2 × frames measures.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "measure/measures.h"
#include "faces/jaw.h"
#include "tests/testing/chewing_sequence.h"

namespace surfreg {
namespace {

bool g_failed = false;
bool g_check_time = true;      // --accuracy_only clears it (smoke runs on small inputs)
double g_measure_seconds = 0;  // one Measure(frame 0, frame 1), from BM_MeasureFramePair

void Fail(const std::string& message) {
  std::fprintf(stderr, "ERROR: %s\n", message.c_str());
  g_failed = true;
}

struct Sequence {
  ChewingOptions chewing;
  std::vector<ChewingFrame> frames;
  std::vector<Surface> surfaces;
};

Sequence& GetSequence() {
  static Sequence sequence;
  return sequence;
}

void Generate(int frames, int points) {
  Sequence& s = GetSequence();
  s.chewing.frames = frames;
  s.chewing.upper_points = s.chewing.lower_points = points;
  s.chewing.period_frames = 24;  // a chewing cycle of 0.8 s at 30 frames per second
  std::fprintf(stderr, "generating %d frames of %d + %d points...\n", frames, points, points);
  s.frames = MakeChewingSequence(ReadFacePoints(DenseFacePath()), s.chewing);
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    s.surfaces.push_back(MakeSurface(s.frames[k].points, {}, "frame " + std::to_string(k)));
  }
}

void BM_MeasureFramePair(benchmark::State& state) {
  const Sequence& s = GetSequence();
  double total = 0;
  int64_t runs = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const MeasureSummary m = Measure(s.surfaces[0], s.surfaces[1]);
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++runs;
    benchmark::DoNotOptimize(m.rho_d);
  }
  g_measure_seconds = total / static_cast<double>(std::max<int64_t>(1, runs));
  state.counters["points"] = static_cast<double>(s.surfaces[0].size());
}

enum class Variant { kAxial, kVolume, kVertical, kNoPrediction };

JawOptions OptionsFor(Variant v) {
  const Sequence& s = GetSequence();
  JawOptions options;
  options.boundary.y_level = s.chewing.boundary_y;
  options.boundary.margin = 2.0;
  if (v == Variant::kVolume) options.cost = JawCost::kVolume;
  if (v == Variant::kVertical) options.normal_distance = false;
  if (v == Variant::kNoPrediction) options.predict = false;
  return options;
}

void BM_TrackJaw(benchmark::State& state, Variant variant) {
  const Sequence& s = GetSequence();
  const JawOptions options = OptionsFor(variant);
  JawSummary summary;
  double total = 0;
  int64_t runs = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    summary = TrackJaw(s.surfaces, options);
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++runs;
    benchmark::DoNotOptimize(summary.failed_frames);
  }
  const double seconds = total / static_cast<double>(std::max<int64_t>(1, runs));
  const double frames = static_cast<double>(s.frames.size());
  double angle = 0, shift = 0, iterations = 0;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const std::array<double, 2> e = MotionDifference(summary.frames[k].jaw, s.frames[k].jaw);
    angle = std::max(angle, e[0]);
    shift = std::max(shift, e[1]);
    iterations += summary.frames[k].upper.iterations + summary.frames[k].lower.iterations;
  }
  state.counters["per_frame_s"] = seconds / frames;
  state.counters["iterations_per_part"] = iterations / (2.0 * (frames - 1));
  state.counters["max_error_deg"] = angle;
  state.counters["max_error_mm"] = shift;
  state.counters["failed_frames"] = summary.failed_frames;
  if (g_measure_seconds > 0) {
    state.counters["measures"] = seconds / g_measure_seconds;
    state.counters["ratio_to_target"] = seconds / (2.0 * frames * g_measure_seconds);
  }
  if (variant != Variant::kAxial) return;
  char text[256];
  if (angle > 0.1 || shift > 0.05) {
    std::snprintf(text, sizeof text, "default jaw run: worst frame %.4g deg, %.4g mm (limits 0.1, 0.05)",
                  angle, shift);
    Fail(text);
  }
  if (g_check_time && g_measure_seconds > 0 && seconds >= 2.0 * frames * g_measure_seconds) {
    std::snprintf(text, sizeof text, "default jaw run: %.3g s, not less than %.0f measures (%.3g s)",
                  seconds, 2.0 * frames, 2.0 * frames * g_measure_seconds);
    Fail(text);
  }
}

// --name=N: our integer flags (removed from argv).
bool TakeFlag(const char* arg, const char* name, int* value) {
  const std::string prefix = std::string("--") + name + "=";
  if (std::strncmp(arg, prefix.c_str(), prefix.size()) != 0) return false;
  *value = std::atoi(arg + prefix.size());
  return true;
}

}  // namespace
}  // namespace surfreg

int main(int argc, char** argv) {
  using namespace surfreg;
  benchmark::Initialize(&argc, argv);
  int frames = 30, points = 20000;
  bool variants = false;
  int out = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--variants") == 0) {
      variants = true;
    } else if (std::strcmp(argv[i], "--accuracy_only") == 0) {
      g_check_time = false;
    } else if (!TakeFlag(argv[i], "frames", &frames) && !TakeFlag(argv[i], "points", &points)) {
      argv[out++] = argv[i];
    }
  }
  argc = out;
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (frames < 2 || points < 100) {
    std::fprintf(stderr, "jaw_bench: need --frames >= 2 and --points >= 100\n");
    return 1;
  }
  Generate(frames, points);
  // Registration order is run order: the measure row first, so the jaw rows
  // can state their time in measures of this process.
  benchmark::RegisterBenchmark("BM_MeasureFramePair", BM_MeasureFramePair)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  std::vector<std::pair<const char*, Variant>> rows = {{"axial", Variant::kAxial}};
  if (variants) {
    rows.insert(rows.end(), {{"volume", Variant::kVolume},
                             {"vertical", Variant::kVertical},
                             {"no_prediction", Variant::kNoPrediction}});
  }
  for (const auto& [name, variant] : rows) {
    benchmark::RegisterBenchmark((std::string("BM_TrackJaw/") + name).c_str(), BM_TrackJaw, variant)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return g_failed ? 2 : 0;
}
