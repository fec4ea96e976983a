// surfreg align --config FILE.yaml [--key=value ...] | REFERENCE MOVING [--key=value ...]:
// rigid registration of MOVING onto REFERENCE (registration/align.h), with the
// settings of tools/align_config.h; writes the transform JSON, the aligned
// surface and a per-iteration CSV where asked, and prints a summary.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "registration/align.h"
#include "tools/align_config.h"
#include "tools/align_run.h"
#include "tools/commands.h"
#include "tools/json_writer.h"
#include "tools/progress_lines.h"
#include "terrain/terrain.h"

// Every config key is a flag, made from its table (tools/key_flags.h); the
// flags here are align's own that are not keys.
DECLARE_bool(quiet);  // tools/run_measure.cc
DEFINE_string(config, "", "align: the YAML config file (instead of REFERENCE MOVING)");
DEFINE_string(manifest, "", "align: CSV of pairs (reference,moving,output[,aligned]) to align in turn");

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Settings: the config file or the two arguments, then the flags given.
AlignConfig LoadConfig(const std::vector<std::string>& args) {
  const bool has_config = !FLAGS_config.empty();
  if (has_config && !args.empty()) {
    throw UsageError("align: give either --config FILE.yaml or REFERENCE MOVING, not both");
  }
  if (!has_config && args.size() != 2) {
    if (args.size() > 2) throw UsageError("align: too many arguments");
    if (args.empty()) throw UsageError("align: missing REFERENCE MOVING or --config FILE.yaml");
    const std::string& only = args[0];
    const bool yaml = (only.size() > 5 && only.compare(only.size() - 5, 5, ".yaml") == 0) ||
                      (only.size() > 4 && only.compare(only.size() - 4, 4, ".yml") == 0);
    throw UsageError(yaml ? "align: missing MOVING (for a config file: --config " + only + ")"
                          : "align: missing MOVING");
  }
  AlignConfig config;
  if (has_config) {
    ApplyAlignConfigFile(FLAGS_config, &config);
  } else {
    ApplyAlignArguments(args[0], args[1], &config);
  }
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    gflags::CommandLineFlagInfo info;
    CHECK(gflags::GetCommandLineFlagInfo(key.name, &info)) << "no flag for key " << key.name;
    if (!info.is_default) ApplyAlignFlag(key.name, info.current_value, &config);
  }
  FinishAlignConfig(&config);
  return config;
}

// Per iteration on stderr: always with `progress`, otherwise once the run
// has taken more than a second (a quiet fast run, a visible slow one).
void PrintProgress(const AlignOptions::Iteration& it, const AlignConfig& config,
                   Clock::time_point start) {
  if (FLAGS_quiet || (!config.progress && Since(start) < 1.0)) return;
  // Stamped on the command's clock, as the stage lines are: a wide search
  // or a stable-terrain round restarts the solve's own.
  AlignOptions::Iteration stamped = it;
  stamped.seconds = Since(start);
  std::fputs(AlignProgressLine(stamped, config.options.levels).c_str(), stderr);
}

void PrintSummary(const AlignConfig& config, const TerrainInputs& inputs, const AlignResult& r) {
  const Surface& reference = inputs.reference;
  const Surface& moving = inputs.moving;
  // A tiled run holds no whole surface: its sample's sizes are in its own lines.
  const auto points = [](const Surface& s) {
    return s.size() > 0 ? "  (" + std::to_string(s.size()) + " points)" : std::string();
  };
  std::printf("reference:    %s%s\n", config.reference.c_str(), points(reference).c_str());
  std::printf("moving:       %s%s\n", config.moving.c_str(), points(moving).c_str());
  // `auto` says what it chose.
  const std::string cost = AlignConfigValue(config, "cost");
  std::printf("cost:         %s, free %s\n", (cost == "auto" ? "auto (" + r.solve_cost + ")" : cost).c_str(),
              AlignConfigValue(config, "free").c_str());
  std::fputs(r.FullReport(LengthUnit(inputs)).c_str(), stdout);
  for (const char* key : {"output", "matrix_txt", "aligned", "log"}) {
    const std::string path = AlignConfigValue(config, key);
    if (!path.empty()) std::printf("%-13s %s\n", (std::string(key) + ":").c_str(), path.c_str());
  }
}

}  // namespace

int RunAlign(const std::vector<std::string>& args) {
  if (!FLAGS_manifest.empty()) return RunAlignManifest(args);  // tools/run_batch.cc
  const Clock::time_point start = Clock::now();
  AlignConfig config = LoadConfig(args);
  // The long stages around the solve, as the iterations: once past a second,
  // or from the start for large inputs (their reading is the first stage).
  const bool large = LargeInputs({config.reference, config.moving});
  if (!FLAGS_quiet && large) PrintReadingLine("align", {config.reference, config.moving});
  config.options.on_stage = [progress = config.progress || large, start](const char* stage, double) {
    // A wide search is announced however short the run.
    const bool wide = std::string(stage).rfind("wide search", 0) == 0;
    if (!FLAGS_quiet && (progress || wide || Since(start) >= 1.0)) {
      std::fprintf(stderr, "align: %s (%.1f s)\n", stage, Since(start));
    }
  };
  const AlignRun run = AlignSurfaces(
      config, std::nullopt, std::nullopt,
      [&config, start](const AlignOptions::Iteration& it) { PrintProgress(it, config, start); });
  const AlignResult& result = run.result;
  LOG(INFO) << "aligned " << config.moving << " onto " << config.reference << ": "
            << VerdictName(result.verdict) << " in " << Since(start) << " s";
  if (result.verdict == Verdict::kFailed || result.verdict == Verdict::kIllConditioned) {
    LOG(WARNING) << "align: " << VerdictName(result.verdict) << ": " << result.verdict_reason;
  }
  if (FLAGS_json) {
    std::printf("%s", run.json.c_str());
  } else {
    PrintSummary(run.config, run.inputs, result);
    if (run.tiled) {
      std::fputs(TiledAlignSummary(*run.tiled).c_str(), stdout);
    } else if (run.terrain) {
      std::printf("%s\n", TerrainSummary(run.config, run.inputs, run.report).c_str());
    }
  }
  // A script must be able to tell a failed alignment (e.g. a mask outside
  // the data) from a good one; the outputs above are written all the same.
  return result.verdict == Verdict::kFailed ? 3 : 0;
}

}  // namespace surfreg
