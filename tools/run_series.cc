// surfreg series E0 E1 ... | --config SERIES.yaml [--key=value ...]: joint
// alignment of a series of surveys (registration/series.h) with the
// settings of tools/series_config.h; writes the series JSON and the aligned
// epochs where asked, a line per stage on stderr and a summary on stdout.
#include <gflags/gflags.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "io/interrupt.h"
#include "tools/commands.h"
#include "tools/json_writer.h"
#include "tools/series_config.h"
#include "tools/series_run.h"

// The series' own keys as flags (strings, so tools/series_config.cc parses
// flags and files alike; "" = not given). The keys it shares with `align`
// (reference, output, progress, classes, columns, frame and the alignment keys)
// use align's flags of the same names, looked up by name.
DECLARE_bool(quiet);     // tools/run_measure.cc
DECLARE_string(config);  // tools/run_align.cc
DEFINE_string(pairs, "",
              "series: the pairs to align, e.g. 0-1,1-2 (default: every pair overlapping enough)");
DEFINE_string(min_overlap, "",
              "series: the smaller footprint's share two epochs must share to be a pair [0.3]");
DEFINE_string(aligned_dir, "", "series: a folder for the epochs moved into the reference's frame");
DEFINE_string(dod_dir, "", "series: a folder for the DoD of each consecutive pair of raster epochs");
DEFINE_string(crs, "", "series: the epochs' CRS where their files do not say, e.g. EPSG:4326 (lon/lat)");
DEFINE_string(dates, "", "series: each surface's date, YYYY-MM-DD, e.g. 2020-05-01,2021-05-01 (change per year)");

namespace surfreg {
namespace {

SeriesConfig LoadConfig(const std::vector<std::string>& args) {
  const bool has_config = !FLAGS_config.empty();
  if (has_config && !args.empty()) {
    throw UsageError("series: give either --config FILE.yaml or the epochs' files, not both");
  }
  if (!has_config && args.size() < 2) {
    throw UsageError(args.empty() ? "series: missing the epochs' files (or --config FILE.yaml)"
                                  : "series: a series needs at least 2 epochs");
  }
  SeriesConfig config;
  if (has_config) {
    ApplySeriesConfigFile(FLAGS_config, &config);
  } else {
    ApplySeriesArguments(args, &config);
  }
  for (const ConfigKey& key : SeriesConfigKeys()) {
    gflags::CommandLineFlagInfo info;
    if (gflags::GetCommandLineFlagInfo(key.name, &info) && !info.is_default) {
      ApplySeriesSetting(key.name, info.current_value, "flag '--" + std::string(key.name) + "'",
                         &config);
    }
  }
  FinishSeriesConfig(&config);
  return config;
}

}  // namespace

int RunSeries(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  const SeriesConfig config = LoadConfig(args);
  const bool show = !FLAGS_quiet && !FLAGS_json;
  const SeriesRun run = AlignSeriesFiles(config, std::nullopt, [&](const std::string& stage) {
    ThrowIfInterrupted();  // between stages
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (show && (config.progress || seconds >= 1.0))
      std::fprintf(stderr, "series: %s (%.1f s)\n", stage.c_str(), seconds);
  });
  if (FLAGS_json) {
    std::fputs(run.json.c_str(), stdout);
  } else {
    std::fputs(SeriesSummary(run).c_str(), stdout);
  }
  return 0;
}

}  // namespace surfreg
