#pragma once
// The body of `surfreg help COMMAND`: every config key of the command with
// what its values look like, its default and its meaning, taken from the
// tables the config parsers use (tools/align_config.h, tools/jaw_config.h,
// tools/measure_run.h), then the command's other flags with gflags'
// descriptions and defaults. A key added to a table is listed without
// further work; tests/cli_help_test.cc checks that none is missing.
#include <string>

namespace surfreg {

// `command`: a command name; `flags`: the flags it reads besides its keys
// (space-separated, as in surfreg_main.cc's table). "" for a command with
// neither.
std::string CommandKeysHelp(const std::string& command, const std::string& flags);

}  // namespace surfreg
