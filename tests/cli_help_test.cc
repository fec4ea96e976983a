// `surfreg help COMMAND` lists every key of the tables the config parsers
// use (tools/cli_help.h): a key added to a table cannot be left out.
#include "tools/cli_help.h"

#include <gtest/gtest.h>

#include <string>

#include "tools/align_config.h"
#include "tools/jaw_config.h"
#include "tools/series_config.h"
#include "tools/measure_run.h"

namespace surfreg {
namespace {

bool Lists(const std::string& help, const std::string& key) {
  return help.find("\n  " + key + ": ") != std::string::npos;
}

TEST(CliHelp, AlignListsEveryKeyWithValuesAndMeaning) {
  const std::string help = CommandKeysHelp("align", "");
  ASSERT_GE(AlignConfigKeys().size(), 40u);
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    EXPECT_TRUE(Lists(help, key.name)) << key.name;
    EXPECT_NE(help.find(std::string(key.name) + ": " + key.type), std::string::npos) << key.name;
    EXPECT_NE(help.find(key.help), std::string::npos) << key.name;
  }
  // Defaults come from AlignOptions.
  EXPECT_NE(help.find("max_iterations: an integer >= 1 (default 100)"), std::string::npos) << help;
}

TEST(CliHelp, JawListsEveryKey) {
  const std::string help = CommandKeysHelp("jaw", "");
  for (const JawConfigKey& key : JawConfigKeys()) EXPECT_TRUE(Lists(help, key.name)) << key.name;
}

TEST(CliHelp, SeriesListsEveryKey) {
  const std::string help = CommandKeysHelp("series", "");
  for (const ConfigKey& key : SeriesConfigKeys()) EXPECT_TRUE(Lists(help, key.name)) << key.name;
}

TEST(CliHelp, MeasureListsItsAlignKeys) {
  const std::string help = CommandKeysHelp("measure", "");
  for (const std::string& name : MeasureKeys()) {
    bool align_key = false;
    for (const AlignConfigKey& key : AlignConfigKeys()) align_key |= name == key.name;
    if (align_key) {
      EXPECT_TRUE(Lists(help, name)) << name;
    }
  }
  EXPECT_FALSE(Lists(help, "max_iterations"));  // not a key of measure
}

TEST(CliHelp, SweepListsItsConfigKeys) {
  const std::string help = CommandKeysHelp("sweep", "");
  for (const char* key : {"pairs", "settings", "sweep", "perturbations", "success", "jobs", "output"}) {
    EXPECT_TRUE(Lists(help, key)) << key;
  }
}

TEST(CliHelp, CommandsWithoutKeysGetNothingForUnknownFlags) {
  EXPECT_EQ(CommandKeysHelp("merge", ""), "");
  EXPECT_EQ(CommandKeysHelp("triangulate", "no_such_flag"), "");
}

}  // namespace
}  // namespace surfreg
