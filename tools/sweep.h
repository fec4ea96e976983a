#pragma once
// The grid of `surfreg sweep` (tools/sweep_config.h): pairs × settings ×
// perturbation magnitudes × directions, each run one Align from a perturbed
// start, its row of the per-run CSV, and the ranking of the settings.
//
// Run ids: run = ((pair · S + setting) · M + magnitude) · D + direction with
// S settings (the product of the swept lists, the first key slowest), M
// magnitudes and D directions. A shard K/N runs the ids with id % N == K − 1.
//
// Perturbation of run (pair, magnitude i, direction k): a rotation by
// rotation_deg[i] degrees about the unit axis u and a shift by
// shift_spacings[i] · spacing along the unit vector d, both about the moving
// centroid c: P(p) = R_u(p − c) + c + shift · d. The start is truth ∘ P
// (P alone without a truth), so the start is off by exactly that angle and
// that distance at c. u and d are drawn uniformly on the sphere from
// std::mt19937_64 seeded with RunSeed(seed, pair name, i, k): deterministic
// and independent of the order in which runs execute.
//
// Errors of a result M against the truth T: rotation = angle of R_M R_Tᵀ
// (degrees); translation = |M c − T c| (data units, and divided by the mean
// sample spacing sqrt(hull area / N) of the reference).
//
// Threads: runs execute on `jobs` threads, each Align single-threaded; the
// surfaces are shared read-only.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "measure/surface.h"
#include "tools/align_config.h"
#include "tools/sweep_config.h"

namespace surfreg {

// ---- CSV (RFC 4180: fields with a comma, quote or newline are quoted) ----
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // each as long as the header
};

std::string CsvLine(const std::vector<std::string>& fields);  // with '\n'
std::string FormatCsv(const CsvTable& table);

// Parses CSV text (`label` starts messages: "FILE:LINE: ..."). A last line
// without its newline is a torn append of an interrupted run: dropped when
// `drop_torn_tail`, an error otherwise. Throws InputError for a row whose
// field count differs from the header's.
CsvTable ParseCsv(const std::string& text, const std::string& label, bool drop_torn_tail);

// The column named `name`, or -1.
int CsvColumn(const CsvTable& table, const std::string& name);

// Sorts rows by their run_id column (first column; integers) and rejects
// duplicates unless identical. Throws InputError naming `label`.
void SortByRunId(CsvTable* table, const std::string& label);

// ---- Shards ----
struct Shard {
  int index = 1;  // K, 1-based
  int count = 1;  // N
  bool Contains(int64_t run_id) const { return run_id % count == index - 1; }
};
// "K/N" with 1 ≤ K ≤ N; "" = the whole grid. Throws InputError naming `label`.
Shard ParseShard(const std::string& text, const std::string& label);

// ---- Geometry ----
Eigen::Vector3d SurfaceCentroid(const Surface& surface);  // mean of the points, input coordinates
// sqrt(area of the convex hull of the xy positions / number of points).
double MeanSampleSpacing(const Surface& surface);

struct MotionErrors {
  double rotation_deg = 0;  // angle of R_estimate R_truthᵀ
  double translation = 0;   // |estimate · c − truth · c|, data units
};
MotionErrors CompareToTruth(const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth,
                            const Eigen::Vector3d& centroid);

// The seed of one run's perturbation directions (splitmix64 mixing of the
// config seed, the pair name's bytes, i and k).
uint64_t RunSeed(uint64_t seed, const std::string& pair, int magnitude, int direction);

struct PerturbationDirections {
  Eigen::Vector3d axis, shift;  // unit vectors
};
PerturbationDirections DrawDirections(uint64_t run_seed);

// truth ∘ P (see above); `shift` in data units.
Eigen::Matrix4d PerturbedStart(const Eigen::Matrix4d& truth, const Eigen::Vector3d& centroid,
                               double angle_deg, double shift, const PerturbationDirections& d);

// ---- The grid ----
struct SweepRun {
  int64_t id = 0;
  int pair = 0, setting = 0, magnitude = 0, direction = 0;
};

struct SweepPairData {
  Surface reference, moving;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of `moving`
  double spacing = 1;                                  // of `reference`
  bool has_truth = false;
  Eigen::Matrix4d truth = Eigen::Matrix4d::Identity();
};

struct SweepPlan {
  SweepConfig config;
  std::vector<std::vector<std::string>> settings;  // per setting: one value per swept key
  std::vector<AlignConfig> run_configs;            // [pair · S + setting], checked
  std::vector<SweepPairData> pairs;                // empty until LoadSweepPairs
  std::vector<SweepRun> runs;                      // every run, in id order
  std::string fingerprint;                         // SweepFingerprint(config): column `sweep`
};

// Expands the grid and checks every (pair, setting) combination with
// FinishAlignConfig (errors name the config line and the setting). Reads no
// surface.
SweepPlan PlanSweep(const SweepConfig& config);

// Reads the surfaces and resolves the truths.
void LoadSweepPairs(SweepPlan* plan);

std::vector<std::string> SweepCsvHeader(const SweepConfig& config);

// The leading CSV fields of a run, which follow from the config alone
// (run_id, pair, setting, the swept values, perturbation_deg,
// perturbation_spacings, direction, seed): --resume checks rows read back
// against them.
std::vector<std::string> SweepRunFields(const SweepPlan& plan, const SweepRun& run);

// One run: Align from the perturbed start, its CSV fields. A start Align
// rejects (InputError: folds, no overlap) is a row with verdict "rejected".
std::vector<std::string> RunOne(const SweepPlan& plan, const SweepRun& run);

// Runs `runs` on `jobs` threads; `on_row` is called for each finished run,
// one call at a time (serialized), in completion order. An exception other
// than a rejected start stops the sweep and is rethrown here.
void RunSweepRuns(const SweepPlan& plan, const std::vector<SweepRun>& runs, int jobs,
                  const std::function<void(const SweepRun&, std::vector<std::string>)>& on_row);

// ---- Ranking ----
struct SettingRank {
  std::string setting;              // the CSV's setting column ("3")
  std::vector<std::string> values;  // the swept keys' values
  int runs = 0;
  double success_rate = 0;                                                      // in [0, 1]
  double median_rotation_error_deg = 0, median_translation_error_spacings = 0;  // NaN: no truth
  double median_error_score = 0;  // median of max(rot / rot_tol, trans / trans_tol); NaN: no truth
  double median_mean_abs_dz = 0;  // after alignment
  double median_seconds = 0, median_iterations = 0;
};

// Settings ranked by success rate (high first), then the median error score
// (or, when no run has a truth, the median final mean |dz|), then the
// median time, then the setting number.
std::vector<SettingRank> RankSettings(const CsvTable& runs,
                                      const std::vector<std::string>& swept_keys,
                                      double rotation_tolerance_deg, double spacing_tolerance);

std::string RankingMarkdown(const std::vector<SettingRank>& ranks,
                            const std::vector<std::string>& swept_keys);

}  // namespace surfreg
