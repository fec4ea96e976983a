// The `surfreg align` settings (tools/align_config.h): every key from YAML
// and from flags, precedence, each class of error message; and the writers
// it uses (io/surface_writer.h, io/atomic_file.h). The shipped
// configs and the key reference: align_config_docs_test.cc.
#include "tools/align_config.h"

#include <dirent.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "tests/testing/file_checks.h"
#include "io/atomic_file.h"
#include "io/surface_reader.h"

namespace surfreg {
namespace {

using testing::Contains;
using testing::ErrorOf;
using testing::TempDir;

constexpr double kPi = 3.14159265358979323846;

AlignConfig FromYaml(const std::string& text, const std::string& file = "t.yaml") {
  AlignConfig config;
  ApplyAlignYaml(text, file, &config);
  return config;
}

std::string YamlError(const std::string& text) {
  return ErrorOf([&] { FromYaml(text); });
}

std::string FlagError(const std::string& key, const std::string& value) {
  return ErrorOf([&] {
    AlignConfig config;
    ApplyAlignFlag(key, value, &config);
  });
}

// --- keys and values ------------------------------------------------------

TEST(AlignConfig, DefaultsAreAlignOptionsDefaults) {
  const AlignConfig config;
  const AlignOptions defaults;
  EXPECT_EQ(config.options.cost, defaults.cost);
  EXPECT_EQ(AlignConfigValue(config, "cost"),
            defaults.cost == CostKind::kAuto ? "auto" : "not the default");
  EXPECT_EQ(AlignConfigValue(config, "loss"), "none");
  EXPECT_EQ(AlignConfigValue(config, "trust_region"), "levenberg_marquardt");
  EXPECT_EQ(AlignConfigValue(config, "line_search"), "lbfgs");
  EXPECT_EQ(AlignConfigValue(config, "max_iterations"), std::to_string(defaults.axial_solver.max_num_iterations));
  EXPECT_EQ(AlignConfigValue(config, "free"), "all");
  EXPECT_EQ(AlignConfigValue(config, "initial_rotation_deg"), "[0, 0, 0]");
  EXPECT_EQ(AlignConfigValue(config, "covariance"), "true");
  EXPECT_EQ(AlignConfigValue(config, "progress"), "false");
  for (const char* key : {"reference", "moving", "mask", "output", "aligned", "log"}) {
    EXPECT_EQ(AlignConfigValue(config, key), "") << key;
  }
  EXPECT_TRUE(config.origin.empty());
  EXPECT_EQ(config.Where("cost"), "key 'cost'");
}

// Writing each default back as a value changes nothing: the printed defaults
// (used in docs/align.md) are exactly the struct's.
TEST(AlignConfig, EveryDefaultReadsBackUnchanged) {
  const AlignConfig defaults;
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    const std::string text = AlignConfigValue(defaults, key.name);
    if (text.empty()) continue;  // a file key naming no file
    AlignConfig yaml = FromYaml(std::string(key.name) + ": " + text + "\n");
    AlignConfig flag;
    ApplyAlignFlag(key.name, text, &flag);
    for (const AlignConfigKey& other : AlignConfigKeys()) {
      EXPECT_EQ(AlignConfigValue(yaml, other.name), AlignConfigValue(defaults, other.name))
          << key.name << " -> " << other.name;
      EXPECT_EQ(AlignConfigValue(flag, other.name), AlignConfigValue(defaults, other.name));
    }
  }
}

const char* const kEveryKey = R"(# every key
reference: a.xyz
moving: "b c.ply"
cost: volume
prealign: false
loss: soft_l1
loss_scale: 0.25
trust_region: dogleg
line_search: nonlinear_cg
max_iterations: 7
function_tolerance: 1e-9
trim_fraction: 0.1
free: [rx, ry, translation]
levels: 3
level_factor: 2.5
multi_start: 4
multi_start_angle_deg: 5
multi_start_shift: 12.5
wide_search: always
initial_rotation_deg: [1, -2, 90]
initial_translation: [10, -20, 0.5]
mask: poly.txt
max_fold_fraction: 0.125
covariance: no
threads: 1
output: out.json
aligned: moved.ply
log: iterations.csv
progress: yes
linear_solver: dense_normal_cholesky
subsample: 0.5
reference_crs: EPSG:2193
moving_crs: lonlat
frame: enu
band: 2
window: [1, 2, 30, 40]
lod: 0.25
dod: dod.tif
dod_png: dod.png
histogram_png: histogram.png
change_csv: change.csv
known_matrix: [1, 0, 0, 5, 0, 1, 0, 6, 0, 0, 1, 7]
mask_raster: stable.tif
stddev: information
stddev_subsamples: 6
holdout: 0.2
holdout_seed: 9
holdout_verdict: true
sigma_reference: 0.25
sigma_moving: sigma.tif
lod_confidence: 0.9
dod_sigma: sigma_dod.tif
dod_thresholded: dod_detected.tif
error_model: variogram
variogram_png: variogram.png
change_mask: roi.gpkg
normal_distance: false
slope_weight: 1.5
gap_weight: 0.7
density_weight: 7
density_correction: 2.5
weights: per_point
domain: hull
domain_max_edge_spacings: 4.5
domain_min_thinness: 0.2
classes: [2, 9]
columns: [E, N, H, 5]
initial_transform: start.txt
matrix_txt: matrix.txt
mask_mode: exclude
mask_layer: slides
max_memory: 1.5G
tile_stats: tiles.csv
patch_shifts: shifts.csv
stable: all
stable_sigmas: 5.5
stable_grow_sigmas: 2.5
stable_map: stable.xyz
cell_kernel: scalar
)";

TEST(AlignConfig, EveryKeyFromYaml) {
  const AlignConfig c = FromYaml(kEveryKey);
  const AlignOptions& o = c.options;
  EXPECT_EQ(c.reference, "a.xyz");
  EXPECT_EQ(c.moving, "b c.ply");
  EXPECT_EQ(o.cost, CostKind::kVolume);
  EXPECT_FALSE(o.prealign);
  EXPECT_EQ(o.loss, LossKind::kSoftL1);
  EXPECT_EQ(o.loss_scale, 0.25);
  EXPECT_EQ(o.axial_solver.trust_region_strategy_type, ceres::DOGLEG);
  EXPECT_EQ(o.volume_solver.line_search_direction_type, ceres::NONLINEAR_CONJUGATE_GRADIENT);
  EXPECT_EQ(o.axial_solver.max_num_iterations, 7);
  EXPECT_EQ(o.volume_solver.max_num_iterations, 7);
  EXPECT_EQ(o.axial_solver.function_tolerance, 1e-9);
  EXPECT_EQ(o.volume_solver.function_tolerance, 1e-9);
  EXPECT_EQ(o.trim_fraction, 0.1);
  EXPECT_FALSE(o.normal_distance);
  EXPECT_EQ(o.slope_weight, 1.5);
  EXPECT_EQ(o.gap_weight, 0.7);
  EXPECT_EQ(o.density_weight, 7.0);
  EXPECT_EQ(o.density_correction, 2.5);
  EXPECT_TRUE(c.per_point_weights);
  EXPECT_EQ(o.domain.kind, DomainKind::kHull);
  EXPECT_EQ(o.domain.max_edge_spacings, 4.5);
  EXPECT_EQ(o.domain.min_boundary_thinness, 0.2);
  EXPECT_EQ(o.free, (std::array<bool, 6>{true, true, false, true, true, true}));
  EXPECT_EQ(o.levels, 3);
  EXPECT_EQ(o.level_factor, 2.5);
  EXPECT_EQ(o.multi_start, 4);
  EXPECT_EQ(o.multi_start_angle_deg, 5);
  EXPECT_EQ(o.multi_start_shift, 12.5);
  EXPECT_EQ(o.wide_search, AlignOptions::WideSearch::kAlways);
  EXPECT_DOUBLE_EQ(o.initial_rotation[0], kPi / 180);
  EXPECT_DOUBLE_EQ(o.initial_rotation[1], -2 * kPi / 180);
  EXPECT_DOUBLE_EQ(o.initial_rotation[2], kPi / 2);
  EXPECT_EQ(o.initial_translation, (std::array<double, 3>{10, -20, 0.5}));
  EXPECT_EQ(c.mask, "poly.txt");
  EXPECT_EQ(o.weight, WeightMode::kUniform);  // until FinishAlignConfig reads the polygon
  EXPECT_EQ(o.max_fold_fraction, 0.125);
  EXPECT_FALSE(o.compute_covariance);
  EXPECT_EQ(o.num_threads, 1);
  EXPECT_EQ(c.output, "out.json");
  EXPECT_EQ(c.aligned, "moved.ply");
  EXPECT_EQ(c.log, "iterations.csv");
  EXPECT_EQ(c.initial_transform, "start.txt");
  EXPECT_EQ(c.matrix_txt, "matrix.txt");
  EXPECT_TRUE(c.initial_matrix.empty());  // until FinishAlignConfig reads the file
  EXPECT_TRUE(c.progress);
  EXPECT_EQ(o.axial_solver.linear_solver_type, ceres::DENSE_NORMAL_CHOLESKY);
  EXPECT_EQ(o.subsample, 0.5);
  const TerrainSettings& t = c.terrain;
  EXPECT_EQ(t.reference_crs, "EPSG:2193");
  EXPECT_EQ(t.moving_crs, "lonlat");
  EXPECT_EQ(t.frame, "enu");
  EXPECT_EQ(t.band, 2);
  EXPECT_EQ(t.window, (std::array<int, 4>{1, 2, 30, 40}));
  EXPECT_EQ(t.lod, 0.25);
  EXPECT_EQ(t.dod, "dod.tif");
  EXPECT_EQ(t.dod_png, "dod.png");
  EXPECT_EQ(t.histogram_png, "histogram.png");
  EXPECT_EQ(t.change_csv, "change.csv");
  EXPECT_EQ(t.known_matrix, (std::vector<double>{1, 0, 0, 5, 0, 1, 0, 6, 0, 0, 1, 7, 0, 0, 0, 1}));
  EXPECT_EQ(t.mask_raster, "stable.tif");
  EXPECT_EQ(o.stddev_method, AlignOptions::StddevMethod::kInformation);
  EXPECT_EQ(o.stddev_subsamples, 6);
  EXPECT_EQ(o.holdout_fraction, 0.2);
  EXPECT_EQ(o.holdout_seed, 9u);
  EXPECT_TRUE(o.holdout_verdict);
  EXPECT_EQ(t.sigma_reference, "0.25");
  EXPECT_EQ(t.sigma_moving, "sigma.tif");
  EXPECT_EQ(t.lod_confidence, 0.9);
  EXPECT_EQ(t.dod_sigma, "sigma_dod.tif");
  EXPECT_EQ(t.dod_thresholded, "dod_detected.tif");
  EXPECT_EQ(t.error_model, "variogram");
  EXPECT_EQ(t.variogram_png, "variogram.png");
  EXPECT_EQ(t.change_mask, "roi.gpkg");
  EXPECT_EQ(c.classes, (std::vector<int>{2, 9}));
  EXPECT_EQ(c.columns, (std::vector<std::string>{"E", "N", "H", "5"}));
  EXPECT_EQ(o.mask_mode, MaskMode::kExclude);
  EXPECT_EQ(c.mask_layer, "slides");
  EXPECT_EQ(t.max_memory, "1.5G");
  EXPECT_EQ(t.tile_stats, "tiles.csv");
  EXPECT_EQ(t.patch_shifts, "shifts.csv");
  EXPECT_EQ(o.stable.mode, StableOptions::Mode::kAll);
  EXPECT_EQ(o.stable.seed_sigmas, 5.5);
  EXPECT_EQ(o.stable.grow_sigmas, 2.5);
  EXPECT_EQ(c.stable_map, "stable.xyz");
  EXPECT_EQ(c.origin.size(), AlignConfigKeys().size());
  EXPECT_EQ(c.Where("cost"), "t.yaml:4: key 'cost'");
  EXPECT_EQ(c.Where("progress"), "t.yaml:29: key 'progress'");
  EXPECT_EQ(AlignConfigValue(c, "free"), "[rx, ry, tx, ty, tz]");
  EXPECT_EQ(AlignConfigValue(c, "initial_rotation_deg"), "[1, -2, 90]");
}

TEST(AlignConfig, EveryKeyFromFlags) {
  // The same settings as flag text: each key's value read back must agree.
  const AlignConfig yaml = FromYaml(kEveryKey);
  AlignConfig flags;
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    std::string text = AlignConfigValue(yaml, key.name);
    if (text.front() == '[') text = text.substr(1, text.size() - 2);  // "1, -2, 90"
    ApplyAlignFlag(key.name, text, &flags);
    EXPECT_EQ(flags.Where(key.name), "flag '--" + std::string(key.name) + "'");
  }
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    EXPECT_EQ(AlignConfigValue(flags, key.name), AlignConfigValue(yaml, key.name)) << key.name;
  }
}

TEST(AlignConfig, ValueSpellings) {
  EXPECT_TRUE(FromYaml("progress: TRUE").progress);
  EXPECT_TRUE(FromYaml("progress: on").progress);
  EXPECT_FALSE(FromYaml("covariance: Off").options.compute_covariance);
  EXPECT_EQ(FromYaml("initial_translation: 1,2,3").options.initial_translation,
            (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(FromYaml("initial_translation: '[1, 2, 3]'").options.initial_translation,
            (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(AlignConfigValue(FromYaml("free: rotation,tz"), "free"), "[rx, ry, rz, tz]");
  EXPECT_EQ(AlignConfigValue(FromYaml("free: [translation, all]"), "free"), "all");
  EXPECT_EQ(AlignConfigValue(FromYaml("free: tz"), "free"), "[tz]");
  // Nothing after a file key: no file (e.g. to switch off a config's output).
  EXPECT_EQ(FromYaml("output: out.json\n").output, "out.json");
  EXPECT_EQ(FromYaml("output:\n").output, "");
  EXPECT_EQ(FromYaml("output: ~\n").output, "");
  AlignConfig config = FromYaml("output: out.json\n");
  ApplyAlignFlag("output", "", &config);
  EXPECT_EQ(config.output, "");
}

// --- precedence -------------------------------------------------------------

TEST(AlignConfig, FlagsOverrideTheFile) {
  AlignConfig config = FromYaml("reference: a.xyz\nmoving: b.xyz\ncost: volume\nlevels: 3\n");
  ApplyAlignFlag("cost", "axial", &config);
  ApplyAlignFlag("moving", "c.xyz", &config);
  EXPECT_EQ(config.options.cost, CostKind::kAxial);
  EXPECT_EQ(config.options.levels, 3);
  EXPECT_EQ(config.moving, "c.xyz");
  EXPECT_EQ(config.Where("moving"), "flag '--moving'");
  EXPECT_EQ(config.Where("levels"), "t.yaml:4: key 'levels'");
}

TEST(AlignConfig, ArgumentsThenFlags) {
  AlignConfig config;
  ApplyAlignArguments("a.xyz", "b.xyz", &config);
  ApplyAlignFlag("reference", "r.ply", &config);
  EXPECT_EQ(config.reference, "r.ply");
  EXPECT_EQ(config.moving, "b.xyz");
  EXPECT_EQ(config.Where("moving"), "argument MOVING");
  EXPECT_TRUE(Contains(ErrorOf([] {
                         AlignConfig c;
                         ApplyAlignArguments("a.xyz", "", &c);
                       }),
                       "argument MOVING expects a surface file"));
}

// --- errors: each names where and what ----------------------------------------

TEST(AlignConfigErrors, UnknownKeySuggestsTheNearest) {
  const std::string e = YamlError("reference: a.xyz\n# comment\ncots: axial\n");
  EXPECT_TRUE(Contains(e, "t.yaml:3: unknown key 'cots' (did you mean 'cost'?)"));
  EXPECT_TRUE(Contains(YamlError("max-iterations: 3"), "did you mean 'max_iterations'?"));
  EXPECT_TRUE(Contains(YamlError("iterations: 3"), "did you mean 'max_iterations'?"));
  EXPECT_TRUE(Contains(YamlError("Threads: 3"), "did you mean 'threads'?"));
  EXPECT_TRUE(Contains(YamlError("mask_mod: exclude"), "did you mean 'mask_mode'?"));
  // Every unknown key of a file in one message, before a bad value is read.
  const std::string two = YamlError("cots: volume\nmax_iterations: many\nsubsampel: 0.5");
  EXPECT_TRUE(Contains(two, "t.yaml:1: unknown key 'cots' (did you mean 'cost'?); "
                            "t.yaml:3: unknown key 'subsampel' (did you mean 'subsample'?)"))
      << two;
  const std::string far = YamlError("banana_split: 1");
  EXPECT_TRUE(Contains(far, "unknown key 'banana_split' (known keys: reference, moving, cost"));
  EXPECT_TRUE(Contains(FlagError("cots", "x"), "flag '--cots': unknown key 'cots'"));
  EXPECT_EQ(NearestAlignKey("outptu"), "output");
  EXPECT_EQ(NearestAlignKey("zzzzzzzz"), "");
}

TEST(AlignConfigErrors, WrongTypeNamesKeyLineTypeAndValue) {
  EXPECT_TRUE(Contains(YamlError("cost: axial\nmax_iterations: 1.5\n"),
                       "t.yaml:2: key 'max_iterations' expects an integer >= 1, got '1.5'"));
  EXPECT_TRUE(
      Contains(YamlError("levels: 0"), "key 'levels' expects an integer in [1, 8], got '0'"));
  EXPECT_TRUE(Contains(YamlError("levels: 9"), "got '9'"));
  EXPECT_TRUE(Contains(YamlError("function_tolerance: 0"), "expects a number in (0, 1), got '0'"));
  EXPECT_TRUE(Contains(YamlError("max_fold_fraction: 1.5"), "expects a number in [0, 1]"));
  EXPECT_EQ(FromYaml("max_fold_fraction: 1").options.max_fold_fraction, 1.0);
  EXPECT_TRUE(Contains(YamlError("loss_scale: -1"), "expects a number >= 0, got '-1'"));
  EXPECT_TRUE(Contains(YamlError("loss_scale: .inf"), "got '.inf'"));
  EXPECT_TRUE(Contains(YamlError("trim_fraction: 0.5"), "expects a number in [0, 0.5)"));
  EXPECT_TRUE(Contains(YamlError("density_correction: 0.5"),
                       "key 'density_correction' expects 0 or a number in [1, 1e6], got '0.5'"));
  EXPECT_EQ(FromYaml("density_correction: 0").options.density_correction, 0.0);
  EXPECT_TRUE(Contains(YamlError("density_weight: 0.5"),
                       "key 'density_weight' expects 0 or a number in [1, 1e6], got '0.5'"));
  EXPECT_EQ(FromYaml("density_weight: 0").options.density_weight, 0.0);
  EXPECT_TRUE(Contains(YamlError("level_factor: 1"), "expects a number in [1.5, 64], got '1'"));
  EXPECT_TRUE(Contains(YamlError("covariance: maybe"), "expects true or false, got 'maybe'"));
  EXPECT_TRUE(Contains(YamlError("threads: [1, 2]"), "expects an integer >= 1, or all, got '[1, 2]'"));
  EXPECT_TRUE(Contains(YamlError("levels:\n  a: 1\n"), "got a mapping"));
  EXPECT_TRUE(Contains(YamlError("levels:"), "expects an integer in [1, 8], got nothing"));
  EXPECT_TRUE(Contains(YamlError("reference:"), "key 'reference' expects a surface file"));
  EXPECT_TRUE(Contains(YamlError("initial_translation: [1, 2]"),
                       "key 'initial_translation' expects a list of 3 numbers [tx, ty, tz], "
                       "got '[1, 2]'"));
  EXPECT_TRUE(Contains(YamlError("initial_rotation_deg: [1, x, 2]"), "got '[1, x, 2]'"));
  EXPECT_TRUE(Contains(YamlError("initial_rotation_deg: [[1], 2, 3]"), "got a nested list"));
  EXPECT_TRUE(Contains(YamlError("initial_rotation_deg: 5"), "got '5'"));
  EXPECT_TRUE(Contains(YamlError("free: [rx, rw]"), "key 'free' expects a list of rx, ry"));
  EXPECT_TRUE(Contains(YamlError("free: []"), "key 'free' expects"));
  EXPECT_TRUE(Contains(FlagError("max_iterations", "ten"),
                       "flag '--max_iterations' expects an integer >= 1, got 'ten'"));
  EXPECT_TRUE(Contains(FlagError("initial_translation", "1,2,3,4"), "got '1,2,3,4'"));
}

TEST(AlignConfigErrors, UnknownEnumValueListsTheAllowed) {
  EXPECT_TRUE(Contains(YamlError("cost: axail"),
                       "t.yaml:1: key 'cost' expects one of auto, volume, axial, axial_sparser, got 'axail'"));
  EXPECT_TRUE(Contains(YamlError("loss: l1"), "expects one of none, huber, soft_l1, cauchy"));
  EXPECT_TRUE(Contains(YamlError("trust_region: lm"), "one of levenberg_marquardt, dogleg"));
  EXPECT_TRUE(Contains(FlagError("line_search", "cg"),
                       "flag '--line_search' expects one of lbfgs, bfgs, nonlinear_cg, got 'cg'"));
}

// The data domain's keys, also as `measure` and `triangulate` read their flags.
TEST(AlignConfig, DomainKeys) {
  EXPECT_EQ(AlignConfig().options.domain.kind, DomainKind::kData);
  EXPECT_EQ(FromYaml("domain: hull").options.domain.kind, DomainKind::kHull);
  EXPECT_EQ(FromYaml("domain: data").options.domain.kind, DomainKind::kData);
  EXPECT_TRUE(Contains(YamlError("domain: convex"),
                       "t.yaml:1: key 'domain' expects one of data, hull, got 'convex'"));
  EXPECT_TRUE(Contains(YamlError("domain_max_edge_spacings: 0.5"),
                       "key 'domain_max_edge_spacings' expects a number in [1, 100], got '0.5'"));
  EXPECT_TRUE(Contains(YamlError("domain_min_thinness: 0.7"),
                       "key 'domain_min_thinness' expects a number in [0, 0.5], got '0.7'"));
  const DomainRule rule = DomainRuleFromFlags("hull", "5", "");
  EXPECT_EQ(rule.kind, DomainKind::kHull);
  EXPECT_EQ(rule.max_edge_spacings, 5.0);
  EXPECT_EQ(rule.min_boundary_thinness, DomainRule().min_boundary_thinness);
  EXPECT_EQ(DomainRuleFromFlags("", "", "").kind, DomainKind::kData);
  try {
    DomainRuleFromFlags("all", "", "");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "flag '--domain' expects one of data, hull, got 'all'");
  }
}

// linear_solver and subsample (the sweep's keys): every value, both bounds.
TEST(AlignConfig, LinearSolverAndSubsample) {
  EXPECT_EQ(FromYaml("linear_solver: dense_qr").options.axial_solver.linear_solver_type, ceres::DENSE_QR);
  EXPECT_EQ(FromYaml("linear_solver: cgnr").options.axial_solver.linear_solver_type, ceres::CGNR);
  EXPECT_EQ(AlignConfigValue(FromYaml("linear_solver: dense_normal_cholesky"), "linear_solver"),
            "dense_normal_cholesky");
  EXPECT_TRUE(Contains(YamlError("linear_solver: sparse_schur"),
                       "t.yaml:1: key 'linear_solver' expects one of dense_qr, "
                       "dense_normal_cholesky, cgnr, got 'sparse_schur'"));
  EXPECT_EQ(FromYaml("subsample: 1").options.subsample, 1.0);
  EXPECT_EQ(FromYaml("subsample: 1e-3").options.subsample, 1e-3);
  EXPECT_TRUE(Contains(YamlError("subsample: 0"), "key 'subsample' expects a number in (0, 1], got '0'"));
  EXPECT_TRUE(Contains(FlagError("subsample", "1.01"), "flag '--subsample' expects a number in (0, 1]"));
  EXPECT_TRUE(Contains(FlagError("subsampel", "0.5"), "did you mean 'subsample'?"));
}

TEST(AlignConfigErrors, ClassesAndColumns) {
  EXPECT_TRUE(Contains(YamlError("classes: [2, 256]"),
                       "key 'classes' expects a list of LAS classifications (integers 0 to 255)"));
  EXPECT_TRUE(Contains(FlagError("classes", "ground"), "flag '--classes' expects"));
  EXPECT_TRUE(Contains(YamlError("columns: [1, 2]"), "key 'columns' expects a list of 3 or 4"));
  EXPECT_TRUE(Contains(YamlError("columns: [0, 1, 2]"), "got '[0, 1, 2]'"));
  EXPECT_TRUE(Contains(YamlError("columns: [1.5, 2, 3]"), "key 'columns' expects"));
  EXPECT_TRUE(Contains(FlagError("columns", "X;Y;Z"), "flag '--columns' expects"));
  EXPECT_EQ(FromYaml("columns: X,Y,Z").columns, (std::vector<std::string>{"X", "Y", "Z"}));
  EXPECT_TRUE(FromYaml("classes:").classes.empty());
}

TEST(AlignConfigErrors, TerrainKeys) {
  EXPECT_TRUE(Contains(YamlError("window: [1, 2, 3]"),
                       "key 'window' expects a list of 4 integers >= 0"));
  EXPECT_TRUE(Contains(YamlError("window: [1, 2, -3, 4]"), "got '-3'"));
  EXPECT_TRUE(Contains(YamlError("band: 0"), "key 'band' expects an integer >= 1"));
  EXPECT_TRUE(Contains(YamlError("frame: lonlat"), "expects one of auto, enu, utm"));
  EXPECT_TRUE(Contains(YamlError("lod: -0.5"), "key 'lod' expects a number >= 0"));
  EXPECT_TRUE(Contains(YamlError("known_matrix: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]"),
                       "key 'known_matrix' expects a list of 16 (or 12) numbers"));
  // The last row of a rigid motion's matrix is 0 0 0 1.
  EXPECT_TRUE(Contains(YamlError("known_matrix: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1]"),
                       "key 'known_matrix'"));
  EXPECT_TRUE(FromYaml("known_matrix: []").terrain.known_matrix.empty());
  EXPECT_FALSE(FromYaml("lod: 0").terrain.Active("a.xyz", "b.ply"));
  EXPECT_TRUE(FromYaml("lod: 0.5").terrain.Active("a.xyz", "b.ply"));
  EXPECT_TRUE(FromYaml("lod: 0").terrain.Active("a.tif", "b.ply"));
}

TEST(AlignConfigErrors, NotAMapping) {
  EXPECT_TRUE(Contains(YamlError("- reference\n- moving\n"),
                       "t.yaml: expected a YAML mapping of 'key: value' lines, found a list"));
  EXPECT_TRUE(Contains(YamlError("just text"), "found a single value"));
  EXPECT_TRUE(Contains(YamlError("# only a comment\n"), "found nothing (an empty file)"));
  EXPECT_TRUE(Contains(YamlError(""), "found nothing"));
}

TEST(AlignConfigErrors, SyntaxErrorsAndRepeatedKeys) {
  EXPECT_TRUE(Contains(YamlError("cost: axial\nlevels: [1, 2\n"), "t.yaml:"));
  EXPECT_TRUE(Contains(YamlError("cost: axial\nlevels: [1, 2\n"), "not valid YAML"));
  EXPECT_TRUE(Contains(YamlError("cost: axial\n  levels: 2\n"), "t.yaml:2: not valid YAML"));
  EXPECT_TRUE(Contains(YamlError("cost: axial\nlevels: 2\ncost: volume\n"),
                       "t.yaml:3: key 'cost' given twice (also at line 1)"));
  EXPECT_TRUE(Contains(YamlError("[a, b]: 1"), "t.yaml:1: expected a key name"));
}

TEST(AlignConfigErrors, ConfigFileAndSurfaceFiles) {
  TempDir dir;
  AlignConfig config;
  const std::string missing = dir.path() + "/none.yaml";
  EXPECT_TRUE(Contains(ErrorOf([&] { ApplyAlignConfigFile(missing, &config); }),
                       "flag '--config': " + missing + ": cannot open"));
  const std::string file =
      dir.File("c.yaml", "reference: " + dir.path() + "/no_such.xyz\nmoving: b.xyz\n");
  ApplyAlignConfigFile(file, &config);
  EXPECT_EQ(config.config_file, file);
  EXPECT_TRUE(Contains(ErrorOf([&] { ReadInput(config, "reference"); }),
                       file + ":1: key 'reference': " + dir.path() + "/no_such.xyz: cannot open"));
  const std::string bad = dir.File("bad.xyz", "0 0 0\n1 0 0\n0 1 x\n");
  ApplyAlignFlag("moving", bad, &config);
  EXPECT_TRUE(Contains(ErrorOf([&] { ReadInput(config, "moving"); }),
                       "flag '--moving': " + bad + ":3: z is not a number"));
}

TEST(AlignConfigErrors, InitialTransformIsReadAndIsTheOnlyStart) {
  TempDir dir;
  const std::string a = dir.File("a.xyz", "0 0 0\n1 0 0\n0 1 0\n");
  const std::string t = dir.File("t.txt", "0 -1 0 5\n1 0 0 6\n0 0 1 7\n0 0 0 1\n");
  const std::string head = "reference: " + a + "\nmoving: " + a + "\ninitial_transform: " + t + "\n";
  AlignConfig config = FromYaml(head + "initial_translation: [0, 0, 0]\n");
  FinishAlignConfig(&config);
  EXPECT_EQ(config.initial_matrix,
            (std::vector<double>{0, -1, 0, 5, 1, 0, 0, 6, 0, 0, 1, 7, 0, 0, 0, 1}));
  const auto finish_error = [](const std::string& yaml) {
    return ErrorOf([&] {
      AlignConfig c = FromYaml(yaml);
      FinishAlignConfig(&c);
    });
  };
  EXPECT_EQ(finish_error(head + "initial_rotation_deg: [0, 0, 1]\n"),
            "t.yaml:3: key 'initial_transform' and t.yaml:4: key 'initial_rotation_deg' both set "
            "the start: give one of them");
  EXPECT_TRUE(Contains(finish_error(head + "output: " + t + "\n"),
                       "key 'output': '" + t + "' is also the initial_transform file"));
  const std::string shear = dir.File("s.txt", "1 1 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_TRUE(Contains(finish_error("reference: " + a + "\nmoving: " + a +
                                    "\ninitial_transform: " + shear + "\n"),
                       "t.yaml:3: key 'initial_transform': " + shear + ": not a rigid motion"));
}

TEST(AlignConfigErrors, FinishChecksRequiredKeysAndOutputs) {
  TempDir dir;
  const std::string a = dir.File("a.xyz", "0 0 0\n1 0 0\n0 1 0\n");
  const std::string head = "reference: " + a + "\nmoving: " + a + "\n";
  const auto finish_error = [](const std::string& yaml) {
    return ErrorOf([&] {
      AlignConfig config = FromYaml(yaml);
      FinishAlignConfig(&config);
    });
  };
  EXPECT_TRUE(Contains(finish_error("moving: " + a + "\n"), "no 'reference' surface given"));
  EXPECT_EQ(finish_error(head + "output: " + dir.path() + "/t.json\n"), "");
  EXPECT_TRUE(Contains(finish_error(head + "output: " + dir.path() + "/no_dir/t.json\n"),
                       "t.yaml:3: key 'output': cannot write '" + dir.path() +
                           "/no_dir/t.json': directory '" + dir.path() +
                           "/no_dir' does not exist"));
  EXPECT_TRUE(Contains(finish_error(head + "log: " + dir.path() + "\n"), "it is a directory"));
  EXPECT_TRUE(Contains(finish_error(head + "aligned: " + dir.path() + "/m.obj\n"),
                       "key 'aligned': cannot write a surface as"));
  EXPECT_TRUE(Contains(finish_error(head + "aligned: " + a + "\n"),
                       "key 'aligned': '" + a + "' is also the reference file"));
  EXPECT_TRUE(
      Contains(finish_error(head + "output: " + dir.path() + "/o\nlog: " + dir.path() + "/o\n"),
               "key 'log': '" + dir.path() + "/o' is also the output file"));
  EXPECT_TRUE(Contains(finish_error(head + "mask: " + dir.path() + "/no_mask.txt\n"),
                       "t.yaml:3: key 'mask': " + dir.path() + "/no_mask.txt: cannot open"));
  EXPECT_EQ(dir.Files().size(), 1u) << "nothing but a.xyz may be created";

  // Settings valid one by one but not together name the key at fault.
  EXPECT_TRUE(Contains(finish_error(head + "cost: volume\ntrim_fraction: 0.1\n"),
                       "t.yaml:4: key 'trim_fraction': "));
  AlignConfig config =
      FromYaml(head + "cost: axial\nmask: " + dir.File("m.txt", "0 0\n1 0\n1 1\n0 1\n"));
  FinishAlignConfig(&config);
  EXPECT_EQ(config.options.weight, WeightMode::kMask);
  EXPECT_EQ(config.options.mask.size(), 1u);
  EXPECT_EQ(config.options.mask[0].size(), 4u);

  // weights: per_point sets μ from the reference's samples; one μ at a time.
  AlignConfig weighted = FromYaml(head + "weights: per_point\n");
  FinishAlignConfig(&weighted);
  EXPECT_EQ(weighted.options.weight, WeightMode::kPerPoint);
  EXPECT_EQ(finish_error(head + "weights: per_point\nmask: " + dir.path() + "/m.txt\n"),
            "t.yaml:3: key 'weights': per_point cannot be combined with 'mask' (t.yaml:4: key "
            "'mask')");
  EXPECT_TRUE(Contains(finish_error(head + "weights: per_point\nmask_raster: s.tif\n"),
                       "per_point cannot be combined with 'mask_raster'"));
  EXPECT_TRUE(Contains(finish_error(head + "weights: mask\n"),
                       "t.yaml:3: key 'weights' expects one of uniform, per_point"));
}

}  // namespace
}  // namespace surfreg
