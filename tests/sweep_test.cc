// The sweep (tools/sweep.h, tools/sweep_config.h): the grid of 2 pairs × 4
// settings × 8 perturbations run in parallel, its errors recomputed from
// each row's transform against the known motions with independent code
// (tests/testing/surface_pairs.h, a gift-wrapping hull); the perturbations'
// exact size; determinism; CSV, shards, ranking (the config: sweep_config_test.cc).
#include "tools/sweep.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

using testing::CompareMotions;

class TempDir {
 public:
  TempDir() {
    std::string pattern = ::testing::TempDir() + "/sweep_test.XXXXXX";
    path_ = mkdtemp(pattern.data()) ? pattern : "";
    EXPECT_FALSE(path_.empty());
  }
  ~TempDir() { std::system(("rm -rf '" + path_ + "'").c_str()); }
  std::string File(const std::string& name, const std::string& text) const {
    const std::string file = path_ + "/" + name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string G17(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  return buffer;
}

std::string Xyz(const std::vector<std::array<double, 3>>& points) {
  std::string text;
  for (const auto& p : points) text += G17(p[0]) + " " + G17(p[1]) + " " + G17(p[2]) + "\n";
  return text;
}

// The InputError message of `f()` ("" if none is thrown); one line.
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  return "";
}

::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

// Hull area by gift wrapping (another algorithm than the sweep's monotone chain).
double HullArea(const std::vector<std::array<double, 3>>& p) {
  std::size_t start = 0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (p[i][0] < p[start][0]) start = i;
  }
  std::vector<std::size_t> hull;
  std::size_t current = start;
  do {
    hull.push_back(current);
    std::size_t next = (current + 1) % p.size();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double cross = (p[next][0] - p[current][0]) * (p[i][1] - p[current][1]) -
                           (p[next][1] - p[current][1]) * (p[i][0] - p[current][0]);
      if (cross < 0) next = i;
    }
    current = next;
  } while (current != start && hull.size() <= p.size());
  double area = 0;
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const auto& a = p[hull[k]];
    const auto& b = p[hull[(k + 1) % hull.size()]];
    area += a[0] * b[1] - b[0] * a[1];
  }
  return std::fabs(area) / 2;
}

// A pair with a known motion, written as files.
struct TestPair {
  std::string reference, moving;
  Eigen::Matrix4d truth;
  Eigen::Vector3d centroid;  // of the moving points
  double spacing = 0;        // of the reference
};

TestPair MakeTestPair(const TempDir& dir, const std::string& name, uint64_t seed_a, uint64_t seed_b,
                      const Eigen::Vector3d& axis, double angle_deg, const Eigen::Vector3d& shift) {
  const int n = 1600;
  const auto a = testing::SampleUniform(testing::SmoothTerrain, n, 0, 100, 0, 100, seed_a);
  const auto b = testing::SampleUniform(testing::SmoothTerrain, n, 0, 100, 0, 100, seed_b);
  TestPair pair;
  pair.truth = testing::TrueMotion(axis, angle_deg, shift, testing::Centroid(b));
  const auto moved = testing::MoveByInverse(b, pair.truth);
  pair.centroid = testing::Centroid(moved);
  pair.spacing = std::sqrt(HullArea(a) / n);
  pair.reference = dir.File(name + "_a.xyz", Xyz(a));
  pair.moving = dir.File(name + "_b.xyz", Xyz(moved));
  return pair;
}

// The truth as rotation_deg / translation about the moving centroid.
std::string AboutCentroid(const TestPair& pair) {
  const Eigen::AngleAxisd aa(Eigen::Matrix3d(pair.truth.topLeftCorner<3, 3>()));
  const Eigen::Vector3d w = aa.axis() * aa.angle() * 180 / M_PI;
  const Eigen::Vector3d t = (pair.truth * pair.centroid.homogeneous()).head<3>() - pair.centroid;
  return "{rotation_deg: [" + G17(w[0]) + ", " + G17(w[1]) + ", " + G17(w[2]) +
         "], translation: [" + G17(t[0]) + ", " + G17(t[1]) + ", " + G17(t[2]) + "]}";
}

std::string AsMatrix(const Eigen::Matrix4d& m) {
  std::string text = "{matrix: [";
  for (int i = 0; i < 4; ++i) {
    text += std::string(i ? ", " : "") + "[" + G17(m(i, 0)) + ", " + G17(m(i, 1)) + ", " +
            G17(m(i, 2)) + ", " + G17(m(i, 3)) + "]";
  }
  return text + "]}";
}

double Field(const CsvTable& t, const std::vector<std::string>& row, const std::string& name) {
  const int c = CsvColumn(t, name);
  EXPECT_GE(c, 0) << name;
  return c < 0 || row[c].empty() ? std::nan("") : std::stod(row[c]);
}

std::string Text(const CsvTable& t, const std::vector<std::string>& row, const std::string& name) {
  const int c = CsvColumn(t, name);
  EXPECT_GE(c, 0) << name;
  return c < 0 ? "" : row[c];
}

// ---- The done-when grid: 2 pairs × 4 settings × 8 perturbations ---------

TEST(Sweep, GridOf64RunsHasTheIndependentlyComputedErrors) {
  TempDir dir;
  const TestPair p1 =
      MakeTestPair(dir, "hills", 1, 1, {1, -2, 0.5}, 4.0, {3, -2, 0.5});  // a self copy
  const TestPair p2 = MakeTestPair(dir, "ridge", 3, 4, {0, 1, 0.2}, -3.0, {-2, 4, -1});
  const std::string yaml =
      "pairs:\n  - {name: hills, reference: " + p1.reference + ", moving: " + p1.moving +
      ", truth: " + AsMatrix(p1.truth) + "}\n  - {name: ridge, reference: " + p2.reference +
      ", moving: " + p2.moving + ", truth: " + AboutCentroid(p2) +
      "}\n"
      "settings: {cost: axial, max_iterations: 100, covariance: false}\n"
      "sweep:\n  trust_region: [levenberg_marquardt, dogleg]\n"
      "  linear_solver: [dense_qr, dense_normal_cholesky]\n"
      "perturbations: {rotation_deg: [1, 3], shift_spacings: [2, 4], directions: 4, seed: 9}\n"
      "output: " +
      dir.path() + "/runs.csv\n";
  SweepPlan plan = PlanSweep(ParseSweepConfig(yaml, "t.yaml"));
  ASSERT_EQ(plan.runs.size(), 64u);
  LoadSweepPairs(&plan);
  CsvTable table;
  table.header = SweepCsvHeader(plan.config);
  RunSweepRuns(plan, plan.runs, 2, [&](const SweepRun&, std::vector<std::string> row) {
    table.rows.push_back(std::move(row));
  });
  SortByRunId(&table, "runs");
  ASSERT_EQ(table.rows.size(), 64u);
  const TestPair* pairs[] = {&p1, &p2};
  const char* regions[] = {"levenberg_marquardt", "levenberg_marquardt", "dogleg", "dogleg"};
  const char* solvers[] = {"dense_qr", "dense_normal_cholesky", "dense_qr",
                           "dense_normal_cholesky"};
  int successes = 0;
  for (int id = 0; id < 64; ++id) {
    const auto& row = table.rows[id];
    const int pair = id / 32, setting = id / 8 % 4, magnitude = id / 4 % 2, direction = id % 4;
    EXPECT_EQ(row[0], std::to_string(id));
    EXPECT_EQ(Text(table, row, "pair"), pair ? "ridge" : "hills");
    EXPECT_EQ(Text(table, row, "setting"), std::to_string(setting));
    EXPECT_EQ(Text(table, row, "trust_region"), regions[setting]);
    EXPECT_EQ(Text(table, row, "linear_solver"), solvers[setting]);
    EXPECT_EQ(Field(table, row, "perturbation_deg"), magnitude ? 3 : 1);
    EXPECT_EQ(Field(table, row, "perturbation_spacings"), magnitude ? 4 : 2);
    EXPECT_EQ(Field(table, row, "direction"), direction);
    const std::string verdict = Text(table, row, "verdict");
    ASSERT_NE(verdict, "rejected") << Text(table, row, "message");
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j)
        m(i, j) = Field(table, row, "m" + std::to_string(i) + std::to_string(j));
    }
    const testing::MotionError e = CompareMotions(m, pairs[pair]->truth, pairs[pair]->centroid);
    const double rotation = Field(table, row, "rotation_error_deg");
    const double translation = Field(table, row, "translation_error");
    EXPECT_NEAR(rotation, e.rotation_deg, 1e-9) << "run " << id;
    EXPECT_NEAR(translation, e.translation, 1e-9 * (1 + e.translation)) << "run " << id;
    EXPECT_NEAR(Field(table, row, "translation_error_spacings"),
                e.translation / pairs[pair]->spacing, 1e-9 * (1 + e.translation))
        << "run " << id;
    const bool success = verdict == "converged_improved" && e.rotation_deg < 0.1 &&
                         e.translation / pairs[pair]->spacing < 0.5;
    EXPECT_EQ(Text(table, row, "success"), success ? "true" : "false") << "run " << id;
    successes += success;
  }
  EXPECT_GE(successes, 32) << "most starts this close should converge";
}

// The start is off the truth by exactly the magnitudes: a degrees and s
// spacings at the moving centroid, whatever the direction.
TEST(Sweep, PerturbedStartIsOffByTheMagnitudes) {
  const Eigen::Vector3d c(500012.5, 4100300.25, 120);
  const Eigen::Matrix4d truth = testing::TrueMotion({0.3, 1, -0.2}, 2.5, {4, -3, 1}, c);
  for (int k = 0; k < 20; ++k) {
    const PerturbationDirections d = DrawDirections(RunSeed(7, "pair", 1, k));
    EXPECT_NEAR(d.axis.norm(), 1, 1e-15);
    EXPECT_NEAR(d.shift.norm(), 1, 1e-15);
    const Eigen::Matrix4d start = PerturbedStart(truth, c, 3.0, 12.5, d);
    const testing::MotionError e = CompareMotions(start, truth, c);
    EXPECT_NEAR(e.rotation_deg, 3.0, 1e-9);
    EXPECT_NEAR(e.translation, 12.5, 1e-7);
    EXPECT_NEAR(CompareToTruth(start, truth, c).rotation_deg, 3.0, 1e-9);
  }
  EXPECT_TRUE(PerturbedStart(truth, c, 0, 0, DrawDirections(1)).isApprox(truth, 1e-15));
}

TEST(Sweep, DirectionsDependOnlyOnTheirSeed) {
  std::set<uint64_t> seeds;
  for (const std::string pair : {"a", "b"}) {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) seeds.insert(RunSeed(1, pair, i, k));
    }
  }
  seeds.insert(RunSeed(2, "a", 0, 0));
  EXPECT_EQ(seeds.size(), 19u);
  const PerturbationDirections a = DrawDirections(RunSeed(1, "a", 0, 1));
  const PerturbationDirections b = DrawDirections(RunSeed(1, "a", 0, 1));
  EXPECT_EQ(a.axis, b.axis);
  EXPECT_EQ(a.shift, b.shift);
  // Uniform on the sphere: the mean of many draws is near 0.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4000; ++k) mean += DrawDirections(RunSeed(3, "x", 0, k)).axis / 4000;
  EXPECT_LT(mean.norm(), 0.05);
}

TEST(Sweep, TruthAboutCentroid) {
  SweepTruth truth;
  truth.kind = SweepTruth::Kind::kAboutCentroid;
  truth.rotation_deg = {0, 0, 90};
  truth.translation = {1, 2, 3};
  const Eigen::Vector3d c(10, 0, 0);
  const Eigen::Matrix4d m = TruthMatrix(truth, c);
  EXPECT_TRUE((m * c.homogeneous()).head<3>().isApprox(Eigen::Vector3d(11, 2, 3), 1e-14));
  // (11, 0, 0) is 1 along x from c: a quarter turn about z takes it 1 along y.
  EXPECT_TRUE(
      (m * Eigen::Vector4d(11, 0, 0, 1)).head<3>().isApprox(Eigen::Vector3d(11, 3, 3), 1e-14));
  EXPECT_EQ(TruthMatrix(SweepTruth(), c), Eigen::Matrix4d::Identity());
}

TEST(Sweep, SpacingAndCentroidOfAGrid) {
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 11; ++i) {
    for (int j = 0; j < 11; ++j) points.push_back({1e6 + 2.0 * i, 5e6 + 2.0 * j, 100.0 + i});
  }
  const Surface s = MakeSurface(points);
  EXPECT_NEAR(MeanSampleSpacing(s), std::sqrt(400.0 / 121), 1e-12);  // hull 20 × 20, 121 points
  EXPECT_TRUE(SurfaceCentroid(s).isApprox(Eigen::Vector3d(1e6 + 10, 5e6 + 10, 105), 1e-15));
}

// The same run gives the same row (timing aside) on 1 or 2 threads, in any order.
TEST(Sweep, RowsDoNotDependOnThreadsOrOrder) {
  TempDir dir;
  const TestPair p = MakeTestPair(dir, "p", 5, 6, {0, 0, 1}, 2.0, {1, 1, 0});
  const std::string yaml =
      "pairs: [{reference: " + p.reference + ", moving: " + p.moving +
      "}]\nsettings: {cost: axial, max_iterations: 8, covariance: false}\n"
      "perturbations: {rotation_deg: 2, shift_spacings: [1, 3], directions: 3}\n"
      "output: x.csv\n";
  SweepPlan plan = PlanSweep(ParseSweepConfig(yaml, "t.yaml"));
  LoadSweepPairs(&plan);
  const int seconds = CsvColumn({SweepCsvHeader(plan.config), {}}, "seconds");
  std::vector<std::vector<std::string>> one(6), two(6);
  RunSweepRuns(plan, plan.runs, 1,
               [&](const SweepRun& r, std::vector<std::string> row) { one[r.id] = row; });
  std::vector<SweepRun> reversed(plan.runs.rbegin(), plan.runs.rend());
  RunSweepRuns(plan, reversed, 2,
               [&](const SweepRun& r, std::vector<std::string> row) { two[r.id] = row; });
  for (int id = 0; id < 6; ++id) {
    EXPECT_EQ(Text({SweepCsvHeader(plan.config), {}}, one[id], "pair"), "pair1");
    one[id][seconds] = two[id][seconds] = "";
    EXPECT_EQ(one[id], two[id]) << id;
  }
}

// A start align refuses (a 90° tilt folds the surface) is a row, not an
// error; an error in the row handler stops the sweep and reaches the caller.
TEST(Sweep, RejectedStartsAndFailingHandlers) {
  TempDir dir;
  const TestPair p = MakeTestPair(dir, "p", 7, 8, {0, 0, 1}, 1.0, {0, 0, 0});
  const std::string yaml = "pairs: [{reference: " + p.reference + ", moving: " + p.moving +
                           "}]\nsettings: {cost: axial, max_iterations: 5, covariance: false}\n"
                           "perturbations: {rotation_deg: 90, directions: 4}\noutput: x.csv\n";
  SweepPlan plan = PlanSweep(ParseSweepConfig(yaml, "t.yaml"));
  LoadSweepPairs(&plan);
  const CsvTable empty{SweepCsvHeader(plan.config), {}};
  int rejected = 0, calls = 0;
  RunSweepRuns(plan, plan.runs, 2, [&](const SweepRun&, std::vector<std::string> row) {
    ASSERT_EQ(row.size(), empty.header.size());
    if (Text(empty, row, "verdict") != "rejected") return;
    ++rejected;
    EXPECT_EQ(Text(empty, row, "success"), "false");
    EXPECT_EQ(Text(empty, row, "iterations"), "");
    EXPECT_TRUE(Contains(Text(empty, row, "message"), "fold"));
  });
  EXPECT_GE(rejected, 1);
  EXPECT_THROW(RunSweepRuns(plan, plan.runs, 2,
                            [&](const SweepRun&, std::vector<std::string>) {
                              if (++calls == 2) throw std::runtime_error("disk full");
                            }),
               std::runtime_error);
  EXPECT_EQ(calls, 2);  // no row handled after the failure
  plan.config.pairs[0].moving = dir.path() + "/missing.xyz";
  EXPECT_TRUE(Contains(ErrorOf([&] { LoadSweepPairs(&plan); }), "t.yaml:1: key 'pairs[1]': "));
}

// ---- CSV, run ids and shards --------------------------------------------

TEST(SweepCsv, QuotedFieldsRoundTrip) {
  CsvTable t{{"run_id", "text"},
             {{"1", "a,b"}, {"2", "say \"hi\""}, {"3", "two\nlines"}, {"4", ""}}};
  const std::string text = FormatCsv(t);
  EXPECT_TRUE(Contains(text, "1,\"a,b\"\n2,\"say \"\"hi\"\"\"\n"));
  const CsvTable back = ParseCsv(text, "t.csv", false);
  EXPECT_EQ(back.header, t.header);
  EXPECT_EQ(back.rows, t.rows);
  EXPECT_EQ(ParseCsv("a,b\r\n1,2\r\n", "t.csv", false).rows[0][1], "2");
}

TEST(SweepCsv, TornTailAndBadRows) {
  EXPECT_EQ(ParseCsv("run_id,x\n1,a\n2,b", "p", true).rows.size(), 1u);
  EXPECT_EQ(ParseCsv("run_id,x\n1,\"a\n", "p", true).rows.size(), 0u);  // torn inside quotes
  EXPECT_TRUE(ParseCsv("run_i", "p", true).header.empty());
  EXPECT_TRUE(Contains(ErrorOf([] { ParseCsv("run_id,x\n1,a\n2,b", "p.csv", false); }),
                       "p.csv:3: the last line has no end"));
  EXPECT_TRUE(Contains(ErrorOf([] { ParseCsv("run_id,x\n1,a\n2\n", "p.csv", false); }),
                       "p.csv:3: 1 fields, the header has 2"));
  EXPECT_TRUE(Contains(ErrorOf([] { ParseCsv("", "p.csv", false); }), "p.csv: empty file"));
}

TEST(SweepCsv, SortByRunIdIsNumericAndRejectsConflicts) {
  CsvTable t{{"run_id", "x"}, {{"10", "a"}, {"9", "b"}, {"10", "a"}, {"0", "c"}}};
  SortByRunId(&t, "m");
  EXPECT_EQ(t.rows, (std::vector<std::vector<std::string>>{{"0", "c"}, {"9", "b"}, {"10", "a"}}));
  CsvTable conflict{{"run_id", "x"}, {{"1", "a"}, {"1", "b"}}};
  EXPECT_TRUE(Contains(ErrorOf([&] { SortByRunId(&conflict, "m"); }), "m: run_id 1 appears twice"));
  CsvTable bad{{"run_id"}, {{"x1"}}};
  EXPECT_TRUE(Contains(ErrorOf([&] { SortByRunId(&bad, "m"); }), "bad run_id 'x1'"));
  CsvTable header{{"id"}, {}};
  EXPECT_TRUE(Contains(ErrorOf([&] { SortByRunId(&header, "m"); }), "first column is not run_id"));
}

TEST(SweepShard, ParseAndPartition) {
  EXPECT_EQ(ParseShard("", "f").count, 1);
  const Shard s = ParseShard("2/3", "f");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 3);
  for (const char* bad : {"0/3", "4/3", "1/0", "a/b", "1/3x", "1", "-1/3"}) {
    EXPECT_TRUE(
        Contains(ErrorOf([&] { ParseShard(bad, "flag '--shard'"); }), "flag '--shard' expects K/N"))
        << bad;
  }
  for (int id = 0; id < 50; ++id) {  // every run in exactly one shard
    int in = 0;
    for (int k = 1; k <= 4; ++k) in += ParseShard(std::to_string(k) + "/4", "f").Contains(id);
    EXPECT_EQ(in, 1);
  }
}

// ---- ranking ----------------------------------------------------------------

TEST(SweepRank, SuccessThenErrorThenTime) {
  CsvTable t;
  t.header = {"setting",
              "loss",
              "success",
              "rotation_error_deg",
              "translation_error_spacings",
              "mean_abs_dz_after",
              "seconds",
              "iterations"};
  // setting 0: 1/2 succeed; 1 and 2: 2/2, 2 more accurate; 3: 2/2 as accurate as 2 but slower.
  t.rows = {{"0", "none", "true", "0.01", "0.1", "1", "1", "5"},
            {"0", "none", "false", "5", "9", "1", "1", "5"},
            {"1", "huber", "true", "0.05", "0.1", "1", "1", "5"},
            {"1", "huber", "true", "0.07", "0.1", "1", "3", "7"},
            {"2", "cauchy", "true", "0.01", "0.2", "1", "2", "5"},
            {"2", "cauchy", "true", "0.01", "0.2", "1", "2", "5"},
            {"3", "soft_l1", "true", "0.01", "0.2", "1", "4", "5"},
            {"3", "soft_l1", "true", "0.01", "0.2", "1", "4", "5"}};
  const std::vector<SettingRank> r = RankSettings(t, {"loss"}, 0.1, 0.5);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0].setting, "2");  // score max(0.1, 0.4) = 0.4 beats setting 1's max(0.6, 0.2) = 0.6
  EXPECT_EQ(r[1].setting, "3");
  EXPECT_EQ(r[2].setting, "1");
  EXPECT_EQ(r[3].setting, "0");
  EXPECT_EQ(r[2].values, std::vector<std::string>{"huber"});
  EXPECT_DOUBLE_EQ(r[2].median_rotation_error_deg, 0.06);
  EXPECT_DOUBLE_EQ(r[2].median_seconds, 2);
  EXPECT_DOUBLE_EQ(r[3].success_rate, 0.5);
  const std::string md = RankingMarkdown(r, {"loss"});
  EXPECT_TRUE(Contains(md, "| 1 | 2 | cauchy | 2 | 100.0 | 0.01 | 0.2 |"));
  EXPECT_TRUE(Contains(md, "| 4 | 0 | none | 2 | 50.0 |"));
}

TEST(SweepRank, WithoutTruthRanksByFinalMeasure) {
  CsvTable t{{"setting", "success", "rotation_error_deg", "translation_error_spacings",
              "mean_abs_dz_after", "seconds", "iterations"},
             {{"0", "true", "", "", "0.5", "1", "3"}, {"1", "true", "", "", "0.2", "9", "3"}}};
  const std::vector<SettingRank> r = RankSettings(t, {}, 0.1, 0.5);
  EXPECT_EQ(r[0].setting, "1");
  EXPECT_TRUE(std::isnan(r[0].median_rotation_error_deg));
  EXPECT_TRUE(Contains(RankingMarkdown(r, {}), "| 1 | 1 | 1 | 100.0 | - | - | 0.2 | 9 | 3 |"));
}

}  // namespace
}  // namespace surfreg
