// surfreg sweep --config SWEEP.yaml [--output=RUNS.csv] [--jobs=N] [--shard=K/N] [--resume]
// and surfreg merge OUT.csv IN.csv...: the grid of tools/sweep.h run in
// parallel, its rows streamed to RUNS.csv.partial as they finish (so that an
// interrupted sweep keeps its work and --resume continues it), then the
// sorted CSV, the ranking (RUNS_summary.md and stdout) and the plots
// (RUNS_basin.png, RUNS_error_time.png, RUNS_translation_time.png).
#include <fcntl.h>
#include <gflags/gflags.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "tools/commands.h"
#include "tools/measure_parts.h"
#include "io/surface_reader_internal.h"
#include "io/plot.h"
#include "tools/sweep.h"
#include "tools/sweep_settings.h"
#include "tools/key_flags.h"

DECLARE_string(config);  // tools/run_align.cc
DECLARE_bool(quiet);     // tools/run_measure.cc
DEFINE_int32(jobs, 0,
             "sweep: parallel runs (default: the config's jobs, else the number of cores)");
DEFINE_string(shard, "", "sweep, align --manifest: run only slice K of N (K/N, 1-based)");
DEFINE_bool(resume, false, "sweep: skip the runs already in OUTPUT.csv.partial or OUTPUT.csv");

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;

bool Exists(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0;
}

std::string Duration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  return buffer;
}

// One line on stderr redrawn with '\r' on a terminal; otherwise a plain
// line at every tenth of the work (logs stay short).
class ProgressBar {
 public:
  ProgressBar(std::size_t total, std::size_t already)
      : total_(total), already_(already), tty_(::isatty(2)), start_(Clock::now()) {}
  void Update(std::size_t done_now) {
    if (FLAGS_quiet) return;
    const std::size_t done = already_ + done_now;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const double eta = done_now > 0 ? elapsed / done_now * (total_ - done) : 0;
    const int percent = total_ ? static_cast<int>(100 * done / total_) : 100;
    if (!tty_ && percent / 10 == last_tenth_ && done < total_) return;
    last_tenth_ = percent / 10;
    const int width = 30, filled = total_ ? static_cast<int>(width * done / total_) : width;
    std::fprintf(stderr, "%ssweep [%s%s] %zu/%zu %3d%%  elapsed %s  ETA %s%s", tty_ ? "\r" : "",
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), done,
                 total_, percent, Duration(elapsed).c_str(), Duration(eta).c_str(),
                 tty_ && done < total_ ? "" : "\n");
    std::fflush(stderr);
  }

 private:
  std::size_t total_, already_;
  bool tty_;
  Clock::time_point start_;
  int last_tenth_ = -1;
};

// Appends rows with one write(2) each, so a killed process leaves whole
// lines (and at most a torn last one, which --resume drops).
class PartialFile {
 public:
  PartialFile(const std::string& path, const std::string& label) : path_(path), label_(label) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd_ < 0)
      throw InputError(label + ": cannot append to '" + path + "': " + std::strerror(errno));
  }
  ~PartialFile() { ::close(fd_); }
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;
  void Append(const std::string& line) {
    std::size_t written = 0;
    while (written < line.size()) {
      const ssize_t n = ::write(fd_, line.data() + written, line.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0)
        throw InputError(label_ + ": cannot write '" + path_ + "': " + std::strerror(errno));
      written += static_cast<std::size_t>(n);
    }
  }

 private:
  std::string path_, label_;
  int fd_ = -1;
};

// Rows already done: from the partial file and the complete CSV, each
// checked to have this sweep's header and, run by run, the fields that
// follow from the config (so a changed config is not silently mixed in);
// a partial file also records the settings (tools/sweep_settings.h).
CsvTable DoneRows(const SweepPlan& plan, const std::string& output, const std::string& partial) {
  CsvTable done;
  done.header = SweepCsvHeader(plan.config);
  const std::vector<std::string>& header = done.header;
  for (const std::string& path : {output, partial}) {
    if (!Exists(path)) continue;
    std::map<std::string, std::string> recorded;  // only a partial file records them
    const std::string csv = SplitSweepSettings(io_internal::ReadFile(path), &recorded);
    CheckSweepSettings(recorded, plan.config, path);
    const CsvTable table = ParseCsv(csv, path, /*drop_torn_tail=*/path == partial);
    if (table.header.empty()) continue;  // killed before the header was complete
    if (table.header != header) {
      throw InputError("flag '--resume': '" + path +
                       "' has other columns than this sweep writes (another config?)");
    }
    done.rows.insert(done.rows.end(), table.rows.begin(), table.rows.end());
  }
  SortByRunId(&done, "flag '--resume'");
  for (const auto& row : done.rows) {
    const long long id = std::atoll(row[0].c_str());
    const std::vector<std::string> expected = id < static_cast<long long>(plan.runs.size())
                                                  ? SweepRunFields(plan, plan.runs[id])
                                                  : std::vector<std::string>{};
    if (expected.empty() || !std::equal(expected.begin(), expected.end(), row.begin())) {
      throw InputError("flag '--resume': run " + row[0] + " in '" + output +
                       "(.partial)' is not this config's run " + row[0] +
                       " (was the config changed? then start afresh with another --output)");
    }
  }
  return done;
}

std::string Stem(const std::string& csv) { return csv.substr(0, csv.size() - 4); }

std::string SettingName(const SettingRank& rank, const std::vector<std::string>& keys) {
  std::string name = "setting " + rank.setting;
  for (std::size_t k = 0; k < keys.size(); ++k)
    name += (k ? ", " : ": ") + keys[k] + "=" + rank.values[k];
  return name;
}

// Writes a chart unless no point can be drawn (e.g. every run rejected).
void Chart(const std::string& path, const std::vector<Series>& series, const FigureText& text,
           const ChartStyle& style, std::vector<std::string>* written) {
  bool any = false;
  for (const Series& s : series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      any |= std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && (!style.log_x || s.x[i] > 0) &&
             (!style.log_y || s.y[i] > 0);
    }
  }
  if (!any) {
    std::fprintf(stderr, "sweep: no plot %s: nothing to draw\n", path.c_str());
    return;
  }
  WriteChartPng(path, series, text, style, "plot '" + path + "'");
  written->push_back(path);
}

// Success rate against the start's offset, per setting; and error against
// time (log-log), per setting.
std::vector<std::string> WritePlots(const CsvTable& runs, const std::vector<SettingRank>& ranks,
                                    const std::vector<std::string>& keys, const std::string& stem) {
  const int setting = CsvColumn(runs, "setting"), deg = CsvColumn(runs, "perturbation_deg"),
            spacings = CsvColumn(runs, "perturbation_spacings"),
            success = CsvColumn(runs, "success");
  const int rot = CsvColumn(runs, "rotation_error_deg"),
            trans = CsvColumn(runs, "translation_error_spacings");
  const int dz = CsvColumn(runs, "mean_abs_dz_after"), seconds = CsvColumn(runs, "seconds");
  std::set<double> degs, shifts;
  bool truth = false;
  for (const auto& row : runs.rows) {
    degs.insert(std::atof(row[deg].c_str()));
    shifts.insert(std::atof(row[spacings].c_str()));
    truth |= !row[rot].empty();
  }
  const bool by_angle = degs.size() > 1 || shifts.size() == 1;
  std::vector<Series> basin, rotation, translation;
  for (const SettingRank& rank : ranks) {
    std::map<std::pair<double, double>, std::pair<int, int>>
        levels;  // (deg, spacings) -> successes, runs
    Series r{SettingName(rank, keys), {}, {}, false, true}, t = r;
    for (const auto& row : runs.rows) {
      if (row[setting] != rank.setting) continue;
      auto& level = levels[{std::atof(row[deg].c_str()), std::atof(row[spacings].c_str())}];
      level.first += row[success] == "true";
      ++level.second;
      const double s = std::atof(row[seconds].c_str());
      r.x.push_back(s);
      t.x.push_back(s);
      r.y.push_back(row[truth ? rot : dz].empty() ? NAN : std::atof(row[truth ? rot : dz].c_str()));
      t.y.push_back(row[trans].empty() ? NAN : std::atof(row[trans].c_str()));
    }
    Series b{SettingName(rank, keys), {}, {}, true, true};
    for (const auto& [level, counts] : levels) {
      b.x.push_back(by_angle ? level.first : level.second);
      b.y.push_back(100.0 * counts.first / counts.second);
    }
    basin.push_back(b);
    rotation.push_back(r);
    translation.push_back(t);
  }
  std::string x_label =
      by_angle ? "initial rotation error (deg)" : "initial shift error (mean sample spacings)";
  if (by_angle && shifts.size() > 1) x_label += ", paired with a shift error (spacings)";
  if (by_angle && shifts.size() == 1 && *shifts.begin() > 0) {
    char note[64];
    std::snprintf(note, sizeof(note), ", shift error %g spacings", *shifts.begin());
    x_label += note;
  }
  std::vector<std::string> written;
  ChartStyle linear;
  linear.y_min = 0;
  linear.y_max = 100;
  Chart(stem + "_basin.png", basin,
        {"Convergence basin: success rate by initial offset", x_label, "success rate (%)"}, linear,
        &written);
  ChartStyle log;
  log.log_x = log.log_y = true;
  Chart(stem + "_error_time.png", rotation,
        {truth ? "Rotation error against time" : "Final mean |dz| against time", "time per run (s)",
         truth ? "rotation error (deg)" : "mean |dz| after alignment (data units)"},
        log, &written);
  if (truth) {
    Chart(stem + "_translation_time.png", translation,
          {"Translation error against time", "time per run (s)",
           "translation error (mean sample spacings)"},
          log, &written);
  }
  return written;
}

void Report(const SweepPlan& plan, const CsvTable& runs, const std::string& output) {
  std::vector<std::string> keys;
  for (const SweptKey& key : plan.config.swept) keys.push_back(key.key);
  const std::vector<SettingRank> ranks =
      RankSettings(runs, keys, plan.config.success_rotation_deg, plan.config.success_spacings);
  char rule[200];
  std::snprintf(
      rule, sizeof(rule),
      "Success: verdict converged_improved and, where the truth is known, rotation error < %g deg "
      "and translation error < %g mean sample spacings.\n",
      plan.config.success_rotation_deg, plan.config.success_spacings);
  const std::string markdown = "# Sweep " + plan.config.file + ": " +
                               std::to_string(runs.rows.size()) + " runs\n\n" + rule + "\n" +
                               RankingMarkdown(ranks, keys);
  const std::string summary = Stem(output) + "_summary.md";
  WriteFileAtomically(summary, markdown, "summary '" + summary + "'");
  std::printf("%s\n", markdown.c_str());
  std::printf("runs:    %s\nsummary: %s\n", output.c_str(), summary.c_str());
  if (!PngFiguresBuilt()) {
    std::printf("plots:   none (this surfreg was built without Cairo)\n");
    return;
  }
  for (const std::string& plot : WritePlots(runs, ranks, keys, Stem(output)))
    std::printf("plot:    %s\n", plot.c_str());
}

}  // namespace

int RunSweep(const std::vector<std::string>& args) {
  if (!args.empty())
    throw UsageError("sweep: unexpected argument '" + args[0] + "' (give --config FILE.yaml)");
  if (FLAGS_config.empty()) throw UsageError("sweep: missing --config FILE.yaml");
  const SweepConfig config = ReadSweepConfig(FLAGS_config);
  SweepPlan plan = PlanSweep(config);
  const std::string output = KeyFlag("output").empty() ? config.output : KeyFlag("output");
  const std::string where = KeyFlag("output").empty() ? config.output_where : "flag '--output'";
  if (output.size() < 5 || output.substr(output.size() - 4) != ".csv") {
    throw InputError(where + " expects a file name ending in .csv, got '" + output + "'");
  }
  CheckOutputPath(output, where);
  const Shard shard = ParseShard(FLAGS_shard, "flag '--shard'");
  // 0 is the default ("not given"), but given it is a mistake like -1.
  if (FLAGS_jobs < 0 || (FLAGS_jobs == 0 && !gflags::GetCommandLineFlagInfoOrDie("jobs").is_default)) {
    throw InputError("flag '--jobs' expects an integer >= 1, got " + std::to_string(FLAGS_jobs));
  }
  const int jobs = FLAGS_jobs > 0 ? FLAGS_jobs
                   : config.jobs > 0
                       ? config.jobs
                       : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));

  const std::string partial = output + ".partial";
  const std::vector<std::string> header = SweepCsvHeader(config);
  if (!FLAGS_resume && Exists(partial)) {
    throw InputError("'" + partial +
                     "' exists (an interrupted sweep): add --resume to continue it, or delete it");
  }
  CsvTable table = FLAGS_resume ? DoneRows(plan, output, partial) : CsvTable{header, {}};
  std::set<long long> done;
  for (const auto& row : table.rows) done.insert(std::atoll(row[0].c_str()));
  std::vector<SweepRun> todo;
  std::size_t in_shard = 0;
  for (const SweepRun& run : plan.runs) {
    if (!shard.Contains(run.id)) continue;
    ++in_shard;
    if (!done.count(run.id)) todo.push_back(run);
  }
  if (FLAGS_resume) {
    std::fprintf(stderr, "sweep: resuming: %zu of %zu runs already done\n", in_shard - todo.size(),
                 in_shard);
  }
  if (!todo.empty()) {
    LoadSweepPairs(&plan);
    // The partial file restarts with the rows kept (dropping a torn line).
    WriteFileAtomically(partial, SweepSettingsComment(plan.config) + FormatCsv(table), where);
    PartialFile stream(partial, where);
    ProgressBar progress(in_shard, in_shard - todo.size());
    std::size_t finished = 0;
    progress.Update(0);
    RunSweepRuns(plan, todo, jobs, [&](const SweepRun&, std::vector<std::string> row) {
      stream.Append(CsvLine(row));
      table.rows.push_back(std::move(row));
      progress.Update(++finished);
    });
  }
  SortByRunId(&table, output);
  WriteFileAtomically(output, FormatCsv(table), where);
  std::remove(partial.c_str());
  if (shard.count > 1) {
    std::fprintf(
        stderr,
        "sweep: shard %d/%d: %zu runs in %s; join the shards with 'surfreg merge', then run the "
        "sweep with --resume on the merged CSV for the ranking and plots\n",
        shard.index, shard.count, table.rows.size(), output.c_str());
    return 0;
  }
  Report(plan, table, output);
  return 0;
}

int RunMerge(const std::vector<std::string>& args) {
  if (args.size() < 2) {
    throw UsageError("merge: expected OUT.csv and at least one IN.csv (or OUT.json and PART.json...)");
  }
  if (LooksLikePart(args[1])) return RunMergeMeasureParts(args);  // JSON: a tiled measure's shards
  CheckOutputPath(args[0], "argument OUT");
  struct stat out;
  if (::stat(args[0].c_str(), &out) == 0) {
    for (std::size_t i = 1; i < args.size(); ++i) {
      struct stat in;
      if (::stat(args[i].c_str(), &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino) {
        throw InputError("argument OUT: '" + args[0] + "' is also input " + std::to_string(i) +
                         " ('" + args[i] + "'); write the merge to another file");
      }
    }
  }
  CsvTable merged;
  std::string fingerprint, fingerprint_file;
  for (std::size_t i = 1; i < args.size(); ++i) {
    CsvTable table = ParseCsv(io_internal::ReadFile(args[i]), args[i], /*drop_torn_tail=*/false);
    if (i == 1) {
      merged.header = table.header;
    } else if (table.header != merged.header) {
      throw InputError(args[i] + ": its header differs from that of " + args[1]);
    }
    // Shards of one sweep share its fingerprint (tools/sweep_settings.h).
    const auto column = std::find(table.header.begin(), table.header.end(), "sweep");
    if (column != table.header.end()) {
      const std::size_t k = static_cast<std::size_t>(column - table.header.begin());
      for (const auto& row : table.rows) {
        if (k >= row.size()) continue;
        if (fingerprint.empty()) fingerprint = row[k], fingerprint_file = args[i];
        if (row[k] != fingerprint) {
          throw InputError(args[i] + ": run " + row[0] + " is of another sweep (fingerprint " +
                           row[k] + ", " + fingerprint_file + " has " + fingerprint +
                           "): merge the shards of one sweep only");
        }
      }
    }
    merged.rows.insert(merged.rows.end(), std::make_move_iterator(table.rows.begin()),
                       std::make_move_iterator(table.rows.end()));
  }
  SortByRunId(&merged, "merge");
  WriteFileAtomically(args[0], FormatCsv(merged), "argument OUT");
  std::printf("merged %zu rows from %zu files into %s\n", merged.rows.size(), args.size() - 1,
              args[0].c_str());
  return 0;
}

}  // namespace surfreg
