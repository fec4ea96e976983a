// surfreg align --manifest=PAIRS.csv [--config BASE.yaml] [--key=value ...]
// [--shard=K/N] [--output=SUMMARY.csv]: many pairs with the same settings.
//
// The manifest is a CSV with a header naming the columns reference, moving,
// output (the transform JSON of the pair) and optionally aligned (the moved
// surface); paths are relative to the current directory, as everywhere. Row
// i (0-based, after the header) is run i: `--shard K/N` aligns the rows with
// i % N == K − 1, and `surfreg merge` joins the shards' summaries.
//
// Rows whose surfaces have at most 1e5 samples align side by side, one
// thread each (AlignmentsAtOnce, registration/align.h); larger pairs after
// them, one at a time on every thread. An alignment's numbers do not
// depend on its threads, so the summary is the same (but its times)
// whatever runs beside what.
//
// Every row is checked before the first alignment (files to write,
// settings). A pair that fails later (a surface file that does not parse,
// surfaces that do not overlap) gets verdict "error" in the summary and the
// batch goes on; the command then exits 2 saying how many failed.
#include <gflags/gflags.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "measure/tasks.h"
#include "registration/align.h"
#include "tools/align_config.h"
#include "tools/align_run.h"
#include "io/atomic_file.h"
#include "tools/commands.h"
#include "io/interrupt.h"
#include "io/raster_resample.h"
#include "io/surface_reader_internal.h"
#include "io/surface_writer.h"
#include "tools/json_writer.h"
#include "tools/sweep.h"
#include "terrain/terrain.h"
#include "tools/transform_json.h"
#include "tools/key_flags.h"

DECLARE_string(config);  // tools/run_align.cc
DECLARE_string(manifest);
DECLARE_string(shard);  // tools/run_sweep.cc

DECLARE_bool(quiet);  // tools/run_measure.cc

namespace surfreg {
namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// Keys a manifest row sets; as flags or config keys they would be ambiguous.
const char* const kPerPair[] = {"reference", "moving", "output", "matrix_txt", "aligned", "log"};

bool PerPair(const std::string& key) {
  for (const char* k : kPerPair) {
    if (key == k) return true;
  }
  return false;
}

// The settings shared by every pair: the config file, then the flags.
AlignConfig BaseConfig() {
  AlignConfig base;
  if (!FLAGS_config.empty()) ApplyAlignConfigFile(FLAGS_config, &base);
  for (const char* key : kPerPair) {
    if (base.origin.count(key)) {
      throw InputError(base.Where(key) +
                       ": not used with --manifest (the manifest names each pair's files)");
    }
  }
  for (const auto& [key, where] : base.origin) {
    if (IsTerrainKey(key)) {
      throw InputError(where + ": terrain inputs and outputs are for single 'surfreg align' runs, "
                       "not --manifest");
    }
  }
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    gflags::CommandLineFlagInfo info;
    if (!gflags::GetCommandLineFlagInfo(key.name, &info) || info.is_default) continue;
    if (std::string(key.name) == "output") continue;  // the summary CSV here
    if (PerPair(key.name)) {
      throw InputError(std::string("flag '--") + key.name +
                       "': not used with --manifest (the manifest names each pair's files)");
    }
    if (IsTerrainKey(key.name)) {
      throw InputError(std::string("flag '--") + key.name +
                       "': terrain inputs and outputs are for single 'surfreg align' runs, not "
                       "--manifest");
    }
    ApplyAlignFlag(key.name, info.current_value, &base);
  }
  return base;
}

struct Row {
  int64_t id = 0;
  AlignConfig config;
};

// The manifest's rows in the shard, each checked as `surfreg align` would.
std::vector<Row> ReadManifest(const AlignConfig& base, const Shard& shard) {
  const std::string& path = FLAGS_manifest;
  const CsvTable table = ParseCsv(io_internal::ReadFile(path), path, /*drop_torn_tail=*/false);
  for (const std::string& column : table.header) {
    if (column != "reference" && column != "moving" && column != "output" && column != "aligned") {
      throw InputError(path + ":1: unknown column '" + column +
                       "' (expected reference, moving, output[, aligned])");
    }
  }
  for (const char* required : {"reference", "moving", "output"}) {
    if (CsvColumn(table, required) < 0) throw InputError(path + ":1: no column '" + required + "'");
  }
  if (table.rows.empty()) throw InputError(path + ": no pairs (only a header)");
  std::vector<Row> rows;
  std::set<std::string> outputs;
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    if (!shard.Contains(static_cast<int64_t>(i))) continue;
    Row row{static_cast<int64_t>(i), base};
    const std::string at = path + ":" + std::to_string(i + 2) + ": column ";
    for (const char* column : {"reference", "moving", "output", "aligned"}) {
      const int c = CsvColumn(table, column);
      if (c < 0) continue;
      try {
        ApplyAlignFlag(column, table.rows[i][c], &row.config);
      } catch (const InputError& e) {  // "flag '--output' ..." said as the manifest's cell
        throw InputError(at + "'" + column + "'" +
                         std::string(e.what()).substr(std::string("flag '--'").size() +
                                                      std::string(column).size()));
      }
      row.config.origin[column] = at + "'" + column + "'";
    }
    FinishAlignConfig(&row.config);
    if (IsGeoTiffPath(row.config.aligned)) {
      throw InputError(at + "'aligned': a GeoTIFF aligned DEM is for single 'surfreg align' runs");
    }
    for (const std::string& file : {row.config.output, row.config.aligned}) {
      if (!file.empty() && !outputs.insert(file).second) {
        throw InputError(at + "'output': '" + file + "' is written by another row too");
      }
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string Text(double value) {
  if (!std::isfinite(value)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value + 0.0);
  return buffer;
}

std::vector<std::string> SummaryRow(const Row& row, const AlignResult* r,
                                    const std::string& error) {
  std::vector<std::string> fields = {std::to_string(row.id), row.config.reference,
                                     row.config.moving, row.config.output};
  if (r == nullptr) {
    fields.push_back("error");
    fields.resize(16, "");
    fields.push_back(error);
    return fields;
  }
  const auto& w = r->rotation_vector;
  char seconds[32];
  std::snprintf(seconds, sizeof(seconds), "%.6f", r->seconds);
  fields.insert(
      fields.end(),
      {VerdictName(r->verdict), Text(std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) * kDegrees),
       Text(w[0] * kDegrees), Text(w[1] * kDegrees), Text(w[2] * kDegrees), Text(r->translation[0]),
       Text(r->translation[1]), Text(r->translation[2]), Text(r->before.mean_abs_dz),
       Text(r->after.mean_abs_dz), std::to_string(r->iterations), seconds, r->verdict_reason});
  return fields;
}

// One row's surfaces, then its result or its InputError's text.
struct Job {
  TerrainInputs inputs;
  bool terrain = false;
  bool read = false;
  std::string error;
  std::vector<std::string> summary;  // its summary row, once done
  std::string verdict;
  double seconds = 0.0;
};

// Reads a row's surfaces as a single align reads them: rasters and CRSs
// too, lon/lat DEMs in one metric frame (which the JSON then names).
void ReadJob(const AlignConfig& c, Job* job) {
  try {
    job->terrain = c.terrain.Active(c.reference, c.moving);
    if (job->terrain) {
      job->inputs = ReadTerrainInputs(c);
    } else {
      job->inputs.reference = ReadInput(c, "reference");
      job->inputs.moving = ReadInput(c, "moving");
    }
    job->read = true;
  } catch (const InputError& e) {
    job->error = e.what();
  }
}

// Aligns a row read on `threads` threads, writes its files and fills its
// summary row; frees its surfaces.
void AlignJob(const Row& row, int threads, Job* job) {
  const AlignConfig& c = row.config;
  if (job->read) {
    try {
      AlignOptions options = c.options;
      options.num_threads = threads;
      ApplyInitialTransform(c, &options);  // one start for every pair
      options.on_iteration = [](const AlignOptions::Iteration&) { ThrowIfInterrupted(); };
      const AlignResult result = Align(job->inputs.reference, job->inputs.moving, options);
      std::string frame;
      if (job->terrain) {
        JsonObject member;
        member.String("frame", job->inputs.frame.Describe())
            .String("reference_crs", job->inputs.reference_crs.name)
            .String("moving_crs", job->inputs.moving_crs.name);
        frame = "\"terrain\": " + member.str();
      }
      WriteFileAtomically(c.output, TransformJson(c, result, frame), c.Where("output"));
      if (!c.aligned.empty()) {
        WriteSurface(c.aligned, TransformSurface(job->inputs.moving, result.matrix), c.Where("aligned"),
                     {"aligned: " + c.moving + " moved onto " + c.reference + " by surfreg align --manifest"});
      }
      job->summary = SummaryRow(row, &result, "");
      job->verdict = VerdictName(result.verdict);
      job->seconds = result.seconds;
    } catch (const InputError& e) {
      job->error = e.what();
    }
  }
  if (!job->error.empty()) job->summary = SummaryRow(row, nullptr, job->error);
  job->inputs = TerrainInputs();
}

}  // namespace

int RunAlignManifest(const std::vector<std::string>& args) {
  if (!args.empty())
    throw UsageError("align: give either --manifest PAIRS.csv or REFERENCE MOVING, not both");
  const Shard shard = ParseShard(FLAGS_shard, "flag '--shard'");
  if (!KeyFlag("output").empty()) CheckOutputPath(KeyFlag("output"), "flag '--output'");
  const std::vector<Row> rows = ReadManifest(BaseConfig(), shard);
  CsvTable summary;
  summary.header = {"run_id",
                    "reference",
                    "moving",
                    "output",
                    "verdict",
                    "rotation_deg",
                    "rx_deg",
                    "ry_deg",
                    "rz_deg",
                    "tx",
                    "ty",
                    "tz",
                    "mean_abs_dz_before",
                    "mean_abs_dz_after",
                    "iterations",
                    "seconds",
                    "message"};
  // Several workers take the rows in turn, each reading and aligning its
  // row on one thread; a pair found larger is left for afterwards, read
  // again and aligned alone on every thread (reading costs little beside
  // aligning a large pair, and no large surfaces wait in memory).
  const int threads = ExecutionFor(rows.empty() ? 1 : rows.front().config.options.num_threads).threads;
  const int count = static_cast<int>(rows.size());
  const int at_once = AlignmentsAtOnce(0, count, threads);
  std::vector<Job> jobs(rows.size());
  std::vector<char> alone(rows.size(), at_once == 1);
  std::mutex progress_mutex;
  const auto report = [&](int k) {  // progress as each pair ends, whatever order they end in
    std::lock_guard<std::mutex> lock(progress_mutex);
    const Job& job = jobs[k];
    if (!job.error.empty()) {
      std::fprintf(stderr, "align: pair %d/%d (row %lld): error: %s\n", k + 1, count,
                   static_cast<long long>(rows[k].id), job.error.c_str());
    } else if (!FLAGS_quiet) {
      std::fprintf(stderr, "align: pair %d/%d (row %lld): %s, %.2f s\n", k + 1, count,
                   static_cast<long long>(rows[k].id), job.verdict.c_str(), job.seconds);
    }
  };
  if (at_once > 1) {
    std::atomic<int> next{0};
    ForEachItem(ExecutionFor(at_once), at_once, [&](int) {
      for (int k = next++; k < count; k = next++) {
        AlignConfig one_thread = rows[k].config;
        one_thread.options.num_threads = 1;
        ReadJob(one_thread, &jobs[k]);
        const std::size_t largest = std::max(jobs[k].inputs.reference.size(), jobs[k].inputs.moving.size());
        if (AlignmentsAtOnce(largest, count, threads) == 1) {
          jobs[k] = Job();
          alone[k] = 1;
          continue;
        }
        AlignJob(rows[k], 1, &jobs[k]);
        report(k);
      }
    });
  }
  for (int k = 0; k < count; ++k) {
    if (!alone[k]) continue;
    ReadJob(rows[k].config, &jobs[k]);
    AlignJob(rows[k], threads, &jobs[k]);
    report(k);
  }
  int failed = 0;
  for (Job& job : jobs) {
    if (!job.error.empty()) ++failed;
    summary.rows.push_back(std::move(job.summary));
  }
  const std::string text = FormatCsv(summary);
  if (KeyFlag("output").empty()) {
    std::printf("%s", text.c_str());
  } else {
    WriteFileAtomically(KeyFlag("output"), text, "flag '--output'");
  }
  if (failed > 0) {
    throw InputError(std::to_string(failed) + " of " + std::to_string(rows.size()) +
                     " pairs failed (verdict 'error' in the summary)");
  }
  return 0;
}

}  // namespace surfreg
