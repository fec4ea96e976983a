#pragma once
// The subcommands of the `surfreg` program (see surfreg_main.cc for the
// dispatch table). Each Run function gets the positional arguments after the
// command name (flags are already parsed by gflags) and returns the exit code.
// Bad input is reported by throwing InputError (exit 2), bad usage by
// throwing UsageError (exit 2, with the command's usage line).
#include <stdexcept>
#include <string>
#include <vector>

namespace surfreg {

class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& message) : std::runtime_error(message) {}
};

// triangulate FILE [--json]: reads a surface, triangulates it, reports counts
// and timings.
int RunTriangulate(const std::vector<std::string>& args);

// measure A B [--volume=overlay|union] [--weights=uniform|per_point|
// mask:POLYGON_FILE] [--json]: reads two surfaces, compares B with A
// (measure/measures.h: ρd, ρ'd, ρs, signed and cut/fill volumes over the
// overlap of their hulls), reports the measures, counts and timings. Bad
// --volume/--weights values and bad polygon files are InputErrors (one line).
int RunMeasure(const std::vector<std::string>& args);

// align --config FILE.yaml | REFERENCE MOVING [--key=value ...] [--json]:
// rigid registration of MOVING onto REFERENCE (registration/align.h) with the
// settings of tools/align_config.h (every config key is also a flag; flags
// win). Writes the transform JSON, the aligned surface and a per-iteration
// CSV where asked (atomically), and prints a summary or, with --json, the
// transform JSON. Bad settings and files are InputErrors naming the key.
int RunAlign(const std::vector<std::string>& args);

}  // namespace surfreg
