#include "tools/sweep.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "measure/convex_hull.h"
#include "measure/input_error.h"
#include "registration/align.h"
#include "io/interrupt.h"
#include "io/surface_reader.h"
#include "tools/sweep_settings.h"
#include "terrain/terrain.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string Number(double value) {
  if (!std::isfinite(value)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value + 0.0);
  return buffer;
}

double ParseDouble(const std::string& text) {
  if (text.empty()) return std::nan("");
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() ? value : std::nan("");
}

uint64_t Mix(uint64_t x) {  // splitmix64
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// A double uniform in [0, 1) from the top 53 bits: the same on every
// platform (std::uniform_real_distribution is not specified bit for bit).
double Unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

Eigen::Vector3d UnitVector(std::mt19937_64& rng) {
  const double z = 2 * Unit(rng) - 1, phi = 2 * kPi * Unit(rng);
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

double Median(std::vector<double> values) {
  values.erase(
      std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
      values.end());
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// NaN sorts last.
double Key(double value) { return std::isfinite(value) ? value : HUGE_VAL; }

}  // namespace

// ---- CSV ----

std::string CsvLine(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i) line += ',';
    const std::string& f = fields[i];
    if (f.find_first_of(",\"\n\r") == std::string::npos) {
      line += f;
      continue;
    }
    line += '"';
    for (char c : f) line += c == '"' ? std::string("\"\"") : std::string(1, c);
    line += '"';
  }
  return line + "\n";
}

std::string FormatCsv(const CsvTable& table) {
  std::string text = CsvLine(table.header);
  for (const auto& row : table.rows) text += CsvLine(row);
  return text;
}

CsvTable ParseCsv(const std::string& text, const std::string& label, bool drop_torn_tail) {
  std::vector<std::vector<std::string>> records;
  std::vector<int> lines;  // line where each record starts
  std::vector<std::string> record;
  std::string field;
  bool quoted = false, in_record = false;
  int line = 1, record_line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (!in_record) in_record = true, record_line = line;
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
        line += c == '\n';
      }
    } else if (c == '"' && field.empty()) {
      quoted = true;
    } else if (c == ',') {
      record.push_back(std::move(field));
      field.clear();
    } else if (c == '\n') {
      if (!field.empty() && field.back() == '\r') field.pop_back();
      record.push_back(std::move(field));
      field.clear();
      records.push_back(std::move(record));
      record.clear();
      lines.push_back(record_line);
      in_record = false;
      ++line;
    } else {
      field += c;
    }
  }
  if (in_record && !drop_torn_tail) {
    throw InputError(label + ":" + std::to_string(record_line) +
                     ": the last line has no end (a torn write?)");
  }
  CsvTable table;
  if (records.empty()) {
    if (drop_torn_tail) return table;
    throw InputError(label + ": empty file (expected a CSV header line)");
  }
  table.header = records[0];
  for (std::size_t r = 1; r < records.size(); ++r) {
    if (records[r].size() == 1 && records[r][0].empty()) continue;  // a blank line
    if (records[r].size() != table.header.size()) {
      throw InputError(label + ":" + std::to_string(lines[r]) + ": " +
                       std::to_string(records[r].size()) + " fields, the header has " +
                       std::to_string(table.header.size()));
    }
    table.rows.push_back(std::move(records[r]));
  }
  return table;
}

int CsvColumn(const CsvTable& table, const std::string& name) {
  const auto at = std::find(table.header.begin(), table.header.end(), name);
  return at == table.header.end() ? -1 : static_cast<int>(at - table.header.begin());
}

void SortByRunId(CsvTable* table, const std::string& label) {
  if (table->header.empty() || table->header[0] != "run_id") {
    throw InputError(label + ": the first column is not run_id");
  }
  std::vector<std::pair<long long, std::size_t>> order;
  for (std::size_t r = 0; r < table->rows.size(); ++r) {
    const std::string& id = table->rows[r][0];
    char* end = nullptr;
    const long long value = std::strtoll(id.c_str(), &end, 10);
    if (id.empty() || end != id.c_str() + id.size() || value < 0) {
      throw InputError(label + ": bad run_id '" + id + "'");
    }
    order.emplace_back(value, r);
  }
  std::stable_sort(order.begin(), order.end());
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto& row = table->rows[order[k].second];
    if (k > 0 && order[k].first == order[k - 1].first) {
      if (row != rows.back()) {
        throw InputError(label + ": run_id " + std::to_string(order[k].first) +
                         " appears twice with different values");
      }
      continue;
    }
    rows.push_back(row);
  }
  table->rows = std::move(rows);
}

// ---- Shards ----

Shard ParseShard(const std::string& text, const std::string& label) {
  Shard shard;
  if (text.empty()) return shard;
  int k = 0, n = 0, used = 0;
  if (std::sscanf(text.c_str(), "%d/%d%n", &k, &n, &used) != 2 ||
      used != static_cast<int>(text.size()) || n < 1 || k < 1 || k > n) {
    throw InputError(label + " expects K/N with 1 <= K <= N (e.g. 2/8), got '" + text + "'");
  }
  shard.index = k;
  shard.count = n;
  return shard;
}

// ---- Geometry ----

Eigen::Vector3d SurfaceCentroid(const Surface& s) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < s.size(); ++i) sum += Eigen::Vector3d(s.xy[i].x, s.xy[i].y, s.z[i]);
  return sum / static_cast<double>(s.size()) +
         Eigen::Vector3d(s.origin[0], s.origin[1], s.origin[2]);
}

double MeanSampleSpacing(const Surface& s) {
  const double area = std::fabs(PolygonArea(ConvexHull(s.xy)));
  return std::sqrt(area / static_cast<double>(s.size()));
}

MotionErrors CompareToTruth(const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth,
                            const Eigen::Vector3d& c) {
  const Eigen::Matrix3d delta =
      estimate.topLeftCorner<3, 3>() * truth.topLeftCorner<3, 3>().transpose();
  MotionErrors e;
  // acos loses precision near 0: the angle from the rotation's quaternion.
  e.rotation_deg = Eigen::AngleAxisd(Eigen::Quaterniond(delta).normalized()).angle() * 180 / kPi;
  e.translation = ((estimate - truth) * Eigen::Vector4d(c.x(), c.y(), c.z(), 1)).head<3>().norm();
  return e;
}

uint64_t RunSeed(uint64_t seed, const std::string& pair, int magnitude, int direction) {
  uint64_t h = Mix(seed);
  for (unsigned char c : pair) h = Mix(h ^ c);
  h = Mix(h ^ static_cast<uint64_t>(magnitude));
  return Mix(h ^ (static_cast<uint64_t>(direction) << 32));
}

PerturbationDirections DrawDirections(uint64_t run_seed) {
  std::mt19937_64 rng(run_seed);
  PerturbationDirections d;
  d.axis = UnitVector(rng);
  d.shift = UnitVector(rng);
  return d;
}

Eigen::Matrix4d PerturbedStart(const Eigen::Matrix4d& truth, const Eigen::Vector3d& c,
                               double angle_deg, double shift, const PerturbationDirections& d) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle_deg * kPi / 180, d.axis).matrix();
  Eigen::Matrix4d p = Eigen::Matrix4d::Identity();
  p.topLeftCorner<3, 3>() = r;
  p.topRightCorner<3, 1>() = c + shift * d.shift - r * c;
  return truth * p;
}

// ---- The grid ----

SweepPlan PlanSweep(const SweepConfig& config) {
  SweepPlan plan;
  plan.config = config;
  plan.fingerprint = SweepFingerprint(config);
  plan.settings = {{}};
  for (const SweptKey& key : config.swept) {  // the first key varies slowest
    std::vector<std::vector<std::string>> next;
    for (const auto& prefix : plan.settings) {
      for (const std::string& value : key.values) {
        next.push_back(prefix);
        next.back().push_back(value);
      }
    }
    plan.settings = std::move(next);
  }
  for (const SweepPair& pair : config.pairs) {
    for (std::size_t s = 0; s < plan.settings.size(); ++s) {
      AlignConfig run = config.base;
      std::string label;
      for (std::size_t k = 0; k < config.swept.size(); ++k) {
        ApplyAlignFlag(config.swept[k].key, plan.settings[s][k], &run);  // checked when parsed
        run.origin[config.swept[k].key] = config.swept[k].where;
        label += (label.empty() ? "" : ", ") + config.swept[k].key + "=" + plan.settings[s][k];
      }
      run.reference = pair.reference;
      run.moving = pair.moving;
      run.origin["reference"] = run.origin["moving"] = pair.where;
      run.config_file = config.file;
      run.options.num_threads = 1;
      try {
        FinishAlignConfig(&run);
      } catch (const InputError& e) {
        throw InputError(std::string(e.what()) + " (setting " + std::to_string(s) +
                         (label.empty() ? "" : ": " + label) + ")");
      }
      plan.run_configs.push_back(std::move(run));
    }
  }
  const int m = static_cast<int>(config.rotation_deg.size());
  SweepRun run;
  for (run.pair = 0; run.pair < static_cast<int>(config.pairs.size()); ++run.pair) {
    for (run.setting = 0; run.setting < static_cast<int>(plan.settings.size()); ++run.setting) {
      for (run.magnitude = 0; run.magnitude < m; ++run.magnitude) {
        for (run.direction = 0; run.direction < config.directions; ++run.direction) {
          plan.runs.push_back(run);
          ++run.id;
        }
      }
    }
  }
  return plan;
}

void LoadSweepPairs(SweepPlan* plan) {
  plan->pairs.clear();
  for (const SweepPair& pair : plan->config.pairs) {
    SweepPairData data;
    try {
      // As a single align reads them: lon/lat DEMs in one metric frame, LAS
      // and text clouds by the settings' classes and columns.
      AlignConfig paths;
      paths.classes = plan->config.base.classes;
      paths.columns = plan->config.base.columns;
      for (const char* key : {"classes", "columns"}) {
        const auto given = plan->config.base.origin.find(key);
        if (given != plan->config.base.origin.end()) paths.origin[key] = given->second;
      }
      ApplyAlignArguments(pair.reference, pair.moving, &paths);
      paths.origin["reference"] = "reference";  // messages: "<pair>: reference: <file>: ..."
      paths.origin["moving"] = "moving";
      if (paths.terrain.Active(pair.reference, pair.moving)) {
        TerrainInputs inputs = ReadTerrainInputs(paths);
        data.reference = std::move(inputs.reference);
        data.moving = std::move(inputs.moving);
      } else {
        data.reference = ReadInput(paths, "reference");
        data.moving = ReadInput(paths, "moving");
      }
    } catch (const InputError& e) {
      throw InputError(pair.where + ": " + e.what());
    }
    data.centroid = SurfaceCentroid(data.moving);
    data.spacing = MeanSampleSpacing(data.reference);
    data.has_truth = pair.truth.kind != SweepTruth::Kind::kNone;
    data.truth = TruthMatrix(pair.truth, data.centroid);
    plan->pairs.push_back(std::move(data));
  }
}

std::vector<std::string> SweepCsvHeader(const SweepConfig& config) {
  std::vector<std::string> header = {"run_id", "sweep", "pair", "setting"};
  for (const SweptKey& key : config.swept) header.push_back(key.key);
  for (const char* name :
       {"perturbation_deg", "perturbation_spacings", "direction", "seed", "success", "verdict",
        "mean_abs_dz_before", "mean_abs_dz_after", "rotation_error_deg", "translation_error",
        "translation_error_spacings", "iterations"}) {
    header.push_back(name);
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) header.push_back("m" + std::to_string(i) + std::to_string(j));
  }
  header.push_back("seconds");
  header.push_back("message");
  return header;
}

std::vector<std::string> SweepRunFields(const SweepPlan& plan, const SweepRun& run) {
  const SweepConfig& config = plan.config;
  const std::string& name = config.pairs.at(run.pair).name;
  std::vector<std::string> row = {std::to_string(run.id), plan.fingerprint, name,
                                  std::to_string(run.setting)};
  row.insert(row.end(), plan.settings[run.setting].begin(), plan.settings[run.setting].end());
  row.insert(row.end(),
             {Number(config.rotation_deg[run.magnitude]),
              Number(config.shift_spacings[run.magnitude]), std::to_string(run.direction),
              std::to_string(RunSeed(config.seed, name, run.magnitude, run.direction))});
  return row;
}

std::vector<std::string> RunOne(const SweepPlan& plan, const SweepRun& run) {
  const SweepConfig& config = plan.config;
  const SweepPairData& pair = plan.pairs.at(run.pair);
  AlignOptions options = plan.run_configs.at(run.pair * plan.settings.size() + run.setting).options;
  const double angle = config.rotation_deg[run.magnitude];
  const double spacings = config.shift_spacings[run.magnitude];
  const uint64_t seed =
      RunSeed(config.seed, config.pairs[run.pair].name, run.magnitude, run.direction);
  options.initial_rotation = options.initial_translation = {0, 0, 0};
  options.initial_reference_from_moving = Rigid3d::FromMatrix(
      PerturbedStart(pair.truth, pair.centroid, angle, spacings * pair.spacing, DrawDirections(seed)));

  // An interrupted run is not a row: the signal ends it between iterations.
  options.on_iteration = [](const AlignOptions::Iteration&) { ThrowIfInterrupted(); };
  std::vector<std::string> row = SweepRunFields(plan, run);
  AlignResult result;
  std::string rejected;
  try {
    result = Align(pair.reference, pair.moving, options);
  } catch (const InputError& e) {
    rejected = e.what();
  }
  if (!rejected.empty()) {
    row.insert(row.end(), {"false", "rejected"});
    row.resize(SweepCsvHeader(config).size() - 1, "");
    row.push_back(rejected);
    return row;
  }
  MotionErrors errors{std::nan(""), std::nan("")};
  if (pair.has_truth) errors = CompareToTruth(result.matrix, pair.truth, pair.centroid);
  const bool success =
      result.verdict == Verdict::kConvergedImproved &&
      (!pair.has_truth || (errors.rotation_deg < config.success_rotation_deg &&
                           errors.translation / pair.spacing < config.success_spacings));
  row.insert(
      row.end(),
      {success ? "true" : "false", VerdictName(result.verdict), Number(result.before.mean_abs_dz),
       Number(result.after.mean_abs_dz), Number(errors.rotation_deg), Number(errors.translation),
       Number(errors.translation / pair.spacing), std::to_string(result.iterations)});
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) row.push_back(Number(result.matrix(i, j)));
  }
  char seconds[32];
  std::snprintf(seconds, sizeof(seconds), "%.6f", result.seconds);
  row.push_back(seconds);
  row.push_back(result.verdict_reason);
  return row;
}

void RunSweepRuns(const SweepPlan& plan, const std::vector<SweepRun>& runs, int jobs,
                  const std::function<void(const SweepRun&, std::vector<std::string>)>& on_row) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;  // serializes on_row and guards `error`
  std::exception_ptr error;
  const auto work = [&] {
    for (std::size_t i; !stop && (i = next++) < runs.size();) {
      try {
        ThrowIfInterrupted();
        std::vector<std::string> row = RunOne(plan, runs[i]);
        std::lock_guard<std::mutex> lock(mutex);
        if (stop) break;
        try {
          on_row(runs[i], std::move(row));
        } catch (...) {
          stop = true;  // before the lock is released: no row is handled after this one
          throw;
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        stop = true;
      }
    }
  };
  const int threads = std::max(1, std::min<int>(jobs, static_cast<int>(runs.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
  if (error) std::rethrow_exception(error);
}

// ---- Ranking ----

std::vector<SettingRank> RankSettings(const CsvTable& runs,
                                      const std::vector<std::string>& swept_keys,
                                      double rotation_tolerance_deg, double spacing_tolerance) {
  const auto column = [&runs](const std::string& name) {
    const int c = CsvColumn(runs, name);
    if (c < 0) throw InputError("runs CSV: no column '" + name + "'");
    return c;
  };
  const int setting = column("setting"), success = column("success"),
            rot = column("rotation_error_deg"), trans = column("translation_error_spacings"),
            dz = column("mean_abs_dz_after"), seconds = column("seconds"),
            iterations = column("iterations");
  std::vector<int> keys;
  for (const std::string& key : swept_keys) keys.push_back(column(key));
  struct Group {
    const std::vector<std::string>* first = nullptr;
    std::vector<double> rot, trans, score, dz, seconds, iterations;
    int runs = 0, successes = 0;
  };
  std::map<long long, Group> groups;
  for (const auto& row : runs.rows) {
    Group& g = groups[std::atoll(row[setting].c_str())];
    if (g.first == nullptr) g.first = &row;
    ++g.runs;
    g.successes += row[success] == "true";
    const double r = ParseDouble(row[rot]), t = ParseDouble(row[trans]);
    g.rot.push_back(r);
    g.trans.push_back(t);
    g.score.push_back(std::max(r / rotation_tolerance_deg, t / spacing_tolerance));
    g.dz.push_back(ParseDouble(row[dz]));
    g.seconds.push_back(ParseDouble(row[seconds]));
    g.iterations.push_back(ParseDouble(row[iterations]));
  }
  std::vector<SettingRank> ranks;
  bool any_truth = false;
  for (const auto& [id, g] : groups) {
    SettingRank r;
    r.setting = std::to_string(id);
    for (int c : keys) r.values.push_back((*g.first)[c]);
    r.runs = g.runs;
    r.success_rate = static_cast<double>(g.successes) / g.runs;
    r.median_rotation_error_deg = Median(g.rot);
    r.median_translation_error_spacings = Median(g.trans);
    r.median_error_score = Median(g.score);
    r.median_mean_abs_dz = Median(g.dz);
    r.median_seconds = Median(g.seconds);
    r.median_iterations = Median(g.iterations);
    any_truth |= std::isfinite(r.median_error_score);
    ranks.push_back(r);
  }
  std::stable_sort(ranks.begin(), ranks.end(),
                   [any_truth](const SettingRank& a, const SettingRank& b) {
                     if (a.success_rate != b.success_rate) return a.success_rate > b.success_rate;
                     const double ea = Key(any_truth ? a.median_error_score : a.median_mean_abs_dz);
                     const double eb = Key(any_truth ? b.median_error_score : b.median_mean_abs_dz);
                     if (ea != eb) return ea < eb;
                     return Key(a.median_seconds) < Key(b.median_seconds);
                   });  // stable: equal settings stay in setting order
  return ranks;
}

std::string RankingMarkdown(const std::vector<SettingRank>& ranks,
                            const std::vector<std::string>& swept_keys) {
  const auto g = [](double v) {
    if (!std::isfinite(v)) return std::string("-");
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.3g", v);
    return std::string(buffer);
  };
  std::string text = "| rank | setting |";
  for (const std::string& key : swept_keys) text += " " + key + " |";
  text +=
      " runs | success (%) | median rotation error (deg) | median translation error (spacings) |"
      " median mean abs dz after | median time (s) | median iterations |\n|---|---|";
  for (std::size_t k = 0; k < swept_keys.size(); ++k) text += "---|";
  text += "---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < ranks.size(); ++i) {
    const SettingRank& r = ranks[i];
    text += "| " + std::to_string(i + 1) + " | " + r.setting + " |";
    for (const std::string& value : r.values) text += " " + value + " |";
    char success[16];
    std::snprintf(success, sizeof(success), "%.1f", 100 * r.success_rate);
    text += " " + std::to_string(r.runs) + " | " + success + " | " +
            g(r.median_rotation_error_deg) + " | " + g(r.median_translation_error_spacings) +
            " | " + g(r.median_mean_abs_dz) + " | " + g(r.median_seconds) + " | " +
            g(r.median_iterations) + " |\n";
  }
  return text;
}

}  // namespace surfreg
