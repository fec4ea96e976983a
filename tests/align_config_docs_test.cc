// The shipped example configs and the key reference (docs/align.md) against
// the code's table of align keys. Run from the project root (ctest does).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "tests/testing/file_checks.h"
#include "tools/align_config.h"

namespace surfreg {
namespace {

using testing::Contains;

TEST(AlignConfig, ShippedConfigsParseAndNameExistingData) {
  for (const char* file : {"configs/terrain_volcano.yaml", "configs/face_mannequin.yaml"}) {
    AlignConfig config;
    ApplyAlignConfigFile(file, &config);
    for (const char* key : {"output", "aligned", "log"}) {
      EXPECT_EQ(AlignConfigValue(config, key).rfind("out/", 0), 0u) << file << " " << key;
      ApplyAlignFlag(key, "", &config);  // out/ need not exist here
    }
    FinishAlignConfig(&config);
    for (const char* key : {"reference", "moving"}) {
      EXPECT_GE(ReadInput(config, key).size(), 3000u) << file << " " << key;
    }
    // Each key of the example is documented there by a comment.
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#' || line[0] == ' ') continue;
      EXPECT_NE(line.find(" # "), std::string::npos) << file << ": no comment on: " << line;
    }
  }
}

std::string FileText(const char* path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path << ": run from the project root";
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The full key reference (docs/align.md, linked from the README's key table)
// has a row for every key of the code's table, with its default.
TEST(AlignConfig, KeyReferenceListsEveryKeyWithItsDefault) {
  const std::string text = FileText("docs/align.md");
  const AlignConfig defaults;
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    const std::string name = key.name;
    std::string value = "`" + AlignConfigValue(defaults, name) + "`";
    if (value == "``") value = name == "reference" || name == "moving" ? "(required)" : "none";
    const std::string row = "| `" + name + "` | " + value + " |";
    EXPECT_TRUE(Contains(text, row)) << "docs/align.md has no row " << row;
  }
  EXPECT_TRUE(Contains(FileText("README.md"), "(docs/align.md#keys)"));
}

}  // namespace
}  // namespace surfreg
