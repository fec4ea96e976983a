// The command line's flags made from the key tables: one flag per config key,
// named and described by its table, so that a key is defined once (in its
// library's table) for config files, flags, help and Python keywords.
#ifndef SURFREG_TOOLS_KEY_FLAGS_H_
#define SURFREG_TOOLS_KEY_FLAGS_H_

#include <string>

namespace surfreg {

// Registers a gflags flag for every key of `align`'s table (tools/align_config.h)
// that no DEFINE_* has made already; call once, before the command line is
// parsed. Keys whose values are "true or false" become boolean flags
// (--progress, --noprogress) with the key's default; the others are strings,
// "" meaning "not given", their values parsed and checked by the table as a
// config file's are.
void RegisterKeyFlags();

// The text of a string flag that RegisterKeyFlags made ("" when not given).
const std::string& KeyFlag(const char* name);

// `--threads` for a command without a config (asymmetry, transform): 0
// (every core) when not given; a bad value refused as the key's table
// refuses it ("flag '--threads' expects an integer >= 1, or all, got 'x'").
int ThreadsFlag();

}  // namespace surfreg

#endif  // SURFREG_TOOLS_KEY_FLAGS_H_
