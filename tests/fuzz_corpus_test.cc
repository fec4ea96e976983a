// The fuzz corpus as a regression test (issue 7): every file of
// tests/fuzz/corpus/<target>/ (seeds, and each input a fuzzer once found,
// kept after the fix) runs through its target of tests/fuzz/fuzz_targets.h,
// which must accept it or refuse it with InputError: any other exception
// (including a broken invariant of the measure) fails the test. Runs in the
// normal build, no clang needed; under tests/run_sanitizers.sh it also
// catches leaks and memory errors on these inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_targets.h"

namespace surfreg::fuzz {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = "tests/fuzz/corpus";  // relative to the source root (the test's cwd)

std::vector<fs::path> CorpusFiles(const std::string& target) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(kCorpus / target)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string Contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class FuzzCorpusTest : public ::testing::TestWithParam<FuzzTarget> {};

TEST_P(FuzzCorpusTest, EveryInputIsAcceptedOrRefusedWithInputError) {
  const FuzzTarget& target = GetParam();
  const std::vector<fs::path> files = CorpusFiles(target.name);
  EXPECT_GE(files.size(), 3u) << "corpus " << target.name << " has too few seeds";
  for (const fs::path& file : files) {
    try {
      target.run(Contents(file));
    } catch (const std::exception& e) {
      ADD_FAILURE() << file.string() << ": " << e.what();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzCorpusTest, ::testing::ValuesIn(FuzzTargets()),
                         [](const ::testing::TestParamInfo<FuzzTarget>& param_info) {
                           return std::string(param_info.param.name);
                         });

}  // namespace
}  // namespace surfreg::fuzz
