// The config of `surfreg sweep` (tools/sweep_config.h): every part parsed,
// each class of error message (file, line, key, the nearest key), a bad
// combination of settings found before any run, and the shipped example.
#include "tools/sweep_config.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "tools/sweep.h"

namespace surfreg {
namespace {

class TempDir {
 public:
  TempDir() {
    std::string pattern = ::testing::TempDir() + "/sweep_config_test.XXXXXX";
    path_ = mkdtemp(pattern.data()) ? pattern : "";
    EXPECT_FALSE(path_.empty());
  }
  ~TempDir() { std::system(("rm -rf '" + path_ + "'").c_str()); }
  std::string File(const std::string& name, const std::string& text) const {
    const std::string file = path_ + "/" + name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }

 private:
  std::string path_;
};

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

const char* const kPairs = "pairs: [{reference: a.xyz, moving: b.xyz}]\noutput: o.csv\n";

std::string ConfigError(const std::string& yaml) {
  return ErrorOf([&] { ParseSweepConfig(yaml, "s.yaml"); });
}

TEST(SweepConfig, ParsesEveryPart) {
  TempDir dir;
  const std::string json = dir.File(
      "t.json", "{\"matrix\": [[1, 0, 0, 5], [0, 1, 0, 6], [0, 0, 1, 7], [0, 0, 0, 1]]}\n");
  const SweepConfig c = ParseSweepConfig(
      "pairs:\n  - {name: one, reference: a.xyz, moving: b.xyz, truth: {file: " + json +
          "}}\n  - {reference: c.xyz, moving: d.xyz}\n"
          "settings: {cost: axial, free: [rx, tz]}\nsweep: {loss: [none, huber], levels: [1, 2, "
          "3]}\n"
          "perturbations: {rotation_deg: [0, 2], shift_spacings: 5, directions: 3, seed: 42}\n"
          "success: {rotation_deg: 0.2, spacings: 1}\njobs: 3\noutput: out.csv\n",
      "s.yaml");
  ASSERT_EQ(c.pairs.size(), 2u);
  EXPECT_EQ(c.pairs[0].name, "one");
  EXPECT_EQ(c.pairs[1].name, "pair2");
  EXPECT_EQ(c.pairs[0].truth.kind, SweepTruth::Kind::kMatrix);
  EXPECT_EQ(c.pairs[0].truth.matrix(1, 3), 6);
  EXPECT_EQ(c.pairs[1].truth.kind, SweepTruth::Kind::kNone);
  EXPECT_EQ(c.base.options.cost, CostKind::kAxial);
  EXPECT_EQ(c.base.Where("cost"), "s.yaml:4: key 'settings.cost'");
  ASSERT_EQ(c.swept.size(), 2u);
  EXPECT_EQ(c.swept[1].key, "levels");
  EXPECT_EQ(c.swept[1].values, (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_EQ(c.rotation_deg, (std::vector<double>{0, 2}));
  EXPECT_EQ(c.shift_spacings, (std::vector<double>{5, 5}));
  EXPECT_EQ(c.directions, 3);
  EXPECT_EQ(c.seed, 42u);
  EXPECT_EQ(c.success_rotation_deg, 0.2);
  EXPECT_EQ(c.success_spacings, 1);
  EXPECT_EQ(c.jobs, 3);
  EXPECT_EQ(c.output, "out.csv");
  const SweepPlan plan = PlanSweep(c);
  EXPECT_EQ(plan.runs.size(), 2u * 6 * 2 * 3);
  EXPECT_EQ(plan.settings[1], (std::vector<std::string>{"none", "2"}));  // the first key slowest
  EXPECT_EQ(plan.run_configs[7].moving, "d.xyz");
  EXPECT_EQ(plan.run_configs[7].options.levels, 2);
  EXPECT_EQ(plan.run_configs[7].options.num_threads, 1);
  EXPECT_EQ(AlignConfigValue(plan.run_configs[7], "free"), "[rx, tz]");
}

TEST(SweepConfig, ErrorsNameFileLineAndKey) {
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "settings: {cots: axial}"),
                       "s.yaml:3: key 'settings.cots': unknown key 'cots' (did you mean 'cost'?)"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "sweep:\n  loss: [none, hubber]\n"),
                       "s.yaml:4: key 'sweep.loss' value 2 expects one of none, huber, soft_l1, "
                       "cauchy, got 'hubber'"));
  EXPECT_TRUE(Contains(
      ConfigError(std::string(kPairs) + "sweep: {loss: huber}"),
      "s.yaml:3: key 'sweep.loss' expects a non-empty list of values to sweep, got 'huber'"));
  EXPECT_TRUE(
      Contains(ConfigError(std::string(kPairs) + "settings: {loss: none}\nsweep: {loss: [huber]}"),
               "key 'sweep.loss': is also set under 'settings:' (s.yaml:3: key 'settings.loss')"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "settings: {threads: 2}"),
                       "key 'settings.threads': not a sweep setting: runs are parallel"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "sweep: {output: [a.json]}"),
                       "not a sweep setting"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "settings: {initial_transform: t.txt}"),
                       "key 'settings.initial_transform': not a sweep setting: the starts are set "
                       "by the truth"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "settings: {matrix_txt: m.txt}"),
                       "key 'settings.matrix_txt': not a sweep setting: a sweep writes no per-run"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "settings: {dod: d.tif}"),
                       "key 'settings.dod': not a sweep setting: terrain inputs"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "sweep: {lod: [0.1, 0.2]}"),
                       "not a sweep setting: terrain inputs"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "perturbatons: {}"),
                       "s.yaml:3: unknown key 'perturbatons' (did you mean 'perturbations'?)"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "cost: axial"),
                       "unknown key 'cost' (align settings go under 'settings:'"));
  EXPECT_TRUE(
      Contains(ConfigError(std::string(kPairs) +
                           "perturbations: {rotation_deg: [1, 2], shift_spacings: [1, 2, 3]}"),
               "paired level by level"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "perturbations: {rotation_deg: [-1]}"),
                       "key 'perturbations.rotation_deg' expects a number >= 0"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "perturbations: {directions: 0}"),
                       "key 'perturbations.directions' expects an integer >= 1, got '0'"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "success: {rotation_deg: 0}"),
                       "expects a number > 0"));
  EXPECT_TRUE(Contains(ConfigError(std::string(kPairs) + "jobs: many"),
                       "key 'jobs' expects an integer >= 1"));
  EXPECT_TRUE(Contains(ConfigError("pairs: [{reference: a.xyz, moving: b.xyz}]\noutput: o.txt\n"),
                       "s.yaml:2: key 'output' expects a file name ending in .csv"));
  EXPECT_TRUE(Contains(ConfigError("output: o.csv\n"), "s.yaml: no 'pairs:'"));
  EXPECT_TRUE(Contains(ConfigError("pairs: [{reference: a.xyz}]\noutput: o.csv\n"),
                       "s.yaml:1: key 'pairs[1]': has no 'moving: FILE'"));
  EXPECT_TRUE(Contains(
      ConfigError("pairs:\n - {name: x, reference: a, moving: b}\n - {name: x, reference: a, "
                  "moving: b}\noutput: o.csv\n"),
      "s.yaml:3: key 'pairs[2]': the name 'x' is used twice"));
  EXPECT_TRUE(
      Contains(ConfigError("pairs:\n - {name: 'a b', reference: a, moving: b}\noutput: o.csv\n"),
               "key 'pairs[1].name' expects a name of letters"));
  EXPECT_TRUE(Contains(
      ConfigError("pairs: [{reference: a, moving: b, truth: {matrix: [[2, 0, 0, 0], [0, 1, 0, 0], "
                  "[0, 0, 1, 0], [0, 0, 0, 1]]}}]\noutput: o.csv\n"),
      "key 'pairs[1].truth.matrix': is not a rigid motion"));
  EXPECT_TRUE(Contains(
      ConfigError("pairs: [{reference: a, moving: b, truth: {matrix: [1, 2]}}]\noutput: o.csv\n"),
      "expects 4 rows of 4 numbers"));
  EXPECT_TRUE(Contains(
      ConfigError("pairs: [{reference: a, moving: b, truth: {rotation_deg: [1, 2, 3], matrix: "
                  "[]}}]\noutput: o.csv\n"),
      "key 'pairs[1].truth': give one of"));
  EXPECT_TRUE(Contains(
      ConfigError("pairs: [{reference: a, moving: b, truth: {file: /nonexistent.json}}]\noutput: "
                  "o.csv\n"),
      "key 'pairs[1].truth.file': "));
  EXPECT_TRUE(Contains(ConfigError("pairs: [a, b]\noutput: o.csv\n"),
                       "key 'pairs[1]' expects a mapping of 'key: value' lines, got 'a'"));
  EXPECT_TRUE(Contains(ConfigError("[1, 2]"), "s.yaml: expected a YAML mapping"));
  EXPECT_TRUE(Contains(ConfigError("pairs: [\n"), "s.yaml:2: not valid YAML"));
}

// A combination of settings align rejects is found before any run, naming
// the line and the setting.
TEST(SweepConfig, BadCombinationNamesTheSetting) {
  const SweepConfig c = ParseSweepConfig(
      std::string(kPairs) + "sweep:\n  cost: [axial, volume]\n  trim_fraction: [0, 0.1]\n",
      "s.yaml");
  EXPECT_TRUE(
      Contains(ErrorOf([&] { PlanSweep(c); }),
               "s.yaml:5: key 'sweep.trim_fraction': trim_fraction applies to cost axial or axial_sparser only "
               "(setting 3: cost=volume, trim_fraction=0.1)"));
}

// The shipped example parses, names existing data, and its truth is the
// moved file's own header matrix.
TEST(SweepConfig, ShippedExample) {
  SweepPlan plan = PlanSweep(ReadSweepConfig("configs/sweep_example.yaml"));
  EXPECT_GE(plan.runs.size(), 16u);
  LoadSweepPairs(&plan);
  std::ifstream in("configs/data/volcano_moved.xyz");
  std::string line;
  while (std::getline(in, line) && line.rfind("# reference_from_moving: ", 0) != 0) {
  }
  std::vector<double> header;
  for (char& ch : line) ch = (ch == '[' || ch == ']' || ch == ',') ? ' ' : ch;
  std::istringstream words(line.substr(line.find(':') + 1));
  for (double v; words >> v;) header.push_back(v);
  ASSERT_EQ(header.size(), 16u);
  for (int k = 0; k < 16; ++k) EXPECT_EQ(plan.pairs[0].truth(k / 4, k % 4), header[k]) << k;
}

}  // namespace
}  // namespace surfreg
